// Computer-assisted proofs of the saddle orbits: the ball vector field, the Krawczyk test on the
// symmetric shooting map and the enclosures of T, F and the monodromy's trace
// (saddle_orbit_proof.hpp; docs/certified.md#saddle-orbits-proven).
#include "saddle_orbit_proof.hpp"

#include <arb_mat.h>

#include <array>
#include <chrono>
#include <cmath>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux::certified_detail {

// ---- the vector field ---------------------------------------------------------------------------

saddle_ball_field::saddle_ball_field(const pendulum_balls& p, arm a, int columns, slong prec)
    : columns_(columns) {
    arb_set(A_.x, p.A.x);
    arb_set(B_.x, p.B.x);
    arb_set(C_.x, p.C.x);
    arb_neg(minus_C_.x, p.C.x);
    arb_sqr(C2_.x, p.C.x, prec);
    arb_mul_2exp_si(two_C2_.x, C2_.x, 1);
    arb_set(D0_.x, p.D0.x);
    // e1 = cos q*_1, e2 = cos q*_2: (1, -1) at arm 2's saddle (0, pi), (-1, 1) at arm 1's
    const int e1 = a == arm::two ? 1 : -1;
    arb_mul_si(e1alpha_.x, p.alpha.x, e1, prec);
    arb_mul_si(e2beta_.x, p.beta.x, -e1, prec);
}

void saddle_ball_field::reserve(slong order) {
    if (order <= reserved_) return;
    reserved_ = order;
    const slong n = order + 1;
    sd_ = series::sin_cos(order);
    s1_ = series::sin_cos(order);
    s2_ = series::sin_cos(order);
    for (ball_vector* v : {&one_, &d_,   &ss_,  &det_, &cc_,  &n1_,  &n2_, &w1_,   &w2_,
                           &ww_,  &p_,   &inv_, &i11_, &i12_, &i22_, &sc_, &ddet_, &nd1_,
                           &nd2_, &dw1_, &dw2_, &dww_, &pd_,  &b_,   &cq_, &pl1_,  &pl2_})
        *v = ball_vector(n);
    arb_one(one_[0]);
    dphi_.assign(static_cast<std::size_t>(columns_), ball_vector(n));
}

void saddle_ball_field::coefficient(const ball_jet& x, slong k, arb_ptr out, slong prec) {
    using series::add_product;
    using series::product;
    arb_srcptr d1 = x.series(0), d2 = x.series(1), l1 = x.series(2), l2 = x.series(3);
    arb_sub(d_[k], d1 + k, d2 + k, prec);
    sd_.next(d_.data(), k, prec);
    s1_.next(d1, k, prec);
    s2_.next(d2, k, prec);
    // det = D0 + C^2 sin^2 d, w = M^-1 l = (B l1 + C c l2, C c l1 + A l2) / det
    product(ss_[k], sd_.s.data(), sd_.s.data(), k, prec);
    arb_mul(det_[k], C2_.x, ss_[k], prec);
    if (k == 0) arb_add(det_[0], det_[0], D0_.x, prec);
    arb_mul(cc_[k], C_.x, sd_.c[k], prec);
    product(n1_[k], cc_.data(), l2, k, prec);
    arb_addmul(n1_[k], B_.x, l1 + k, prec);
    product(n2_[k], cc_.data(), l1, k, prec);
    arb_addmul(n2_[k], A_.x, l2 + k, prec);
    series::quotient(w1_.data(), n1_.data(), det_.data(), k, prec);
    series::quotient(w2_.data(), n2_.data(), det_.data(), k, prec);
    // P = -C sin(d) w1 w2
    product(ww_[k], w1_.data(), w2_.data(), k, prec);
    product(p_[k], sd_.s.data(), ww_.data(), k, prec);
    arb_mul(p_[k], p_[k], minus_C_.x, prec);
    arb_set(out + 0, w1_[k]);
    arb_set(out + 1, w2_[k]);
    arb_mul(out + 2, e1alpha_.x, s1_.s[k], prec);  // l1' = -P - e1 alpha sin delta1
    arb_add(out + 2, out + 2, p_[k], prec);
    arb_neg(out + 2, out + 2);
    arb_mul(out + 3, e2beta_.x, s2_.s[k], prec);  // l2' = P - e2 beta sin delta2
    arb_sub(out + 3, p_[k], out + 3, prec);
    product(out + 4, w1_.data(), l1, k, prec);  // action' = l.w
    add_product(out + 4, w2_.data(), l2, k, prec);
    if (columns_ > 0) variational(x, k, out, prec);
}

