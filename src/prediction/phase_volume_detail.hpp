// Internal to src/prediction: the routes of phase_volume(), each in its own translation unit.
#pragma once

#include "flipflux/prediction/phase_volume.hpp"

namespace flipflux::detail {

/// Omega by the 2-D configuration-space quadrature (phase_volume_2d.inst.cpp).
template <class Real>
prediction_result<Real> phase_volume_quadrature_2d(const double_pendulum<Real>& model,
                                                   const energy_level<Real>& energy);

#define FLIPFLUX_PHASE_VOLUME_2D_EXTERN(R)                                                        \
    extern template prediction_result<R> phase_volume_quadrature_2d<R>(const double_pendulum<R>&, \
                                                                       const energy_level<R>&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_PHASE_VOLUME_2D_EXTERN)
#undef FLIPFLUX_PHASE_VOLUME_2D_EXTERN

}  // namespace flipflux::detail
