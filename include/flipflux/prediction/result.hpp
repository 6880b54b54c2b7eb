// The result of a prediction routine: a value with its estimated absolute error, and the
// propagation of errors through R = f / Omega.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "flipflux/core/real.hpp"

namespace flipflux {

template <class Real>
struct prediction_result {
    Real value{0};                ///< the quantity
    Real error_estimate{0};       ///< estimated absolute error (quadrature + rounding)
    std::size_t evaluations = 0;  ///< integrand evaluations (0 for closed forms)
};

/// R = f / Omega, with relative errors added: the statistical flip rate (paper eq.
/// eq:flip_rate_formula) for any flux f, e.g. the saddle-orbit flux computed by orbits/.
/// Omega must be > 0.
template <class Real>
prediction_result<Real> rate_from(const prediction_result<Real>& flux,
                                  const prediction_result<Real>& omega) {
    using std::abs;
    prediction_result<Real> r;
    r.value = flux.value / omega.value;
    r.error_estimate = flux.error_estimate / abs(omega.value) +
                       abs(r.value) * omega.error_estimate / abs(omega.value) +
                       abs(r.value) * epsilon<Real>();
    r.evaluations = flux.evaluations + omega.evaluations;
    return r;
}

}  // namespace flipflux
