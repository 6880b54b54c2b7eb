// Omega(E) by the 1-D elliptic reduction and the closed form above the maximum; the
// configuration-space density and its marginals (paper Sec. 4.1, App. C; see
// include/flipflux/prediction/phase_volume.hpp and docs/theory.md#phase-volume-and-fluxes).
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "allowed_region.hpp"
#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "flipflux/special/elliptic.hpp"
#include "phase_volume_detail.hpp"

namespace flipflux {
namespace {

template <class Real>
void require_finite_energy(const Real& energy, const char* function) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    if (!isfinite(energy)) throw std::domain_error(std::string(function) + ": energy not finite");
}

/// The elliptic parameter m = -C^2/D0 of sqrt(det M) = sqrt(D0) sqrt(1 - m sin^2(th1 - th2)).
template <class Real>
Real density_parameter(const double_pendulum<Real>& model) {
    const auto& k = model.coefficients();
    return -(k.C * k.C) / k.D0;
}

/// E(m) of the density parameter: 1 - m = (D0 + C^2)/D0 = A B / D0, without cancellation.
template <class Real>
Real complete_e(const double_pendulum<Real>& model) {
    const auto& k = model.coefficients();
    return elliptic_e_complete(density_parameter(model), Real(k.A * k.B / k.D0));
}

/// The marginal density where the other angle is free: 2 pi sqrt(D0) 4 E(m) = 8 pi sqrt(D0) E(m).
template <class Real>
Real full_marginal(const double_pendulum<Real>& model) {
    using std::sqrt;
    return 8 * pi<Real>() * sqrt(model.coefficients().D0) * complete_e(model);
}

/// 2 pi sqrt(D0) [E(t + x|m) + E(t - x|m)]: the marginal at x in [0, pi] with half-width t,
/// given to_pi = pi - x and E(m) = *complete (null: computed where needed). Since E(phi + k pi|m) =
/// E(phi|m) + 2 k E(m), the bracket is also E(t + u|m) + E(t - u|m) with u = pi - x; near x = pi
/// (where t can be small: just above the saddle level 2 w_this) that form keeps t - u and t + u to
/// full relative precision, where the form in x adds and removes 2 E(m) and leaves the small sum to
/// the rounding of t + x.
template <class Real>
Real marginal_from_half_width(const double_pendulum<Real>& model, const Real& x, const Real& t,
                              const Real& to_pi, const Real* complete) {
    using std::sqrt;
    const Real m = density_parameter(model);
    const Real& y = to_pi < x ? to_pi : x;
    if constexpr (std::is_same_v<Real, quad>) {
        // at quad one float128 elliptic integral instead of two (the integrals' cost): the
        // addition theorem (special/elliptic.hpp), for Omega's nodes and a lone density alike;
        // double and mp keep the two, bit for bit
        // (E(m) as elliptic_e_sum's contract and Omega's nodes take it: from 1 - m)
        return two_pi<Real>() * sqrt(model.coefficients().D0) *
               elliptic_e_sum(t, y, m, complete ? *complete : elliptic_e_complete(m, Real(1 - m)));
    }
    return two_pi<Real>() * sqrt(model.coefficients().D0) *
           (complete ? elliptic_e(Real(t + y), m, *complete) + elliptic_e(Real(t - y), m, *complete)
                     : elliptic_e(Real(t + y), m) + elliptic_e(Real(t - y), m));
}

/// The integral over [a, b] of a marginal whose branch points beyond a and b lie at the distances
/// `near` (0: none), m the density parameter. At quad, where each evaluation costs a float128
/// elliptic integral (one, by elliptic_e_sum), the nested Clenshaw-Curtis rules in sin^2 (up to 256
/// intervals: 127 or 255 evaluations) are tried first unless a branch point is close enough to need
/// grading (nearer than a quarter of the width); tanh-sinh, graded towards a close branch point,
/// everywhere else and where the pair has not converged. Double keeps tanh-sinh alone (its results
/// bit for bit; 0.2 ms), as does mp, whose pair would need n growing with the digits.
template <class Real>
quadrature_result<Real> piece_integral(endpoint_integrand<Real> f, const Real& a, const Real& b,
                                       const std::array<Real, 2>& near, const Real& m) {
    if constexpr (std::is_same_v<Real, quad>) {
        const Real quarter = (b - a) / 4;
        const auto far = [&](const Real& r) { return !(r > 0) || r >= quarter; };
        // sqrt(1 - m sin^2) has branch points asinh(1/sqrt|m|) off the real axis: at |m| = 10
        // (m1 = 0.1) the rules never converged on the paper's energies (255 evaluations lost
        // before tanh-sinh); at |m| = 1 they converge at 127 or 255
        if (far(near[0]) && far(near[1]) && -m <= 4) {
            if (auto r = sine_squared_clenshaw_curtis<Real>(f, a, b, 256)) return *r;
            // not converged: every node of the 256-interval rule was evaluated
            quadrature_result<Real> r = tanh_sinh_integrate_graded<Real>(f, a, b, near[0], near[1]);
            r.evaluations += 255;
            return r;
        }
    }
    return tanh_sinh_integrate_graded<Real>(f, a, b, near[0], near[1]);
}

/// The integral of the marginal rho_which over [0, x], 0 <= x <= pi.
template <class Real>
quadrature_result<Real> marginal_integral(const double_pendulum<Real>& model,
                                          const level_arg<Real>& energy, configuration_angle which,
                                          const Real& x) {
    using std::min;
    const detail::angle_support<Real> sup(model, energy, which);
    quadrature_result<Real> r;
    const Real full = full_marginal(model);
    const Real a = sup.theta_full < x ? sup.theta_full : x;
    r.value = a * full;
    r.l1_norm = r.value;
    r.error_estimate = 4 * epsilon<Real>() * r.value;
    const Real b = sup.theta_edge < x ? sup.theta_edge : x;
    if (a < b) {
        const Real edge_gap = sup.theta_edge - b;  // 0 when the piece ends at theta_edge
        // pi - b, from the support's supplement when the piece ends at its edge
        const Real b_to_pi = b == sup.theta_edge ? sup.edge_supplement : Real(pi<Real>() - b);
        // E(m) for the half periods, once: as elliptic_e(phi, m) computes it (from 1 - m), so the
        // values are those of the two-argument form bit for bit
        const Real m = density_parameter(model);
        const Real complete = elliptic_e_complete(m, Real(1 - m));
        auto f = [&](const Real& th, const Real& to_a, const Real& to_b) -> Real {
            const Real t = sup.half_width(th, Real(edge_gap + to_b), to_a);
            return marginal_from_half_width(model, th, t, Real(b_to_pi + to_b), &complete);
        };
        const std::array<Real, 2> near = detail::singularity_distances(sup, b);
        r += piece_integral<Real>(f, a, b, near, density_parameter(model));
    }
    return r;
}

}  // namespace

