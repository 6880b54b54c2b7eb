// Cross-verification of the prediction module: every route against every other and every
// precision against the next, for the egalitarian pendulum and three non-egalitarian ones, both
// arms, 2 < E <= 100 and the hard cases E = E_s + 1e-12, E = E_max +- 1e-12, E = 1e6, to the
// issue's targets (relative: double 1e-14, quad 1e-31, mp:50 1e-46). The 2-D routes in MPFR are
// the expensive part; they run on a few points (their cost per precision: docs/accuracy.md).
#include <gtest/gtest.h>

#include "flipflux/prediction/prediction.hpp"
#include "pendulums.hpp"

namespace flipflux {
namespace {

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

/// The default routes of f1 and f2 at E (decimal text) in mp:digits, as decimal text: the
/// references of the lower precisions.
std::pair<std::string, std::string> fluxes_in_mp(int digits, const test::model_spec& spec, arm a,
                                                 const std::string& energy) {
    return test::in_mp(digits, [&] {
        const double_pendulum<mp> reference = test::make_model<mp>(spec);
        const mp e = parse_real<mp>(energy, "E");
        return std::pair{to_decimal(upright_flux(reference, a, e).value),
                         to_decimal(approximate_saddle_flux(reference, a, e).value)};
    });
}

TEST(PredictionRoutes, EveryRouteAgreesInQuadAndMatchesMp50) {
    // NOTE: test time (quad is slow at -O0): two pendulums, three energies per arm
    for (std::size_t i : {0, 2}) {
        const auto& spec = test::model_specs()[i];
        const double_pendulum<quad> model = test::make_model<quad>(spec);
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
                const auto [f1, f2] = fluxes_in_mp(50, spec, a, to_decimal(E, 140));
                EXPECT_LE(relative_error(r.flux_approx[0].second, f2), target<quad>()) << where;
                EXPECT_LE(relative_error(r.flux_upright[0].second, f1), target<quad>()) << where;
            }
        }
    }
}

TEST(PredictionRoutes, Mp50RoutesAgreeAndMatchMp100) {
    // the references in mp:100 first: omega and f2 at E = 3 (arm 2), f2 at E = 5 (arm 1)
    // (a pair, not a structured binding: clang 14 cannot capture bindings in a lambda)
    const auto reference_3 = test::in_mp(100, [] {
        const double_pendulum<mp> reference;
        return std::pair{to_decimal(phase_volume(reference, mp(3)).value),
                         to_decimal(approximate_saddle_flux(reference, arm::two, mp(3)).value)};
    });
    const std::string& omega3 = reference_3.first;
    const std::string& f2_3 = reference_3.second;
    const std::string f2_5 = fluxes_in_mp(100, test::model_specs()[0], arm::one, "5").second;
    test::in_mp(50, [&] {
        const double_pendulum<mp> model;
        // every route at one energy per arm (the 2-D phase volume once: it is not per arm)
        const mp E2(3), E1(5);
        const auto r2 = evaluate_routes(model, arm::two, E2, true);
        expect_routes_agree(r2.omega, target<mp>(), "egalitarian omega");
        expect_routes_agree(r2.flux_upright, target<mp>(), "egalitarian arm 2 f1");
        expect_routes_agree(r2.flux_approx, target<mp>(), "egalitarian arm 2 f2");
        EXPECT_LE(relative_error(r2.omega[0].second, omega3), target<mp>());
        EXPECT_LE(relative_error(r2.flux_approx[0].second, f2_3), target<mp>());
        const mp f2 = approximate_saddle_flux(model, arm::one, E1).value;
        EXPECT_LE(
            relative_error(
                approximate_saddle_flux(model, arm::one, E1, curve_flux_method::momentum).value,
                f2),
            target<mp>());
        EXPECT_LE(relative_error(f2, f2_5), target<mp>());
        EXPECT_LE(
            relative_error(upright_flux(model, arm::one, E1).value,
                           upright_flux(model, arm::one, E1, upright_flux_method::integral).value),
            target<mp>());
    });
}

TEST(PredictionRoutes, Mp100IndependentRoutes) {
    test::in_mp(100, [] {
        const double_pendulum<mp> model;
        for (arm a : {arm::two, arm::one}) {
            const mp E = a == arm::two ? mp(3) : mp(5);
            const mp f1 = upright_flux(model, a, E).value;
            EXPECT_LE(
                relative_error(upright_flux(model, a, E, upright_flux_method::integral).value, f1),
                target<mp>());
            EXPECT_LE(
                relative_error(upright_flux(model, a, E, upright_flux_method::curve).value, f1),
                target<mp>());
        }
        // Omega above the maximum: elliptic route, closed form and 2-D ring
        const mp E(20);
        const mp omega = phase_volume(model, E, phase_volume_method::closed_form).value;
        EXPECT_LE(relative_error(phase_volume(model, E).value, omega), target<mp>());
        EXPECT_LE(
            relative_error(phase_volume(model, E, phase_volume_method::quadrature_2d).value, omega),
            target<mp>());
    });
}

