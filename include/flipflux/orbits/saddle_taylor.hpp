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
// momentum columns 2, 3 only; the monodromy needs all four). Without the action (Action = false,
// the single trajectories) the state is the four components alone.
//
// A double tail at quad (Columns = 0, the fixed-precision types wider than double, graded
// precision on): a term c_k h^k of a Jorba-Zou step is ~ e^(-2k) of the state, so coefficient k
// needs only ~ 2 (p - 1 - k) / ln 2 bits relative to itself (integrators/taylor.hpp's graded
// precision). Where that plus double_tail_guard_bits fits in a double's 53, the coefficient is
// computed in double: every auxiliary series and the jet's components are mirrored in double at
// the first such k (the split), and the same recurrences run on the mirrors for k >= split. At
// quad (p = 40) the split is 28: coefficients 28..39, ~50 % of the convolutions' work, run in
// hardware arithmetic instead of libgcc's software float128 (docs/theory.md#the-taylor-integrator).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "flipflux/integrators/taylor.hpp"
#include "flipflux/orbits/saddle_frame.hpp"

namespace flipflux {

namespace detail {

/// The constants of the state recurrences in one number type.
template <class T>
struct saddle_constants {
    T A, B, C, D0, C2, e1alpha, e2beta;
};

/// The state recurrences' auxiliary series in one number type (the working one, or the double
/// mirrors of the tail).
template <class T>
struct saddle_state_series {
    taylor::sin_cos_series<T> sd, s1, s2;  ///< of d = delta1 - delta2, delta1, delta2
    std::vector<T> d, ss, det, cc, n1, n2, w1, w2, ww, p;
    saddle_state_series(int order, bool graded)
        : sd(order, graded), s1(order, graded), s2(order, graded) {
        for (auto* v : {&d, &ss, &det, &cc, &n1, &n2, &w1, &w2, &ww, &p})
            v->assign(static_cast<std::size_t>(order + 1), T(0));
    }
};

}  // namespace detail

/// Bits of margin below a double's 53 that a coefficient computed in the double tail keeps over
/// what its share of the step's error needs (see the file comment).
inline constexpr int double_tail_guard_bits = 20;

/// The first coefficient of an order-p expansion that the double tail computes: the smallest
/// k >= 1 with 2 (p - 1 - k) / ln 2 + double_tail_guard_bits <= 53 (p + 1: none, when graded
/// precision is off). Like MPFR's graded precision, this assumes the expansion is used with steps
/// no longer than its order's Jorba-Zou step (taylor_order_for, step_size,
/// taylor_steps_for_tolerance): an order-4 expansion at quad (split 1) is accurate only to its own
/// order's tolerance, e^-6.
inline int double_tail_split(int order) {
    if (!taylor::graded_precision().load()) return order + 1;
    const int span = static_cast<int>(
        std::floor((53 - double_tail_guard_bits) * std::log(2.0) / 2));  // p - 1 - k at most
    const int k = order - 1 - span;
    return k < 1 ? 1 : k;
}

/// Taylor coefficients of the orbit's flow: state (delta1, delta2, l1, l2, action) and, when
/// Columns > 0, the last `Columns` columns of Phi (row-major in the 4 x Columns block after the
/// action: component 5 + Columns i + j is Phi_{i, 4 - Columns + j}). Action = false drops the
/// action (then the state is 4 components, and Columns must be 0).
template <class Real, int Columns = 0, bool Action = true>
class saddle_taylor_flow {
    static_assert(Action || Columns == 0, "the variational columns follow the action");

  public:
    static constexpr std::size_t state_size = Action ? 5 : 4;
    static constexpr std::size_t size = state_size + 4 * static_cast<std::size_t>(Columns);
    using jet_type = std::array<std::vector<Real>, size>;
    using state = std::array<Real, size>;
    /// A double tail: only for the state alone (Columns = 0) in a fixed precision above double's.
    static constexpr bool has_double_tail =
        Columns == 0 && !has_variable_precision_v<Real> && std::numeric_limits<Real>::digits > 53;

