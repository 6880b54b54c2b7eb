// The least-squares solve through Ceres' plugin (orbits/least_squares.hpp), on problems whose
// solutions are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "flipflux/orbits/least_squares.hpp"

namespace flipflux::test {
namespace {

/// Rosenbrock's residuals r = (10 (y - x^2), 1 - x): minimum 0 at (1, 1).
const least_squares_function rosenbrock = [](const double* p, double* r, double* jacobian) {
    r[0] = 10 * (p[1] - p[0] * p[0]);
    r[1] = 1 - p[0];
    if (jacobian) {
        jacobian[0] = -20 * p[0];  // dr0/dx
        jacobian[1] = 10;          // dr0/dy
        jacobian[2] = -1;
        jacobian[3] = 0;
    }
    return true;
};

least_squares_settings tight() {
    least_squares_settings s;
    s.max_iterations = 100;
    s.function_tolerance = 1e-30;
    s.gradient_tolerance = 1e-30;
    s.parameter_tolerance = 1e-15;
    return s;
}

TEST(LeastSquares, RosenbrockReachesItsZero) {
    std::vector<double> x{-1.2, 1.0};
    const auto r = solve_least_squares(rosenbrock, x, 2, {}, tight());
    EXPECT_TRUE(r.usable) << r.report;
    EXPECT_NEAR(x[0], 1.0, 1e-12) << r.report;
    EXPECT_NEAR(x[1], 1.0, 1e-12) << r.report;
    EXPECT_LT(r.final_cost, 1e-24);
    EXPECT_GT(r.iterations, 1);
    EXPECT_FALSE(r.report.empty());
}

TEST(LeastSquares, LowerBoundsAreHonoured) {
    // Ceres projects its steps onto the bounds; it is no exact solver of an active bound (here it
    // stops short of the constrained minimum), which the orbits never need: their bound (T above a
    // quarter of its guess) only keeps trial points away from T <= 0.
    // An inactive bound: the unconstrained zero
    std::vector<double> x{-1.2, 1.0};
    auto r = solve_least_squares(rosenbrock, x, 2, {-10.0, -HUGE_VAL}, tight());
    EXPECT_NEAR(x[0], 1.0, 1e-12) << r.report;
    EXPECT_NEAR(x[1], 1.0, 1e-12) << r.report;
    // an active one, x >= 1.5: never crossed, and the cost falls towards its constrained minimum
    // (1 - 1.5)^2 / 2 = 0.125 from 50.5
    x = {2.0, 3.0};
    r = solve_least_squares(rosenbrock, x, 2, {1.5, -HUGE_VAL}, tight());
    EXPECT_TRUE(r.usable) << r.report;
    EXPECT_GE(x[0], 1.5) << r.report;
    EXPECT_GE(r.final_cost, 0.125);
    EXPECT_LT(r.final_cost, 0.13) << r.report;
}

// An exception of the function (e.g. a CPU budget's, which `--max-seconds` turns into a one-line
// error) reaches the caller, and Ceres writes nothing to stderr on the way: it logs "Terminating:
// Residual and Jacobian evaluation failed." through glog despite logging_type = SILENT, which
// once made that one-line error three (the plugin silences glog below FATAL).
TEST(LeastSquares, AnExceptionOfTheFunctionReachesTheCaller) {
    const least_squares_function f = [](const double*, double*, double*) -> bool {
        throw std::domain_error("outside the model's domain");
    };
    std::vector<double> x{0.0, 0.0};
    testing::internal::CaptureStderr();
    EXPECT_THROW(solve_least_squares(f, x, 2, {}, tight()), std::domain_error);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    std::vector<double> y{0.0};
    EXPECT_THROW(solve_least_squares(rosenbrock, y, 2, {0.0, 0.0}, tight()), std::invalid_argument);
}

}  // namespace
}  // namespace flipflux::test
