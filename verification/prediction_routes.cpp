// Cross-verification of the prediction module: every route against every other and every
// precision against the next, for the egalitarian pendulum and three non-egalitarian ones, both
// arms, 2 < E <= 100 and the hard cases E = E_s + 1e-12, E = E_max +- 1e-12, E = 1e6, to the
// issue's targets (relative: double 1e-14, quad 1e-31, mp:50 1e-46). The 2-D routes in MPFR are
// the expensive part; they run on a few points (their cost per precision: docs/accuracy.md).
#include <gtest/gtest.h>

// NOTE: the shared test support (tests/support.hpp) runs the CLI from FLIPFLUX_EXE, which
// verification executables do not define; nothing here runs the CLI.
#ifndef FLIPFLUX_EXE
#define FLIPFLUX_EXE "flipflux"
#endif
#include "../tests/prediction/models.hpp"
#include "flipflux/prediction/prediction.hpp"

namespace flipflux {
namespace {

using test::exactly;
using test::relative_error;
using test::target;

/// Every route of every quantity at energy E, in Real.
template <class Real>
struct all_routes {
    std::vector<std::pair<std::string, Real>> omega, flux_upright, flux_approx;
};

template <class Real>
all_routes<Real> evaluate_routes(const double_pendulum<Real>& model, arm a, const Real& E,
                                 bool two_dimensional) {
    all_routes<Real> r;
    r.omega.emplace_back("elliptic", phase_volume(model, E).value);
    if (E >= model.maximum_energy())
        r.omega.emplace_back("closed-form",
                             phase_volume(model, E, phase_volume_method::closed_form).value);
    if (two_dimensional)
        r.omega.emplace_back("2-d",
                             phase_volume(model, E, phase_volume_method::quadrature_2d).value);
    for (upright_flux_method m : {upright_flux_method::elliptic, upright_flux_method::integral,
                                  upright_flux_method::curve, upright_flux_method::momentum}) {
        if (m == upright_flux_method::momentum && !two_dimensional) continue;
        r.flux_upright.emplace_back(to_string(m), upright_flux(model, a, E, m).value);
    }
    r.flux_approx.emplace_back("kinetic", approximate_saddle_flux(model, a, E).value);
    if (two_dimensional)
        r.flux_approx.emplace_back(
            "momentum", approximate_saddle_flux(model, a, E, curve_flux_method::momentum).value);
    return r;
}

template <class Real>
void expect_routes_agree(const std::vector<std::pair<std::string, Real>>& v, double tol,
                         const std::string& where) {
    for (std::size_t i = 1; i < v.size(); ++i) {
        EXPECT_LE(relative_error(v[i].second, v[0].second), tol)
            << where << ": " << v[i].first << " vs " << v[0].first;
    }
}

/// Energies relative to the arm's saddle and the maximum: 2 < E <= 100 scaled to the pendulum.
template <class Real>
std::vector<Real> energies(const double_pendulum<Real>& model, arm a, bool many) {
    const Real es = model.saddle_energy(a), em = model.maximum_energy();
    std::vector<Real> e{Real(es + (em - es) / 16), Real(es + (em - es) / 2),
                        Real(es + (em - es) * 15 / 16), Real(em * 4 / 3), Real(em * 50 / 3)};
    if (many) {
        e.push_back(Real(es + (em - es) / 4));
        e.push_back(Real(es + (em - es) * 3 / 4));
        e.push_back(Real(em * 5));
    }
    return e;
}

TEST(PredictionRoutes, EveryRouteAgreesInDouble) {
    for (const auto& spec : test::model_specs()) {
        const double_pendulum<double> model = test::make_model<double>(spec);
        for (arm a : {arm::two, arm::one}) {
            for (double E : energies(model, a, true)) {
                const std::string where =
                    spec.name + " arm " + to_string(a) + " E " + std::to_string(E);
                const auto r = evaluate_routes(model, a, E, true);
                expect_routes_agree(r.omega, target<double>(), where + " omega");
                expect_routes_agree(r.flux_upright, target<double>(), where + " f1");
                expect_routes_agree(r.flux_approx, target<double>(), where + " f2");
            }
        }
    }
}

TEST(PredictionRoutes, EveryRouteAgreesInQuadAndMatchesMp50) {
    // NOTE: test time (quad is slow at -O0): two pendulums, three energies per arm
    for (std::size_t i : {0, 2}) {
        const auto& spec = test::model_specs()[i];
        const double_pendulum<quad> model = test::make_model<quad>(spec);
        const double_pendulum<mp50> reference = test::make_model<mp50>(spec);
        for (arm a : {arm::two, arm::one}) {
            for (const quad& E : energies(model, a, false)) {
                const auto grid = energies(model, a, false);
                if (E != grid[1] && E != grid[3]) continue;
                const std::string where =
                    spec.name + " arm " + to_string(a) + " E " + to_decimal(E, 8);
                const bool two_d = i == 0 && E == grid[1];  // 2-D routes on one point
                const auto r = evaluate_routes(model, a, E, two_d);
                expect_routes_agree(r.omega, target<quad>(), where + " omega");
                expect_routes_agree(r.flux_upright, target<quad>(), where + " f1");
                expect_routes_agree(r.flux_approx, target<quad>(), where + " f2");
                const mp50 e = exactly<mp50>(E);
                EXPECT_LE(relative_error(r.flux_approx[0].second,
                                         approximate_saddle_flux(reference, a, e).value),
                          target<quad>())
                    << where;
                EXPECT_LE(
                    relative_error(r.flux_upright[0].second, upright_flux(reference, a, e).value),
                    target<quad>())
                    << where;
            }
        }
    }
}

TEST(PredictionRoutes, Mp50RoutesAgreeAndMatchMp100) {
    const double_pendulum<mp50> model;
    const double_pendulum<mp100> reference;
    // every route at one energy per arm (the 2-D phase volume once: it is not per arm)
    const mp50 E2(3), E1(5);
    const auto r2 = evaluate_routes(model, arm::two, E2, true);
    expect_routes_agree(r2.omega, target<mp50>(), "egalitarian omega");
    expect_routes_agree(r2.flux_upright, target<mp50>(), "egalitarian arm 2 f1");
    expect_routes_agree(r2.flux_approx, target<mp50>(), "egalitarian arm 2 f2");
    EXPECT_LE(relative_error(r2.omega[0].second, phase_volume(reference, mp100(3)).value),
              target<mp50>());
    EXPECT_LE(relative_error(r2.flux_approx[0].second,
                             approximate_saddle_flux(reference, arm::two, mp100(3)).value),
              target<mp50>());
    const mp50 f2 = approximate_saddle_flux(model, arm::one, E1).value;
    EXPECT_LE(
        relative_error(
            approximate_saddle_flux(model, arm::one, E1, curve_flux_method::momentum).value, f2),
        target<mp50>());
    EXPECT_LE(relative_error(f2, approximate_saddle_flux(reference, arm::one, mp100(5)).value),
              target<mp50>());
    EXPECT_LE(
        relative_error(upright_flux(model, arm::one, E1).value,
                       upright_flux(model, arm::one, E1, upright_flux_method::integral).value),
        target<mp50>());
}

TEST(PredictionRoutes, Mp100IndependentRoutes) {
    const double_pendulum<mp100> model;
    for (arm a : {arm::two, arm::one}) {
        const mp100 E = a == arm::two ? mp100(3) : mp100(5);
        const mp100 f1 = upright_flux(model, a, E).value;
        EXPECT_LE(
            relative_error(upright_flux(model, a, E, upright_flux_method::integral).value, f1),
            target<mp100>());
        EXPECT_LE(relative_error(upright_flux(model, a, E, upright_flux_method::curve).value, f1),
                  target<mp100>());
    }
    // Omega above the maximum: elliptic route, closed form and 2-D ring
    const mp100 E(20);
    const mp100 omega = phase_volume(model, E, phase_volume_method::closed_form).value;
    EXPECT_LE(relative_error(phase_volume(model, E).value, omega), target<mp100>());
    EXPECT_LE(
        relative_error(phase_volume(model, E, phase_volume_method::quadrature_2d).value, omega),
        target<mp100>());
}

// The hard cases at every precision: relative accuracy at E_s + 1e-12 (both saddles), at
// E_max +- 1e-12 and at E = 1e6, against the next precision up (quad for double, mp50 for quad,
// mp100 for mp50) and, in double and quad, across routes. NOTE: in mp50 the phase volume is
// compared with mp100 at the kink and the huge energy only (test time); its saddle cases are in
// the golden data (2.05, 4.05) and in the unit tests' power laws.
template <class Real, class Ref>
void hard_cases(bool with_routes) {
    const double_pendulum<Real> model;
    const double_pendulum<Ref> reference;
    const Real d = Real(1) / 1000000000000;
    std::vector<std::pair<arm, Real>> cases{{arm::two, Real(2 + d)},
                                            {arm::one, Real(4 + d)},
                                            {arm::two, Real(6 - d)},
                                            {arm::one, Real(6 + d)},
                                            {arm::two, Real(1000000)}};
    for (const auto& [a, E] : cases) {
        const std::string where = "arm " + to_string(a) + " E " + to_decimal(E, 20);
        const Ref e = exactly<Ref>(E);
        const Real f1 = upright_flux(model, a, E).value;
        const Real f2 = approximate_saddle_flux(model, a, E).value;
        EXPECT_LE(
            relative_error(f1, upright_flux(reference, a, e, upright_flux_method::integral).value),
            target<Real>())
            << where;
        EXPECT_LE(relative_error(f2, approximate_saddle_flux(reference, a, e).value),
                  target<Real>())
            << where;
        if (with_routes || E > 5) {
            const Real omega = phase_volume(model, E).value;
            EXPECT_LE(relative_error(omega, phase_volume(reference, e).value), target<Real>())
                << where;
            if (with_routes) {
                EXPECT_LE(
                    relative_error(phase_volume(model, E, phase_volume_method::quadrature_2d).value,
                                   omega),
                    target<Real>())
                    << where;
                EXPECT_LE(
                    relative_error(
                        approximate_saddle_flux(model, a, E, curve_flux_method::momentum).value,
                        f2),
                    target<Real>())
                    << where;
            }
        }
    }
}

TEST(PredictionRoutes, HardCasesDouble) {
    hard_cases<double, quad>(true);
}
TEST(PredictionRoutes, HardCasesQuad) {
    hard_cases<quad, mp50>(false);
}
TEST(PredictionRoutes, HardCasesMp50) {
    hard_cases<mp50, mp100>(false);
}

}  // namespace
}  // namespace flipflux