    saddle_taylor_flow(const saddle_frame<Real>& frame, int order)
        : k_(constants<Real>(frame)),
          precision_(order),
          r_(order, true),
          split_(has_double_tail ? double_tail_split(order) : order + 1),
          precision_order_(order),
          tail_(has_double_tail && split_ <= order ? order : 0, false),
          tail_k_(constants<double>(frame)) {
        const auto n = static_cast<std::size_t>(order + 1);
        if (split_ <= order)
            for (auto& v : xd_)
                v.assign(n, 0.0);
        if constexpr (Columns > 0) {
            for (auto* v : {&i11_, &i12_, &i22_, &sc_, &ddet_, &nd1_, &nd2_, &dw1_, &dw2_, &pd_,
                            &pl1_, &pl2_, &a_, &b_, &c_})
                v->assign(n, Real(0));
            for (auto& v : dphi_)
                v.assign(n, Real(0));
        }
    }

    /// The first coefficient computed in the double tail (order + 1: none).
    int split() const { return split_; }
    /// How many coefficients of f the last expansion took from the double tail (fewer than
    /// order - split when it turned itself off: the rest are the working precision's).
    int tail_coefficients() const { return tail_count_; }

    void operator()(const jet_type& x, int k, state& f) {
        if (k == 0) {
            tail_on_ = split_ <= precision_order_;
            tail_count_ = 0;
        }
        if (k < split_ || !tail_on_)
            state_coefficient(k_, r_, precision_, x, k, f);
        else
            tail_coefficient(x, k, f);
        if constexpr (Columns > 0) variational_coefficient(x, k, f);
    }

  private:
    using series = std::vector<Real>;

    template <class T>
    static detail::saddle_constants<T> constants(const saddle_frame<Real>& frame) {
        const auto& k = frame.coefficients();
        const auto to = [](const Real& x) { return static_cast<T>(x); };
        return {to(k.A),
                to(k.B),
                to(k.C),
                to(k.D0),
                to(k.C * k.C),
                to(frame.e1() * k.alpha),
                to(frame.e2() * k.beta)};
    }

    /// Coefficient k of the state's right-hand side (f[0..state_size)) from the jet x's
    /// coefficients 0..k, in the number type T of the series b.
    template <class T, class Jet, class Out>
    static void state_coefficient(const detail::saddle_constants<T>& c,
                                  detail::saddle_state_series<T>& b,
                                  const taylor::coefficient_precision<T>& precision, const Jet& x,
                                  int k, Out& f) {
        using taylor::mul_add;
        using taylor::product;
        const auto K = static_cast<std::size_t>(k);
        const auto trim = [&precision, k](T& v) { precision.trim(v, k); };
        taylor::sub(b.d[K], x[0][K], x[1][K]);
        trim(b.d[K]);
        b.sd.next(b.d, k);
        b.s1.next(x[0], k);
        b.s2.next(x[1], k);
        product(b.sd.s, b.sd.s, k, b.ss[K]);
        trim(b.ss[K]);
        b.det[K] = c.C2 * b.ss[K];
        if (k == 0) b.det[0] += c.D0;
        trim(b.det[K]);
        b.cc[K] = c.C * b.sd.c[K];
        trim(b.cc[K]);
        product(b.cc, x[3], k, b.n1[K]);
        b.n1[K] += c.B * x[2][K];
        trim(b.n1[K]);
        product(b.cc, x[2], k, b.n2[K]);
        b.n2[K] += c.A * x[3][K];
        trim(b.n2[K]);
        taylor::quotient(b.n1, b.det, b.w1, k);
        trim(b.w1[K]);
        taylor::quotient(b.n2, b.det, b.w2, k);
        trim(b.w2[K]);
        product(b.w1, b.w2, k, b.ww[K]);
        trim(b.ww[K]);
        product(b.sd.s, b.ww, k, b.p[K]);
        b.p[K] *= -c.C;
        trim(b.p[K]);
        f[0] = b.w1[K];
        f[1] = b.w2[K];
        // (no unary minus on a rounded coefficient: see taylor.hpp's graded precision)
        f[2] = c.e1alpha * b.s1.s[K];
        f[2] += b.p[K];
        taylor::negate(f[2]);
        f[3] = b.p[K] - c.e2beta * b.s2.s[K];
        if constexpr (Action) {
            product(b.w1, x[2], k, f[4]);
            for (int j = 0; j <= k; ++j)
                mul_add(f[4], b.w2[static_cast<std::size_t>(j)],
                        x[3][K - static_cast<std::size_t>(j)]);
        }
    }