void saddle_ball_field::variational(const ball_jet& x, slong k, arb_ptr out, slong prec) {
    using series::add_product;
    using series::product;
    arb_srcptr l1 = x.series(2), l2 = x.series(3);
    // the inverse mass matrix i = (B, C c, A) / det
    series::quotient(inv_.data(), one_.data(), det_.data(), k, prec);
    arb_mul(i11_[k], B_.x, inv_[k], prec);
    arb_mul(i22_[k], A_.x, inv_[k], prec);
    product(i12_[k], cc_.data(), inv_.data(), k, prec);
    // along d at fixed l: det' = 2 C^2 s c, dw1 = (-C s l2 - w1 det') / det, dw2 likewise
    product(sc_[k], sd_.s.data(), sd_.c.data(), k, prec);
    arb_mul(ddet_[k], two_C2_.x, sc_[k], prec);
    product(nd1_[k], sd_.s.data(), l2, k, prec);
    arb_mul(nd1_[k], nd1_[k], minus_C_.x, prec);
    arb_ball t;
    product(t.x, w1_.data(), ddet_.data(), k, prec);
    arb_sub(nd1_[k], nd1_[k], t.x, prec);
    product(nd2_[k], sd_.s.data(), l1, k, prec);
    arb_mul(nd2_[k], nd2_[k], minus_C_.x, prec);
    product(t.x, w2_.data(), ddet_.data(), k, prec);
    arb_sub(nd2_[k], nd2_[k], t.x, prec);
    series::quotient(dw1_.data(), nd1_.data(), det_.data(), k, prec);
    series::quotient(dw2_.data(), nd2_.data(), det_.data(), k, prec);
    // P_d = -C (c w1 w2 + s (dw1 w2 + w1 dw2)), P_l1 = -C s (i11 w2 + w1 i12),
    // P_l2 = -C s (i12 w2 + w1 i22)
    product(dww_[k], dw1_.data(), w2_.data(), k, prec);
    add_product(dww_[k], w1_.data(), dw2_.data(), k, prec);
    product(pd_[k], sd_.c.data(), ww_.data(), k, prec);
    add_product(pd_[k], sd_.s.data(), dww_.data(), k, prec);
    arb_mul(pd_[k], pd_[k], minus_C_.x, prec);
    product(b_[k], i11_.data(), w2_.data(), k, prec);
    add_product(b_[k], w1_.data(), i12_.data(), k, prec);
    product(pl1_[k], sd_.s.data(), b_.data(), k, prec);
    arb_mul(pl1_[k], pl1_[k], minus_C_.x, prec);
    product(cq_[k], i12_.data(), w2_.data(), k, prec);
    add_product(cq_[k], w1_.data(), i22_.data(), k, prec);
    product(pl2_[k], sd_.s.data(), cq_.data(), k, prec);
    arb_mul(pl2_[k], pl2_[k], minus_C_.x, prec);
    for (int col = 0; col < columns_; ++col) {
        const slong base = 5 + 5 * col;
        arb_srcptr v0 = x.series(base), v1 = x.series(base + 1), v2 = x.series(base + 2),
                   v3 = x.series(base + 3);
        ball_vector& D = dphi_[static_cast<std::size_t>(col)];
        arb_sub(D[k], v0 + k, v1 + k, prec);
        arb_ptr r = out + base;
        // v0' = dw1 D + i11 v2 + i12 v3,  v1' = dw2 D + i12 v2 + i22 v3
        product(r + 0, dw1_.data(), D.data(), k, prec);
        add_product(r + 0, i11_.data(), v2, k, prec);
        add_product(r + 0, i12_.data(), v3, k, prec);
        product(r + 1, dw2_.data(), D.data(), k, prec);
        add_product(r + 1, i12_.data(), v2, k, prec);
        add_product(r + 1, i22_.data(), v3, k, prec);
        // Q = P_d D + P_l1 v2 + P_l2 v3; v2' = -Q - e1 alpha c1 v0, v3' = Q - e2 beta c2 v1
        arb_ball q;
        product(q.x, pd_.data(), D.data(), k, prec);
        add_product(q.x, pl1_.data(), v2, k, prec);
        add_product(q.x, pl2_.data(), v3, k, prec);
        product(t.x, s1_.c.data(), v0, k, prec);
        arb_mul(r + 2, e1alpha_.x, t.x, prec);
        arb_add(r + 2, r + 2, q.x, prec);
        arb_neg(r + 2, r + 2);
        product(t.x, s2_.c.data(), v1, k, prec);
        arb_mul(r + 3, e2beta_.x, t.x, prec);
        arb_sub(r + 3, q.x, r + 3, prec);
        // the action's tangent: grad(l.w) . v = 2 (P D + w1 v2 + w2 v3)
        product(r + 4, p_.data(), D.data(), k, prec);
        add_product(r + 4, w1_.data(), v2, k, prec);
        add_product(r + 4, w2_.data(), v3, k, prec);
        arb_mul_2exp_si(r + 4, r + 4, 1);
    }
}

