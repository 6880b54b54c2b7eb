// Predicted flip rates R = f / Omega (paper eq. eq:three_flip_rate_predictions) for the upright
// and approximate-saddle criteria, each route combining independent routes for f and Omega.
#include <cmath>
#include <stdexcept>

#include "flipflux/core/instantiate.hpp"
#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/prediction/rates.hpp"
#include "flipflux/prediction/upright_flux.hpp"

namespace flipflux {

template <class Real>
prediction_result<Real> predicted_rate(const double_pendulum<Real>& model, arm a,
                                       flip_criterion criterion, const level_arg<Real>& energy,
                                       rate_route route) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    if (!isfinite(energy.value) || !(energy.value > 0)) {  // value > 0: the decimal is too
        throw std::domain_error("predicted_rate: needs a finite E > 0 (Omega = 0 otherwise)");
    }
    const bool closed = route == rate_route::closed_form;
    const prediction_result<Real> omega = phase_volume(
        model, energy, closed ? phase_volume_method::elliptic : phase_volume_method::quadrature_2d);
    prediction_result<Real> flux;
    if (criterion == flip_criterion::upright) {
        flux = upright_flux(model, a, energy,
                            closed ? upright_flux_method::elliptic : upright_flux_method::integral);
    } else {
        flux = approximate_saddle_flux(
            model, a, energy, closed ? curve_flux_method::kinetic : curve_flux_method::momentum);
    }
    return rate_from(flux, omega);
}

template prediction_result<inst_real> predicted_rate<inst_real>(const double_pendulum<inst_real>&,
                                                                arm, flip_criterion,
                                                                const level_arg<inst_real>&,
                                                                rate_route);

}  // namespace flipflux