    /// Coefficient k >= split_ in the double tail: at the split the working series' coefficients
    /// 0..k-1 and the jet's are mirrored in double, then the jet's coefficient k each time. A
    /// value outside double's comfortable range (|v| in {0} or [2^-400, 2^400]; checked: the
    /// inputs, the outputs and the products of several series; an overflow in between shows as
    /// a non-finite output, an underflow only loses terms far below the others) turns the tail
    /// off for the rest of the expansion: the working series are then brought up to k from the
    /// jet and k computed there.
    void tail_coefficient(const jet_type& x, int k, state& f) {
        const auto K = static_cast<std::size_t>(k);
        bool safe = true;
        const auto to_double = [&safe](const Real& v) {
            const double d = static_cast<double>(v);
            safe = safe && in_tail_range(d);
            return d;
        };
        if (k == split_) {
            safe = in_tail_range(tail_k_);
            const auto mirror = [&to_double](const std::vector<Real>& from, std::vector<double>& to,
                                             std::size_t n) {
                for (std::size_t j = 0; j < n; ++j)
                    to[j] = to_double(from[j]);
            };
            for (auto [from, to] : {std::pair{&r_.d, &tail_.d},
                                    {&r_.ss, &tail_.ss},
                                    {&r_.det, &tail_.det},
                                    {&r_.cc, &tail_.cc},
                                    {&r_.n1, &tail_.n1},
                                    {&r_.n2, &tail_.n2},
                                    {&r_.w1, &tail_.w1},
                                    {&r_.w2, &tail_.w2},
                                    {&r_.ww, &tail_.ww},
                                    {&r_.p, &tail_.p}})
                mirror(*from, *to, K);
            for (auto [from, to] :
                 {std::pair{&r_.sd, &tail_.sd}, {&r_.s1, &tail_.s1}, {&r_.s2, &tail_.s2}}) {
                mirror(from->s, to->s, K);
                mirror(from->c, to->c, K);
                mirror(from->ju, to->ju, K - 1);  // (ju[K - 1] is next()'s to write)
            }
            for (std::size_t i = 0; i < 4; ++i)
                mirror(x[i], xd_[i], K);
        }
        for (std::size_t i = 0; i < 4; ++i)
            xd_[i][K] = to_double(x[i][K]);
        std::array<double, state_size> fd;
        if (safe) {
            state_coefficient(tail_k_, tail_, no_precision_, xd_, k, fd);
            // the outputs and the products of three series (p = -C s w1 w2 and its factors)
            for (const double v : fd)
                safe = safe && in_tail_range(v);
            for (const double v : {tail_.w1[K], tail_.w2[K], tail_.ww[K], tail_.p[K]})
                safe = safe && in_tail_range(v);
        }
        if (!safe) {
            tail_on_ = false;
            for (int j = split_; j <= k; ++j)
                state_coefficient(k_, r_, precision_, x, j, f);
            return;
        }
        for (std::size_t i = 0; i < state_size; ++i)
            f[i] = Real(fd[i]);
        ++tail_count_;
    }

