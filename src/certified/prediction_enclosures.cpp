// Enclosures of Omega(E) and f1(E) (docs/certified.md has the derivations).
//
// Omega = 2 [ th_full 8 pi sqrt(D0) E(m) + 2 pi sqrt(D0) int_{th_full}^{th_edge} F(th1) dth1 ],
//     F(th1) = E(t2 + th1 | m) + E(t2 - th1 | m),   m = -C^2/D0,
// with t2(th1) the half-width of the allowed th2 interval (2 beta sin^2(t2/2) = E - 2 alpha
// sin^2(th1/2)); Omega = 16 pi^2 sqrt(D0) E(m) for E >= E_max. The integrand has square-root
// branch points at th_full (t2 = pi) and th_edge (t2 = 0); there th1 = th_full + u^2 and
// th1 = th_edge - u^2 make it holomorphic in u (the square roots are factored as u times the
// square root of a function that does not vanish), and the middle piece is integrated in th1.
// E(phi | m) is evaluated from sin phi and cos phi, reduced by k quarter periods to |x| <= pi/4:
//     k even: E(phi) = k E(m) + E(x | m),
//     k odd:  E(phi) = k E(m) + sqrt(1 - m) E(x | m / (m - 1)),
// each E(x | .) by Carlson's form s R_F(c^2, 1 - m s^2, 1) - (m/3) s^3 R_D(c^2, 1 - m s^2, 1),
// holomorphic while c^2 and 1 - m s^2 keep positive real parts (checked on every ball).
//
// f1 (either arm; J, w, E_s as in prediction/upright_flux.hpp, E_max = E_s + 2w, p = delta/(2w)):
//     E_s < E < E_max:  f1 = 32 sqrt(J w) [E(p) - (1 - p) K(p)]
//     E >= E_max:       f1 = 16 sqrt(2 J delta) E(2w / delta)
// Both Omega and f1 are non-decreasing in E: an energy ball that straddles a kink (a saddle
// energy, E_max) is enclosed by the union of the enclosures at two exact energies on either side.
#include "prediction_enclosures.hpp"

#include <acb_calc.h>
#include <acb_elliptic.h>
#include <arb_hypgeom.h>

#include <cmath>
#include <functional>
#include <vector>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/error.hpp"