// ---- the start and the centre -------------------------------------------------------------------

namespace {

/// sqrt(2 (E - E_s)) S with S = M*^(1/2) = (M* + sqrt(D0) I) / sqrt(A + B + 2 sqrt(D0)),
/// M* = [[A, -C], [-C, B]]: the rows (sxx, sxy), (sxy, syy) scaled.
struct start_map {
    arb_ball sxx, sxy, syy;
};

start_map start_matrix(const pendulum_balls& p, arm a, const arb_t E, slong prec) {
    arb_ball es, excess, m, r, n;
    arb_mul_2exp_si(es.x, a == arm::two ? p.beta.x : p.alpha.x, 1);
    arb_sub(excess.x, E, es.x, prec);
    if (!arb_is_positive(excess.x))
        throw certification_error("the energy is not proven above the saddle energy");
    arb_mul_2exp_si(m.x, excess.x, 1);
    arb_sqrt(m.x, m.x, prec);
    arb_sqrt(r.x, p.D0.x, prec);
    arb_mul_2exp_si(n.x, r.x, 1);
    arb_add(n.x, n.x, p.A.x, prec);
    arb_add(n.x, n.x, p.B.x, prec);
    arb_sqrt(n.x, n.x, prec);
    arb_div(m.x, m.x, n.x, prec);
    start_map s;
    arb_add(s.sxx.x, p.A.x, r.x, prec);
    arb_mul(s.sxx.x, s.sxx.x, m.x, prec);
    arb_mul(s.sxy.x, p.C.x, m.x, prec);
    arb_neg(s.sxy.x, s.sxy.x);
    arb_add(s.syy.x, p.B.x, r.x, prec);
    arb_mul(s.syy.x, s.syy.x, m.x, prec);
    return s;
}

/// l0(beta) = m S (cos, sin) and dl0/dbeta = m S (-sin, cos).
void start_momentum(const start_map& s, const arb_t beta, arb_ptr l, arb_ptr dl, slong prec) {
    arb_ball c, sn;
    arb_sin_cos(sn.x, c.x, beta, prec);
    arb_mul(l + 0, s.sxx.x, c.x, prec);
    arb_addmul(l + 0, s.sxy.x, sn.x, prec);
    arb_mul(l + 1, s.sxy.x, c.x, prec);
    arb_addmul(l + 1, s.syy.x, sn.x, prec);
    arb_mul(dl + 0, s.sxy.x, c.x, prec);
    arb_submul(dl + 0, s.sxx.x, sn.x, prec);
    arb_mul(dl + 1, s.syy.x, c.x, prec);
    arb_submul(dl + 1, s.sxy.x, sn.x, prec);
}

}  // namespace

ball_vector saddle_start(const pendulum_balls& p, arm a, const arb_t energy, const arb_t beta,
                         int columns, slong prec) {
    ball_vector y(5 + 5 * columns);  // zero
    ball_vector dl(2);
    start_momentum(start_matrix(p, a, energy, prec), beta, y[2], dl.data(), prec);
    if (columns == 1) {
        arb_set(y[5 + 2], dl[0]);
        arb_set(y[5 + 3], dl[1]);
    } else {
        for (int c = 0; c < columns && c < 4; ++c)
            arb_one(y[5 + 5 * c + c]);
    }
    return y;
}

