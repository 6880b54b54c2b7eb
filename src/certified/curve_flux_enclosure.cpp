// Enclosure of f2, the flux through the approximate saddle curve th_flip = pi + A sin s
// (prediction/curve_flux.hpp; derivation and the argument for rigour in docs/certified.md).
//
// In the curve's coordinates (s, flip angle), with (w_s, w_f, M_ss, M_ff) = (alpha, beta, A, B)
// for arm 2 and (beta, alpha, B, A) for arm 1, E_s = 2 w_f, E_max = E_s + 2 w_s:
//     f2 = 8 int_0^pi sqrt(2 K(s) Q(s))_+ ds,
//     K(s) = (E - E_s) - 2 w_s sin^2(s/2) + 2 w_f sin^2(h/2),   h = A sin s,
//     Q(s) = M_ss + 2 C c h' + M_ff h'^2,   c = -cos(s - h),   h' = A cos s
// (K and Q are even in s, so 4 int_-pi^pi = 8 int_0^pi). The slope A of the centre mode:
//     x = the positive root of D0 x^2 - (w_s M_ff - w_f M_ss) x - w_s w_f = 0,
//     A = x C / (w_f + x M_ff).
// The zeros of K on [0, pi] are isolated by arb_calc_isolate_roots (sign change and K' != 0 on
// each block: exactly one simple zero) and refined by the interval Newton operator. At a zero r
// the integrand has a square-root branch point; s = r -+ u^2 removes it exactly, because
//     K(rho) - K(rho - t) = t D(rho, t),
//     D(rho, t) = -w_s sin(c) sinc(t/2)
//                 + w_f A cos(c) sinc(t/2) sinc(A cos(c) sin(t/2)) sin(A sin(c) cos(t/2)),
//     c = rho - t/2,
// (from cos a - cos b = -2 sin((a+b)/2) sin((a-b)/2)) is holomorphic in (rho, t) and K(r) = 0:
// K(r - u^2) = -u^2 D(r, u^2) and K(r + u^2) = u^2 D(r + u^2, u^2), so the integrand over u is
// 2 u^2 sqrt(-+2 D Q), holomorphic at u = 0. D is evaluated on the root's ball: it contains
// the value at the true root, so the quadrature encloses the true piece.
#include <acb_calc.h>
#include <arb_calc.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "flipflux/certified/enclosure.hpp"
#include "prediction_enclosures.hpp"

