// Quantities of the prediction module (issue "Phase volume, fluxes and predicted flip rates"):
//     omega          Omega(E), the microcanonical phase volume       [elliptic, quadrature-2d,
//                                                                      closed-form]
//     flux-upright   f1, flux through th_flip = pi                   [elliptic, integral, curve,
//                                                                      momentum]
//     flux-approx    f2, flux through th_flip = pi + A sin s         [kinetic, momentum]
//     rate-upright   f1 / Omega                                      [closed-form, quadrature]
//     rate-approx    f2 / Omega                                      [closed-form, quadrature]
// The first method of each is its default; every other method is an independent route (see the
// headers in include/flipflux/prediction/). Domain: E > 0 (the energy surface is empty at and
// below the potential minimum); closed-form omega needs E >= E_max.
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/prediction/prediction.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

/// The method named `method` ("" = the table's first, the default); input_error naming the field
/// `method` and the quantity's methods otherwise.
template <named_enum Method>
Method method_named(const std::string& quantity, const std::string& method) {
    const auto& entries = enum_table<Method>::entries;
    if (method.empty()) return entries.front().first;
    for (const auto& [value, name] : entries)
        if (name == method) return value;
    throw input_error::about("method", "'" + method + "' is not a method of " + quantity +
                                           " (known: " + name_list<Method>() + ")");
}

template <class Real>
void require_positive_energy(const std::string& quantity, const energy_level<Real>& energy) {
    const std::string text = energy.text();
    if (!energy.positive())
        throw input_error::about("energy", "'" + text + "' is outside the domain of " + quantity +
                                               " (needs E > 0: the energy surface is empty at "
                                               "and below the potential minimum 0)");
    // a positive decimal that Real cannot hold at all (1e-999999 in double)
    if (!(energy.value > 0))
        throw input_error::about("energy", "'" + text + "' underflows " + precision_name<Real>() +
                                               " (it rounds to " + to_decimal(energy.value) +
                                               "); try mp:N");
}

template <class Real>
quantity_value<Real> value_of(const prediction_result<Real>& r, const std::string& method) {
    return {r.value, r.error_estimate, method};
}

}  // namespace

void add_prediction_quantities(std::vector<quantity>& list) {
    list.push_back(make_quantity(
        "omega", "phase volume Omega(E) of the energy surface (all arms)",
        names_of<phase_volume_method>(), false,
        []<class Real>(const double_pendulum<Real>& model, arm, const energy_level<Real>& energy,
                       const std::string& method) {
            const auto m = method_named<phase_volume_method>("omega", method);
            require_positive_energy("omega", energy);
            if (m == phase_volume_method::closed_form &&
                !(energy.above(model.maximum_level()) >= 0)) {
                throw input_error::about(
                    "energy", "'" + energy.text() +
                                  "' is below the threshold of method closed-form of omega "
                                  "(needs E >= E_max = " +
                                  to_decimal(model.maximum_energy()) + ", the potential maximum)");
            }
            return value_of(phase_volume(model, energy, m), to_string(m));
        }));
    list.push_back(make_quantity(
        "flux-upright", "phase flux f1 through the upright surface th_arm = pi (both directions)",
        names_of<upright_flux_method>(), true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const energy_level<Real>& energy,
                       const std::string& method) {
            const auto m = method_named<upright_flux_method>("flux-upright", method);
            require_positive_energy("flux-upright", energy);
            return value_of(upright_flux(model, a, energy, m), to_string(m));
        }));
    list.push_back(make_quantity(
        "flux-approx",
        "phase flux f2 through the approximate saddle curve th_arm = pi + A sin(other angle)",
        names_of<curve_flux_method>(), true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const energy_level<Real>& energy,
                       const std::string& method) {
            const auto m = method_named<curve_flux_method>("flux-approx", method);
            require_positive_energy("flux-approx", energy);
            const curve_flux_result<Real> r = approximate_saddle_flux(model, a, energy, m);
            return value_of<Real>(r, to_string(m));
        }));
    list.push_back(make_quantity(
        "rate-upright", "predicted flip rate f1 / Omega of the upright criterion",
        names_of<rate_route>(), true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const energy_level<Real>& energy,
                       const std::string& method) {
            const auto m = method_named<rate_route>("rate-upright", method);
            require_positive_energy("rate-upright", energy);
            return value_of(predicted_rate(model, a, flip_criterion::upright, energy, m),
                            to_string(m));
        }));
    list.push_back(make_quantity(
        "rate-approx", "predicted flip rate f2 / Omega of the approximate saddle criterion",
        names_of<rate_route>(), true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const energy_level<Real>& energy,
                       const std::string& method) {
            const auto m = method_named<rate_route>("rate-approx", method);
            require_positive_energy("rate-approx", energy);
            return value_of(predicted_rate(model, a, flip_criterion::approximate_saddle, energy, m),
                            to_string(m));
        }));
}

}  // namespace flipflux
