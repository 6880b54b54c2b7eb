// Quantities of the saddle-orbit module: period T, action F, saddle flux f3 = 2 F, the Floquet
// multiplier and stability index (and, with the prediction module, the rate f3 / Omega).
// Methods: "periodic" (the paper's shooting, Ceres then Gauss-Newton in Real) and "symmetric"
// (time-reversal shooting to the brake point, Newton); both give the same orbit. Either may name
// the integrator after a slash, "periodic/gauss-legendre", "symmetric/taylor" (default: the
// type's, default_orbit_integrator; `flipflux eval --integrator`).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/prediction/result.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

const std::vector<std::string> orbit_methods = names_of<orbit_method>();

template <class Real>
saddle_orbit<Real> orbit_for(const double_pendulum<Real>& model, arm a,
                             const energy_level<Real>& energy, const std::string& method) {
    orbit_options<Real> options;
    const std::size_t slash = method.find('/');
    const std::string name = method.substr(0, slash);
    options.method =
        name.empty() ? orbit_method::periodic : parse_name<orbit_method>(name, "method");
    if (slash != std::string::npos)
        options.integrator = parse_name<orbit_integrator>(method.substr(slash + 1), "integrator");
    check_orbit_energy(model, a, energy);
    saddle_orbit<Real> orbit = find_or_solve_saddle_orbit(model, a, energy, options);
    if (orbit.status == orbit_status::not_converged)
        throw_not_converged(model, a, energy, orbit, "saddle orbit");
    return orbit;
}

template <class Real>
std::string method_text(const saddle_orbit<Real>& orbit) {
    return (orbit.method == orbit_method::periodic
                ? std::string("periodic shooting (Ceres, then Gauss-Newton in the working "
                              "precision)")
                : std::string("symmetric shooting to the brake point (Newton)")) +
           ", " +
           (orbit.integrator == orbit_integrator::taylor
                ? "order-" + std::to_string(orbit.order) + " Taylor series, "
                : std::to_string(orbit.stages) + "-stage Gauss-Legendre, ") +
           std::to_string(orbit.steps) + " steps" +
           (orbit.status == orbit_status::stalled ? ", stalled at the rounding floor" : "");
}

struct period_fn {
    template <class Real>
    quantity_value<Real> operator()(const double_pendulum<Real>& model, arm a,
                                    const energy_level<Real>& energy,
                                    const std::string& method) const {
        const auto o = orbit_for(model, a, energy, method);
        return {o.period, o.error_estimate_period, method_text(o)};
    }
};

struct action_fn {
    template <class Real>
    quantity_value<Real> operator()(const double_pendulum<Real>& model, arm a,
                                    const energy_level<Real>& energy,
                                    const std::string& method) const {
        const auto o = orbit_for(model, a, energy, method);
        return {o.action, o.error_estimate_action, method_text(o)};
    }
};

struct flux_fn {
    template <class Real>
    quantity_value<Real> operator()(const double_pendulum<Real>& model, arm a,
                                    const energy_level<Real>& energy,
                                    const std::string& method) const {
        const auto o = orbit_for(model, a, energy, method);
        return {o.flux(), 2 * o.error_estimate_action, "f3 = 2 F, " + method_text(o)};
    }
};

/// Error of the nontrivial multiplier: the largest of the trace route against Eigen's largest
/// eigenvalue, the orbit's relative error times log|mu| (mu ~ exp(lambda T)), and the rounding
/// error of the monodromy itself, which grows with |mu|.
///
/// NOTE: a rounding error eps in the state moves the integrated trajectory off the orbit by
/// eps |mu|^(t/T); the monodromy is the flow's derivative along that trajectory, so its dominant
/// eigenvalue is off by a relative ~eps |mu| when the whole period is integrated (periodic
/// shooting), and ~eps |mu|^(1/4) when a quarter period is integrated and the monodromy assembled
/// by the symmetries (symmetric shooting). Measured against quad (egalitarian, both arms,
/// E = 5.9 ... 6 - 1e-6, |mu| = 2e5 ... 1e26): periodic <= 0.7 eps |mu|; symmetric 0.1 ... 46
/// eps |mu|^(1/4). An independent cross-check of rigid pendulums (2026-11-30) found 1.4 eps |mu|
/// (periodic, |mu| = 5.7e11) and an orbit-dominated error 2.1 times the second term (|mu| =
/// 1297); the same orbit, its last bits moved when the continuation's steps were refined by the
/// action identity (2026-11-30), 5.2 times it at double (the error against quad 3.9e-9, while the
/// period stayed within a fifth of its estimate: the multiplier sees the start's error in beta
/// too, which the period's estimate does not carry): the estimate takes 8 eps |mu|, 64 eps
/// |mu|^(1/4) and 16 times the orbit's term, each above every measured case
/// (verify_orbits_estimates checks it up to E_max - 1e-6).
template <class Real>
Real multiplier_error(const saddle_orbit<Real>& o) {
    using std::abs;
    using std::log;
    using std::max;
    using std::sqrt;
    const Real eig = abs(o.floquet.eigenvalues[3]);
    const Real mu = abs(o.floquet.multiplier);
    const Real rel = o.error_estimate_period / o.period;
    const Real eps = std::numeric_limits<Real>::epsilon();
    const Real rounding =
        o.method == orbit_method::periodic ? Real(8 * eps * mu) : Real(64 * eps * sqrt(sqrt(mu)));
    return max({abs(eig - mu), Real(16 * mu * rel * (1 + log(mu))), Real(mu * rounding)});
}