// The hard cases at every precision: relative accuracy at E_s + 1e-12 (both saddles), at
// E_max +- 1e-12 and at E = 1e6, against a higher precision (quad for double, mp:50 for quad,
// mp:100 for mp:50, mp:320 for mp:300) and, in double and quad, across routes. NOTE: in mp the
// phase volume is compared with the reference at the kink and the huge energy only (test time);
// its saddle cases are in the golden data (2.05, 4.05) and in the unit tests' power laws.

/// The hard-case energies rounded to Real, as exact decimal text (140 digits: exact for every
/// precision up to mp:130, and 1e-140 relative beyond).
template <class Real>
std::vector<std::pair<arm, std::string>> hard_energies() {
    const Real d = Real(1) / 1000000000000;
    const std::pair<arm, Real> cases[] = {{arm::two, Real(2 + d)},
                                          {arm::one, Real(4 + d)},
                                          {arm::two, Real(6 - d)},
                                          {arm::one, Real(6 + d)},
                                          {arm::two, Real(1000000)}};
    std::vector<std::pair<arm, std::string>> out;
    for (const auto& [a, E] : cases)
        out.emplace_back(a, to_decimal(E, 140));
    return out;
}

struct hard_values {
    std::string f1, f2, omega, omega_2d, f2_momentum;
    double target = 0;
};

/// The values at one hard case in Real: the default routes (the reference: f1 by its integral
/// route, an independent one), omega when asked, the 2-D routes with `routes`.
template <class Real>
hard_values hard_values_in(arm a, const std::string& energy, bool omega, bool routes,
                           bool reference) {
    const double_pendulum<Real> model;
    const Real E = parse_real<Real>(energy, "E");
    hard_values v;
    v.target = target<Real>();
    v.f1 = to_decimal(
        upright_flux(model, a, E,
                     reference ? upright_flux_method::integral : upright_flux_method::elliptic)
            .value);
    v.f2 = to_decimal(approximate_saddle_flux(model, a, E).value);
    if (omega) v.omega = to_decimal(phase_volume(model, E).value);
    if (routes) {
        v.omega_2d = to_decimal(phase_volume(model, E, phase_volume_method::quadrature_2d).value);
        v.f2_momentum =
            to_decimal(approximate_saddle_flux(model, a, E, curve_flux_method::momentum).value);
    }
    return v;
}

void hard_cases(const precision& p, const precision& reference, bool with_routes) {
    const auto cases = dispatch(p, []<class Real>() { return hard_energies<Real>(); });
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const arm a = cases[i].first;  // not a structured binding: the lambdas below capture it
        const std::string& e = cases[i].second;
        const std::string where =
            precision_name(p) + " arm " + to_string(a) + " E " + e.substr(0, 20);
        const bool omega = with_routes || i >= 2;  // E > 5
        const hard_values v = dispatch(
            p, [&]<class Real>() { return hard_values_in<Real>(a, e, omega, with_routes, false); });
        const hard_values r = dispatch(reference, [&]<class Real>() {
            return hard_values_in<Real>(a, e, omega, false, true);
        });
        EXPECT_LE(relative_error(v.f1, r.f1), v.target) << where;
        EXPECT_LE(relative_error(v.f2, r.f2), v.target) << where;
        if (omega) {
            EXPECT_LE(relative_error(v.omega, r.omega), v.target) << where;
        }
        if (with_routes) {
            EXPECT_LE(relative_error(v.omega_2d, v.omega), v.target) << where;
            EXPECT_LE(relative_error(v.f2_momentum, v.f2), v.target) << where;
        }
    }
}

TEST(PredictionRoutes, HardCasesDouble) {
    hard_cases(precision{real_kind::double_}, precision{real_kind::quad}, true);
}
TEST(PredictionRoutes, HardCasesQuad) {
    hard_cases(precision{real_kind::quad}, mp_precision(50), false);
}
TEST(PredictionRoutes, HardCasesMp50) {
    hard_cases(mp_precision(50), mp_precision(100), false);
}

}  // namespace
}  // namespace flipflux