orbit_centre saddle_orbit_centre(const model_text& model, arm a, const std::string& energy,
                                 int digits) {
    const precision_scope scope(mp_precision(digits));
    const double_pendulum<mp> pendulum = make_model<mp>(model);
    const energy_level<mp> level = parse_energy_level<mp>(energy, "energy");
    check_orbit_energy(pendulum, a, level);
    const saddle_orbit<mp> o = find_or_solve_saddle_orbit(pendulum, a, level, orbit_options<mp>{});
    if (o.status == orbit_status::not_converged)
        throw certification_error(
            "saddle orbit at E = " + energy + " (arm " + to_string(a) +
            "): the non-rigorous orbit (the proof's centre) did not converge");
    const int shown = mp_working_digits(digits) + 2;
    return {to_decimal(o.beta, shown), to_decimal(mp(o.period / 4), shown)};
}

// ---- the proof ----------------------------------------------------------------------------------

namespace {

/// The vector field's value (coefficient 0) at the state y.
ball_vector field_at(saddle_ball_field& f, arb_srcptr y, slong prec) {
    f.reserve(1);
    ball_jet jet(f.dimension(), 0);
    for (slong i = 0; i < f.dimension(); ++i)
        arb_set(jet.series(i), y + i);
    ball_vector out(f.dimension());
    f.coefficient(jet, 0, out.data(), prec);
    return out;
}

/// Exact midpoint of the decimal text at prec bits.
void exact_midpoint(arb_t out, const std::string& text, const char* what, slong prec) {
    if (arb_set_str(out, text.c_str(), prec) != 0 || !arb_is_finite(out))
        throw certification_error(std::string("the orbit's ") + what + " '" + text +
                                  "' is not a decimal number");
    mag_zero(arb_radref(out));
}

/// tr N^2 for N = R Phi^-1 R Phi, Phi^-1 = -J Phi^T J (R = diag(1, 1, -1, -1),
/// J = [[0, I], [-I, 0]]): the monodromy's trace from the quarter period's Phi.
void monodromy_trace(arb_t res, const arb_mat_t phi, slong prec) {
    arb_mat_t J, R, t, inv, n;
    arb_mat_init(J, 4, 4), arb_mat_init(R, 4, 4), arb_mat_init(t, 4, 4);
    arb_mat_init(inv, 4, 4), arb_mat_init(n, 4, 4);
    for (int i = 0; i < 2; ++i) {
        arb_one(arb_mat_entry(J, i, i + 2));
        arb_set_si(arb_mat_entry(J, i + 2, i), -1);
        arb_one(arb_mat_entry(R, i, i));
        arb_set_si(arb_mat_entry(R, i + 2, i + 2), -1);
    }
    arb_mat_transpose(t, phi);
    arb_mat_mul(inv, J, t, prec);
    arb_mat_mul(inv, inv, J, prec);
    arb_mat_neg(inv, inv);
    arb_mat_mul(n, R, inv, prec);
    arb_mat_mul(n, n, R, prec);
    arb_mat_mul(n, n, phi, prec);
    arb_mat_sqr(t, n, prec);
    arb_mat_trace(res, t, prec);
    arb_mat_clear(J), arb_mat_clear(R), arb_mat_clear(t), arb_mat_clear(inv), arb_mat_clear(n);
}

}  // namespace

