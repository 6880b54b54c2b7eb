// Omega(E) by the 1-D elliptic reduction and the closed form above the maximum; the
// configuration-space density and its marginals (paper Sec. 4.1, App. C; see
// include/flipflux/prediction/phase_volume.hpp and docs/theory.md#phase-volume-and-fluxes).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <vector>

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

/// The integral over [a, b] of a marginal whose nearest singularities at the ends lie at the
/// distances `near` (0: none): branch points beyond a or b, or a kink's complex pair at a or b
/// (kink_points). At quad, where each evaluation costs a float128 elliptic integral (one, by
/// elliptic_e_sum), the nested Clenshaw-Curtis rules in sin^2 (up to 256 intervals: 127 or 255
/// evaluations) are tried first unless a singularity is within a sixteenth of the width of an
/// end; tanh-sinh, graded towards a close singularity, everywhere else and where the pair has not
/// converged. NOTE: closer to an end the rules' agreement can mislead: a kink 5e-5 off a piece of
/// width 0.14 (|m| = 3e7) gave two rules agreeing to the tolerance and a value 1.6e4 eps off,
/// where graded tanh-sinh is good to 2 eps. A sixteenth keeps the rules well inside their
/// convergence (n ~ 130 needed, 256 available); a quarter, the bound before the kinks were split
/// off, kept the rules off most parts next to a kink, at more nodes for the same digits. Double
/// keeps tanh-sinh alone (0.2 ms), as does mp, whose pair would need n growing with the digits.
template <class Real>
quadrature_result<Real> piece_integral(endpoint_integrand<Real> f, const Real& a, const Real& b,
                                       const std::array<Real, 2>& near) {
    if constexpr (std::is_same_v<Real, quad>) {
        const Real least = (b - a) / 16;
        const auto far = [&](const Real& r) { return !(r > 0) || r >= least; };
        if (far(near[0]) && far(near[1])) {
            if (auto r = sine_squared_clenshaw_curtis<Real>(f, a, b, 256)) return *r;
            // not converged: every node of the 256-interval rule was evaluated
            quadrature_result<Real> r = tanh_sinh_integrate_graded<Real>(f, a, b, near[0], near[1]);
            r.evaluations += 255;
            return r;
        }
    }
    return tanh_sinh_integrate_graded<Real>(f, a, b, near[0], near[1]);
}

/// A kink of the marginal inside its middle piece and the distance of its complex branch points
/// from the real axis.
template <class Real>
struct kink {
    Real at, distance;
};

