// Flux through a dividing curve th_flip = pi + h(s): the kinetic (1-D) and momentum (2-D) routes,
// and the zeros of K along the curve. See include/flipflux/prediction/curve_flux.hpp and
// docs/theory.md#phase-volume-and-fluxes.
#include <algorithm>
#include <array>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
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
    Real above_max;      ///< E - E_max
    Real w_s, w_f;       ///< weights of s and of the flip angle in V
    Real M_ss, M_ff, C;  ///< diagonal entries of M for s and for the flip angle; C
    Real D0;             ///< M_ss M_ff - C^2 (the model's, without cancellation)
    /// The domain is a full turn (hi - lo = 2 pi): s beyond hi is the point s - (hi - lo) of it
    /// (intervals_of may start its window inside the domain and end it past hi).
    bool periodic = false;

    curve_frame(const double_pendulum<Real>& m, const energy_level<Real>& energy,
                const curve_view<Real>& c)
        : model(m), curve(c) {
        using boost::multiprecision::isfinite;
        using std::abs;
        using std::isfinite;
        if (!isfinite(energy.value) || !isfinite(energy.residual))
            throw std::domain_error("curve_flux: energy not finite");
        const auto& k = m.coefficients();
        const bool two = c.flip_arm == arm::two;
        delta = energy.above(m.saddle_level(c.flip_arm));
        above_max = energy.above(m.maximum_level());
        w_s = two ? k.alpha : k.beta;
        w_f = two ? k.beta : k.alpha;
        M_ss = two ? k.A : k.B;
        M_ff = two ? k.B : k.A;
        C = k.C;
        D0 = k.D0;
        const Real width = c.domain[1] - c.domain[0];
        periodic = abs(width - two_pi<Real>()) <= 16 * epsilon<Real>() * two_pi<Real>();
    }

    /// s as a point of the curve's domain (a periodic domain's s past hi, one turn back).
    Real in_domain(const Real& s) const {
        return periodic && s > curve.domain[1] ? Real(s - (curve.domain[1] - curve.domain[0])) : s;
    }

    /// K = (E - E_s) - 2 w_s sin^2(s/2) + 2 w_f sin^2(h/2): E - V at (s, pi + h); for
    /// |s| > pi/2 as (E - E_max) + 2 w_s cos^2(s/2) + 2 w_f sin^2(h/2), whose terms are small
    /// where K is (near the maximum).
    /// (The form is chosen by s reduced to [-pi, pi]: a domain such as [0, 2 pi] reaches s near
    /// 2 pi, where K is the first form's.)
    Real kinetic(const Real& at) const {
        using std::abs;
        using std::cos;
        using std::sin;
        const Real s = in_domain(at);
        const Real h = curve.offset(s);
        const Real sh = sin(h / 2);
        const Real p = s > pi<Real>()    ? Real(s - two_pi<Real>())
                       : s < -pi<Real>() ? Real(s + two_pi<Real>())
                                         : s;
        if (abs(p) > half_pi<Real>()) {
            const Real cs = cos(p / 2);
            return above_max + 2 * w_s * cs * cs + 2 * w_f * sh * sh;
        }
        const Real ss = sin(p / 2);
        return delta - 2 * w_s * ss * ss + 2 * w_f * sh * sh;
    }
    /// dK/ds = -w_s sin s + w_f sin(h) h'.
    Real kinetic_slope(const Real& at) const {
        using std::sin;
        const Real s = in_domain(at);
        return -w_s * sin(s) + w_f * sin(curve.offset(s)) * curve.slope(s);
    }
    /// Q = n^T adj(M) n = M_ss + 2 C c h' + M_ff h'^2, c = cos(th1 - th2) = -cos(s - h), in a
    /// form without cancellation: for a nearly singular M its terms, ~ max M, cancel to ~ D0 / M_ff
    /// where h' ~ -+C / M_ff and c ~ -+1 (quad lost 5 digits just above a saddle with C^2 / D0 =
    /// 2e6). With u = s - h: Q = M_ff (h' - C/M_ff)^2 + D0/M_ff + 4 C h' sin^2(u/2) where cos u >=
    /// 0, and M_ff (h' + C/M_ff)^2 + D0/M_ff - 4 C h' cos^2(u/2) where it is negative (each the
    /// expression above: 2 sin^2(u/2) = 1 - cos u, 2 cos^2(u/2) = 1 + cos u).
    Real normal_weight(const Real& at) const {
        using std::cos;
        using std::sin;
        const Real s = in_domain(at);
        const Real h = curve.offset(s), hp = curve.slope(s);
        const Real u = s - h;
        const Real r = C / M_ff, floor = D0 / M_ff;
        if (cos(u) >= 0) {
            const Real d = hp - r, su = sin(u / 2);
            return M_ff * d * d + floor + 4 * C * hp * su * su;
        }
        const Real d = hp + r, cu = cos(u / 2);
        return M_ff * d * d + floor - 4 * C * hp * cu * cu;
    }
    /// (th1, th2) at s.
    std::array<Real, 2> angles(const Real& at) const {
        const Real s = in_domain(at);
        const Real flip = pi<Real>() + curve.offset(s);
        return curve.flip_arm == arm::two ? std::array<Real, 2>{s, flip}
                                          : std::array<Real, 2>{flip, s};
    }
    /// n = grad g in (th1, th2).
    std::array<Real, 2> normal(const Real& s) const {
        const Real hp = curve.slope(in_domain(s));
        return curve.flip_arm == arm::two ? std::array<Real, 2>{-hp, Real(1)}
                                          : std::array<Real, 2>{Real(1), -hp};
    }
};

