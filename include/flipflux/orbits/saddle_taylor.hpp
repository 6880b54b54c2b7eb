// The Taylor recurrences of Hamilton's equations in the saddle frame (orbits/saddle_frame.hpp;
// docs/theory.md#the-taylor-integrator), for integrators/taylor.hpp.
//
// With d = delta1 - delta2 and the series (each coefficient k from coefficients 0..k of the state):
//     (s, c) = (sin d, cos d),  (s1, c1) = (sin delta1, cos delta1),  (s2, c2) likewise,
//     det = D0 + C^2 s s,   n1 = B l1 + C c l2,   n2 = C c l1 + A l2,
//     w1 = n1 / det,   w2 = n2 / det,   P = -C s (w1 w2),
//     delta1' = w1,  delta2' = w2,  l1' = -P - e1 alpha s1,  l2' = P - e2 beta s2,
//     action' = w1 l1 + w2 l2,
// the same formulas as saddle_frame::rhs, term by term in the series arithmetic.
//
// The variational equations Phi' = J Phi take J's entries (saddle_frame::rhs_and_jacobian) as
// series too: i11 = B / det, i12 = C c / det, i22 = A / det, det_d = 2 C^2 s c,
//     dw1 = (-C s l2 - w1 det_d) / det,   dw2 = (-C s l1 - w2 det_d) / det,
//     P_d = -C (c w1 w2 + s (dw1 w2 + w1 dw2)),
//     P_l1 = -C s (i11 w2 + w1 i12),   P_l2 = -C s (i12 w2 + w1 i22);
// per column phi of Phi, with D = phi_0 - phi_1 and Q = P_d D + P_l1 phi_2 + P_l2 phi_3:
//     phi_0' = dw1 D + i11 phi_2 + i12 phi_3,   phi_1' = dw2 D + i12 phi_2 + i22 phi_3,
//     phi_2' = -Q - e1 alpha c1 phi_0,          phi_3' = Q - e2 beta c2 phi_1,
// which is J phi with J's rows {dw1, -dw1, i11, i12}, {dw2, -dw2, i12, i22},
// {-P_d - e1 alpha c1, P_d, -P_l1, -P_l2}, {P_d, -P_d - e2 beta c2, P_l1, P_l2}.
// Only the columns in [first_column, 4) are propagated (the shooting's Newton steps need the
// momentum columns 2, 3 only; the monodromy needs all four).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "flipflux/integrators/taylor.hpp"
#include "flipflux/orbits/saddle_frame.hpp"

namespace flipflux {

/// Taylor coefficients of the orbit's flow: state (delta1, delta2, l1, l2, action) and, when
/// Columns > 0, the last `Columns` columns of Phi (row-major in the 4 x Columns block after the
/// action: component 5 + Columns i + j is Phi_{i, 4 - Columns + j}).
template <class Real, int Columns = 0>
class saddle_taylor_flow {
  public:
    static constexpr std::size_t size = 5 + 4 * static_cast<std::size_t>(Columns);
    using jet_type = std::array<std::vector<Real>, size>;
    using state = std::array<Real, size>;

    saddle_taylor_flow(const saddle_frame<Real>& frame, int order)
        : k_(frame.coefficients()),
          e1alpha_(frame.e1() * frame.coefficients().alpha),
          e2beta_(frame.e2() * frame.coefficients().beta),
          C2_(frame.coefficients().C * frame.coefficients().C),
          precision_(order),
          sd_(order, true),
          s1_(order, true),
          s2_(order, true) {
        const auto n = static_cast<std::size_t>(order + 1);
        for (auto* v : {&d_, &ss_, &det_, &cc_, &n1_, &n2_, &w1_, &w2_, &ww_, &p_})
            v->assign(n, Real(0));
        if constexpr (Columns > 0) {
            for (auto* v : {&i11_, &i12_, &i22_, &sc_, &ddet_, &nd1_, &nd2_, &dw1_, &dw2_, &pd_,
                            &pl1_, &pl2_, &a_, &b_, &c_})
                v->assign(n, Real(0));
            for (auto& v : dphi_)
                v.assign(n, Real(0));
        }
    }