/// The marginal's kinks in (a, b), the middle piece of marginal_integral (b - th = edge_gap +
/// the distance to b), close enough to the path to need a split. The marginal
/// 2 pi sqrt(D0) [E(th + t|m) - E(th - t|m)] (t the other angle's half-width) has, besides the
/// support's edges, branch points where 1 - m sin^2 phi = 0 for phi = th - t or th + t: at
/// phi = k pi +- i asinh(1/sqrt|m|) (m < 0). Near a th where th - t(th) = 0 or th + t(th) = pi (in
/// the middle piece t falls from pi to 0, so th - t = 0 once and th + t - pi changes sign an odd
/// number of times, or an even one) they lie at +- i asinh(1/sqrt|m|) / |phi'(th)| off the real
/// axis: for a heavy second arm (|m| = m2 / m1 for point masses: 2^21 for the cross-check's
/// pendulum E) within 1e-3 of the path, where the marginal has a near-corner that no rule on the
/// whole piece resolves (pendulum E at quad: ~5 s and an error estimate of 1e-10 for a value good
/// to 1e-27; m2/m1 = 4: 2530 evaluations where 255 do at m2/m1 = 1). Splitting the piece there
/// leaves the near-singularity at an end, where the graded rules concentrate their nodes. Kinks
/// whose pair lies a quarter of the piece's width or more off the path are left inside: the rules
/// converge across them as fast as with the split, which would double the nodes (the paper's
/// pendulum, |m| = 1: its Omega unchanged bit for bit at double at the 13 energies of
/// bench/results/omega_quad_kinks.txt, and at 8 of them at quad). A sign change on a 16-point grid
/// (t once per point) gives the kink's bracket and |phi'| there; a kink that needs the split is
/// refined by 60 bisections (where the split falls does not change the integral, only how fast the
/// rules converge). None for m = 0.
template <class Real>
std::vector<kink<Real>> kink_points(const detail::angle_support<Real>& sup, const Real& a,
                                    const Real& b, const Real& edge_gap, const Real& m) {
    using std::abs;
    using std::asinh;
    using std::sqrt;
    std::vector<kink<Real>> out;
    if (!(m < 0) || !(b > a)) return out;
    const Real s = asinh(1 / sqrt(-m));
    const Real w = b - a;
    auto t = [&](const Real& th) {
        return sup.half_width(th, Real(edge_gap + (b - th)), Real(th - a));
    };
    // phi(th) - k pi of the two kinds, from t(th): th - t, th + t - pi
    auto phi = [](int kind, const Real& th, const Real& t_th) {
        return kind == 0 ? Real(th - t_th) : Real(th + t_th - pi<Real>());
    };
    constexpr int grid = 16;
    std::array<Real, grid + 1> x, tx;
    for (int j = 0; j <= grid; ++j) {
        x[j] = j == grid ? b : Real(a + w * j / grid);
        tx[j] = t(x[j]);
    }
    for (int kind = 0; kind < 2; ++kind) {
        for (int j = 1; j <= grid; ++j) {
            const Real f_lo = phi(kind, x[j - 1], tx[j - 1]), f_hi = phi(kind, x[j], tx[j]);
            if (!((f_lo < 0 && f_hi > 0) || (f_lo > 0 && f_hi < 0))) continue;
            // |phi'| from the bracket (the kink's pair lies asinh(1/sqrt|m|) / |phi'| off)
            const Real slope = abs(f_hi - f_lo) / (x[j] - x[j - 1]);
            const Real distance = s / slope;
            if (!(distance < w / 4)) continue;
            Real x0 = x[j - 1], x1 = x[j];
            const bool rising = f_lo < 0;
            for (int it = 0; it < 60; ++it) {
                const Real mid = (x0 + x1) / 2;
                ((phi(kind, mid, t(mid)) < 0) == rising ? x0 : x1) = mid;
            }
            const Real c = (x0 + x1) / 2;
            // a kink within 1e-9 of the piece's width of an end is left to that end
            if (c - a > w * Real(1e-9) && b - c > w * Real(1e-9)) out.push_back({c, distance});
        }
    }
    std::sort(out.begin(), out.end(),
              [](const kink<Real>& p, const kink<Real>& q) { return p.at < q.at; });
    return out;
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
        // the marginal's kinks (kink_points): pieces between them, each graded towards a kink
        // at its end as towards a branch point beyond it
        const std::vector<kink<Real>> kinks = kink_points(sup, a, b, edge_gap, m);
        Real p = a, near_p = near[0];
        for (std::size_t i = 0; i <= kinks.size(); ++i) {
            const Real q = i < kinks.size() ? kinks[i].at : b;
            const Real near_q = i < kinks.size() ? kinks[i].distance : near[1];
            const Real before = p - a, after = b - q;  // the piece's distances to a and b
            auto piece = [&](const Real& th, const Real& to_p, const Real& to_q) -> Real {
                return f(th, Real(before + to_p), Real(after + to_q));
            };
            r += piece_integral<Real>(piece, p, q, {near_p, near_q});
            p = q;
            near_p = near_q;
        }
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
    // marginal's evaluation: 8 eps of the value. (It had grown with the elliptic parameter,
    // 4 eps (1 + sqrt|m|), |m| = C^2 / D0, while the kinks were inside the pieces: what it
    // covered was their truncation. With the kinks split off, 80 random pendulums with |m| from
    // 0.3 to 5e7 at energies from the well to above the maximum are within 5.3 eps at double and
    // quad of 45-digit values: bench/results/omega_kinks_sweep.txt,
    // tests/prediction/test_error_estimates.cpp.)
    r.error_estimate = 2 * half.error_estimate + 8 * epsilon<Real>() * r.value;
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