/// A zero of f in [a, b] given f(a), f(b) of opposite signs (or one of them zero), to full
/// precision: Brent's method (R. P. Brent, "Algorithms for Minimization without Derivatives",
/// 1973, ch. 4, zeroin), to 2 eps |x| plus an absolute eps^2 (|a| + |b|) (for a zero at 0; just
/// above a saddle the zeros lie ~ sqrt(E - E_s) from 0 and need their full relative precision).
/// NOTE: not Boost's toms748_solve: in Boost 1.74 it keeps a function-static `T mu`, made at the
/// precision of its first call. At mp every later call in another precision then mixes two
/// precisions, and each of its expressions sets the process-wide default precision while it
/// runs: with golden --jobs 2 the other thread's adaptive quadrature then met a tolerance 50 digits
/// beyond its values' accuracy and never finished (light-upper-arm, flux-approx, mp:50 check pass).
template <class Real, class F>
Real bracketed_zero(F f, Real a, Real b, Real fa, Real fb) {
    using std::abs;
    if (fa == 0) return a;
    if (fb == 0) return b;
    const Real eps = epsilon<Real>();
    const Real floor = eps * eps * (abs(a) + abs(b));
    Real c = a, fc = fa, d = b - a, e = d;
    for (int it = 0; it < 100000; ++it) {
        if ((fb > 0) == (fc > 0)) {  // the zero is between a and b: restart c there
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if (abs(fc) < abs(fb)) {  // b the best estimate
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        const Real tol = 2 * eps * abs(b) + floor;
        const Real m = (c - b) / 2;
        if (abs(m) <= tol || fb == 0) return b;
        if (abs(e) >= tol && abs(fa) > abs(fb)) {
            // inverse quadratic interpolation (secant when a = c)
            Real p, q;
            const Real s = fb / fa;
            if (a == c) {
                p = 2 * m * s;
                q = 1 - s;
            } else {
                const Real qa = fa / fc, r = fb / fc;
                p = s * (2 * m * qa * (qa - r) - (b - a) * (r - 1));
                q = (qa - 1) * (r - 1) * (s - 1);
            }
            if (p > 0)
                q = -q;
            else
                p = -p;
            if (2 * p < 3 * m * q - abs(tol * q) && p < abs(e * q / 2)) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;  // bisection
            e = m;
        }
        a = b;
        fa = fb;
        b += abs(d) > tol ? d : (m > 0 ? tol : Real(-tol));
        fb = f(b);
    }
    throw std::runtime_error("curve_flux: the root finder did not converge");
}

/// The accessible pieces of the curve with, for each end, the distance to the nearest branch
/// point of sqrt(K) beyond it (the zero across a forbidden gap, or the complex zeros of K near
/// a grazing minimum): what tanh_sinh_integrate_graded needs.
template <class Real>
struct accessible_pieces {
    std::vector<std::array<Real, 2>> pieces;
    std::vector<std::array<Real, 2>> radii;
};

/// A full turn accessible at its seam (lo = hi): the sampling window (samples s, K, dK of [lo, hi])
/// starts instead at the sample where K is largest and ends a turn later (curve_frame::in_domain),
/// so that no piece is cut where K may nearly vanish. Above E_max the sine curve's K has its
/// minimum, ~ E - E_max, at the seam s = pi: cut there, the pieces' ends met the branch points of
/// sqrt(K) at s = pi +- i r, r ~ sqrt(E - E_max), unseen, and tanh-sinh lost up to 6 digits of
/// quad beyond its estimate (an independent audit, 2 December 2026).
template <class Real>
void start_where_K_is_largest(std::vector<Real>& s, std::vector<Real>& K, std::vector<Real>& dK,
                              const Real& turn) {
    const std::size_t n = s.size() - 1;
    const auto top = std::size_t(std::max_element(K.begin(), K.end() - 1) - K.begin());
    if (top == 0) return;
    std::vector<Real> s2(n + 1), K2(n + 1), dK2(n + 1);
    for (std::size_t i = 0; i <= n; ++i) {
        const std::size_t j = (i + top) % n;
        s2[i] = i + top < n ? s[j] : Real(s[j] + turn);
        K2[i] = K[j];
        dK2[i] = dK[j];
    }
    s.swap(s2);
    K.swap(K2);
    dK.swap(dK2);
}

template <class Real>
accessible_pieces<Real> intervals_of(const curve_frame<Real>& frame) {
    using boost::multiprecision::isfinite;
    using std::abs;
    using std::ceil;
    using std::isfinite;
    using std::sqrt;
    Real lo = frame.curve.domain[0], hi = frame.curve.domain[1];
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
    if (frame.periodic && K[0] > 0 && K[n] > 0) start_where_K_is_largest(s, K, dK, hi - lo);
    lo = s[0];
    hi = s[n];
    // the rounding level of K's terms: a K within it of zero is a touch of K = 0 (below)
    const Real noise = 16 * epsilon<Real>() * (abs(frame.delta) + 2 * frame.w_s + 2 * frame.w_f);
    auto kinetic = [&frame](const Real& x) { return frame.kinetic(x); };
    auto kinetic_slope = [&frame](const Real& x) { return frame.kinetic_slope(x); };
    std::vector<Real> breaks{lo, hi};
    std::vector<std::array<Real, 2>> grazing;  // (point, radius of the complex zeros of K)
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
            // grazing: K touches zero (or nearly) at m; K ~ Km + K''/2 (s - m)^2 has complex
            // zeros at distance sqrt(2 Km / K'') from m
            const Real h = sqrt(epsilon<Real>()) * (1 + abs(m));
            const Real curvature =
                (frame.kinetic_slope(Real(m + h)) - frame.kinetic_slope(Real(m - h))) / (2 * h);
            // NOTE: a minimum below the rounding level of K's terms is a true touch (radius 0:
            // sqrt(K) ~ |s - m| is smooth on each side); resolving noise would never converge.
            const Real radius =
                curvature > 0 && Km > noise ? Real(sqrt(2 * Km / curvature)) : Real(0);
            breaks.push_back(m);
            grazing.push_back({m, radius});
        }
    }
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    // A forbidden gap whose K stays within the rounding noise of its terms is a touch of K = 0
    // seen through rounding, as a grazing minimum below the noise is (above): e.g. E = E_max of
    // decimal parameters, where the level lands 1e-(digits) off E and the curve's top becomes a
    // gap ~1e-(digits/2) wide whose zeros, branch points of sqrt(K), stalled the quadrature
    // (minutes at mp:20). The gap collapses to a touch point of radius 0 (an end of the domain
    // when the gap is there); the flux changes by O(gap^2), below the rounding.
    for (std::size_t j = 0; j + 1 < breaks.size() && breaks.size() > 2;) {
        const Real mid = (breaks[j] + breaks[j + 1]) / 2;
        const Real Kmid = frame.kinetic(mid);
        if (Kmid > 0 || Kmid < -noise) {
            ++j;
            continue;
        }
        if (j == 0) {  // at the start of the domain: its first end stays, as a touch
            grazing.push_back({breaks[0], Real(0)});
            breaks.erase(breaks.begin() + 1);
        } else if (j + 2 == breaks.size()) {  // at the end of the domain
            grazing.push_back({breaks[j + 1], Real(0)});
            breaks.erase(breaks.begin() + std::ptrdiff_t(j));
            break;
        } else {  // inside: both zeros become one touch point
            breaks[j] = mid;
            breaks.erase(breaks.begin() + std::ptrdiff_t(j) + 1);
            grazing.push_back({mid, Real(0)});
            ++j;
        }
    }
    const std::size_t nb = breaks.size();
    std::vector<bool> open(nb - 1);
    for (std::size_t j = 0; j + 1 < nb; ++j)
        open[j] = frame.kinetic((breaks[j] + breaks[j + 1]) / 2) > 0;
    const bool periodic = frame.periodic;
    // the radius at break point j seen from the piece on its `side` (+1: piece j, -1: piece j-1)
    auto radius = [&](std::size_t j, int side) -> Real {
        for (const auto& g : grazing)
            if (g[0] == breaks[j]) return g[1];
        // the neighbouring piece across break j
        std::ptrdiff_t other = side > 0 ? std::ptrdiff_t(j) - 1 : std::ptrdiff_t(j);
        if (other < 0 || other >= std::ptrdiff_t(nb - 1)) {
            if (!periodic) return Real(0);
            other = other < 0 ? std::ptrdiff_t(nb - 2) : 0;
        }
        if (open[other]) return Real(0);           // K > 0 on both sides: no branch point here
        return breaks[other + 1] - breaks[other];  // the zero at the far end of the gap
    };
    accessible_pieces<Real> result;
    for (std::size_t j = 0; j + 1 < nb; ++j) {
        if (!open[j]) continue;
        result.pieces.push_back({breaks[j], breaks[j + 1]});
        result.radii.push_back({radius(j, +1), radius(j + 1, -1)});
    }
    return result;
}