    void operator()(const jet_type& x, int k, state& f) {
        state_coefficient(x, k, f);
        if constexpr (Columns > 0) variational_coefficient(x, k, f);
    }

  private:
    using series = std::vector<Real>;

    void state_coefficient(const jet_type& x, int k, state& f) {
        using taylor::mul_add;
        using taylor::product;
        const auto K = static_cast<std::size_t>(k);
        const auto trim = [this, k](Real& x) { precision_.trim(x, k); };
        taylor::sub(d_[K], x[0][K], x[1][K]);
        trim(d_[K]);
        sd_.next(d_, k);
        s1_.next(x[0], k);
        s2_.next(x[1], k);
        product(sd_.s, sd_.s, k, ss_[K]);
        trim(ss_[K]);
        det_[K] = C2_ * ss_[K];
        if (k == 0) det_[0] += k_.D0;
        trim(det_[K]);
        cc_[K] = k_.C * sd_.c[K];
        trim(cc_[K]);
        product(cc_, x[3], k, n1_[K]);
        n1_[K] += k_.B * x[2][K];
        trim(n1_[K]);
        product(cc_, x[2], k, n2_[K]);
        n2_[K] += k_.A * x[3][K];
        trim(n2_[K]);
        taylor::quotient(n1_, det_, w1_, k);
        trim(w1_[K]);
        taylor::quotient(n2_, det_, w2_, k);
        trim(w2_[K]);
        product(w1_, w2_, k, ww_[K]);
        trim(ww_[K]);
        product(sd_.s, ww_, k, p_[K]);
        p_[K] *= -k_.C;
        trim(p_[K]);
        f[0] = w1_[K];
        f[1] = w2_[K];
        // (no unary minus on a rounded coefficient: see taylor.hpp's graded precision)
        f[2] = e1alpha_ * s1_.s[K];
        f[2] += p_[K];
        taylor::negate(f[2]);
        f[3] = p_[K] - e2beta_ * s2_.s[K];
        product(w1_, x[2], k, f[4]);
        for (int j = 0; j <= k; ++j)
            mul_add(f[4], w2_[static_cast<std::size_t>(j)], x[3][K - static_cast<std::size_t>(j)]);
    }