    static bool in_tail_range(double v) {
        const double a = std::abs(v);
        return a == 0 || (a >= 0x1p-400 && a <= 0x1p400);
    }
    static bool in_tail_range(const detail::saddle_constants<double>& c) {
        for (const double v : {c.A, c.B, c.C, c.D0, c.C2, c.e1alpha, c.e2beta})
            if (!in_tail_range(v)) return false;
        return true;
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
        taylor::quotient(i11_, r_.det, i11_, k);  // in place: a_k is read before q_k is written
        trim(i11_[K]);
        taylor::quotient(i22_, r_.det, i22_, k);
        trim(i22_[K]);
        taylor::quotient(r_.cc, r_.det, i12_, k);
        trim(i12_[K]);
        product(r_.sd.s, r_.sd.c, k, sc_[K]);
        trim(sc_[K]);
        ddet_[K] = 2 * k_.C2 * sc_[K];
        trim(ddet_[K]);
        // nd1 = -C s l2 - w1 det_d, nd2 = -C s l1 - w2 det_d
        product(r_.sd.s, x[3], k, nd1_[K]);
        nd1_[K] *= -C;
        for (int j = 0; j <= k; ++j)
            mul_sub(nd1_[K], r_.w1[static_cast<std::size_t>(j)],
                    ddet_[K - static_cast<std::size_t>(j)]);
        trim(nd1_[K]);
        product(r_.sd.s, x[2], k, nd2_[K]);
        nd2_[K] *= -C;
        for (int j = 0; j <= k; ++j)
            mul_sub(nd2_[K], r_.w2[static_cast<std::size_t>(j)],
                    ddet_[K - static_cast<std::size_t>(j)]);
        trim(nd2_[K]);
        taylor::quotient(nd1_, r_.det, dw1_, k);
        trim(dw1_[K]);
        taylor::quotient(nd2_, r_.det, dw2_, k);
        trim(dw2_[K]);
        // P_d = -C (c ww + s a), a = dw1 w2 + w1 dw2
        product(dw1_, r_.w2, k, a_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(a_[K], r_.w1[static_cast<std::size_t>(j)],
                    dw2_[K - static_cast<std::size_t>(j)]);
        trim(a_[K]);
        product(r_.sd.c, r_.ww, k, pd_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(pd_[K], r_.sd.s[static_cast<std::size_t>(j)],
                    a_[K - static_cast<std::size_t>(j)]);
        pd_[K] *= -C;
        trim(pd_[K]);
        // P_l1 = -C s b, b = i11 w2 + w1 i12; P_l2 = -C s c, c = i12 w2 + w1 i22
        product(i11_, r_.w2, k, b_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(b_[K], r_.w1[static_cast<std::size_t>(j)],
                    i12_[K - static_cast<std::size_t>(j)]);
        trim(b_[K]);
        product(i12_, r_.w2, k, c_[K]);
        for (int j = 0; j <= k; ++j)
            mul_add(c_[K], r_.w1[static_cast<std::size_t>(j)],
                    i22_[K - static_cast<std::size_t>(j)]);
        trim(c_[K]);
        product(r_.sd.s, b_, k, pl1_[K]);
        pl1_[K] *= -C;
        trim(pl1_[K]);
        product(r_.sd.s, c_, k, pl2_[K]);
        pl2_[K] *= -C;
        trim(pl2_[K]);
        for (int col = 0; col < Columns; ++col)
            column_coefficient(x, k, col, f);
    }

    /// Coefficient k of J phi for one column phi of Phi (components state_size + Columns i + col).
    void column_coefficient(const jet_type& x, int k, int col, state& f) {
        using taylor::mul_add;
        const auto K = static_cast<std::size_t>(k);
        const auto at = [col](int row) {
            return static_cast<std::size_t>(state_size + Columns * row + col);
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
            mul_add(t0_, r_.s1.c[J], p0[R]);
            mul_add(t1_, r_.s2.c[J], p1[R]);
        }
        r2 = q_;
        taylor::negate(r2);  // (not r2 = -q_, see taylor.hpp's graded precision)
        mul_sub_scaled(r2, k_.e1alpha, t0_);
        r3 = q_;
        mul_sub_scaled(r3, k_.e2beta, t1_);
    }

    static void mul_sub_scaled(Real& acc, const Real& a, const Real& b) {
        taylor::mul_sub(acc, a, b);
    }

    detail::saddle_constants<Real> k_;
    taylor::coefficient_precision<Real> precision_;  ///< of every series' coefficient k
    detail::saddle_state_series<Real> r_;            ///< the working precision's series
    int split_;                                      ///< first coefficient of the double tail
    int precision_order_;                            ///< the expansion's order
    bool tail_on_ = false;                           ///< this expansion's tail in double
    int tail_count_ = 0;                             ///< tail_coefficients()
    detail::saddle_state_series<double> tail_;       ///< the double tail's mirrors
    detail::saddle_constants<double> tail_k_;
    taylor::coefficient_precision<double> no_precision_;
    std::array<std::vector<double>, 4> xd_;  ///< the jet's state components in double
    series i11_, i12_, i22_, sc_, ddet_, nd1_, nd2_, dw1_, dw2_, pd_, pl1_, pl2_, a_, b_, c_;
    std::array<series, static_cast<std::size_t>(Columns > 0 ? Columns : 1)> dphi_;
    Real q_{0}, t0_{0}, t1_{0};
};

}  // namespace flipflux