namespace flipflux::certified_detail {

namespace {

/// A ball that avoids the branch cut (-inf, 0] of sqrt, log and Carlson's integrals: its real part
/// is positive.
bool right_half_plane(const acb_t z) {
    return arb_is_positive(acb_realref(z));
}

/// E(x | m) by Carlson's form from s = sin x, c = cos x (|Re x| < pi/2); false when a ball leaves
/// the region where the form is holomorphic (then res is undefined).
bool carlson_e(acb_t res, const acb_t s, const acb_t c, const arb_t m, slong prec) {
    acb_ball c2, delta, one, rf, rd, t;
    acb_sqr(c2.x, c, prec);
    acb_sqr(delta.x, s, prec);
    acb_mul_arb(delta.x, delta.x, m, prec);
    acb_sub_si(delta.x, delta.x, 1, prec);
    acb_neg(delta.x, delta.x);  // 1 - m s^2
    if (!right_half_plane(c) || !right_half_plane(c2.x) || !right_half_plane(delta.x)) return false;
    acb_one(one.x);
    acb_elliptic_rf(rf.x, c2.x, delta.x, one.x, 0, prec);
    acb_elliptic_rj(rd.x, c2.x, delta.x, one.x, one.x, 0, prec);  // R_D(x, y, 1) = R_J(x, y, 1, 1)
    acb_mul(res, s, rf.x, prec);
    acb_pow_ui(t.x, s, 3, prec);
    acb_mul(t.x, t.x, rd.x, prec);
    acb_mul_arb(t.x, t.x, m, prec);
    acb_div_ui(t.x, t.x, 3, prec);
    acb_sub(res, res, t.x, prec);
    return true;
}

/// g(V) = sqrt(1 - m sin^2 V) on a box V; false when 1 - m sin^2 leaves the right half-plane on V
/// (then g is not holomorphic there).
bool integrand_box(acb_t g, const acb_t v, const arb_t m, slong prec) {
    acb_sin(g, v, prec);
    acb_sqr(g, g, prec);
    acb_mul_arb(g, g, m, prec);
    acb_sub_si(g, g, 1, prec);
    acb_neg(g, g);
    if (!right_half_plane(g)) return false;
    acb_sqrt(g, g, prec);
    return true;
}

/// E(x | m), |Re x| < pi/2, on a wide ball (the ellipses of the error bounds), where Carlson's
/// duplication overflows. The mean-value form about the real c = mid(Re x) when the box X meets
/// the real axis there: E(x | m) = E(c | m) + int_c^x g(v) dv, g(v) = sqrt(1 - m sin^2 v), lies
/// in E(c | m) + (X - c) g(X) (X is convex and contains c, so every segment [c, x] lies in X, and
/// the rectangle g(X) contains g's mean over it; g holomorphic on X). Else the hull form
/// E(x | m) = x int_0^1 g(t x) dt in x g(V), V the rectangle hull of 0 and X. The mean-value
/// form is the tight one: the hull reaches |Im| = |Im x| at every real part down to 0, where
/// g's branch points are nearest the real axis (asinh(1/sqrt(-m)) away: 0.31 for m = -10, a
/// light upper arm, whose proofs took minutes with the hull form alone).
bool bounded_e(acb_t res, const acb_t x, const arb_t m, slong prec) {
    if (arb_contains_zero(acb_imagref(x))) {
        acb_ball c, s, co, ec, g, d;
        arb_set_arf(acb_realref(c.x), arb_midref(acb_realref(x)));
        acb_sin_cos(s.x, co.x, c.x, prec);
        if (carlson_e(ec.x, s.x, co.x, m, prec) && acb_is_finite(ec.x) &&
            integrand_box(g.x, x, m, prec)) {
            acb_sub(d.x, x, c.x, prec);
            acb_mul(d.x, d.x, g.x, prec);
            acb_add(res, ec.x, d.x, prec);
            return true;
        }
    }
    acb_ball zero, hull, g;
    acb_union(hull.x, zero.x, x, prec);
    if (!integrand_box(g.x, hull.x, m, prec)) return false;
    acb_mul(res, x, g.x, prec);
    return true;
}

/// E(x | m), |Re x| < pi/2: Carlson's form on narrow balls (order 0: the quadrature nodes), the
/// hull bound where that is not finite and on the ellipses of the error bounds (order 1).
bool reduced_e(acb_t res, const acb_t x, const arb_t m, slong order, slong prec) {
    if (order == 0) {
        acb_ball s, c;
        acb_sin_cos(s.x, c.x, x, prec);
        if (carlson_e(res, s.x, c.x, m, prec) && acb_is_finite(res)) return true;
    }
    return bounded_e(res, x, m, prec);
}

/// The constants of the phase-volume integrand.
struct volume_constants {
    arb_ball m, m_conj, sqrt_one_minus_m, complete_e;  // m = -C^2/D0, m/(m-1), sqrt(1-m), E(m)
    arb_ball half_pi;
};

/// E(phi | m) for a ball phi, reduced by q quarter periods (q = the nearest integer to
/// mid(phi)/(pi/2)) to x = phi - q pi/2 (see the file comment).
bool elliptic_e_of_angle(acb_t res, const acb_t phi, const volume_constants& k, slong order,
                         slong prec) {
    const double approx = arf_get_d(arb_midref(acb_realref(phi)), ARF_RND_NEAR);
    const long q = std::lround(approx / (M_PI / 2));
    acb_ball x;
    arb_ball shift;
    arb_mul_si(shift.x, k.half_pi.x, q, prec);
    acb_sub_arb(x.x, phi, shift.x, prec);
    arb_ball reach;  // |Re x| < pi/2: the reduced form is valid on the ball
    arb_abs(reach.x, acb_realref(x.x));
    if (!arb_lt(reach.x, k.half_pi.x)) return false;
    if (q % 2 == 0) {
        if (!reduced_e(res, x.x, k.m.x, order, prec)) return false;
    } else {
        if (!reduced_e(res, x.x, k.m_conj.x, order, prec)) return false;
        acb_mul_arb(res, res, k.sqrt_one_minus_m.x, prec);
    }
    arb_mul_si(shift.x, k.complete_e.x, q, prec);
    acb_add_arb(res, res, shift.x, prec);
    return true;
}

enum class piece { plain, from_full, to_edge };

struct volume_integrand {
    piece kind = piece::plain;
    const arb_struct* E = nullptr;
    const arb_struct* e_minus_two_alpha = nullptr;
    const arb_struct* two_beta_minus_e = nullptr;
    const arb_struct* e_max_minus_e = nullptr;
    const arb_struct* alpha = nullptr;
    const arb_struct* beta = nullptr;
    const arb_struct* anchor = nullptr;             // th_full (from_full) or th_edge (to_edge)
    const arb_struct* anchor_supplement = nullptr;  // pi - anchor, computed without cancellation
    bool anchor_is_kink = false;  // th_full = 0 or th_edge = pi exactly (E at a kink)
    const volume_constants* k = nullptr;
    /// the CPU-time budget (eval --max-seconds) ran out during the quadrature: the integrand
    /// returns zero from then on (so that Arb returns at once) and integrate_exact throws
    /// budget_exceeded
    bool spent = false;
};

double mid_double(const acb_t z) {
    return arf_get_d(arb_midref(acb_realref(z)), ARF_RND_NEAR);
}

/// z * sqrt(alpha sinc(z^2/2) sin(anchor +- z^2/2)), the square root of 2 alpha sin(z^2/2)
/// sin(anchor +- z^2/2) that is holomorphic at z = 0; at a kink (sin(anchor +- z^2/2) =
/// sin(z^2/2)) it is z^2 sinc(z^2/2) sqrt(alpha/2).
bool factored_root(acb_t res, const acb_t z, const volume_integrand& f, int sign, slong prec) {
    acb_ball h, sc, t;
    acb_sqr(h.x, z, prec);
    acb_mul_2exp_si(h.x, h.x, -1);  // z^2/2
    acb_sinc(sc.x, h.x, prec);
    if (f.anchor_is_kink) {
        arb_ball r;
        arb_mul_2exp_si(r.x, f.alpha, -1);
        arb_sqrt(r.x, r.x, prec);
        acb_sqr(t.x, z, prec);
        acb_mul(t.x, t.x, sc.x, prec);
        acb_mul_arb(res, t.x, r.x, prec);
        return true;
    }
    // sin(anchor +- h), or sin(supplement -+ h) past pi/2 (accurate where the anchor is near pi)
    const bool near_pi = arf_get_d(arb_midref(f.anchor), ARF_RND_NEAR) > M_PI / 2;
    acb_set_arb(t.x, near_pi ? f.anchor_supplement : f.anchor);
    if ((sign > 0) != near_pi)
        acb_add(t.x, t.x, h.x, prec);
    else
        acb_sub(t.x, t.x, h.x, prec);
    acb_sin(t.x, t.x, prec);
    acb_mul(t.x, t.x, sc.x, prec);
    acb_mul_arb(t.x, t.x, f.alpha, prec);
    if (!right_half_plane(t.x)) return false;
    acb_sqrt(t.x, t.x, prec);
    acb_mul(res, t.x, z, prec);
    return true;
}

/// The integrand F(th1(z)) dth1/dz of one piece (acb_calc_func_t).
int volume_integrand_eval(acb_ptr out, const acb_t z, void* param, slong order, slong prec) {
    auto& f = *static_cast<volume_integrand*>(param);
    if (budget_spent(f.spent)) {  // Arb finishes at once on a zero integrand; the result is
        acb_zero(out);            // discarded (integrate_exact throws)
        return 0;
    }
    acb_ball th, jac, rem, gap, s2, c2, t;
    // th1, the Jacobian, and sqrt(2 beta) sin(t2/2) (s2) and sqrt(2 beta) cos(t2/2) (c2)
    if (f.kind == piece::plain) {
        acb_set(th.x, z);
        acb_one(jac.x);
    } else {
        acb_sqr(th.x, z, prec);
        if (f.kind == piece::to_edge) acb_neg(th.x, th.x);
        acb_add_arb(th.x, th.x, f.anchor, prec);
        acb_mul_2exp_si(jac.x, z, 1);
    }
    // rem = E - 2 alpha sin^2(th/2) (= 2 beta sin^2(t2/2)), gap = 2 beta - rem, written without
    // cancellation: past pi/2, rem = (E - 2 alpha) + 2 alpha cos^2(th/2) and gap = (E_max - E) -
    // 2 alpha cos^2(th/2) (small near pi when E is near 2 alpha or E_max), else rem = E - 2 alpha
    // sin^2(th/2) and gap = (2 beta - E) + 2 alpha sin^2(th/2)
    {
        acb_ball sh, ch;
        acb_mul_2exp_si(t.x, th.x, -1);
        acb_sin_cos(sh.x, ch.x, t.x, prec);
        acb_sqr(sh.x, sh.x, prec);
        acb_mul_arb(sh.x, sh.x, f.alpha, prec);
        acb_mul_2exp_si(sh.x, sh.x, 1);  // 2 alpha sin^2(th/2)
        if (mid_double(th.x) > M_PI / 2) {
            acb_sqr(ch.x, ch.x, prec);
            acb_mul_arb(ch.x, ch.x, f.alpha, prec);
            acb_mul_2exp_si(ch.x, ch.x, 1);  // 2 alpha cos^2(th/2)
            acb_add_arb(rem.x, ch.x, f.e_minus_two_alpha, prec);
            acb_neg(gap.x, ch.x);
            acb_add_arb(gap.x, gap.x, f.e_max_minus_e, prec);
        } else {
            acb_set_arb(rem.x, f.E);
            acb_sub(rem.x, rem.x, sh.x, prec);
            acb_add_arb(gap.x, sh.x, f.two_beta_minus_e, prec);
        }
    }
    if (f.kind == piece::to_edge) {
        if (!factored_root(s2.x, z, f, -1, prec)) goto fail;
    } else {
        if (!right_half_plane(rem.x)) goto fail;
        acb_sqrt(s2.x, rem.x, prec);
    }
    if (f.kind == piece::from_full) {
        if (!factored_root(c2.x, z, f, +1, prec)) goto fail;
    } else {
        if (!right_half_plane(gap.x)) goto fail;
        acb_sqrt(c2.x, gap.x, prec);
    }
    {
        // t2 = 2 atan(s2/c2) or pi - 2 atan(c2/s2) (whichever ratio is smaller at the midpoint:
        // both are holomorphic where the ratio avoids the cuts +-i[1, inf))
        acb_ball ratio, t2, phi, ep, em;
        arb_ball im, pi;
        const bool small_t2 = std::abs(mid_double(s2.x)) <= std::abs(mid_double(c2.x));
        if (small_t2)
            acb_div(ratio.x, s2.x, c2.x, prec);
        else
            acb_div(ratio.x, c2.x, s2.x, prec);
        arb_abs(im.x, acb_imagref(ratio.x));
        arb_sub_ui(im.x, im.x, 1, prec);
        if (!arb_is_positive(acb_realref(ratio.x)) && !arb_is_negative(im.x)) goto fail;
        acb_atan(t2.x, ratio.x, prec);
        acb_mul_2exp_si(t2.x, t2.x, 1);
        if (!small_t2) {
            acb_neg(t2.x, t2.x);
            arb_mul_2exp_si(pi.x, f.k->half_pi.x, 1);
            acb_add_arb(t2.x, t2.x, pi.x, prec);
        }
        acb_add(phi.x, t2.x, th.x, prec);
        if (!elliptic_e_of_angle(ep.x, phi.x, *f.k, order, prec)) goto fail;
        acb_sub(phi.x, t2.x, th.x, prec);
        if (!elliptic_e_of_angle(em.x, phi.x, *f.k, order, prec)) goto fail;
        acb_add(out, ep.x, em.x, prec);
        acb_mul(out, out, jac.x, prec);
    }
    return 0;
fail:
    acb_indeterminate(out);
    return 0;
}

/// int_a^b f over a real segment with exact endpoints.
void integrate_exact(arb_t res, volume_integrand& f, const arf_t a, const arf_t b, slong prec) {
    acb_ball ca, cb, r;
    acb_zero(ca.x);
    acb_zero(cb.x);
    arb_set_arf(acb_realref(ca.x), a);
    arb_set_arf(acb_realref(cb.x), b);
    mag_t tol;
    mag_init(tol);
    mag_set_ui_2exp_si(tol, 1, -prec);
    acb_calc_integrate_opt_t opt;
    acb_calc_integrate_opt_init(opt);
    acb_calc_integrate(r.x, volume_integrand_eval, &f, ca.x, cb.x, prec, tol, opt, prec);
    mag_clear(tol);
    throw_if_spent(f.spent);
    arb_set(res, acb_realref(r.x));  // the integrand is real on the real segment
}

/// int_a^b f for ball endpoints: the integral between their midpoints plus (b - b0) f(b) -
/// (a - a0) f(a), f evaluated on the endpoint balls (each term encloses the integral over the
/// piece between the midpoint and the true endpoint).
void integrate_balls(arb_t res, volume_integrand& f, const arb_t a, const arb_t b, slong prec) {
    integrate_exact(res, f, arb_midref(a), arb_midref(b), prec);
    for (int end = 0; end < 2; ++end) {
        const arb_struct* x = end == 0 ? a : b;
        if (mag_is_zero(arb_radref(x))) continue;
        acb_ball ball, fx;
        acb_set_arb(ball.x, x);
        volume_integrand_eval(fx.x, ball.x, &f, 0, prec);
        arb_ball width;
        arb_zero(width.x);
        mag_set(arb_radref(width.x), arb_radref(x));  // x - x0 lies in [-rad, rad]
        arb_mul(width.x, width.x, acb_realref(fx.x), prec);
        if (end == 0)
            arb_sub(res, res, width.x, prec);
        else
            arb_add(res, res, width.x, prec);
    }
}

/// m = -C^2/D0 and the constants derived from it.
void make_volume_constants(volume_constants& k, const pendulum_balls& p, slong prec) {
    arb_ball c2;
    arb_sqr(c2.x, p.C.x, prec);
    arb_div(k.m.x, c2.x, p.D0.x, prec);
    arb_neg(k.m.x, k.m.x);
    arb_mul(k.m_conj.x, p.A.x, p.B.x, prec);
    arb_div(k.m_conj.x, c2.x, k.m_conj.x, prec);  // m/(m-1) = C^2/(A B)
    arb_mul(k.sqrt_one_minus_m.x, p.A.x, p.B.x, prec);
    arb_div(k.sqrt_one_minus_m.x, k.sqrt_one_minus_m.x, p.D0.x, prec);
    arb_sqrt(k.sqrt_one_minus_m.x, k.sqrt_one_minus_m.x, prec);  // 1 - m = A B / D0
    {
        acb_ball mm, e;
        acb_set_arb(mm.x, k.m.x);
        acb_elliptic_e(e.x, mm.x, prec);
        arb_set(k.complete_e.x, acb_realref(e.x));
    }
    arb_const_pi(k.half_pi.x, prec);
    arb_mul_2exp_si(k.half_pi.x, k.half_pi.x, -1);
}

/// The ends of the allowed th1 interval and their supplements (pi - angle): th_full (E >= 2 beta:
/// sin^2(th_full/2) = (E - 2 beta)/(2 alpha), else 0), th_edge (E <= 2 alpha: sin^2(th_edge/2) =
/// E/(2 alpha), else pi), the supplements from cos^2(th_full/2) = (E_max - E)/(2 alpha) and
/// cos^2(th_edge/2) = (2 alpha - E)/(2 alpha): each angle from the formula that does not cancel.
struct allowed_interval {
    arb_ball th_full, th_edge, psi_full, psi_edge;
};

allowed_interval allowed_interval_of(const pendulum_balls& p, const arb_t E, int vs_full,
                                     int vs_edge, const arb_t pi, slong prec) {
    allowed_interval r;
    arb_ball t, e_max;
    auto angle = [&](arb_t out, const arb_t numerator) {  // 2 asin(sqrt(numerator / (2 alpha)))
        arb_div(out, numerator, p.alpha.x, prec);
        arb_mul_2exp_si(out, out, -1);
        arb_sqrt(out, out, prec);
        arb_asin(out, out, prec);
        arb_mul_2exp_si(out, out, 1);
    };
    auto settle = [&](arb_t th, arb_t psi) {  // keep the smaller of th, pi - th; derive the other
        if (arf_cmp_si(arb_midref(th), 2) < 0)
            arb_sub(psi, pi, th, prec);
        else
            arb_sub(th, pi, psi, prec);
    };
    arb_add(e_max.x, p.alpha.x, p.beta.x, prec);
    arb_mul_2exp_si(e_max.x, e_max.x, 1);
    if (vs_full > 0) {
        arb_mul_2exp_si(t.x, p.beta.x, 1);
        arb_sub(t.x, E, t.x, prec);
        angle(r.th_full.x, t.x);
        arb_sub(t.x, e_max.x, E, prec);
        angle(r.psi_full.x, t.x);
        settle(r.th_full.x, r.psi_full.x);
    } else {
        arb_zero(r.th_full.x);
        arb_set(r.psi_full.x, pi);
    }
    if (vs_edge < 0) {
        angle(r.th_edge.x, E);
        arb_mul_2exp_si(t.x, p.alpha.x, 1);
        arb_sub(t.x, t.x, E, prec);
        angle(r.psi_edge.x, t.x);
        settle(r.th_edge.x, r.psi_edge.x);
    } else {
        arb_set(r.th_edge.x, pi);
        arb_zero(r.psi_edge.x);
    }
    return r;
}

/// The complete integrals E(m) and K(m) of m = 1 - q, with the complement q given (0 < q <= 1,
/// known to more relative digits than m near m = 1). For q >= 1/2 Arb's acb_elliptic_e/k of m;
/// for q < 1/2 Carlson's forms K = R_F(0, q, 1), E = 2 R_G(0, q, 1) (Arb's acb_elliptic_e loses
/// most digits near m = 1), E evaluated at the exact midpoint q0 of q and widened by
/// rad(q) max |dE/dq|, dE/dq = (K - E) / (2 m) bounded on the ball (mean value theorem: Arb's own
/// propagation of a radius through R_G near q = 0 is loose by many orders).
void complete_integrals(arb_t e, arb_t k, const arb_t q, slong prec) {
    acb_ball zero, one, qq, r;
    acb_one(one.x);
    acb_set_arb(qq.x, q);
    if (arf_cmp_2exp_si(arb_midref(q), -1) >= 0) {
        acb_sub(r.x, one.x, qq.x, prec);  // m
        acb_ball ee, kk;
        acb_elliptic_e(ee.x, r.x, prec);
        acb_elliptic_k(kk.x, r.x, prec);
        arb_set(e, acb_realref(ee.x));
        arb_set(k, acb_realref(kk.x));
        return;
    }
    acb_elliptic_rf(r.x, zero.x, qq.x, one.x, 0, prec);
    arb_set(k, acb_realref(r.x));
    acb_ball crude_e;
    acb_elliptic_rg(crude_e.x, zero.x, qq.x, one.x, 0, prec);
    acb_mul_2exp_si(crude_e.x, crude_e.x, 1);
    arb_ball slope, m;
    arb_sub(slope.x, k, acb_realref(crude_e.x), prec);
    arb_sub_ui(m.x, q, 1, prec);
    arb_neg(m.x, m.x);
    arb_mul_2exp_si(m.x, m.x, 1);
    arb_div(slope.x, slope.x, m.x, prec);  // dE/dq on the ball
    arb_abs(slope.x, slope.x);
    acb_zero(qq.x);
    arb_set_arf(acb_realref(qq.x), arb_midref(q));
    acb_elliptic_rg(r.x, zero.x, qq.x, one.x, 0, prec);
    acb_mul_2exp_si(r.x, r.x, 1);
    arb_set(e, acb_realref(r.x));
    arb_ball width;
    arb_zero(width.x);
    mag_set(arb_radref(width.x), arb_radref(q));
    arb_mul(width.x, width.x, slope.x, prec);
    arb_add(e, e, width.x, prec);
}

/// Omega for an energy whose position relative to 2 alpha, 2 beta and E_max is decided.
void phase_volume_decided(arb_t res, const pendulum_balls& p, const arb_t E, int vs_full,
                          int vs_edge, int vs_max, slong prec) {
    volume_constants k;
    make_volume_constants(k, p, prec);
    arb_ball root_d0, pi;
    arb_sqrt(root_d0.x, p.D0.x, prec);
    arb_const_pi(pi.x, prec);
    if (vs_max >= 0) {  // E >= E_max: 16 pi^2 sqrt(D0) E(m)
        arb_sqr(res, pi.x, prec);
        arb_mul_ui(res, res, 16, prec);
        arb_mul(res, res, root_d0.x, prec);
        arb_mul(res, res, k.complete_e.x, prec);
        return;
    }
    const allowed_interval ends = allowed_interval_of(p, E, vs_full, vs_edge, pi.x, prec);
    arb_ball t, e_max;
    arb_add(e_max.x, p.alpha.x, p.beta.x, prec);
    arb_mul_2exp_si(e_max.x, e_max.x, 1);
    const bool singular_left = vs_full >= 0, singular_right = vs_edge <= 0;
    arb_ball e_minus_two_alpha, two_beta_minus_e;
    arb_mul_2exp_si(t.x, p.alpha.x, 1);
    arb_sub(e_minus_two_alpha.x, E, t.x, prec);
    arb_mul_2exp_si(t.x, p.beta.x, 1);
    arb_sub(two_beta_minus_e.x, t.x, E, prec);
    volume_integrand base;
    base.E = E;
    base.e_minus_two_alpha = e_minus_two_alpha.x;
    base.two_beta_minus_e = two_beta_minus_e.x;
    arb_ball e_max_minus_e;
    arb_sub(e_max_minus_e.x, e_max.x, E, prec);
    base.e_max_minus_e = e_max_minus_e.x;
    base.alpha = p.alpha.x;
    base.beta = p.beta.x;
    base.k = &k;
    // u-pieces of length about a third of [th_full, th_edge] at each singular end
    arb_ball span, u;
    arb_sub(span.x, ends.th_edge.x, ends.th_full.x, prec);
    arb_div_ui(u.x, span.x, 3, prec);
    arb_sqrt(u.x, u.x, prec);
    arf_t U, zero;
    arf_init(U);
    arf_init(zero);
    arf_set_round(U, arb_midref(u.x), 30, ARF_RND_DOWN);  // an exact short dyadic
    arb_ball integral, piece_value, a, b;
    arb_zero(integral.x);
    arb_set(a.x, ends.th_full.x);
    arb_set(b.x, ends.th_edge.x);
    // the u-piece at a singular end, th1 = anchor +- u^2 for u in [0, U]; that end moves to
    // anchor +- U^2 for the plain piece
    const auto add_end_piece = [&](piece kind, const arb_ball& anchor, const arb_ball& supplement,
                                   bool kink, arb_ball& end) {
        volume_integrand f = base;
        f.kind = kind;
        f.anchor = anchor.x;
        f.anchor_supplement = supplement.x;
        f.anchor_is_kink = kink;
        integrate_exact(piece_value.x, f, zero, U, prec);
        arb_add(integral.x, integral.x, piece_value.x, prec);
        arb_set_arf(t.x, U);
        arb_sqr(t.x, t.x, prec);
        if (kind == piece::from_full)
            arb_add(end.x, anchor.x, t.x, prec);
        else
            arb_sub(end.x, anchor.x, t.x, prec);
    };
    if (singular_left)
        add_end_piece(piece::from_full, ends.th_full, ends.psi_full, vs_full == 0, a);
    if (singular_right) add_end_piece(piece::to_edge, ends.th_edge, ends.psi_edge, vs_edge == 0, b);
    {
        volume_integrand f = base;
        f.kind = piece::plain;
        integrate_balls(piece_value.x, f, a.x, b.x, prec);
        arb_add(integral.x, integral.x, piece_value.x, prec);
    }
    arf_clear(U);
    arf_clear(zero);
    // Omega = 4 pi sqrt(D0) [4 th_full E(m) + int F]
    arb_mul(t.x, ends.th_full.x, k.complete_e.x, prec);
    arb_mul_2exp_si(t.x, t.x, 2);
    arb_add(res, integral.x, t.x, prec);
    arb_mul(res, res, pi.x, prec);
    arb_mul(res, res, root_d0.x, prec);
    arb_mul_2exp_si(res, res, 2);
}

}  // namespace

void enclose_phase_volume(arb_t res, const pendulum_balls& p, const arb_t E, slong prec) {
    arb_ball two_alpha, two_beta, e_max;
    arb_mul_2exp_si(two_alpha.x, p.alpha.x, 1);
    arb_mul_2exp_si(two_beta.x, p.beta.x, 1);
    arb_add(e_max.x, two_alpha.x, two_beta.x, prec);
    monotone_enclosure(
        res,
        [&](arb_t out, const arb_t e) {
            phase_volume_decided(out, p, e, compare_energy(e, two_beta.x),
                                 compare_energy(e, two_alpha.x), compare_energy(e, e_max.x), prec);
        },
        E, {two_alpha.x, two_beta.x, e_max.x}, prec);
}

void enclose_upright_flux(arb_t res, const pendulum_balls& p, arm a, const arb_t E, slong prec) {
    // (J, w, E_s): arm 2 (A, alpha, 2 beta), arm 1 (B, beta, 2 alpha)
    const arb_struct* J = a == arm::two ? p.A.x : p.B.x;
    const arb_struct* w = a == arm::two ? p.alpha.x : p.beta.x;
    arb_ball e_s, e_max;
    arb_mul_2exp_si(e_s.x, a == arm::two ? p.beta.x : p.alpha.x, 1);
    arb_mul_2exp_si(e_max.x, w, 1);
    arb_add(e_max.x, e_max.x, e_s.x, prec);
    monotone_enclosure(
        res,
        [&](arb_t out, const arb_t e) {
            const int vs_saddle = compare_energy(e, e_s.x), vs_max = compare_energy(e, e_max.x);
            if (vs_saddle <= 0) {
                arb_zero(out);
                return;
            }
            arb_ball delta, two_w, t;
            arb_sub(delta.x, e, e_s.x, prec);
            arb_mul_2exp_si(two_w.x, w, 1);
            arb_ball ek, kk, q;
            if (vs_max >= 0) {  // 16 sqrt(2 J delta) E(2w/delta), 1 - 2w/delta = (E - E_max)/delta
                if (vs_max == 0) {
                    arb_one(ek.x);  // E(1) = 1
                } else {
                    arb_sub(q.x, e, e_max.x, prec);
                    arb_div(q.x, q.x, delta.x, prec);
                    complete_integrals(ek.x, kk.x, q.x, prec);
                }
                arb_mul(t.x, J, delta.x, prec);
                arb_mul_2exp_si(t.x, t.x, 1);
                arb_sqrt(t.x, t.x, prec);
                arb_mul(out, t.x, ek.x, prec);
                arb_mul_ui(out, out, 16, prec);
                return;
            }
            // 32 sqrt(J w) [E(p) - (1 - p) K(p)], p = delta/(2w), 1 - p = (E_max - E)/(2w)
            arb_sub(q.x, e_max.x, e, prec);
            arb_div(q.x, q.x, two_w.x, prec);
            complete_integrals(ek.x, kk.x, q.x, prec);
            arb_mul(t.x, q.x, kk.x, prec);
            arb_sub(out, ek.x, t.x, prec);
            arb_mul(t.x, J, w, prec);
            arb_sqrt(t.x, t.x, prec);
            arb_mul(out, out, t.x, prec);
            arb_mul_ui(out, out, 32, prec);
        },
        E, {e_s.x, e_max.x}, prec);
}

}  // namespace flipflux::certified_detail