    void variational_coefficient(const jet_type& x, int k, state& f) {
        using taylor::mul_add;
        using taylor::mul_sub;
        using taylor::product;
        const auto K = static_cast<std::size_t>(k);
        const Real& C = k_.C;
        const auto trim = [this, k](Real& x) { precision_.trim(x, k); };
        // the inverse mass matrix and the derivatives along d of w
        i11_[K] = k == 0 ? k_.B : Real(0);
        i22_[K] = k == 0 ? k_.A : Real(0);
        taylor::quotient(i11_, det_, i11_, k);  // in place: a_k is read before q_k is written
        trim(i11_[K]);
        taylor::quotient(i22_, det_, i22_, k);
        trim(i22_[K]);
        taylor::quotient(cc_, det_, i12_, k);
        trim(i12_[K]);
        product(sd_.s, sd_.c, k, sc_[K]);
        trim(sc_[K]);
        ddet_[K] = 2 * C2_ * sc_[K];
        trim(ddet_[K]);
        // nd1 = -C s l2 - w1 det_d, nd2 = -C s l1 - w2 det_d
        product(sd_.s, x[3], k, nd1_[K]);
        nd1_[K] *= -C;
        for (int j = 0; j <= k; ++j)
            mul_sub(nd1_[K], w1_[static_cast<std::size_t>(j)],
                    ddet_[K - static_cast<std::size_t>(j)]);
        trim(nd1_[K]);
        product(sd_.s, x[2], k, nd2_[K]);
        nd2_[K] *= -C;
        for (int j = 0; j <= k; ++j)
            mul_sub(nd2_[K], w2_[static_cast<std::size_t>(j)],
                    ddet_[K - static_cast<std::size_t>(j)]);
        trim(nd2_[K]);
        taylor::quotient(nd1_, det_, dw1_, k);
        trim(dw1_[K]);
        taylor::quotient(nd2_, det_, dw2_, k);
        trim(dw2_[K]);
        // P_d = -C (c ww + s a), a = dw1 w2 + w1 dw2
        product(dw1_, w2_, k, a_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(a_[K], w1_[static_cast<std::size_t>(j)], dw2_[K - static_cast<std::size_t>(j)]);
        trim(a_[K]);
        product(sd_.c, ww_, k, pd_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(pd_[K], sd_.s[static_cast<std::size_t>(j)],
                    a_[K - static_cast<std::size_t>(j)]);
        pd_[K] *= -C;
        trim(pd_[K]);
        // P_l1 = -C s b, b = i11 w2 + w1 i12; P_l2 = -C s c, c = i12 w2 + w1 i22
        product(i11_, w2_, k, b_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(b_[K], w1_[static_cast<std::size_t>(j)], i12_[K - static_cast<std::size_t>(j)]);
        trim(b_[K]);
        product(i12_, w2_, k, c_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(c_[K], w1_[static_cast<std::size_t>(j)], i22_[K - static_cast<std::size_t>(j)]);
        trim(c_[K]);
        product(sd_.s, b_, k, pl1_[K]);
        pl1_[K] *= -C;
        trim(pl1_[K]);
        product(sd_.s, c_, k, pl2_[K]);
        pl2_[K] *= -C;
        trim(pl2_[K]);
        for (int col = 0; col < Columns; ++col)
            column_coefficient(x, k, col, f);
    }

    /// Coefficient k of J phi for one column phi of Phi (components 5 + Columns i + col).
    void column_coefficient(const jet_type& x, int k, int col, state& f) {
        using taylor::mul_add;
        const auto K = static_cast<std::size_t>(k);
        const auto at = [col](int row) {
            return static_cast<std::size_t>(5 + Columns * row + col);
        };
        const series& p0 = x[at(0)];
        const series& p1 = x[at(1)];
        const series& p2 = x[at(2)];
        const series& p3 = x[at(3)];
        series& D = dphi_[static_cast<std::size_t>(col)];
        taylor::sub(D[K], p0[K], p1[K]);
        precision_.trim(D[K], k);
        Real& r0 = f[at(0)];
        Real& r1 = f[at(1)];
        Real& r2 = f[at(2)];
        Real& r3 = f[at(3)];
        for (Real* acc : {&r0, &r1, &q_, &t0_, &t1_})
            precision_.zero(*acc, k);
        for (int j = 0; j <= k; ++j) {
            const auto J = static_cast<std::size_t>(j), R = K - J;
            mul_add(r0, dw1_[J], D[R]);
            mul_add(r0, i11_[J], p2[R]);
            mul_add(r0, i12_[J], p3[R]);
            mul_add(r1, dw2_[J], D[R]);
            mul_add(r1, i12_[J], p2[R]);
            mul_add(r1, i22_[J], p3[R]);
            mul_add(q_, pd_[J], D[R]);
            mul_add(q_, pl1_[J], p2[R]);
            mul_add(q_, pl2_[J], p3[R]);
            mul_add(t0_, s1_.c[J], p0[R]);
            mul_add(t1_, s2_.c[J], p1[R]);
        }
        r2 = q_;
        taylor::negate(r2);  // (not r2 = -q_, see taylor.hpp's graded precision)
        mul_sub_scaled(r2, e1alpha_, t0_);
        r3 = q_;
        mul_sub_scaled(r3, e2beta_, t1_);
    }

    static void mul_sub_scaled(Real& acc, const Real& a, const Real& b) {
        taylor::mul_sub(acc, a, b);
    }

    lagrangian_coefficients<Real> k_;
    Real e1alpha_, e2beta_, C2_;
    taylor::coefficient_precision<Real> precision_;  ///< of every series' coefficient k
    taylor::sin_cos_series<Real> sd_, s1_, s2_;
    series d_, ss_, det_, cc_, n1_, n2_, w1_, w2_, ww_, p_;
    series i11_, i12_, i22_, sc_, ddet_, nd1_, nd2_, dw1_, dw2_, pd_, pl1_, pl2_, a_, b_, c_;
    std::array<series, static_cast<std::size_t>(Columns > 0 ? Columns : 1)> dphi_;
    Real q_{0}, t0_{0}, t1_{0};
};

}  // namespace flipflux