/// Gauss-Kronrod (61 points, Boost's nodes in Real) on `panels` equal panels of
/// [-pi/2, pi/2], with cos and sin of every node tabulated once per (type, panel count): the
/// momentum integrand then needs no trigonometric function. Kronrod and Gauss sums give the
/// error estimate.
template <class Real>
struct half_circle_rule {
    std::vector<Real> cos_x, sin_x, w_kronrod, w_gauss;  // w_gauss = 0 at Kronrod-only nodes

    explicit half_circle_rule(std::size_t panels) {
        using std::cos;
        using std::sin;
        const gauss_kronrod_rule<Real>& rule = gauss_kronrod_61<Real>();
        const auto& x = rule.abscissa;
        const auto& wk = rule.kronrod_weights;
        const auto& wg = rule.gauss_weights;
        const Real half_width = pi<Real>() / (2 * panels);
        for (std::size_t p = 0; p < panels; ++p) {
            const Real centre = -half_pi<Real>() + (2 * p + 1) * half_width;
            for (std::size_t i = 0; i < x.size(); ++i) {
                // the rule stores the non-negative half; its 30-point Gauss rule (even order)
                // uses the odd indices, not the centre
                const Real g = i % 2 == 1 ? wg[i / 2] : Real(0);
                for (int sign : {1, -1}) {
                    if (i == 0 && sign < 0) continue;
                    const Real node = centre + sign * half_width * x[i];
                    cos_x.push_back(cos(node));
                    sin_x.push_back(sin(node));
                    w_kronrod.push_back(half_width * wk[i]);
                    w_gauss.push_back(half_width * g);
                }
            }
        }
    }