template <class Real>
Real phase_volume_above_maximum(const double_pendulum<Real>& model) {
    return two_pi<Real>() * full_marginal(model);
}

template <class Real>
Real configuration_density(const double_pendulum<Real>& model, const Real& energy, const Real& th1,
                           const Real& th2) {
    using std::sqrt;
    require_finite_energy(energy, "configuration_density");
    const Real kinetic = energy - model.potential(th1, th2);
    if (kinetic < 0) return Real(0);
    const Real rho = two_pi<Real>() * sqrt(model.mass_determinant(th1, th2));
    return kinetic > 0 ? rho : rho / 2;
}

template <class Real>
Real allowed_half_width(const double_pendulum<Real>& model, const Real& energy,
                        configuration_angle which, const Real& theta) {
    require_finite_energy(energy, "allowed_half_width");
    const detail::angle_support<Real> sup(model, energy, which);
    const Real x = detail::folded_angle(theta);
    return sup.half_width(x, Real(sup.theta_edge - x), Real(x - sup.theta_full));
}

template <class Real>
Real marginal_density(const double_pendulum<Real>& model, const Real& energy,
                      configuration_angle which, const Real& theta) {
    const Real x = detail::folded_angle(theta);
    const Real t = allowed_half_width(model, energy, which, theta);
    if (t == 0) return Real(0);
    if (t == pi<Real>()) return full_marginal(model);
    return marginal_from_half_width<Real>(model, x, t, Real(pi<Real>() - x), nullptr);
}

