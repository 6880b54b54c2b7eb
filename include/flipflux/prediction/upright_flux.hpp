// f1: the flux through the upright-arm surface th_flip = pi (paper eqs.
// eq:upright_arm_flux_integral, eq:upright_arm_flux_incomplete_elliptic,
// eq:upright_arm_flux_complete_elliptic and App. C), for either arm and any pendulum. Derivation:
// docs/theory.md#phase-volume-and-fluxes.
//
// With n = e_flip, n^T adj(M) n = J (A for arm 2, B for arm 1) is constant, so
//     f1 = 4 sqrt(2 J) integral_{-pi}^{pi} sqrt(delta - 2 w sin^2(s/2))_+ ds,
//     delta = E - E_s,  (J, w, E_s) = (A, alpha, 2 beta) for arm 2 and (B, beta, 2 alpha) for
//     arm 1.
// Substituting x = s/2 and m = 2 w / delta:
//     E_s < E <= E_max:  f1 = 16 sqrt(2 J delta) E(phi_0 | m),   sin^2 phi_0 = 1/m   (m >= 1),
//     E >= E_max:        f1 = 16 sqrt(2 J delta) E(m)                               (m <= 1),
// and, by the reciprocal-modulus transformation (DLMF 19.7.4), for E_s < E < E_max also
//     f1 = 16 sqrt(J / w) [2 w E(p) - (2 w - delta) K(p)],   p = delta / (2 w)
// (accurate away from E_s only: the bracket cancels to ~delta/2 there). Near the saddle
//     f1 = 4 pi sqrt(J / w) delta (1 + delta / (16 w) + O(delta^2)).
// Routes: elliptic (the incomplete / complete closed forms, continuous at E_max where both give
// 16 sqrt(2 J delta)), integral (the 1-D integral by tanh-sinh, K from the distances to the
// zeros, no cancellation), curve and momentum (curve_flux with the upright curve).
// f1 = 0 for E <= E_s. Domain: any finite E; errors: std::domain_error for a non-finite energy.
// Accuracy: relative a few eps at every precision, E_s < E <= 1e6.
#pragma once

#include <string>

#include "flipflux/core/names.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/prediction/result.hpp"

namespace flipflux {

enum class upright_flux_method { elliptic, integral, curve, momentum };

/// "elliptic", "integral", "curve", "momentum".
template <>
struct enum_table<upright_flux_method> {
    static constexpr std::string_view noun = "an upright-flux method";
    static constexpr std::array<std::pair<upright_flux_method, std::string_view>, 4> entries{
        {{upright_flux_method::elliptic, "elliptic"},
         {upright_flux_method::integral, "integral"},
         {upright_flux_method::curve, "curve"},
         {upright_flux_method::momentum, "momentum"}}};
};

template <class Real>
prediction_result<Real> upright_flux(const double_pendulum<Real>& model, arm a,
                                     const level_arg<Real>& energy,
                                     upright_flux_method method = upright_flux_method::elliptic);

/// 16 sqrt(2 J delta) E(phi_0 | 2w/delta), sin^2 phi_0 = delta / (2w): E_s < E <= E_max only.
template <class Real>
Real upright_flux_incomplete_elliptic(const double_pendulum<Real>& model, arm a,
                                      const level_arg<Real>& energy);

/// 16 sqrt(2 J delta) E(2w/delta): E >= E_max only.
template <class Real>
Real upright_flux_complete_elliptic(const double_pendulum<Real>& model, arm a,
                                    const level_arg<Real>& energy);

/// 16 sqrt(J/w) [2w E(p) - (2w - delta) K(p)], p = delta/(2w): E_s < E < E_max only (a check:
/// loses relative accuracy ~ eps w / delta near E_s).
template <class Real>
Real upright_flux_reciprocal_modulus(const double_pendulum<Real>& model, arm a,
                                     const level_arg<Real>& energy);

/// 4 pi sqrt(J/w) delta (1 + delta/(16 w)): the first two terms of f1 at small delta = E - E_s.
template <class Real>
Real upright_flux_near_saddle(const double_pendulum<Real>& model, arm a,
                              const level_arg<Real>& energy);

#define FLIPFLUX_UPRIGHT_FLUX_EXTERN(R)                                                   \
    extern template prediction_result<R> upright_flux<R>(                                 \
        const double_pendulum<R>&, arm, const level_arg<R>&, upright_flux_method);        \
    extern template R upright_flux_incomplete_elliptic<R>(const double_pendulum<R>&, arm, \
                                                          const level_arg<R>&);           \
    extern template R upright_flux_complete_elliptic<R>(const double_pendulum<R>&, arm,   \
                                                        const level_arg<R>&);             \
    extern template R upright_flux_reciprocal_modulus<R>(const double_pendulum<R>&, arm,  \
                                                         const level_arg<R>&);            \
    extern template R upright_flux_near_saddle<R>(const double_pendulum<R>&, arm,         \
                                                  const level_arg<R>&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_UPRIGHT_FLUX_EXTERN)
#undef FLIPFLUX_UPRIGHT_FLUX_EXTERN

}  // namespace flipflux
