// Saddle orbits, precision against precision: T and F at double against quad (<= 1e-12), quad
// against mp:50 (<= 1e-28), mp:50 against mp:100 (<= 1e-40); and the hard cases at double and quad:
// just above both saddles (E_s + 1e-8, tiny orbits that must keep their relative accuracy) and
// near the maximum (E_max - 1e-6, long near-homoclinic orbits whose period is ill conditioned:
// the tolerance there is eps times the condition number E |dT/dE| / T reported by the solver).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {
namespace {

template <class Real>
saddle_orbit<Real> orbit(arm a, const std::string& energy, orbit_method m,
                         const Real& tolerance = 0, int stages = 0) {
    const double_pendulum<Real> model;
    orbit_options<Real> o;
    o.method = m;
    o.tolerance = tolerance;
    o.stages = stages;
    auto r = solve_saddle_orbit(model, a, parse_real<Real>(energy, "E"), o);
    EXPECT_NE(r.status, orbit_status::not_converged) << r.double_stage;
    return r;
}

/// What the comparisons need of an orbit, as text (orbits of two mp precisions cannot share a
/// scope): T, F, mu + 1/mu with every digit, the relative error estimates.
struct orbit_summary {
    arm flip_arm = arm::two;
    std::string energy, period, action, stability_index;
    double period_estimate = 0, action_estimate = 0;
};

template <class Real>
orbit_summary summary(const saddle_orbit<Real>& o) {
    auto all = [](const Real& x) { return to_decimal(x, full_digits(x)); };
    return {o.flip_arm,
            to_decimal(o.energy, 12),
            all(o.period),
            all(o.action),
            all(o.floquet.stability_index),
            static_cast<double>(o.error_estimate_period / o.period),
            static_cast<double>(o.error_estimate_action / o.action)};
}

/// The summary of an orbit in mp:digits (tolerance given as decimal text, "" for the default).
orbit_summary mp_orbit(int digits, arm a, const std::string& energy, orbit_method m,
                       const std::string& tolerance, int stages) {
    const precision_scope scope(mp_precision(digits));
    return summary(orbit<mp>(a, energy, m,
                             tolerance.empty() ? mp(0) : parse_real<mp>(tolerance, "tol"), stages));
}

void compare(const orbit_summary& lo, const orbit_summary& hi, double t_tol, double f_tol,
             const char* label) {
    const double dT = relative_error(lo.period, hi.period),
                 dF = relative_error(lo.action, hi.action);
    const double dmu = relative_error(lo.stability_index, hi.stability_index);
    std::printf("  %-28s arm %s E = %s: T %.2e (est. %.1e), F %.2e (est. %.1e), mu+1/mu %.1e\n",
                label, to_string(lo.flip_arm).c_str(), hi.energy.c_str(), dT, lo.period_estimate,
                dF, lo.action_estimate, dmu);
    EXPECT_LE(dT, t_tol) << label;
    EXPECT_LE(dF, f_tol) << label;
    // the solver's own estimates are not optimistic
    EXPECT_LE(dT, 4 * lo.period_estimate + 1e-300);
    EXPECT_LE(dF, 4 * lo.action_estimate + 1e-300);
}

template <class Lo, class Hi>
void compare(const saddle_orbit<Lo>& lo, const saddle_orbit<Hi>& hi, double t_tol, double f_tol,
             const char* label) {
    compare(summary(lo), summary(hi), t_tol, f_tol, label);
}
template <class Lo>
void compare(const saddle_orbit<Lo>& lo, const orbit_summary& hi, double t_tol, double f_tol,
             const char* label) {
    compare(summary(lo), hi, t_tol, f_tol, label);
}

TEST(OrbitsPrecision, DoubleAgainstQuad) {
    for (const char* E : {"2.3", "3", "4", "5", "5.9"}) {
        const auto ref = orbit<quad>(arm::two, E, orbit_method::symmetric);
        compare(orbit<double>(arm::two, E, orbit_method::periodic), ref, 1e-12, 1e-12,
                "double periodic vs quad");
        compare(orbit<double>(arm::two, E, orbit_method::symmetric), ref, 1e-12, 1e-12,
                "double symmetric vs quad");
    }
    for (const char* E : {"4.3", "5", "5.9"}) {
        const auto ref = orbit<quad>(arm::one, E, orbit_method::symmetric);
        compare(orbit<double>(arm::one, E, orbit_method::periodic), ref, 1e-12, 1e-12,
                "double periodic vs quad");
    }
}

TEST(OrbitsPrecision, QuadAgainstMp50) {
    // the reference in mp:50 to 1e-40 (fewer steps than its full precision, still 10^6 x finer)
    compare(orbit<quad>(arm::two, "3", orbit_method::periodic),
            mp_orbit(50, arm::two, "3", orbit_method::symmetric, "1e-40", 12), 1e-28, 1e-28,
            "quad periodic vs mp:50");
    compare(orbit<quad>(arm::one, "5", orbit_method::symmetric),
            mp_orbit(50, arm::one, "5", orbit_method::symmetric, "1e-40", 12), 1e-28, 1e-28,
            "quad symmetric vs mp:50");
}

TEST(OrbitsPrecision, Mp50AgainstMp100) {
    compare(mp_orbit(50, arm::two, "2.5", orbit_method::symmetric, "", 0),
            mp_orbit(100, arm::two, "2.5", orbit_method::symmetric, "1e-72", 14), 1e-40, 1e-40,
            "mp:50 symmetric vs mp:100");
}

TEST(OrbitsPrecision, JustAboveBothSaddles) {
    // E = E_s + 1e-8 (exact in quad; in double the nearest double, the same number for both)
    for (arm a : {arm::two, arm::one}) {
        const double e = (a == arm::two ? 2.0 : 4.0) + 1e-8;
        // NOTE: all digits of the double, so that quad and mp:50 see exactly the same energy (with
        // 25 digits quad's rounding of E would move E - E_s by 4e-34 / 1e-8 = 4e-26 relative)
        const std::string E = to_decimal(e, 60);
        const orbit_summary ref = mp_orbit(50, a, E, orbit_method::symmetric, "1e-40", 10);
        compare(orbit<double>(a, E, orbit_method::periodic), ref, 1e-12, 1e-12,
                "E_s + 1e-8: double periodic");
        compare(orbit<double>(a, E, orbit_method::symmetric), ref, 1e-12, 1e-12,
                "E_s + 1e-8: double symmetric");
        compare(orbit<quad>(a, E, orbit_method::symmetric), ref, 1e-28, 1e-28,
                "E_s + 1e-8: quad symmetric");
        compare(orbit<quad>(a, E, orbit_method::periodic), ref, 1e-28, 1e-28,
                "E_s + 1e-8: quad periodic");
    }
}

TEST(OrbitsPrecision, JustBelowTheMaximum) {
    // E = 6 - 1e-6: T ~ 39, |mu| ~ 1e27 (the periodic single shooting is out of reach at double:
    // eps |mu| >> 1); T's condition number E |dT/dE| / T ~ 4e5 bounds its attainable accuracy
    for (arm a : {arm::two, arm::one}) {
        const std::string E = "5.999999";
        const auto ref = orbit<quad>(a, E, orbit_method::symmetric);
        const auto d = orbit<double>(a, E, orbit_method::symmetric);
        const double kappa = static_cast<double>(ref.energy * ref.period_derivative / ref.period);
        std::printf(
            "  E = 6 - 1e-6 arm %s: T = %s, dT/dE = %s, condition of T %.2e, "
            "|mu| = %.3e\n",
            to_string(a).c_str(), to_decimal(ref.period).c_str(),
            to_decimal(ref.period_derivative, 8).c_str(), kappa,
            static_cast<double>(ref.floquet.multiplier));
        EXPECT_GT(kappa, 1e5);
        compare(d, ref, 64 * kappa * 2.2e-16, 1e-12, "6 - 1e-6: double symmetric");
        // quad by the symmetric formulation against itself at a tighter tolerance and other
        // stages: the attained accuracy, not just repeatability
        const auto fine = orbit<quad>(a, E, orbit_method::symmetric, quad(1e-33), 14);
        compare(ref, fine, 64 * kappa * 1.93e-34, 1e-28, "6 - 1e-6: quad s=10 vs s=14");
    }
    // the periodic formulation at quad, nearer the maximum than double can follow it
    for (arm a : {arm::two, arm::one}) {
        const std::string E = "5.9999";
        const auto sym = orbit<quad>(a, E, orbit_method::symmetric);
        const auto per = orbit<quad>(a, E, orbit_method::periodic);
        compare(per, sym, 1e-26, 1e-28, "6 - 1e-4: quad periodic");
    }
}

}  // namespace
}  // namespace flipflux
