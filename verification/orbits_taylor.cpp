// Saddle orbits by the Taylor integrator at high precision (label "verify": minutes in release):
// against the independent route (Gauss-Legendre, symmetric shooting) at mp:100, and against
// itself at 20 more digits at mp:100 (E = 4, 5.95, 5.99, both arms where the family exists) and
// mp:300 (E = 4). Every check prints the digits of T and F it reached and its seconds; the
// agreement required is the sum of the two error estimates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ctime>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {
namespace {

/// An orbit's T, F, stability index and estimates as text, with its solve's seconds.
struct solved {
    std::string period, action, stability_index, period_estimate, action_estimate;
    double seconds = 0;
    long steps = 0;
    int order = 0;
};

solved solve(int digits, const std::string& energy, arm a, orbit_integrator integrator,
             orbit_method method) {
    const precision_scope scope(mp_precision(digits));
    const double_pendulum<mp> model;
    orbit_options<mp> options;
    options.integrator = integrator;
    options.method = method;
    // CPU seconds (the solver is serial; wall time depends on the machine's other jobs)
    timespec c0{}, c1{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
    const auto o = solve_saddle_orbit(model, a, parse_real<mp>(energy, "E"), options);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
    const double s = static_cast<double>(c1.tv_sec - c0.tv_sec) +
                     1e-9 * static_cast<double>(c1.tv_nsec - c0.tv_nsec);
    EXPECT_EQ(o.status, orbit_status::converged) << o.double_stage;
    auto all = [](const mp& x) { return to_decimal(x, full_digits(x)); };
    return {all(o.period),
            all(o.action),
            all(o.floquet.stability_index),
            to_decimal(o.error_estimate_period, 3),
            to_decimal(o.error_estimate_action, 3),
            s,
            o.steps,
            o.order};
}

/// |a - b| <= ea + eb, in mp:digits + 20 from the decimal texts.
bool agree(const std::string& a, const std::string& b, const std::string& ea, const std::string& eb,
           int digits) {
    const precision_scope scope(mp_precision(digits + 20));
    using std::abs;
    return abs(parse_real<mp>(a, "a") - parse_real<mp>(b, "b")) <=
           parse_real<mp>(ea, "ea") + parse_real<mp>(eb, "eb");
}

void against_more_digits(int digits, const std::string& energy, arm a, orbit_method method) {
    const solved o = solve(digits, energy, a, orbit_integrator::taylor, method);
    const solved ref = solve(digits + 20, energy, a, orbit_integrator::taylor, method);
    const double dT = correct_digits(o.period, ref.period);
    const double dF = correct_digits(o.action, ref.action);
    std::printf(
        "  Taylor mp:%d %s arm %s E = %s: %.2f CPU s (%ld steps, order %d), digits T %.1f, "
        "F %.1f (against mp:%d)\n",
        digits, to_string(method).c_str(), to_string(a).c_str(), energy.c_str(), o.seconds, o.steps,
        o.order, dT, dF, digits + 20);
    EXPECT_TRUE(agree(o.period, ref.period, o.period_estimate, ref.period_estimate, digits));
    EXPECT_TRUE(agree(o.action, ref.action, o.action_estimate, ref.action_estimate, digits));
    // full precision: T and F to N digits (less the period's condition near E_max: 2 digits)
    EXPECT_GE(dT, digits - 2);
    EXPECT_GE(dF, digits - 1);
}

TEST(OrbitsTaylor, AgreesWithGaussLegendreAtMp100) {
    const solved t = solve(100, "4", arm::two, orbit_integrator::taylor, orbit_method::symmetric);
    const solved g =
        solve(100, "4", arm::two, orbit_integrator::gauss_legendre, orbit_method::symmetric);
    std::printf(
        "  mp:100 symmetric arm 2 E = 4: Taylor %.2f CPU s, Gauss-Legendre %.2f (ratio %.1f);"
        " T agree to %.1f digits, F %.1f, stability index %.1f\n",
        t.seconds, g.seconds, g.seconds / t.seconds, correct_digits(t.period, g.period),
        correct_digits(t.action, g.action), correct_digits(t.stability_index, g.stability_index));
    EXPECT_TRUE(agree(t.period, g.period, t.period_estimate, g.period_estimate, 100));
    EXPECT_TRUE(agree(t.action, g.action, t.action_estimate, g.action_estimate, 100));
    // the multiplier mu = 3.7e3: the quarter orbit's monodromy loses ~1 digit
    EXPECT_GE(correct_digits(t.stability_index, g.stability_index), 97);
}

TEST(OrbitsTaylor, Mp100AtE4) {
    against_more_digits(100, "4", arm::two, orbit_method::periodic);
    against_more_digits(100, "4", arm::two, orbit_method::symmetric);
    against_more_digits(100, "5", arm::one, orbit_method::periodic);
}

TEST(OrbitsTaylor, Mp100NearTheMaximum) {
    for (arm a : {arm::one, arm::two}) {
        against_more_digits(100, "5.95", a, orbit_method::periodic);
        against_more_digits(100, "5.95", a, orbit_method::symmetric);
        against_more_digits(100, "5.99", a, orbit_method::symmetric);
    }
}

TEST(OrbitsTaylor, Mp300AtE4) {
    against_more_digits(300, "4", arm::two, orbit_method::symmetric);
}

}  // namespace
}  // namespace flipflux
