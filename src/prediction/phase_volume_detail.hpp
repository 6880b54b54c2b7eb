// Internal to src/prediction: the routes of phase_volume(), each in its own translation unit.
#pragma once

#include "flipflux/prediction/phase_volume.hpp"

namespace flipflux::detail {

/// Omega by the 2-D configuration-space quadrature (phase_volume_2d.inst.cpp).
template <class Real>
prediction_result<Real> phase_volume_quadrature_2d(const double_pendulum<Real>& model,
                                                   const Real& energy);

extern template prediction_result<double> phase_volume_quadrature_2d<double>(
    const double_pendulum<double>&, const double&);
extern template prediction_result<quad> phase_volume_quadrature_2d<quad>(
    const double_pendulum<quad>&, const quad&);
extern template prediction_result<mp50> phase_volume_quadrature_2d<mp50>(
    const double_pendulum<mp50>&, const mp50&);
extern template prediction_result<mp100> phase_volume_quadrature_2d<mp100>(
    const double_pendulum<mp100>&, const mp100&);

}  // namespace flipflux::detail