    /// The rule with the smallest power of two >= panels (<= 64) panels; built on first use at
    /// each working precision.
    static const half_circle_rule& get(std::size_t panels) {
        static std::mutex mutex;
        // keyed by (binary digits, log2 panels): 1, 2, 4, ..., 64 panels
        static std::map<std::pair<int, std::size_t>, std::unique_ptr<half_circle_rule>> rules;
        std::size_t k = 0;
        while ((std::size_t(1) << k) < panels && k < 6)
            ++k;
        const std::lock_guard<std::mutex> lock(mutex);
        auto& rule = rules[{binary_digits<Real>(), k}];
        if (!rule) rule = std::make_unique<half_circle_rule>(std::size_t(1) << k);
        return *rule;
    }
};

/// The momentum integral at s done numerically: det M sqrt(2K) int_0^2pi |n.e| (e^T M e)^(-3/2)
/// d psi, psi the direction of the velocity. With psi = psi_n + x (psi_n the direction of n),
/// n.e = |n| cos x >= 0 on [-pi/2, pi/2], and the other half circle gives the same
/// (x -> x + pi flips n.e and keeps e^T M e): 2 |n| int cos x q(x)^(-3/2), q = e'^T M' e' in the
/// frame (n/|n|, t) rotated by psi_n. q = lambda_1 cos^2(x - x0) + lambda_2 sin^2(x - x0) (the
/// eigenvalues of M) vanishes at Im x = +-atanh(sqrt(lambda_min/lambda_max)): the strip that
/// sets the number of Gauss-Kronrod panels.
template <class Real>
quadrature_result<Real> momentum_integral(const curve_frame<Real>& frame, const Real& s) {
    using std::abs;
    using std::atan2;
    using std::atanh;
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Real K = frame.kinetic(s);
    if (!(K > 0)) return {};
    const std::array<Real, 2> th = frame.angles(s), n = frame.normal(s);
    const sym2<Real> M = frame.model.mass_matrix(th[0], th[1]);
    const Real det = frame.model.mass_determinant(th[0], th[1]);
    const Real norm = sqrt(n[0] * n[0] + n[1] * n[1]);
    const Real u0 = n[0] / norm, u1 = n[1] / norm;  // unit normal; tangent (-u1, u0)
    const Real qxx = M.xx * u0 * u0 + 2 * M.xy * u0 * u1 + M.yy * u1 * u1;
    const Real qxy = -M.xx * u0 * u1 + M.xy * (u0 * u0 - u1 * u1) + M.yy * u0 * u1;
    const Real qyy = M.xx * u1 * u1 - 2 * M.xy * u0 * u1 + M.yy * u0 * u0;
    // q in M's eigenbasis, q = lambda_max cos^2(x - x_max) + lambda_min sin^2(x - x_max) (x_max
    // the direction of lambda_max's eigenvector in the frame, lambda_min = det / lambda_max):
    // two non-negative terms. The frame's quadratic form qxx c^2 + 2 qxy c s + qyy s^2 is the
    // same number, but where M is nearly singular it cancels to lambda_min at the peak, losing
    // lambda_max / lambda_min of its relative accuracy (C^2 / D0 = 182: 1e-11 in the flux).
    const Real trace = M.xx + M.yy;
    const Real spread = sqrt((M.xx - M.yy) * (M.xx - M.yy) + 4 * M.xy * M.xy);
    const Real lambda_max = (trace + spread) / 2, lambda_min = det / lambda_max;
    const Real x_max = atan2(2 * qxy, qxx - qyy) / 2;
    const Real c_max = cos(x_max), s_max = sin(x_max);
    auto f = [&](const Real& c, const Real& sn) -> Real {
        const Real along = c * c_max + sn * s_max, across = sn * c_max - c * s_max;
        const Real q = lambda_max * along * along + lambda_min * across * across;
        return c / (q * sqrt(q));
    };
    // eigenvalue ratio of M: lambda_min / lambda_max = det / lambda_max^2
    const Real strip = atanh(sqrt(det) / lambda_max);
    const std::size_t panels = kronrod_panels(pi<Real>(), strip);
    quadrature_result<Real> r;
    if (panels > 0) {
        const half_circle_rule<Real>& rule = half_circle_rule<Real>::get(panels);
        Real gauss_sum = 0;
        for (std::size_t i = 0; i < rule.cos_x.size(); ++i) {
            const Real v = f(rule.cos_x[i], rule.sin_x[i]);
            r.value += rule.w_kronrod[i] * v;
            gauss_sum += rule.w_gauss[i] * v;
        }
        r.evaluations = rule.cos_x.size();
        r.error_estimate = abs(r.value - gauss_sum);
    }
    using std::pow;
    if (panels == 0 || r.error_estimate > pow(epsilon<Real>(), Real(2) / 3) * r.value) {
        // a nearly singular mass matrix: adaptive quadrature over the half circle, in
        // u = tan(x / 2) (cos x = (1 - u^2) w, sin x = 2 u w, dx = 2 w du, w = 1 / (1 + u^2),
        // x in [-pi/2, pi/2] for u in [-1, 1]): no sine or cosine per node, which at quad and
        // mp:N is most of a node's cost (E = E_max with C^2 / D0 = 180: 108 s at quad before)
        const std::size_t used = r.evaluations;
        r = gauss_kronrod_integrate<Real>(
            [&](const Real& u) -> Real {
                const Real w = 1 / (1 + u * u);
                return 2 * w * f((1 - u * u) * w, 2 * u * w);
            },
            Real(-1), Real(1));
        r.evaluations += used;
    }
    r.l1_norm = r.value;
    const Real factor = 2 * norm * det * sqrt(2 * K);
    r.value *= factor;
    r.error_estimate = factor * r.error_estimate + epsilon<Real>() * r.value;
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
    return intervals_of(curve_frame<Real>(model, energy, curve)).pieces;
}

