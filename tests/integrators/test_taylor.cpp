// Taylor-series arithmetic and the Taylor integrator: the recurrences against closed-form series
// (sin/cos of a line, exp of a quadratic, 1/(1+t), a product of polynomials), the integrator on the
// harmonic oscillator (exact solution) and on the simple pendulum (quarter period K(k) from
// Boost's ellint_1: the velocity vanishes there), dense output, the Jorba-Zou order, failures.
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/factorials.hpp>
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/integrators/taylor.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class Taylor : public test::real_test<Real> {};
TYPED_TEST_SUITE(Taylor, real_types, real_name);

template <class Real>
Real factorial(int n) {
    Real f = 1;
    for (int i = 2; i <= n; ++i)
        f *= i;
    return f;
}

TYPED_TEST(Taylor, SeriesArithmeticMatchesClosedForms) {
    using Real = TypeParam;
    using std::abs;
    using std::cos;
    using std::exp;
    using std::sin;
    const Real e = eps<Real>();
    const int n = 30;
    // sin/cos of u = a + b t: coefficient k is b^k / k! sin(a + k pi / 2) (cos likewise)
    const Real a = Real(3) / 7, b = Real(-5) / 4;
    std::vector<Real> u(n + 1, Real(0));
    u[0] = a;
    u[1] = b;
    const auto sc = taylor::series_sin_cos(u);
    Real worst = 0;
    for (int k = 0; k <= n; ++k) {
        const Real w = pow(b, k) / factorial<Real>(k);
        const Real phase = a + k * half_pi<Real>();
        worst = std::max<Real>(worst, abs(sc.s[k] - w * sin(phase)));
        worst = std::max<Real>(worst, abs(sc.c[k] - w * cos(phase)));
    }
    EXPECT_LE(static_cast<double>(worst / e), 64.0);
    // exp(a + b t + t^2) = e^a sum_{j + 2 m = k} b^j / j! / m!
    u[2] = 1;
    const auto ex = taylor::series_exp(u);
    worst = 0;
    for (int k = 0; k <= n; ++k) {
        Real ref = 0;
        for (int m = 0; 2 * m <= k; ++m)
            ref += pow(b, k - 2 * m) / factorial<Real>(k - 2 * m) / factorial<Real>(m);
        ref *= exp(a);
        worst = std::max<Real>(worst, abs(ex[k] - ref) / (1 + abs(ref)));
    }
    EXPECT_LE(static_cast<double>(worst / e), 256.0);
    // 1 / (1 + t) = sum (-t)^k; (1 + 2t) / (1 + t) = 1 + t - t^2 + ... = 2 - 1/(1 + t)
    std::vector<Real> one(n + 1, Real(0)), den(n + 1, Real(0)), num(n + 1, Real(0));
    one[0] = 1;
    den[0] = den[1] = 1;
    num[0] = 1;
    num[1] = 2;
    const auto q = taylor::series_quotient(one, den);
    const auto r = taylor::series_quotient(num, den);
    for (int k = 0; k <= n; ++k) {
        EXPECT_EQ(q[k], k % 2 == 0 ? Real(1) : Real(-1)) << k;
        EXPECT_EQ(r[k], k == 0 ? Real(1) : (k % 2 == 1 ? Real(1) : Real(-1))) << k;
    }
    // (1 + t)(1 - t + t^2) = 1 + t^3
    std::vector<Real> p1{Real(1), Real(1), Real(0), Real(0)},
        p2{Real(1), Real(-1), Real(1), Real(0)};
    const auto pr = taylor::series_product(p1, p2);
    EXPECT_EQ(pr, (std::vector<Real>{Real(1), Real(0), Real(0), Real(1)}));
    EXPECT_THROW(taylor::series_quotient(one, std::vector<Real>(n + 1, Real(0))),
                 std::invalid_argument);
}

/// x'' = -x as (x, v): f_k = (v_k, -x_k).
template <class Real>
struct oscillator {
    explicit oscillator(int) {}
    void operator()(const std::array<std::vector<Real>, 2>& x, int k, std::array<Real, 2>& f) {
        f[0] = x[1][static_cast<std::size_t>(k)];
        f[1] = -x[0][static_cast<std::size_t>(k)];
    }
};

TYPED_TEST(Taylor, HarmonicOscillatorToWorkingPrecision) {
    using Real = TypeParam;
    using std::abs;
    using std::cos;
    using std::sin;
    const Real tol = 64 * eps<Real>();
    const std::array<Real, 2> x0{Real(1), Real(0)}, scale{Real(1), Real(1)};
    const Real T = 10;
    const auto est = taylor_steps_for_tolerance<Real, 2>([](int p) { return oscillator<Real>(p); },
                                                         x0, T, tol, scale);
    ASSERT_GT(est.steps, 0);
    EXPECT_LE(static_cast<double>(est.error_estimate / tol), 16.0);
    taylor_integrator<Real, 2> ti(taylor_order_for(tol));
    oscillator<Real> f(ti.order());
    std::array<Real, 2> x = x0;
    const auto r = ti.integrate(f, x, T / est.steps, est.steps);
    ASSERT_TRUE(r.success);
    EXPECT_EQ(r.statistics.steps, est.steps);
    const double err = static_cast<double>(std::max(abs(x[0] - cos(T)), abs(x[1] + sin(T))));
    EXPECT_LE(err, 16 * static_cast<double>(tol)) << "steps " << est.steps;
    // backward to the start
    const auto back = ti.integrate(f, x, -T / est.steps, est.steps);
    ASSERT_TRUE(back.success);
    EXPECT_LE(static_cast<double>(abs(x[0] - 1) + abs(x[1])), 32 * static_cast<double>(tol));
    // dense output: the last step's polynomial inside the step (from its start t = h)
    const Real h = T / est.steps;
    const Real theta = h * 3 / 7;
    const auto mid = ti.evaluate(-theta);
    const Real t = h - theta;  // backward step from t = h
    EXPECT_LE(static_cast<double>(abs(mid[0] - cos(t)) + abs(mid[1] + sin(t))),
              32 * static_cast<double>(tol));
}