namespace {

/// An owned Arb matrix.
struct ball_matrix {
    arb_mat_t m;
    ball_matrix(slong r, slong c) { arb_mat_init(m, r, c); }
    ball_matrix(const ball_matrix&) = delete;
    ball_matrix& operator=(const ball_matrix&) = delete;
    ~ball_matrix() { arb_mat_clear(m); }
    arb_ptr operator()(slong i, slong j) { return arb_mat_entry(m, i, j); }
};

/// max(1, |x|) 10^-digits, rounded up to an exact 30-bit number.
void box_radius(arb_t r, const arb_t x, int digits, slong prec) {
    arb_ball ten, one;
    arb_one(one.x);
    arb_set_ui(ten.x, 10);
    arb_pow_ui(ten.x, ten.x, static_cast<ulong>(digits), prec);
    arb_abs(r, x);
    arb_max(r, r, one.x, prec);
    arb_div(r, r, ten.x, prec);
    arf_t u;
    arf_init(u);
    arb_get_ubound_arf(u, r, 30);
    arb_set_arf(r, u);
    arf_clear(u);
}

/// What the point z^ gives: G(z^) = (y2, y3), a(z^) = y4 and Y = mid(G'(z^))^-1.
struct centre_shot {
    ball_vector y;
    ball_matrix Y{2, 2};
    bool invertible = false;
};

/// The Krawczyk test on the box z^ +/- (rb, rt) (exact radii); true and `out` filled when K(X)
/// lies in the interior of X.
bool krawczyk_test(const orbit_proof_input& in, const arb_t bh, const arb_t th,
                   const centre_shot& c, const arb_t rb, const arb_t rt, bool monodromy,
                   slong order, slong prec, orbit_proof& out) {
    const pendulum_balls& p = in.pendulum;
    const arm a = in.flip_arm;
    arb_ball Xb, Xt;
    arb_set(Xb.x, bh);
    arb_add_error(Xb.x, rb);
    arb_set(Xt.x, th);
    arb_add_error(Xt.x, rt);
    // G'(X) = [[dl1/dbeta, l1'], [dl2/dbeta, l2']] over the box, from one integration of the
    // state, the action and the tangents over every start in X for every duration in X_tau
    const int columns = monodromy ? 4 : 1;
    saddle_ball_field wide(p, a, columns, prec);
    ball_vector yb = saddle_start(p, a, in.energy.x, Xb.x, columns, prec);
    rigorous_statistics sb;
    if (!integrate_rigorous(wide, yb.data(), Xt.x, order, prec, &sb))
        throw certification_error(
            "the rigorous integration over the box around the orbit failed "
            "at E = " +
            in.energy_text);
    out.steps_box = sb.steps;
    ball_vector fb = field_at(wide, yb.data(), prec);
    ball_matrix GX(2, 2);
    arb_ball dadb;  // d action / d beta over X
    if (columns == 1) {
        arb_set(GX(0, 0), yb[5 + 2]);
        arb_set(GX(1, 0), yb[5 + 3]);
        arb_set(dadb.x, yb[5 + 4]);
    } else {
        ball_vector l(2), dl(2);
        start_momentum(start_matrix(p, a, in.energy.x, prec), Xb.x, l.data(), dl.data(), prec);
        for (int i = 0; i < 2; ++i) {  // Phi's momentum columns 2, 3 times dl0/dbeta
            arb_mul(GX(i, 0), yb[5 + 5 * 2 + 2 + i], dl[0], prec);
            arb_addmul(GX(i, 0), yb[5 + 5 * 3 + 2 + i], dl[1], prec);
        }
        arb_mul(dadb.x, yb[5 + 5 * 2 + 4], dl[0], prec);
        arb_addmul(dadb.x, yb[5 + 5 * 3 + 4], dl[1], prec);
    }
    arb_set(GX(0, 1), fb[2]);
    arb_set(GX(1, 1), fb[3]);
    // K(X) - z^ = -Y G(z^) + (I - Y G'(X)) (X - z^)
    ball_matrix G(2, 1), YG(2, 1), dX(2, 1), K(2, 1), M(2, 2);
    arb_set(G(0, 0), c.y[2]);
    arb_set(G(1, 0), c.y[3]);
    arb_mat_mul(YG.m, c.Y.m, G.m, prec);
    arb_mat_mul(M.m, c.Y.m, GX.m, prec);
    arb_mat_neg(M.m, M.m);
    for (int i = 0; i < 2; ++i)
        arb_add_ui(M(i, i), M(i, i), 1, prec);
    arb_add_error(dX(0, 0), rb);
    arb_add_error(dX(1, 0), rt);
    arb_mat_mul(K.m, M.m, dX.m, prec);
    arb_mat_sub(K.m, K.m, YG.m, prec);
    for (int i = 0; i < 2; ++i) {
        arb_ball d;
        arb_abs(d.x, K(i, 0));
        if (!arb_is_finite(d.x) || !arb_lt(d.x, i == 0 ? rb : rt)) return false;
    }
    arb_add(out.beta.x, bh, K(0, 0), prec);
    arb_add(out.quarter.x, th, K(1, 0), prec);
    arb_mul_2exp_si(out.period.x, out.quarter.x, 2);
    // F = 4 (a(z^) + da/dbeta (beta* - b^) + da/dtau (tau* - t^)), da/dtau = l.w at the end
    arb_mul(out.action.x, dadb.x, K(0, 0), prec);
    arb_addmul(out.action.x, fb[4], K(1, 0), prec);
    arb_add(out.action.x, out.action.x, c.y[4], prec);
    arb_mul_2exp_si(out.action.x, out.action.x, 2);
    if (monodromy) {
        ball_matrix phi(4, 4);
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                arb_set(phi(i, j), yb[5 + 5 * j + i]);
        monodromy_trace(out.trace.x, phi.m, prec);
        arb_sub_ui(out.stability_index.x, out.trace.x, 2, prec);
    }
    return true;
}

}  // namespace