template <class Real>
prediction_result<Real> marginal_cdf(const double_pendulum<Real>& model, const Real& energy,
                                     configuration_angle which, const Real& theta) {
    using std::abs;
    require_finite_energy(energy, "marginal_cdf");
    if (!(energy > 0)) throw std::domain_error("marginal_cdf: needs E > 0 (Omega = 0)");
    if (!(abs(theta) <= pi<Real>())) throw std::domain_error("marginal_cdf: needs |theta| <= pi");
    const quadrature_result<Real> half = marginal_integral(model, energy, which, pi<Real>());
    const quadrature_result<Real> part = marginal_integral(model, energy, which, abs(theta));
    const Real ratio = part.value / half.value;
    prediction_result<Real> r;
    r.value = theta < 0 ? (1 - ratio) / 2 : (1 + ratio) / 2;
    r.error_estimate =
        (part.error_estimate + ratio * half.error_estimate) / (2 * half.value) + epsilon<Real>();
    r.evaluations = half.evaluations + part.evaluations;
    return r;
}

template <class Real>
prediction_result<Real> phase_volume(const double_pendulum<Real>& model,
                                     const level_arg<Real>& energy, phase_volume_method method) {
    require_finite_energy(energy.value, "phase_volume");
    prediction_result<Real> r;
    switch (method) {
        case phase_volume_method::closed_form:
            if (!(energy.above(model.maximum_level()) >= 0)) {
                throw std::domain_error("phase_volume: the closed form needs E >= E_max");
            }
            r.value = phase_volume_above_maximum(model);
            r.error_estimate = 8 * epsilon<Real>() * r.value;
            return r;
        case phase_volume_method::quadrature_2d:
            return detail::phase_volume_quadrature_2d(model, energy);
        case phase_volume_method::elliptic:
            break;
    }
    if (!(energy.value > 0)) return r;
    // Omega = 2 * integral_0^pi rho_1 (rho_1 is even).
    const quadrature_result<Real> half =
        marginal_integral(model, energy, configuration_angle::theta1, pi<Real>());
    r.value = 2 * half.value;
    // the quadrature's estimate (with its rounding floor eps L1) and the rounding of the
    // marginal's evaluation, which grows with the elliptic parameter |m| = C^2 / D0 (a light
    // first link, |m| = 14: measured 5 eps at quad; m1 = 0.01, |m| = 100: 3 eps at double;
    // m1 = 0.05, L2 = 3 near E_max: 14 eps at double): 4 eps (1 + sqrt|m|) of the value
    // (tests/prediction/test_error_estimates.cpp)
    using std::sqrt;
    r.error_estimate = 2 * half.error_estimate +
                       4 * epsilon<Real>() * (1 + sqrt(Real(-density_parameter(model)))) * r.value;
    r.evaluations = half.evaluations;
    return r;
}

#define FLIPFLUX_PHASE_VOLUME_INSTANTIATE(R)                                                      \
    template prediction_result<R> phase_volume<R>(const double_pendulum<R>&,                      \
                                                  const energy_level<R>&, phase_volume_method);   \
    template R phase_volume_above_maximum<R>(const double_pendulum<R>&);                          \
    template R configuration_density<R>(const double_pendulum<R>&, const R&, const R&, const R&); \
    template R allowed_half_width<R>(const double_pendulum<R>&, const R&, configuration_angle,    \
                                     const R&);                                                   \
    template R marginal_density<R>(const double_pendulum<R>&, const R&, configuration_angle,      \
                                   const R&);                                                     \
    template prediction_result<R> marginal_cdf<R>(const double_pendulum<R>&, const R&,            \
                                                  configuration_angle, const R&)
FLIPFLUX_PHASE_VOLUME_INSTANTIATE(inst_real);

}  // namespace flipflux