namespace flipflux::certified_detail {
namespace {

/// The curve and the pendulum in the curve's coordinates (see the file comment).
struct curve_data {
    arb_ball ws, wf, Mss, Mff, C, A;  // weights in V, diagonal of M, C, the curve's slope
    arb_ball delta, above_max;        // E - E_s, E - E_max
    arb_ball pi;
};

bool right_half_plane(const acb_t z) {
    return arb_is_positive(acb_realref(z));
}

double mid_double(const arb_t x) {
    return arf_get_d(arb_midref(x), ARF_RND_NEAR);
}

/// K on a real ball s (and dK/ds = -w_s sin s + w_f sin(h) h' for order 2): arb_calc_func_t.
/// Past pi/2, K = (E - E_max) + 2 w_s cos^2(s/2) + 2 w_f sin^2(h/2), whose terms are small where
/// K is (near pi when E is near E_max).
int kinetic_real(arb_ptr out, const arb_t s, void* param, slong order, slong prec) {
    const auto& c = *static_cast<const curve_data*>(param);
    arb_ball h, sh, t, sn, cs;
    arb_sin_cos(sn.x, cs.x, s, prec);
    arb_mul(h.x, sn.x, c.A.x, prec);
    arb_mul_2exp_si(sh.x, h.x, -1);
    arb_sin(sh.x, sh.x, prec);
    arb_sqr(sh.x, sh.x, prec);
    arb_mul(sh.x, sh.x, c.wf.x, prec);
    arb_mul_2exp_si(sh.x, sh.x, 1);  // 2 w_f sin^2(h/2)
    arb_mul_2exp_si(t.x, s, -1);
    if (mid_double(s) > M_PI / 2) {
        arb_cos(t.x, t.x, prec);
        arb_sqr(t.x, t.x, prec);
        arb_mul(t.x, t.x, c.ws.x, prec);
        arb_mul_2exp_si(t.x, t.x, 1);
        arb_add(out, c.above_max.x, t.x, prec);
    } else {
        arb_sin(t.x, t.x, prec);
        arb_sqr(t.x, t.x, prec);
        arb_mul(t.x, t.x, c.ws.x, prec);
        arb_mul_2exp_si(t.x, t.x, 1);
        arb_sub(out, c.delta.x, t.x, prec);
    }
    arb_add(out, out, sh.x, prec);
    if (order > 1) {
        arb_sin(h.x, h.x, prec);
        arb_mul(h.x, h.x, c.wf.x, prec);
        arb_mul(h.x, h.x, c.A.x, prec);
        arb_mul(h.x, h.x, cs.x, prec);  // w_f sin(h) A cos s
        arb_mul(t.x, sn.x, c.ws.x, prec);
        arb_sub(out + 1, h.x, t.x, prec);
    }
    for (slong i = 2; i < order; ++i)
        arb_indeterminate(out + i);  // never asked for by isolate_roots
    return 0;
}

/// K on a complex ball z (the plain pieces' integrand), as kinetic_real.
void kinetic_complex(acb_t res, const acb_t z, const curve_data& c, slong prec) {
    acb_ball sh, t;
    acb_sin(sh.x, z, prec);
    acb_mul_arb(sh.x, sh.x, c.A.x, prec);
    acb_mul_2exp_si(sh.x, sh.x, -1);
    acb_sin(sh.x, sh.x, prec);
    acb_sqr(sh.x, sh.x, prec);
    acb_mul_arb(sh.x, sh.x, c.wf.x, prec);
    acb_mul_2exp_si(sh.x, sh.x, 1);
    acb_mul_2exp_si(t.x, z, -1);
    if (mid_double(acb_realref(z)) > M_PI / 2) {
        acb_cos(t.x, t.x, prec);
        acb_sqr(t.x, t.x, prec);
        acb_mul_arb(t.x, t.x, c.ws.x, prec);
        acb_mul_2exp_si(t.x, t.x, 1);
        acb_add_arb(res, t.x, c.above_max.x, prec);
    } else {
        acb_sin(t.x, t.x, prec);
        acb_sqr(t.x, t.x, prec);
        acb_mul_arb(t.x, t.x, c.ws.x, prec);
        acb_mul_2exp_si(t.x, t.x, 1);
        acb_neg(t.x, t.x);
        acb_add_arb(res, t.x, c.delta.x, prec);
    }
    acb_add(res, res, sh.x, prec);
}

/// Q(s) = M_ss + 2 C c h' + M_ff h'^2 (c = -cos(s - h), h = A sin s, h' = A cos s).
void normal_weight(acb_t res, const acb_t s, const curve_data& c, slong prec) {
    acb_ball h, hp, cc, t;
    acb_sin_cos(h.x, hp.x, s, prec);
    acb_mul_arb(h.x, h.x, c.A.x, prec);
    acb_mul_arb(hp.x, hp.x, c.A.x, prec);
    acb_sub(cc.x, s, h.x, prec);
    acb_cos(cc.x, cc.x, prec);
    acb_neg(cc.x, cc.x);
    acb_mul(t.x, cc.x, hp.x, prec);
    acb_mul_arb(t.x, t.x, c.C.x, prec);
    acb_mul_2exp_si(t.x, t.x, 1);
    acb_sqr(res, hp.x, prec);
    acb_mul_arb(res, res, c.Mff.x, prec);
    acb_add(res, res, t.x, prec);
    acb_add_arb(res, res, c.Mss.x, prec);
}

/// D(rho, t) = (K(rho) - K(rho - t)) / t in its holomorphic form (file comment).
void divided_difference(acb_t res, const acb_t rho, const acb_t t, const curve_data& c,
                        slong prec) {
    acb_ball ht, cc, s_ht, c_ht, sinc_ht, sn, cs, u, v;
    acb_mul_2exp_si(ht.x, t, -1);
    acb_sub(cc.x, rho, ht.x, prec);  // c = rho - t/2
    acb_sin_cos(s_ht.x, c_ht.x, ht.x, prec);
    acb_sinc(sinc_ht.x, ht.x, prec);
    acb_sin_cos(sn.x, cs.x, cc.x, prec);
    acb_mul(res, sn.x, sinc_ht.x, prec);
    acb_mul_arb(res, res, c.ws.x, prec);
    acb_neg(res, res);  // -w_s sin(c) sinc(t/2)
    acb_mul(u.x, cs.x, s_ht.x, prec);
    acb_mul_arb(u.x, u.x, c.A.x, prec);
    acb_sinc(u.x, u.x, prec);  // sinc(A cos(c) sin(t/2))
    acb_mul(v.x, sn.x, c_ht.x, prec);
    acb_mul_arb(v.x, v.x, c.A.x, prec);
    acb_sin(v.x, v.x, prec);  // sin(A sin(c) cos(t/2))
    acb_mul(u.x, u.x, v.x, prec);
    acb_mul(u.x, u.x, cs.x, prec);
    acb_mul(u.x, u.x, sinc_ht.x, prec);
    acb_mul_arb(u.x, u.x, c.A.x, prec);
    acb_mul_arb(u.x, u.x, c.wf.x, prec);
    acb_add(res, res, u.x, prec);
}

enum class piece { plain, from_root, to_root };

struct flux_integrand {
    piece kind = piece::plain;
    const arb_struct* root = nullptr;  // the zero of K the u-pieces start from
    const curve_data* c = nullptr;
    /// the CPU-time budget (eval --max-seconds) ran out during the quadrature: the integrand
    /// returns zero from then on (so that Arb returns at once) and integrate_exact throws
    /// budget_exceeded
    bool spent = false;
};

/// sqrt(2 K Q) (plain, in s) or 2 u^2 sqrt(+-2 D Q) (u-pieces): acb_calc_func_t. Square roots
/// only of balls in the right half plane; otherwise an indeterminate ball (not holomorphic here).
int flux_integrand_eval(acb_ptr out, const acb_t z, void* param, slong /*order*/, slong prec) {
    auto& f = *static_cast<flux_integrand*>(param);
    if (budget_spent(f.spent)) {  // Arb finishes at once on a zero integrand; the result is
        acb_zero(out);            // discarded (integrate_exact throws)
        return 0;
    }
    acb_ball s, t, k, q;
    if (f.kind == piece::plain) {
        acb_set(s.x, z);
        kinetic_complex(k.x, s.x, *f.c, prec);
    } else {
        acb_sqr(t.x, z, prec);
        acb_set_arb(s.x, f.root);
        if (f.kind == piece::from_root) {
            acb_add(s.x, s.x, t.x, prec);  // K(r + t) = t D(r + t, t)
            divided_difference(k.x, s.x, t.x, *f.c, prec);
        } else {
            divided_difference(k.x, s.x, t.x, *f.c, prec);  // K(r - t) = -t D(r, t)
            acb_neg(k.x, k.x);
            acb_sub(s.x, s.x, t.x, prec);
        }
    }
    normal_weight(q.x, s.x, *f.c, prec);
    acb_mul(k.x, k.x, q.x, prec);
    acb_mul_2exp_si(k.x, k.x, 1);
    if (!right_half_plane(k.x)) {
        acb_indeterminate(out);
        return 0;
    }
    acb_sqrt(out, k.x, prec);
    if (f.kind != piece::plain) {
        acb_mul(out, out, t.x, prec);
        acb_mul_2exp_si(out, out, 1);
    }
    return 0;
}

/// int_a^b f over a real segment with exact ends, to about 2^-prec relative to `scale`.
void integrate_exact(arb_t res, flux_integrand& f, const arf_t a, const arf_t b, const arf_t scale,
                     slong prec) {
    acb_ball ca, cb, r;
    arb_set_arf(acb_realref(ca.x), a);
    arb_set_arf(acb_realref(cb.x), b);
    mag_t tol;
    mag_init(tol);
    arf_get_mag(tol, scale);
    mag_mul_2exp_si(tol, tol, -prec);
    acb_calc_integrate_opt_t opt;
    acb_calc_integrate_opt_init(opt);
    acb_calc_integrate(r.x, flux_integrand_eval, &f, ca.x, cb.x, prec, tol, opt, prec);
    mag_clear(tol);
    throw_if_spent(f.spent);
    arb_set(res, acb_realref(r.x));  // real on the real segment
}

/// int_a^b f for ball ends: between their midpoints, plus (b - b0) f(b) - (a - a0) f(a) (each an
/// enclosure of the integral between a midpoint and the true end, f evaluated on the end's ball).
void integrate_balls(arb_t res, flux_integrand& f, const arb_t a, const arb_t b, const arf_t scale,
                     slong prec) {
    integrate_exact(res, f, arb_midref(a), arb_midref(b), scale, prec);
    for (int end = 0; end < 2; ++end) {
        const arb_struct* x = end == 0 ? a : b;
        if (mag_is_zero(arb_radref(x))) continue;
        acb_ball ball, fx;
        acb_set_arb(ball.x, x);
        flux_integrand_eval(fx.x, ball.x, &f, 0, prec);
        arb_ball width;
        mag_set(arb_radref(width.x), arb_radref(x));  // x - x0 in [-rad, rad]
        arb_mul(width.x, width.x, acb_realref(fx.x), prec);
        if (end == 0)
            arb_sub(res, res, width.x, prec);
        else
            arb_add(res, res, width.x, prec);
    }
}

/// Refines a block holding exactly one simple zero of K (a sign change and K' != 0 on it) to a
/// ball: a few bisections by the sign at the midpoint (arb_calc_refine_root_bisect), then the
/// interval Newton operator N(X) = m - K(m) / K'(X) (m the midpoint of X; the zero lies in X and
/// in N(X), so in their intersection) while it at least halves the radius.
bool refine_zero(arb_t root, curve_data& c, const arf_interval_t block, slong prec) {
    arf_interval_t narrow;
    arf_interval_init(narrow);
    const int status = arb_calc_refine_root_bisect(narrow, kinetic_real, &c, block, 40, prec);
    arb_ball x, m, n, fm;
    arf_interval_get_arb(x.x, status == ARB_CALC_SUCCESS ? narrow : block, prec);
    arf_interval_clear(narrow);
    arb_struct fx[2];
    arb_init(fx);
    arb_init(fx + 1);
    bool ok = true;
    for (int it = 0; it < prec; ++it) {
        arb_get_mid_arb(m.x, x.x);
        kinetic_real(fm.x, m.x, &c, 1, prec);
        kinetic_real(fx, x.x, &c, 2, prec);
        if (arb_contains_zero(fx + 1)) {
            ok = false;  // cannot happen on an isolating block
            break;
        }
        arb_div(n.x, fm.x, fx + 1, prec);
        arb_sub(n.x, m.x, n.x, prec);
        if (!arb_intersection(n.x, n.x, x.x, prec)) {
            ok = false;  // no zero in x: cannot happen on an isolating block
            break;
        }
        mag_t half;
        mag_init(half);
        mag_mul_2exp_si(half, arb_radref(x.x), -1);
        const bool halved = mag_cmp(arb_radref(n.x), half) <= 0;
        mag_clear(half);
        arb_swap(x.x, n.x);
        if (!halved) break;
    }
    arb_clear(fx);
    arb_clear(fx + 1);
    arb_set(root, x.x);
    return ok;
}

/// The zeros of K in [0, pi], each a ball around one simple zero, sorted; false when they cannot
/// be isolated (a double zero: E at a critical value of V along the curve) or K may vanish at the
/// ends.
bool zeros_of_kinetic(std::vector<arb_ball>& zeros, curve_data& c, slong prec) {
    arf_interval_t whole;
    arf_interval_init(whole);
    arf_zero(&whole->a);
    arb_get_lbound_arf(&whole->b, c.pi.x, prec);  // below pi; [pi_lo, pi] is checked below
    arf_interval_ptr blocks = nullptr;
    int* flags = nullptr;
    const slong n = arb_calc_isolate_roots(&blocks, &flags, kinetic_real, &c, whole, prec + 64,
                                           64 * prec + 10000, 64, prec);
    bool ok = true;
    for (slong i = 0; i < n && ok; ++i) {
        if (flags[i] != 1) {
            ok = false;
            break;
        }
        zeros.emplace_back();
        ok = refine_zero(zeros.back().x, c, blocks + i, prec);
    }
    _arf_interval_vec_clear(blocks, n);
    flint_free(flags);
    // K does not vanish on [pi_lo, pi] (nor at 0: E is not at the saddle energy)
    arb_ball tail, k;
    arb_set_arf(tail.x, &whole->b);
    arb_union(tail.x, tail.x, c.pi.x, prec);
    kinetic_real(k.x, tail.x, &c, 1, prec);
    ok = ok && !arb_contains_zero(k.x);
    arf_interval_clear(whole);
    std::sort(zeros.begin(), zeros.end(), [](const arb_ball& u, const arb_ball& v) {
        return arf_cmp(arb_midref(u.x), arb_midref(v.x)) < 0;
    });
    return ok;
}

/// int over [a, b] of sqrt(2 K Q), K > 0 inside; an end that is a zero of K is singular: the
/// pieces [a, a + U^2] and [b - U^2, b] are integrated in u (U^2 about a third of b - a, an exact
/// short dyadic), the rest in s.
void accessible_piece(arb_t res, curve_data& c, const arb_t a, bool a_zero, const arb_t b,
                      bool b_zero, slong prec) {
    arf_t scale, U, zero;
    arf_init(scale), arf_init(U), arf_init(zero);
    arb_ball len, t, lo, hi, part;
    arb_sub(len.x, b, a, prec);
    {  // the magnitude of the integral, for the absolute tolerance: (b - a) sqrt(2 K Q) at the
       // middle, or (b - a) sqrt(Q) sqrt(|K'| (b - a)) when that is small (a narrow piece)
        acb_ball m, k, q;
        arb_add(acb_realref(m.x), a, b, 64);
        arb_mul_2exp_si(acb_realref(m.x), acb_realref(m.x), -1);
        kinetic_complex(k.x, m.x, c, 64);
        normal_weight(q.x, m.x, c, 64);
        const double size =
            std::abs(mid_double(len.x)) *
            std::sqrt(std::abs(2 * mid_double(acb_realref(k.x)) * mid_double(acb_realref(q.x))));
        arf_set_d(scale, size > 0 && std::isfinite(size) ? size : 1.0);
    }
    arb_div_ui(t.x, len.x, 3, prec);
    arb_sqrt(t.x, t.x, prec);
    arf_set_round(U, arb_midref(t.x), 30, ARF_RND_DOWN);
    arb_set_arf(t.x, U);
    arb_sqr(t.x, t.x, prec);  // U^2
    arb_zero(res);
    arb_set(lo.x, a);
    arb_set(hi.x, b);
    flux_integrand f;
    f.c = &c;
    if (a_zero) {
        f.kind = piece::from_root;
        f.root = a;
        integrate_exact(part.x, f, zero, U, scale, prec);
        arb_add(res, res, part.x, prec);
        arb_add(lo.x, a, t.x, prec);
    }
    if (b_zero) {
        f.kind = piece::to_root;
        f.root = b;
        integrate_exact(part.x, f, zero, U, scale, prec);
        arb_add(res, res, part.x, prec);
        arb_sub(hi.x, b, t.x, prec);
    }
    f.kind = piece::plain;
    f.root = nullptr;
    integrate_balls(part.x, f, lo.x, hi.x, scale, prec);
    arb_add(res, res, part.x, prec);
    arf_clear(scale), arf_clear(U), arf_clear(zero);
}

/// f2 for an energy strictly on one side of E_s and of E_max (c.delta and c.above_max set).
void flux_decided(arb_t res, curve_data& c, slong prec) {
    std::vector<arb_ball> zeros;
    if (!zeros_of_kinetic(zeros, c, prec)) {
        arb_indeterminate(res);
        return;
    }
    // break points 0, the zeros, pi; the pieces where K > 0 (decided at an interior point)
    std::vector<arb_ball> ends(zeros.size() + 2);
    arb_zero(ends.front().x);
    for (std::size_t i = 0; i < zeros.size(); ++i)
        arb_set(ends[i + 1].x, zeros[i].x);
    arb_set(ends.back().x, c.pi.x);
    arb_zero(res);
    arb_ball inner, k, part;
    for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
        arb_add(inner.x, ends[i].x, ends[i + 1].x, prec);
        arb_mul_2exp_si(inner.x, inner.x, -1);
        arb_get_mid_arb(inner.x, inner.x);
        kinetic_real(k.x, inner.x, &c, 1, prec);
        if (arb_is_negative(k.x)) continue;
        if (!arb_is_positive(k.x)) {
            arb_indeterminate(res);
            return;
        }
        accessible_piece(part.x, c, ends[i].x, i > 0, ends[i + 1].x, i + 2 < ends.size(), prec);
        arb_add(res, res, part.x, prec);
    }
    arb_mul_ui(res, res, 8, prec);
}

/// True when w_f A^2 < w_s (proven on the balls). Then, at E = E_s, K = 2 sin^2(s/2) G(s) with
/// G = -w_s + w_f A^2 cos^2(s/2) sinc^2(A sin(s) / 2) <= -w_s + w_f A^2 < 0 on the real line: the
/// curve is inaccessible except at the saddle and f2(E_s) = 0. (w_s - w_f A^2 = x (M_ss - 2 C A +
/// M_ff A^2) > 0 for the centre mode, x > 0; the balls decide it unless it is below their radii.)
bool saddle_isolated(const curve_data& c, slong prec) {
    arb_ball g;
    arb_sqr(g.x, c.A.x, prec);
    arb_mul(g.x, g.x, c.wf.x, prec);
    return arb_lt(g.x, c.ws.x);
}

/// The union of f2 at exact energies 2^20 |K| 2^-prec below and above the exact kink K (f2 is
/// non-decreasing in E: it contains f2(K)).
void straddle_exact_kink(arb_t res, curve_data& c, const arb_t E, const arb_t e_s,
                         const arb_t e_max, slong prec) {
    arb_ball step, e, v_lo;
    arb_mul_2exp_si(step.x, E, 20 - prec);
    for (int side = 0; side < 2; ++side) {
        if (side == 0)
            arb_sub(e.x, E, step.x, prec);
        else
            arb_add(e.x, E, step.x, prec);
        arb_sub(c.delta.x, e.x, e_s, prec);
        arb_sub(c.above_max.x, e.x, e_max, prec);
        flux_decided(side == 0 ? v_lo.x : res, c, prec);
    }
    arb_union(res, res, v_lo.x, prec);
}

}  // namespace

