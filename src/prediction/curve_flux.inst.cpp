// Flux through a dividing curve th_flip = pi + h(s): the kinetic (1-D) and momentum (2-D) routes,
// and the zeros of K along the curve. See include/flipflux/prediction/curve_flux.hpp and
// docs/theory.md#phase-volume-and-fluxes.
#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <stdexcept>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/quadrature/quadrature.hpp"

namespace flipflux {
namespace {

/// Samples of K per 2 pi of curve parameter when looking for its zeros.
constexpr int samples_per_period = 128;

/// The curve in the pendulum's configuration space, with K, K' and Q along it.
template <class Real>
struct curve_frame {
    const double_pendulum<Real>& model;
    const curve_view<Real>& curve;
    Real delta;          ///< E - E_s
    Real w_s, w_f;       ///< weights of s and of the flip angle in V
    Real M_ss, M_ff, C;  ///< diagonal entries of M for s and for the flip angle; C

    curve_frame(const double_pendulum<Real>& m, const Real& energy, const curve_view<Real>& c)
        : model(m), curve(c) {
        using boost::multiprecision::isfinite;
        using std::isfinite;
        if (!isfinite(energy)) throw std::domain_error("curve_flux: energy not finite");
        const auto& k = m.coefficients();
        const bool two = c.flip_arm == arm::two;
        delta = energy - m.saddle_energy(c.flip_arm);
        w_s = two ? k.alpha : k.beta;
        w_f = two ? k.beta : k.alpha;
        M_ss = two ? k.A : k.B;
        M_ff = two ? k.B : k.A;
        C = k.C;
    }