/// The simple pendulum theta'' = -sin theta as (theta, v).
template <class Real>
struct pendulum {
    taylor::sin_cos_series<Real> sc;
    explicit pendulum(int order) : sc(order) {}
    void operator()(const std::array<std::vector<Real>, 2>& x, int k, std::array<Real, 2>& f) {
        sc.next(x[0], k);
        f[0] = x[1][static_cast<std::size_t>(k)];
        f[1] = -sc.s[static_cast<std::size_t>(k)];
    }
};

TYPED_TEST(Taylor, SimplePendulumQuarterPeriodIsEllipticK) {
    using Real = TypeParam;
    using std::abs;
    // from theta = 0 with v0 = 2 k: amplitude sin(theta_max / 2) = k, quarter period K(k)
    const Real k = Real(9) / 10;
    const Real quarter = boost::math::ellint_1(k);
    const Real tol = 64 * eps<Real>();
    const std::array<Real, 2> x0{Real(0), 2 * k}, scale{Real(1), Real(1)};
    const auto est = taylor_steps_for_tolerance<Real, 2>([](int p) { return pendulum<Real>(p); },
                                                         x0, quarter, tol, scale);
    ASSERT_GT(est.steps, 0);
    taylor_integrator<Real, 2> ti(taylor_order_for(tol));
    pendulum<Real> f(ti.order());
    std::array<Real, 2> x = x0;
    ASSERT_TRUE(ti.integrate(f, x, quarter / est.steps, est.steps).success);
    // the turning point: v = 0, theta = 2 asin(k); the velocity's error is the period's times
    // |v'| = sin(theta_max)
    using std::asin;
    EXPECT_LE(static_cast<double>(abs(x[1])), 64 * static_cast<double>(tol)) << est.steps;
    EXPECT_LE(static_cast<double>(abs(x[0] - 2 * asin(k))), 64 * static_cast<double>(tol));
}

TYPED_TEST(Taylor, OrderFollowsTheTolerance) {
    using Real = TypeParam;
    // Jorba-Zou: ceil(-ln(tol) / 2) + 1
    EXPECT_EQ(taylor_order_for(Real(1) / 1000), 5);  // ln 1000 = 6.9
    EXPECT_EQ(taylor_order_for(Real(1)), 2);
    const int p = taylor_order_for(64 * eps<Real>());
    const double digits = binary_digits<Real>() * std::log(2.0);
    EXPECT_NEAR(p, (digits - std::log(64.0)) / 2 + 1, 1.0);
}

/// A right-hand side with a pole at t = 1: x' = x^2, x(0) = 1 (x = 1 / (1 - t)).
template <class Real>
struct blow_up {
    explicit blow_up(int) {}
    void operator()(const std::array<std::vector<Real>, 1>& x, int k, std::array<Real, 1>& f) {
        taylor::product(x[0], x[0], k, f[0]);
    }
};

TYPED_TEST(Taylor, FailuresAreReported) {
    using Real = TypeParam;
    EXPECT_THROW((taylor_integrator<Real, 1>(0)), std::invalid_argument);
    // the coefficients of 1 / (1 - t) are all 1: a step of 10^6000 (beyond every range) overflows
    taylor_integrator<Real, 1> ti(20);
    blow_up<Real> f(20);
    std::array<Real, 1> x{Real(1)};
    ASSERT_TRUE(ti.expand(f, x));
    for (int k = 0; k <= 20; ++k)
        EXPECT_EQ(ti.jet()[0][k], Real(1));
    // the Jorba-Zou step stays inside the radius of convergence 1
    const Real h = ti.step_size(Real(1) / 1000000, {Real(1)});
    EXPECT_LT(h, Real(1));
    EXPECT_GT(h, Real(1) / 10);
    std::array<Real, 1> y{std::numeric_limits<Real>::max()};
    EXPECT_FALSE(ti.step(f, y, Real(1)));
    EXPECT_EQ(y[0], std::numeric_limits<Real>::max());
    std::array<Real, 1> z{std::numeric_limits<Real>::max()};
    EXPECT_FALSE(ti.integrate(f, z, Real(1), 3).success);
    // no step selection through the pole
    const auto est = taylor_steps_for_tolerance<Real, 1>(
        [](int p) { return blow_up<Real>(p); },
        std::array<Real, 1>{std::numeric_limits<Real>::max()}, Real(2), Real(1) / 1000000,
        std::array<Real, 1>{Real(1)});
    EXPECT_EQ(est.steps, 0);
}

}  // namespace
}  // namespace flipflux::test