void enclose_centre_mode_slope(arb_t res, const pendulum_balls& p, arm a, slong prec) {
    const bool two = a == arm::two;
    const arb_struct* ws = two ? p.alpha.x : p.beta.x;
    const arb_struct* wf = two ? p.beta.x : p.alpha.x;
    const arb_struct* Mss = two ? p.A.x : p.B.x;
    const arb_struct* Mff = two ? p.B.x : p.A.x;
    arb_ball b, root, x, t;
    arb_mul(b.x, ws, Mff, prec);  // b = w_s M_ff - w_f M_ss
    arb_mul(t.x, wf, Mss, prec);
    arb_sub(b.x, b.x, t.x, prec);
    arb_mul(root.x, ws, wf, prec);  // sqrt(b^2 + 4 D0 w_s w_f), a sum of non-negative terms
    arb_mul(root.x, root.x, p.D0.x, prec);
    arb_mul_2exp_si(root.x, root.x, 2);
    arb_addmul(root.x, b.x, b.x, prec);
    arb_sqrt(root.x, root.x, prec);
    if (arf_sgn(arb_midref(b.x)) >= 0) {  // x = (b + root) / (2 D0), no cancellation
        arb_add(x.x, b.x, root.x, prec);
        arb_div(x.x, x.x, p.D0.x, prec);
        arb_mul_2exp_si(x.x, x.x, -1);
    } else {  // x = 2 w_s w_f / (root - b), the same root written without cancellation
        arb_sub(t.x, root.x, b.x, prec);
        arb_mul(x.x, ws, wf, prec);
        arb_mul_2exp_si(x.x, x.x, 1);
        arb_div(x.x, x.x, t.x, prec);
    }
    arb_mul(t.x, x.x, Mff, prec);  // A = x C / (w_f + x M_ff)
    arb_add(t.x, t.x, wf, prec);
    arb_mul(res, x.x, p.C.x, prec);
    arb_div(res, res, t.x, prec);
}

