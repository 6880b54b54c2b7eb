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

/// The index of `method` in `methods` ("" = 0); input_error naming --method otherwise.
std::size_t method_index(const std::string& quantity, const std::vector<std::string>& methods,
                         const std::string& method) {
    if (method.empty()) return 0;
    std::string known;
    for (std::size_t i = 0; i < methods.size(); ++i) {
        if (methods[i] == method) return i;
        known += (i ? ", " : "") + methods[i];
    }
    throw input_error("--method: '" + method + "' is not a method of " + quantity +
                      " (known: " + known + ")");
}

template <class Real>
void require_positive_energy(const std::string& quantity, const Real& energy) {
    if (!(energy > 0)) {
        throw input_error("--energy: '" + to_decimal(energy) + "' is outside the domain of " +
                          quantity +
                          " (needs E > 0: the energy surface is empty at and below the "
                          "potential minimum 0)");
    }
}

template <class Real>
quantity_value<Real> value_of(const prediction_result<Real>& r, const std::string& method) {
    return {r.value, r.error_estimate, method};
}

const std::vector<std::string> omega_methods{"elliptic", "quadrature-2d", "closed-form"};
const std::vector<std::string> upright_methods{"elliptic", "integral", "curve", "momentum"};
const std::vector<std::string> approx_methods{"kinetic", "momentum"};
const std::vector<std::string> rate_methods{"closed-form", "quadrature"};

}  // namespace

void add_prediction_quantities(std::vector<quantity>& list) {
    list.push_back(make_quantity(
        "omega", "phase volume Omega(E) of the energy surface (all arms)", omega_methods, false,
        []<class Real>(const double_pendulum<Real>& model, arm, const Real& energy,
                       const std::string& method) {
            const std::size_t i = method_index("omega", omega_methods, method);
            require_positive_energy("omega", energy);
            if (i == 2 && !(energy >= model.maximum_energy())) {
                throw input_error("--energy: '" + to_decimal(energy) +
                                  "' is below the threshold of method closed-form of omega "
                                  "(needs E >= E_max = " +
                                  to_decimal(model.maximum_energy()) + ", the potential maximum)");
            }
            const phase_volume_method m = i == 0   ? phase_volume_method::elliptic
                                          : i == 1 ? phase_volume_method::quadrature_2d
                                                   : phase_volume_method::closed_form;
            return value_of(phase_volume(model, energy, m), omega_methods[i]);
        }));
    list.push_back(make_quantity(
        "flux-upright", "phase flux f1 through the upright surface th_arm = pi (both directions)",
        upright_methods, true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const Real& energy,
                       const std::string& method) {
            const std::size_t i = method_index("flux-upright", upright_methods, method);
            require_positive_energy("flux-upright", energy);
            return value_of(upright_flux(model, a, energy, static_cast<upright_flux_method>(i)),
                            upright_methods[i]);
        }));
    list.push_back(make_quantity(
        "flux-approx",
        "phase flux f2 through the approximate saddle curve th_arm = pi + A sin(other angle)",
        approx_methods, true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const Real& energy,
                       const std::string& method) {
            const std::size_t i = method_index("flux-approx", approx_methods, method);
            require_positive_energy("flux-approx", energy);
            const curve_flux_result<Real> r = approximate_saddle_flux(
                model, a, energy,
                i == 0 ? curve_flux_method::kinetic : curve_flux_method::momentum);
            return value_of<Real>(r, approx_methods[i]);
        }));
    list.push_back(make_quantity(
        "rate-upright", "predicted flip rate f1 / Omega of the upright criterion", rate_methods,
        true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const Real& energy,
                       const std::string& method) {
            const std::size_t i = method_index("rate-upright", rate_methods, method);
            require_positive_energy("rate-upright", energy);
            return value_of(
                predicted_rate(model, a, flip_criterion::upright, energy,
                               i == 0 ? rate_route::closed_form : rate_route::quadrature),
                rate_methods[i]);
        }));
    list.push_back(make_quantity(
        "rate-approx", "predicted flip rate f2 / Omega of the approximate saddle criterion",
        rate_methods, true,
        []<class Real>(const double_pendulum<Real>& model, arm a, const Real& energy,
                       const std::string& method) {
            const std::size_t i = method_index("rate-approx", rate_methods, method);
            require_positive_energy("rate-approx", energy);
            return value_of(
                predicted_rate(model, a, flip_criterion::approximate_saddle, energy,
                               i == 0 ? rate_route::closed_form : rate_route::quadrature),
                rate_methods[i]);
        }));
}

}  // namespace flipflux