struct multiplier_fn {
    template <class Real>
    quantity_value<Real> operator()(const double_pendulum<Real>& model, arm a,
                                    const energy_level<Real>& energy,
                                    const std::string& method) const {
        const auto o = orbit_for(model, a, energy, method);
        if (!o.floquet.hyperbolic) {
            throw std::runtime_error(
                "saddle orbit at E = " + to_decimal(energy.value) +
                " is elliptic: its nontrivial multipliers are exp(+-i nu) with nu = " +
                to_decimal(o.floquet.angle) + " (see stability-index)");
        }
        return {o.floquet.multiplier, multiplier_error(o),
                "real multiplier |mu| > 1 from the monodromy's trace, " + method_text(o)};
    }
};

struct stability_fn {
    template <class Real>
    quantity_value<Real> operator()(const double_pendulum<Real>& model, arm a,
                                    const energy_level<Real>& energy,
                                    const std::string& method) const {
        const auto o = orbit_for(model, a, energy, method);
        return {o.floquet.stability_index, multiplier_error(o),
                "mu + 1/mu = tr(monodromy) - 2, " + method_text(o)};
    }
};

struct rate_fn {
    template <class Real>
    quantity_value<Real> operator()(const double_pendulum<Real>& model, arm a,
                                    const energy_level<Real>& energy,
                                    const std::string& method) const {
        const auto o = orbit_for(model, a, energy, method);
        const prediction_result<Real> flux{o.flux(), 2 * o.error_estimate_action, 0};
        const auto omega = phase_volume(model, energy, phase_volume_method::elliptic);
        const auto r = rate_from(flux, omega);
        return {r.value, r.error_estimate,
                "R3 = f3 / Omega (Omega: elliptic route), " + method_text(o)};
    }
};

}  // namespace

void add_orbit_quantities(std::vector<quantity>& list) {
    const std::size_t first = list.size();
    list.push_back(
        make_quantity("period", "period T of the saddle orbit", orbit_methods, true, period_fn{}));
    list.push_back(make_quantity("action", "action F = oint l.dtheta of the saddle orbit (> 0)",
                                 orbit_methods, true, action_fn{}));
    list.push_back(make_quantity("flux-saddle", "saddle-orbit flux f3 = 2 F (both directions)",
                                 orbit_methods, true, flux_fn{}));
    list.push_back(make_quantity("rate-saddle",
                                 "predicted flip rate R3 = f3 / Omega (saddle-orbit criterion)",
                                 orbit_methods, true, rate_fn{}));
    list.push_back(make_quantity("multiplier",
                                 "Floquet multiplier |mu| > 1 of the (hyperbolic) saddle orbit",
                                 orbit_methods, true, multiplier_fn{}));
    list.push_back(make_quantity("stability-index",
                                 "mu + 1/mu = tr(monodromy) - 2 of the saddle orbit", orbit_methods,
                                 true, stability_fn{}));
    for (std::size_t i = first; i < list.size(); ++i) {
        list[i].needs_saddle_orbit = true;
        // certified by the other shooting (another unknown, another condition, another Newton)
        // with the Taylor integrator named: Gauss-Legendre in mp:50 takes over an hour for the
        // golden grid near E_max (it is the route of verification/ and of the double check)
        list[i].check_methods = {"symmetric/taylor"};
    }
}

}  // namespace flipflux