orbit_proof prove_saddle_orbit(const orbit_proof_input& in, slong prec, bool monodromy) {
    const auto start = std::chrono::steady_clock::now();
    const pendulum_balls& p = in.pendulum;
    const arm a = in.flip_arm;
    const std::string where = "E = " + in.energy_text + " (arm " + to_string(a) + ")";
    const slong order = rigorous_order_for(prec);
    orbit_proof out;
    out.with_monodromy = monodromy;
    arb_ball bh, th;  // the centre z^, exact
    exact_midpoint(bh.x, in.centre.beta, "beta", prec);
    exact_midpoint(th.x, in.centre.quarter, "quarter period", prec);
    if (!arb_is_positive(th.x))
        throw certification_error("the orbit's quarter period at " + where + " is not positive");

    // G(z^), a(z^) and the tangent along beta from the point z^
    centre_shot c;
    saddle_ball_field thin(p, a, 1, prec);
    c.y = saddle_start(p, a, in.energy.x, bh.x, 1, prec);
    rigorous_statistics st;
    if (!integrate_rigorous(thin, c.y.data(), th.x, order, prec, &st))
        throw certification_error("the rigorous integration from the orbit's centre failed at " +
                                  where);
    out.steps_thin = st.steps;
    const ball_vector fy = field_at(thin, c.y.data(), prec);
    ball_matrix Jm(2, 2);
    for (int i = 0; i < 2; ++i) {
        arb_get_mid_arb(Jm(i, 0), c.y[5 + 2 + i]);
        arb_get_mid_arb(Jm(i, 1), fy[2 + i]);
    }
    c.invertible = arb_mat_inv(c.Y.m, Jm.m, prec) != 0;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            mag_zero(arb_radref(c.Y(i, j)));
    // the box: 4 |Y G(z^)| (what one Newton step would move the centre by), at least the centre's
    // claimed accuracy 10^-box_digits and at most the fallback's 10^-fallback_box_digits (a
    // centre farther from a zero than that is not the orbit this box is about: the test fails);
    // if it does not contract, the fallback box
    bool proved = false;
    if (c.invertible) {
        ball_matrix G(2, 1), YG(2, 1);
        arb_set(G(0, 0), c.y[2]);
        arb_set(G(1, 0), c.y[3]);
        arb_mat_mul(YG.m, c.Y.m, G.m, prec);
        const int widest = in.fallback_box_digits > 0 ? in.fallback_box_digits : in.box_digits;
        std::array<arb_ball, 2> r, rmax;
        for (int i = 0; i < 2; ++i) {
            const arb_struct* z = i == 0 ? bh.x : th.x;
            arb_ball lo;
            box_radius(lo.x, z, in.box_digits, prec);
            box_radius(rmax[i].x, z, widest, prec);
            arb_abs(r[i].x, YG(i, 0));
            arb_mul_2exp_si(r[i].x, r[i].x, 2);
            arb_max(r[i].x, r[i].x, lo.x, prec);
            arb_min(r[i].x, r[i].x, rmax[i].x, prec);
            arf_t u;
            arf_init(u);
            arb_get_ubound_arf(u, r[i].x, 30);
            arb_set_arf(r[i].x, u);
            arf_clear(u);
        }
        proved = krawczyk_test(in, bh.x, th.x, c, r[0].x, r[1].x, monodromy, order, prec, out);
        if (!proved && (!arb_equal(r[0].x, rmax[0].x) || !arb_equal(r[1].x, rmax[1].x)))
            proved =
                krawczyk_test(in, bh.x, th.x, c, rmax[0].x, rmax[1].x, monodromy, order, prec, out);
    }
    if (!proved)
        throw certification_error("Krawczyk test failed at " + where +
                                  ": the box did not contract");
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace flipflux::certified_detail