namespace {

/// The approximate curve of arm a in the curve's coordinates (delta and above_max left unset).
void set_curve(curve_data& c, const pendulum_balls& p, arm a, slong prec) {
    const bool two = a == arm::two;
    arb_set(c.ws.x, two ? p.alpha.x : p.beta.x);
    arb_set(c.wf.x, two ? p.beta.x : p.alpha.x);
    arb_set(c.Mss.x, two ? p.A.x : p.B.x);
    arb_set(c.Mff.x, two ? p.B.x : p.A.x);
    arb_set(c.C.x, p.C.x);
    arb_const_pi(c.pi.x, prec);
    enclose_centre_mode_slope(c.A.x, p, a, prec);
}

}  // namespace

bool approximate_curve_above_saddle(const pendulum_balls& p, arm a, slong prec) {
    curve_data c;
    set_curve(c, p, a, prec);
    return saddle_isolated(c, prec);
}

void enclose_approximate_flux(arb_t res, const pendulum_balls& p, arm a, const arb_t E,
                              slong prec) {
    curve_data c;
    set_curve(c, p, a, prec);
    arb_ball e_s, e_max;
    arb_mul_2exp_si(e_s.x, c.wf.x, 1);
    arb_mul_2exp_si(e_max.x, c.ws.x, 1);
    arb_add(e_max.x, e_max.x, e_s.x, prec);
    monotone_enclosure(
        res,
        [&](arb_t out, const arb_t e) {
            const int vs_saddle = compare_energy(e, e_s.x), vs_max = compare_energy(e, e_max.x);
            if (vs_saddle == 0 && saddle_isolated(c, prec)) {  // exactly at the saddle energy
                arb_zero(out);
                return;
            }
            if (vs_saddle == 0 || vs_max == 0) {
                straddle_exact_kink(out, c, e, e_s.x, e_max.x, prec);
                return;
            }
            arb_sub(c.delta.x, e, e_s.x, prec);
            arb_sub(c.above_max.x, e, e_max.x, prec);
            flux_decided(out, c, prec);
        },
        E, {e_s.x, e_max.x}, prec);
}

}  // namespace flipflux::certified_detail
