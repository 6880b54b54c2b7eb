// The microcanonical phase volume Omega(E) and its configuration-space densities (paper Sec. 4.1,
// eqs. eq:configuration_space_density, eq:phase_space_volume_egalitatian_double_pendu,
// eq:phase_space_volume_incomplete_elliptic and the closed form for E >= 6; App. C), for any
// admissible double pendulum. Derivations: docs/theory.md#phase-volume-and-fluxes.
//
// Integrating the momenta out of delta(H - E) leaves the configuration-space density
//     rho(th1, th2) = 2 pi sqrt(det M) Theta(E - V),     det M = D0 + C^2 sin^2(th1 - th2),
// and Omega(E) = integral of rho over the torus [-pi, pi]^2. At fixed th1 the allowed th2 form
// the interval |th2| <= t2(th1) (V is even and increasing in |th2|), and with u = th2 - th1
//     rho_1(th1) = 2 pi sqrt(D0) [E(t2 + th1 | m) + E(t2 - th1 | m)],     m = -C^2 / D0,
// in the parameter convention of special/elliptic.hpp; likewise rho_2(th2) with t1(th2).
// Routes for Omega:
//   elliptic       integral of rho_1 over th1 (tanh-sinh, split where t2 reaches 0 and pi, so
//                  every piece has only square-root endpoint behaviour, and graded towards an
//                  end whose mirror branch point is close): the paper's 1-D reduction,
//                  generalised. Exactly the closed form when E >= E_max.
//   quadrature_2d  integral of rho_2 over th2 whose inner integral over th1 is done numerically
//                  between the boundary points -t1, t1 of V = E (Gauss-Kronrod panels sized by
//                  the strip where sqrt(det M) is analytic; tanh-sinh as fallback): the paper's
//                  2-D integral with the boundary resolved, in the other order, no elliptic
//                  integrals.
//   closed_form    16 pi^2 sqrt(D0) E(-C^2/D0), valid for E >= E_max = 2(alpha + beta) only.
//
// Domain: any finite E. Omega = 0 and the densities vanish for E <= 0 (empty energy surface).
// closed_form with E < E_max and non-finite arguments throw std::domain_error.
// Accuracy (tests/prediction, verification/prediction*.cpp): relative error a few eps across
// 0 < E <= 1e6 at double, quad and mp:N, the routes agreeing to the same level.
#pragma once

#include <string>
#include <string_view>

#include "flipflux/core/names.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/prediction/result.hpp"

namespace flipflux {

enum class phase_volume_method { elliptic, quadrature_2d, closed_form };

/// "elliptic", "quadrature-2d", "closed-form".
template <>
struct enum_table<phase_volume_method> {
    static constexpr std::string_view noun = "a phase-volume method";
    static constexpr std::array<std::pair<phase_volume_method, std::string_view>, 3> entries{
        {{phase_volume_method::elliptic, "elliptic"},
         {phase_volume_method::quadrature_2d, "quadrature-2d"},
         {phase_volume_method::closed_form, "closed-form"}}};
};

/// Omega(E) by the chosen route. Near a critical level (a saddle, E_max) Omega has a
/// log-singular derivative, so E's distance to the level matters to full relative precision:
/// it is taken as energy_level::above (exact when the energy and the model both come from
/// decimal texts; a Real energy converts, and is then the exact E).
template <class Real>
prediction_result<Real> phase_volume(const double_pendulum<Real>& model,
                                     const level_arg<Real>& energy,
                                     phase_volume_method method = phase_volume_method::elliptic);

/// 16 pi^2 sqrt(D0) E(-C^2/D0): Omega(E) for every E >= E_max (the whole torus is allowed).
template <class Real>
Real phase_volume_above_maximum(const double_pendulum<Real>& model);

/// Which configuration angle a marginal density is a function of.
enum class configuration_angle { theta1 = 1, theta2 = 2 };

/// rho(th1, th2) = 2 pi sqrt(det M) Theta(E - V): the density of the microcanonical ensemble in
/// configuration space (momenta integrated out), unnormalised: its integral over the torus is
/// Omega(E). Theta(0) = 1/2 on the boundary V = E.
template <class Real>
Real configuration_density(const double_pendulum<Real>& model, const Real& energy, const Real& th1,
                           const Real& th2);

/// Half-width of the allowed interval of the other angle at fixed `theta` of angle `which`:
/// the allowed th2 at fixed th1 (which = theta1) are |th2| <= t (mod 2 pi), t in [0, pi];
/// t = 0 where none (or a single point) is allowed, t = pi where all are.
template <class Real>
Real allowed_half_width(const double_pendulum<Real>& model, const Real& energy,
                        configuration_angle which, const Real& theta);

/// The marginal density of angle `which`: rho_1(th1) = integral of rho over th2 (which = theta1),
/// rho_2(th2) = integral over th1 (which = theta2), in closed form (incomplete elliptic integrals
/// of parameter -C^2/D0). Unnormalised: its integral over [-pi, pi] is Omega(E); the probability
/// density of the angle in the microcanonical ensemble is rho_i / Omega. 2 pi-periodic and even.
/// Accuracy: a few eps relative.
template <class Real>
Real marginal_density(const double_pendulum<Real>& model, const Real& energy,
                      configuration_angle which, const Real& theta);

/// The cumulative distribution of angle `which` in the microcanonical ensemble:
/// integral of rho_i over [-pi, theta] divided by Omega(E), for theta in [-pi, pi]
/// (tanh-sinh over pieces split at the support's edges). For Kolmogorov-Smirnov tests of samplers.
template <class Real>
prediction_result<Real> marginal_cdf(const double_pendulum<Real>& model, const Real& energy,
                                     configuration_angle which, const Real& theta);

#define FLIPFLUX_PHASE_VOLUME_EXTERN(R)                                                       \
    extern template prediction_result<R> phase_volume<R>(                                     \
        const double_pendulum<R>&, const energy_level<R>&, phase_volume_method);              \
    extern template R phase_volume_above_maximum<R>(const double_pendulum<R>&);               \
    extern template R configuration_density<R>(const double_pendulum<R>&, const R&, const R&, \
                                               const R&);                                     \
    extern template R allowed_half_width<R>(const double_pendulum<R>&, const R&,              \
                                            configuration_angle, const R&);                   \
    extern template R marginal_density<R>(const double_pendulum<R>&, const R&,                \
                                          configuration_angle, const R&);                     \
    extern template prediction_result<R> marginal_cdf<R>(const double_pendulum<R>&, const R&, \
                                                         configuration_angle, const R&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_PHASE_VOLUME_EXTERN)
#undef FLIPFLUX_PHASE_VOLUME_EXTERN

}  // namespace flipflux