/// Where Q = n^T adj(M) n nearly vanishes inside [a, b] (a nearly singular mass matrix: Q is a
/// sum of terms ~ |M| that cancel to its smallest eigenvalue), sqrt(Q) has a pair of complex
/// branch points at distance r ~ sqrt(2 Q_min / Q'') from the real axis, and tanh-sinh across
/// the dip converges slowly while its error estimate does not see why (an independent
/// cross-check: m2 = 2^20 m1, Q from 2.8e5 down to 0.125, double 3x beyond its estimate, quad
/// and mp:40 16 digits). Returns {m, r} with the dip's minimum m where min Q < 1e-4 max Q over
/// 63 interior samples (refined by Brent's method), else r = -1: the integral is split at m and
/// graded towards it.
template <class Real>
std::array<Real, 2> q_dip(const curve_frame<Real>& frame, const Real& a, const Real& b) {
    using std::sqrt;
    constexpr int n = 64;
    const Real step = (b - a) / n;
    int at = 0;
    Real q_min = 0, q_max = 0;
    for (int i = 1; i < n; ++i) {
        const Real q = frame.normal_weight(Real(a + step * i));
        if (i == 1 || q < q_min) {
            q_min = q;
            at = i;
        }
        if (i == 1 || q > q_max) q_max = q;
    }
    if (!(q_min < Real(1e-4) * q_max)) return {Real(0), Real(-1)};
    // Brent's minimisation between the lowest sample's neighbours (Q is smooth and convex near its
    // dip), to half the working digits (all a minimum's abscissa has)
    const auto q = [&frame](const Real& s) { return frame.normal_weight(s); };
    std::uintmax_t iterations = 200;
    const Real m = boost::math::tools::brent_find_minima(q, Real(a + step * (at - 1)),
                                                         Real(a + step * (at + 1)),
                                                         binary_digits<Real>() / 2, iterations)
                       .first;
    const Real qm = q(m);
    // Q'' from a symmetric difference over 1/64 of a sample step (Q is quadratic there)
    const Real d = step / 64;
    const Real q2 = (q(Real(m + d)) - 2 * qm + q(Real(m - d))) / (d * d);
    const Real r = q2 > 0 && qm > 0 ? sqrt(2 * qm / q2) : Real(0);
    return {m, r};
}

