// Saddle orbits, method against method: dF/dE = T (the action's differences against the
// Gauss-Legendre integral of the period over energy, at double and quad), the periodic and the
// symmetric shooting formulations against each other (double and quad, egalitarian and other
// pendulums), and whole families for other pendulums (rigid links included).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "flipflux/core/decimal.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "pendulums.hpp"

namespace flipflux {
namespace {

template <class Real>
double rel(const Real& a, const Real& b) {
    using std::abs;
    return static_cast<double>(abs(a - b) / abs(b));
}

/// F(E2) - F(E1) against the n-point Gauss-Legendre rule for integral_E1^E2 T dE (T analytic on
/// the interval). Returns the relative difference.
template <class Real>
double action_difference_vs_period_integral(const double_pendulum<Real>& model, arm a,
                                            const Real& e1, const Real& e2, int n,
                                            orbit_method method) {
    const auto& t = gauss_legendre_tableau_of<Real>(n);
    std::vector<Real> energies{e1};
    for (int i = 0; i < n; ++i)
        energies.push_back(e1 + (e2 - e1) * t.c[i]);
    energies.push_back(e2);
    orbit_options<Real> options;
    options.method = method;
    const auto family = continue_saddle_family(model, a, energies, options);
    EXPECT_EQ(family.orbits.size(), energies.size()) << family.stop_reason;
    if (family.orbits.size() != energies.size()) return 1;
    Real integral = 0;
    for (int i = 0; i < n; ++i) {
        EXPECT_NE(family.orbits[1 + i].status, orbit_status::not_converged);
        integral += t.b[i] * family.orbits[1 + i].period;
    }
    integral *= e2 - e1;
    const Real difference = family.orbits.back().action - family.orbits.front().action;
    const double r = rel(difference, integral);
    std::printf("  %s arm %s [%s, %s]: F(E2) - F(E1) = %s, int T dE = %s, rel. diff %.2e\n",
                precision_name<Real>().c_str(), to_string(a).c_str(), to_decimal(e1, 6).c_str(),
                to_decimal(e2, 6).c_str(), to_decimal(difference).c_str(),
                to_decimal(integral).c_str(), r);
    return r;
}

TEST(OrbitsVerification, ActionDerivativeIsThePeriodAtDouble) {
    // T is analytic in E on [E_s, E_max) (a log singularity at E_max): 12 nodes resolve it to
    // ~1e-13 on intervals at least their length away from E_max
    const double_pendulum<double> model;
    struct interval {
        arm a;
        double e1, e2;
    };
    for (const auto& iv : std::vector<interval>{{arm::two, 2.05, 2.5},
                                                {arm::two, 3.5, 4.5},
                                                {arm::two, 5.3, 5.7},
                                                {arm::one, 4.2, 4.8},
                                                {arm::one, 5.2, 5.7}}) {
        for (auto m : {orbit_method::periodic, orbit_method::symmetric})
            EXPECT_LE(action_difference_vs_period_integral(model, iv.a, iv.e1, iv.e2, 12, m),
                      1e-10);
    }
}

TEST(OrbitsVerification, ActionDerivativeIsThePeriodAtQuad) {
    const double_pendulum<quad> model;
    EXPECT_LE(action_difference_vs_period_integral(model, arm::two, quad(3), quad(16) / 5, 10,
                                                   orbit_method::symmetric),
              1e-25);
    EXPECT_LE(action_difference_vs_period_integral(model, arm::one, quad(5), quad(26) / 5, 10,
                                                   orbit_method::symmetric),
              1e-25);
}

/// Other pendulums: a heavy short upper link, a light second mass, two uniform rods (rigid
/// links), and a strongly unequal pair where arm 1's saddle lies below arm 2's.
std::vector<physical_parameters<double>> other_pendulums() {
    std::vector<physical_parameters<double>> v;
    physical_parameters<double> p;
    p.m2 = 3;
    p.L2 = 0.5;
    v.push_back(p);
    p = {};
    p.m1 = 5;
    p.m2 = 0.2;
    p.L1 = 0.4;
    p.L2 = 1.3;
    v.push_back(p);
    v.push_back(test::uniform_rods_parameters());
    p = {};
    p.m1 = 0.3;
    p.m2 = 2;
    p.L1 = 0.5;
    p.L2 = 1.5;
    p.g = 2;
    v.push_back(p);
    return v;
}

template <class Real>
void check_formulations(const double_pendulum<Real>& model, arm a, const Real& energy,
                        double tolerance) {
    orbit_options<Real> per, sym;
    per.method = orbit_method::periodic;
    sym.method = orbit_method::symmetric;
    const auto p = solve_saddle_orbit(model, a, energy, per);
    const auto s = solve_saddle_orbit(model, a, energy, sym);
    ASSERT_NE(p.status, orbit_status::not_converged) << p.double_stage;
    ASSERT_NE(s.status, orbit_status::not_converged) << s.double_stage;
    const double dT = rel(p.period, s.period), dF = rel(p.action, s.action);
    std::printf("  %s arm %s E = %s: T = %s, F = %s; periodic vs symmetric: T %.1e, F %.1e\n",
                precision_name<Real>().c_str(), to_string(a).c_str(), to_decimal(energy).c_str(),
                to_decimal(s.period).c_str(), to_decimal(s.action).c_str(), dT, dF);
    EXPECT_LE(dT, tolerance);
    EXPECT_LE(dF, tolerance);
    // the monodromy's trace is only as good as eps |mu| (a period's amplification)
    const double mu = static_cast<double>(s.floquet.multiplier);
    EXPECT_LE(rel(p.floquet.stability_index, s.floquet.stability_index),
              1e3 * mu * static_cast<double>(std::numeric_limits<Real>::epsilon()));
}

TEST(OrbitsVerification, FormulationsAgreeAtDouble) {
    const double_pendulum<double> model;
    for (double E : {2.2, 3.0, 4.0, 5.0, 5.9})
        check_formulations(model, arm::two, E, 1e-13);
    for (double E : {4.2, 5.0, 5.9})
        check_formulations(model, arm::one, E, 1e-13);
    for (const auto& p : other_pendulums()) {
        const double_pendulum<double> m(p);
        for (arm a : {arm::two, arm::one}) {
            const double lo = m.saddle_energy(a), hi = m.maximum_energy();
            check_formulations(m, a, lo + 0.5 * (hi - lo), 1e-13);
        }
    }
}

TEST(OrbitsVerification, FormulationsAgreeAtQuad) {
    const double_pendulum<quad> model;
    check_formulations(model, arm::two, quad(4), 1e-31);
    check_formulations(model, arm::one, quad(5), 1e-31);
    physical_parameters<quad> p;
    p.m2 = 3;
    p.L2 = quad(1) / 2;
    p.a2 = p.L2;
    const double_pendulum<quad> heavy(p);
    check_formulations(heavy, arm::two, heavy.saddle_energy(arm::two) + 1, 1e-31);
}

TEST(OrbitsVerification, FamiliesOfOtherPendulumsReachTheMaximum) {
    // for every parameter set and arm: the family from the centre mode to E_max - 1e-5 range,
    // F increasing with dF/dE = T by the trapezoidal-free check of neighbouring orbits, and a
    // curve that is a graph
    for (const auto& p : other_pendulums()) {
        const double_pendulum<double> model(p);
        for (arm a : {arm::two, arm::one}) {
            const double lo = model.saddle_energy(a), hi = model.maximum_energy();
            std::vector<double> energies;
            for (double f : {1e-6, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.9999, 1 - 1e-5})
                energies.push_back(lo + f * (hi - lo));
            orbit_options<double> options;
            options.method = orbit_method::symmetric;
            const auto fam = continue_saddle_family(model, a, energies, options);
            ASSERT_EQ(fam.orbits.size(), energies.size()) << fam.stop_reason;
            std::printf(
                "  m1=%g m2=%g L1=%g L2=%g a1=%g a2=%g I1=%g I2=%g g=%g arm %d: E in (%g, "
                "%g), %zu steps, %d halvings; T %.6g .. %.6g\n",
                p.m1, p.m2, p.L1, p.L2, p.a1, p.a2, p.I1, p.I2, p.g, int(a), lo, hi,
                fam.steps.size(), fam.halvings, fam.orbits.front().period,
                fam.orbits.back().period);
            for (std::size_t i = 0; i < fam.orbits.size(); ++i) {
                const auto& o = fam.orbits[i];
                EXPECT_NE(o.status, orbit_status::not_converged);
                EXPECT_GT(o.action, 0);
                if (i > 0) {
                    // mean value theorem: (F_i - F_{i-1}) / (E_i - E_{i-1}) lies between the T's
                    const double slope =
                        (o.action - fam.orbits[i - 1].action) / (energies[i] - energies[i - 1]);
                    EXPECT_GE(slope, fam.orbits[i - 1].period * (1 - 1e-9));
                    EXPECT_LE(slope, o.period * (1 + 1e-9));
                }
                if (i + 1 < fam.orbits.size()) {
                    EXPECT_NO_THROW(make_saddle_curve(model, o));
                }
            }
        }
    }
}

}  // namespace
}  // namespace flipflux