    /// K = (E - E_s) - 2 w_s sin^2(s/2) + 2 w_f sin^2(h/2): E - V at (s, pi + h).
    Real kinetic(const Real& s) const {
        using std::sin;
        const Real h = curve.offset(s);
        const Real ss = sin(s / 2), sh = sin(h / 2);
        return delta - 2 * w_s * ss * ss + 2 * w_f * sh * sh;
    }
    /// dK/ds = -w_s sin s + w_f sin(h) h'.
    Real kinetic_slope(const Real& s) const {
        using std::sin;
        return -w_s * sin(s) + w_f * sin(curve.offset(s)) * curve.slope(s);
    }
    /// Q = n^T adj(M) n = M_ss + 2 C c h' + M_ff h'^2, c = cos(th1 - th2) = -cos(s - h).
    Real normal_weight(const Real& s) const {
        using std::cos;
        const Real h = curve.offset(s), hp = curve.slope(s);
        const Real c = -cos(s - h);
        return M_ss + 2 * C * c * hp + M_ff * hp * hp;
    }
    /// (th1, th2) at s.
    std::array<Real, 2> angles(const Real& s) const {
        const Real flip = pi<Real>() + curve.offset(s);
        return curve.flip_arm == arm::two ? std::array<Real, 2>{s, flip}
                                          : std::array<Real, 2>{flip, s};
    }
    /// n = grad g in (th1, th2).
    std::array<Real, 2> normal(const Real& s) const {
        const Real hp = curve.slope(s);
        return curve.flip_arm == arm::two ? std::array<Real, 2>{-hp, Real(1)}
                                          : std::array<Real, 2>{Real(1), -hp};
    }
};

/// A zero of f in [a, b] given f(a), f(b) of opposite signs (or one of them zero), to full
/// precision (TOMS 748).
template <class Real, class F>
Real bracketed_zero(F f, const Real& a, const Real& b, const Real& fa, const Real& fb) {
    if (fa == 0) return a;
    if (fb == 0) return b;
    std::uintmax_t iterations = 400;
    const auto bracket = boost::math::tools::toms748_solve(
        f, a, b, fa, fb, boost::math::tools::eps_tolerance<Real>(), iterations);
    return (bracket.first + bracket.second) / 2;
}

template <class Real>
std::vector<std::array<Real, 2>> intervals_of(const curve_frame<Real>& frame) {
    using boost::multiprecision::isfinite;
    using std::ceil;
    using std::isfinite;
    const Real lo = frame.curve.domain[0], hi = frame.curve.domain[1];
    if (!isfinite(lo) || !isfinite(hi) || !(lo < hi)) {
        throw std::domain_error("curve_flux: the curve's domain must be a finite interval");
    }
    const int n =
        std::max(16, static_cast<int>(ceil(samples_per_period * (hi - lo) / two_pi<Real>())));
    std::vector<Real> s(n + 1), K(n + 1), dK(n + 1);
    for (int i = 0; i <= n; ++i) {
        s[i] = i == n ? hi : lo + (hi - lo) * i / n;
        K[i] = frame.kinetic(s[i]);
        dK[i] = frame.kinetic_slope(s[i]);
    }
    auto kinetic = [&frame](const Real& x) { return frame.kinetic(x); };
    auto kinetic_slope = [&frame](const Real& x) { return frame.kinetic_slope(x); };
    std::vector<Real> breaks{lo, hi};
    for (int i = 0; i < n; ++i) {
        const Real &a = s[i], &b = s[i + 1];
        if (K[i] == 0) breaks.push_back(a);
        if ((K[i] < 0 && K[i + 1] > 0) || (K[i] > 0 && K[i + 1] < 0)) {
            breaks.push_back(bracketed_zero<Real>(kinetic, a, b, K[i], K[i + 1]));
            continue;
        }
        // K keeps its sign at both samples: an extremum inside may still cross zero twice (a
        // narrow accessible or forbidden piece) or graze it.
        const bool minimum = dK[i] < 0 && dK[i + 1] > 0;
        const bool maximum = dK[i] > 0 && dK[i + 1] < 0;
        if (!(minimum && K[i] > 0) && !(maximum && K[i] < 0)) continue;
        const Real m = bracketed_zero<Real>(kinetic_slope, a, b, dK[i], dK[i + 1]);
        const Real Km = frame.kinetic(m);
        if ((minimum && Km < 0) || (maximum && Km > 0)) {
            breaks.push_back(bracketed_zero<Real>(kinetic, a, m, K[i], Km));
            breaks.push_back(bracketed_zero<Real>(kinetic, m, b, Km, K[i + 1]));
        } else if (minimum) {
            breaks.push_back(m);  // grazing: K touches zero (or nearly) at m
        }
    }
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    std::vector<std::array<Real, 2>> pieces;
    for (std::size_t j = 0; j + 1 < breaks.size(); ++j) {
        const Real mid = (breaks[j] + breaks[j + 1]) / 2;
        if (frame.kinetic(mid) > 0) pieces.push_back({breaks[j], breaks[j + 1]});
    }
    return pieces;
}

/// The momentum integral at s done numerically: det M sqrt(2K) int_0^2pi |n.e| (e^T M e)^(-3/2).
template <class Real>
quadrature_result<Real> momentum_integral(const curve_frame<Real>& frame, const Real& s) {
    using std::atan2;
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Real K = frame.kinetic(s);
    if (!(K > 0)) return {};
    const std::array<Real, 2> th = frame.angles(s), n = frame.normal(s);
    const sym2<Real> M = frame.model.mass_matrix(th[0], th[1]);
    const Real det = frame.model.mass_determinant(th[0], th[1]);
    // n.e(psi) = |n| cos(psi - psi_n) >= 0 on [psi_n - pi/2, psi_n + pi/2]; the other half circle
    // gives the same (psi -> psi + pi flips n.e and keeps e^T M e).
    const Real psi_n = atan2(n[1], n[0]);
    auto f = [&](const Real& psi) -> Real {
        const Real c = cos(psi), sn = sin(psi);
        const Real q = M.xx * c * c + 2 * M.xy * c * sn + M.yy * sn * sn;
        const Real along = n[0] * c + n[1] * sn;
        return along > 0 ? along / (q * sqrt(q)) : Real(0);
    };
    quadrature_result<Real> r =
        gauss_kronrod_integrate<Real>(f, psi_n - half_pi<Real>(), psi_n + half_pi<Real>());
    const Real factor = 2 * det * sqrt(2 * K);
    r.value *= factor;
    r.error_estimate *= factor;
    r.l1_norm *= factor;
    return r;
}

}  // namespace

template <class Real>
Real curve_kinetic_energy(const double_pendulum<Real>& model, const Real& energy,
                          const curve_view<Real>& curve, const Real& s) {
    return curve_frame<Real>(model, energy, curve).kinetic(s);
}

template <class Real>
std::vector<std::array<Real, 2>> accessible_intervals(const double_pendulum<Real>& model,
                                                      const Real& energy,
                                                      const curve_view<Real>& curve) {
    return intervals_of(curve_frame<Real>(model, energy, curve));
}

template <class Real>
curve_flux_result<Real> curve_flux(const double_pendulum<Real>& model, const Real& energy,
                                   const curve_view<Real>& curve, curve_flux_method method) {
    using std::sqrt;
    const curve_frame<Real> frame(model, energy, curve);
    curve_flux_result<Real> r;
    r.intervals = intervals_of(frame);
    quadrature_result<Real> total;
    for (const auto& piece : r.intervals) {
        if (method == curve_flux_method::kinetic) {
            auto f = [&frame](const Real& s, const Real&, const Real&) -> Real {
                const Real K = frame.kinetic(s);
                return K > 0 ? 4 * sqrt(2 * K * frame.normal_weight(s)) : Real(0);
            };
            total += tanh_sinh_integrate<Real>(f, piece[0], piece[1]);
        } else {
            auto inner = [&frame](const Real& s, const Real&, const Real&) {
                return momentum_integral(frame, s);
            };
            total += nested_integrate<Real>(inner, piece[0], piece[1]);
        }
    }
    r.value = total.value;
    r.error_estimate = total.error_estimate + 16 * epsilon<Real>() * total.l1_norm;
    r.evaluations = total.evaluations;
    return r;
}

template <class Real>
Real near_saddle_flux(const double_pendulum<Real>& model, arm a, const Real& energy,
                      const Real& slope) {
    using std::sqrt;
    const auto& k = model.coefficients();
    const bool two = a == arm::two;
    // At the saddle c = cos(th1 - th2) = -1: M* = [[M_ss, -C], [-C, M_ff]] in (s, flip) order,
    // K* = diag(w_s, -w_f).
    const Real M_ss = two ? k.A : k.B, M_ff = two ? k.B : k.A;
    const Real w_s = two ? k.alpha : k.beta, w_f = two ? k.beta : k.alpha;
    const Real mass = M_ss - 2 * k.C * slope + M_ff * slope * slope;
    const Real stiffness = w_s - w_f * slope * slope;
    if (!(stiffness > 0)) {
        throw std::domain_error(
            "near_saddle_flux: the curve's tangent is not transverse to the "
            "saddle's runaway direction (d^T K* d <= 0)");
    }
    return 4 * pi<Real>() * (energy - model.saddle_energy(a)) * sqrt(mass / stiffness);
}

#define FLIPFLUX_CURVE_FLUX_INSTANTIATE(R)                                                        \
    template R curve_kinetic_energy<R>(const double_pendulum<R>&, const R&, const curve_view<R>&, \
                                       const R&);                                                 \
    template std::vector<std::array<R, 2>> accessible_intervals<R>(                               \
        const double_pendulum<R>&, const R&, const curve_view<R>&);                               \
    template curve_flux_result<R> curve_flux<R>(const double_pendulum<R>&, const R&,              \
                                                const curve_view<R>&, curve_flux_method);         \
    template R near_saddle_flux<R>(const double_pendulum<R>&, arm, const R&, const R&)
FLIPFLUX_CURVE_FLUX_INSTANTIATE(inst_real);

}  // namespace flipflux