template <class Real>
curve_flux_result<Real> curve_flux(const double_pendulum<Real>& model,
                                   const level_arg<Real>& energy, const curve_view<Real>& curve,
                                   curve_flux_method method) {
    using std::sqrt;
    const curve_frame<Real> frame(model, energy, curve);
    curve_flux_result<Real> r;
    const accessible_pieces<Real> found = intervals_of(frame);
    r.intervals = found.pieces;
    quadrature_result<Real> total;
    for (std::size_t j = 0; j < found.pieces.size(); ++j) {
        const auto& piece = found.pieces[j];
        const auto& near = found.radii[j];
        if (method == curve_flux_method::kinetic) {
            auto f = [&frame](const Real& s, const Real&, const Real&) -> Real {
                const Real K = frame.kinetic(s);
                return K > 0 ? 4 * sqrt(2 * K * frame.normal_weight(s)) : Real(0);
            };
            const std::array<Real, 2> dip = q_dip(frame, piece[0], piece[1]);
            if (dip[1] < 0) {
                total += tanh_sinh_integrate_graded<Real>(f, piece[0], piece[1], near[0], near[1]);
            } else {  // split at Q's dip, graded towards it from both sides
                total += tanh_sinh_integrate_graded<Real>(f, piece[0], dip[0], near[0], dip[1]);
                total += tanh_sinh_integrate_graded<Real>(f, dip[0], piece[1], dip[1], near[1]);
            }
        } else {
            auto inner = [&frame](const Real& s, const Real&, const Real&) {
                return momentum_integral(frame, s);
            };
            total += nested_integrate<Real>(inner, piece[0], piece[1], near[0], near[1]);
        }
    }
    r.value = total.value;
    r.error_estimate = total.error_estimate + 16 * epsilon<Real>() * total.l1_norm;
    r.evaluations = total.evaluations;
    return r;
}

template <class Real>
Real near_saddle_flux(const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy,
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
    return 4 * pi<Real>() * energy.above(model.saddle_level(a)) * sqrt(mass / stiffness);
}

#define FLIPFLUX_CURVE_FLUX_INSTANTIATE(R)                                                        \
    template R curve_kinetic_energy<R>(const double_pendulum<R>&, const R&, const curve_view<R>&, \
                                       const R&);                                                 \
    template std::vector<std::array<R, 2>> accessible_intervals<R>(                               \
        const double_pendulum<R>&, const R&, const curve_view<R>&);                               \
    template curve_flux_result<R> curve_flux<R>(const double_pendulum<R>&, const level_arg<R>&,   \
                                                const curve_view<R>&, curve_flux_method);         \
    template R near_saddle_flux<R>(const double_pendulum<R>&, arm, const level_arg<R>&, const R&)
FLIPFLUX_CURVE_FLUX_INSTANTIATE(inst_real);

}  // namespace flipflux
