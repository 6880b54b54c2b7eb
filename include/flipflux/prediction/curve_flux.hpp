// Phase-space flux through a dividing curve in configuration space (paper Sec. 4.2, eqs. def:g2,
// eq:approximate_saddle_flux, generalised to any curve, arm and pendulum; derivation in
// docs/theory.md#phase-volume-and-fluxes).
//
// For a curve g = th_flip - pi - h(s) = 0 (model/dividing_curve.hpp: arm 2 has s = th1,
// th_flip = th2; arm 1 has s = th2, th_flip = th1) the bidirectional flux
//     f = integral d^2th d^2l delta(H - E) delta(g) |dg/dt|
// has, with n = grad g and l -> y = L l (M^-1 = L^T L), the momentum integral
//     integral d^2l delta(l^T M^-1 l / 2 - K) |n^T M^-1 l| = 4 sqrt(2K) sqrt(n^T adj(M) n) Theta(K)
// (adj(M) = det M M^-1), so that
//     f = 4 integral over the curve's domain of sqrt(2 K(s))_+ sqrt(Q(s)) ds,
//     K(s) = E - V(curve(s))     (the kinetic energy ON the curve; see docs/errata.md),
//     Q(s) = n^T adj(M) n = M_ss + 2 C c h' + M_ff h'^2,   c = cos(th1 - th2) = -cos(s - h),
// with M_ss, M_ff the diagonal entries of M for s and for the flip angle ((A, B) for arm 2,
// (B, A) for arm 1). Routes:
//   kinetic   the 1-D integral above (tanh-sinh), split at the zeros of K along the curve (found
//             to full precision) so that each piece has square-root endpoints;
//   momentum  the momentum integral done numerically instead: in velocity polar coordinates
//             v = rho (cos psi, sin psi), integral d^2l delta(...) |n.v| = det M sqrt(2K)
//             integral_0^2pi |n.e(psi)| (e^T M e)^(-3/2) d psi, by Gauss-Kronrod split at the
//             zeros of n.e, inside the same outer integral: a 2-D quadrature that shares no
//             formula with the kinetic route but the definition of K.
//
// The curve is any type satisfying dividing_curve<Curve, Real> (upright_curve, sine_curve, the
// saddle-orbit interpolant of orbits/); only its domain() is integrated over (outside it the curve
// is inaccessible). K is evaluated as (E - E_s) - 2 w_s sin^2(s/2) + 2 w_flip sin^2(h/2)
// ((w_s, w_flip) = (alpha, beta) for arm 2, (beta, alpha) for arm 1), without cancellation near
// the saddle energy, so fluxes keep their relative accuracy as E -> E_s.
// Zeros of K: K and K' are sampled on 128 points per 2 pi of domain; sign changes of K are
// refined by TOMS 748 to full precision, extrema of K between samples of equal sign (sign
// changes of K') by TOMS 748 on K' and, if they cross zero, the two zeros around them; minima
// with K >= 0 (grazing) become break points too. Each accessible piece is integrated by graded
// tanh-sinh (quadrature.hpp), graded towards an end whose next branch point of sqrt(K) (the zero
// across a narrow forbidden gap, or the complex zeros near a grazing minimum) lies close beyond
// it: E = E_max +- 1e-12 keeps full relative accuracy.
//
// Domain: any finite E (f = 0 when K <= 0 on the whole curve, e.g. below the saddle energy);
// the curve's offset and slope must be finite on its domain. Errors: std::domain_error for a
// non-finite energy or an empty domain.
// Accuracy (tests/prediction, verification/prediction_routes.cpp, docs/accuracy.md): relative
// error a few eps for the sine and upright curves from E_s + 1e-12 to 1e6, both arms, both
// routes, at double, quad and mp:N. The error estimate is the quadrature's last-level
// difference: conservative, usually by many orders of magnitude.
#pragma once

#include <array>
#include <vector>

#include "flipflux/core/names.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/prediction/result.hpp"
#include "flipflux/quadrature/quadrature.hpp"

namespace flipflux {

enum class curve_flux_method { kinetic, momentum };

/// "kinetic", "momentum".
template <>
struct enum_table<curve_flux_method> {
    static constexpr std::string_view noun = "a curve-flux method";
    static constexpr std::array<std::pair<curve_flux_method, std::string_view>, 2> entries{
        {{curve_flux_method::kinetic, "kinetic"}, {curve_flux_method::momentum, "momentum"}}};
};

/// A dividing curve seen through references (valid while the referenced callables live): what the
/// compiled flux routines take. Build it with make_curve_view or pass the curve to curve_flux.
template <class Real>
struct curve_view {
    arm flip_arm;
    std::array<Real, 2> domain;
    function_ref<Real(const Real&)> offset;  ///< h(s)
    function_ref<Real(const Real&)> slope;   ///< h'(s)
};

template <class Real>
struct curve_flux_result : prediction_result<Real> {
    std::vector<std::array<Real, 2>> intervals;  ///< the pieces of the domain where K > 0
};

/// K(s) = E - V on the curve at parameter s.
template <class Real>
Real curve_kinetic_energy(const double_pendulum<Real>& model, const Real& energy,
                          const curve_view<Real>& curve, const Real& s);

/// The pieces of the curve's domain where K > 0 (sorted; their ends are zeros of K to full
/// precision, or ends of the domain, or grazing minima of K).
template <class Real>
std::vector<std::array<Real, 2>> accessible_intervals(const double_pendulum<Real>& model,
                                                      const Real& energy,
                                                      const curve_view<Real>& curve);

template <class Real>
curve_flux_result<Real> curve_flux(const double_pendulum<Real>& model,
                                   const level_arg<Real>& energy, const curve_view<Real>& curve,
                                   curve_flux_method method);

/// The flux through any dividing curve (see above).
template <class Real, class Curve>
requires dividing_curve<Curve, Real> curve_flux_result<Real> curve_flux(
    const double_pendulum<Real>& model, const level_arg<Real>& energy, const Curve& curve,
    curve_flux_method method = curve_flux_method::kinetic) {
    auto offset = [&curve](const Real& s) -> Real { return curve.offset(s); };
    auto slope = [&curve](const Real& s) -> Real { return curve.slope(s); };
    const curve_view<Real> view{curve.flip_arm(), curve.domain(), offset, slope};
    return curve_flux<Real>(model, energy, view, method);
}

/// f2: the flux through the approximate saddle curve th_flip = pi + A sin s of `a`, with A the
/// slope of the saddle's centre mode (paper eq. eq:approximate_saddle_flux for arm 2).
template <class Real>
curve_flux_result<Real> approximate_saddle_flux(
    const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy,
    curve_flux_method method = curve_flux_method::kinetic) {
    return curve_flux(model, energy, approximate_saddle_curve(model, a), method);
}

/// The leading behaviour just above the saddle energy of a straight curve through the saddle
/// with tangent d = (1, slope) in (s, th_flip): f ~ 4 pi (E - E_s) sqrt(d^T M* d / d^T K* d)
/// (M*, K* the mass and stiffness matrices at the saddle in (s, th_flip) order). For the
/// centre-mode slope this is 4 pi (E - E_s) / omega_centre, the minimum over all slopes.
/// Requires d^T K* d > 0 (std::domain_error otherwise).
template <class Real>
Real near_saddle_flux(const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy,
                      const Real& slope);

#define FLIPFLUX_CURVE_FLUX_EXTERN(R)                                                             \
    extern template R curve_kinetic_energy<R>(const double_pendulum<R>&, const R&,                \
                                              const curve_view<R>&, const R&);                    \
    extern template std::vector<std::array<R, 2>> accessible_intervals<R>(                        \
        const double_pendulum<R>&, const R&, const curve_view<R>&);                               \
    extern template curve_flux_result<R> curve_flux<R>(                                           \
        const double_pendulum<R>&, const level_arg<R>&, const curve_view<R>&, curve_flux_method); \
    extern template R near_saddle_flux<R>(const double_pendulum<R>&, arm, const level_arg<R>&,    \
                                          const R&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_CURVE_FLUX_EXTERN)
#undef FLIPFLUX_CURVE_FLUX_EXTERN

}  // namespace flipflux
