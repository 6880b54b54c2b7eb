// A rigorous Taylor integrator in Arb ball arithmetic for autonomous systems x' = f(x) (private to
// certified/; docs/certified.md#the-rigorous-taylor-step, docs/theory.md).
//
// Series arithmetic (integrators/taylor.hpp has the same recurrences in Real): a series
// u(t) = sum_k u_k t^k is the vector of its coefficients; coefficient k of
//     a b:        sum_{j=0..k} a_j b_{k-j}
//     q = a / b:  q_k = (a_k - sum_{j=1..k} b_j q_{k-j}) / b_0
//     sin, cos:   s_k = (1/k) sum_{j=1..k} j u_j c_{k-j},  c_k = -(1/k) sum_{j=1..k} j u_j s_{k-j}
// computed on balls: each coefficient contains the exact coefficient for every point of the input
// balls. The solution's coefficients follow from x_{k+1} = f_k / (k + 1).
//
// One step of length h in H = [h_lo, h_hi] (a ball, h_lo >= 0) from a ball y:
//   1. the coefficients y_0..y_p of the solution through y (balls: for every point of y);
//   2. an a-priori enclosure B: a box with y + [0, h_hi] f(B) contained in B. Then for every
//      x0 in y the Picard operator u -> x0 + int_0^t f(u) maps the continuous functions
//      [0, h_hi] -> B into themselves (the integral's mean lies in the convex box f(B)), so the
//      solution exists on [0, h_hi] and stays in B (Schauder; unique since f is Lipschitz);
//   3. Lagrange's remainder, componentwise: x_i(h) = sum_{k<=p} x_{i,k} h^k + h^(p+1) c_i with
//      c_i = x_i^(p+1)(xi) / (p+1)! for some xi in [0, h], which is coefficient p + 1 of the
//      Taylor series of the solution through x(xi), a point of B: c_i lies in the ball
//      coefficient p + 1 of the expansion on B.
// So x(h) lies in sum_k y_k H^k + H^(p+1) c(B) for every x0 in y and every h in H.
//
// B is found by the iteration B <- y + [0, h] f(inflate(B)) from B = y + [0, h] f(y) (accepted
// when the image lies in the inflated box); the step is halved when that fails or when the
// remainder exceeds the tolerance (2^-prec relative to each component group's scale).
#pragma once

#include <arb.h>

#include <string>
#include <vector>

#include "arb_handle.hpp"

namespace flipflux::certified_detail {

/// A vector of balls (Arb's _arb_vec), owned.
class ball_vector {
  public:
    ball_vector() = default;
    explicit ball_vector(slong n) : n_(n), v_(n > 0 ? _arb_vec_init(n) : nullptr) {}
    ball_vector(const ball_vector& o) : ball_vector(o.n_) { _arb_vec_set(v_, o.v_, n_); }
    ball_vector& operator=(const ball_vector& o) {
        if (this != &o) {
            resize(o.n_);
            _arb_vec_set(v_, o.v_, n_);
        }
        return *this;
    }
    ~ball_vector() {
        if (v_) _arb_vec_clear(v_, n_);
    }
    void resize(slong n) {
        if (n == n_) return;
        if (v_) _arb_vec_clear(v_, n_);
        n_ = n;
        v_ = n > 0 ? _arb_vec_init(n) : nullptr;
    }
    slong size() const { return n_; }
    arb_ptr data() { return v_; }
    arb_srcptr data() const { return v_; }
    arb_ptr operator[](slong i) { return v_ + i; }
    arb_srcptr operator[](slong i) const { return v_ + i; }

  private:
    slong n_ = 0;
    arb_ptr v_ = nullptr;
};

/// Coefficients 0..order of n series, component i's at series(i)[0..order].
class ball_jet {
  public:
    ball_jet(slong n, slong order) : n_(n), len_(order + 1), v_(n * (order + 1)) {}
    slong components() const { return n_; }
    slong order() const { return len_ - 1; }
    arb_ptr series(slong i) { return v_[i * len_]; }
    arb_srcptr series(slong i) const { return v_[i * len_]; }

  private:
    slong n_, len_;
    ball_vector v_;
};

namespace series {

/// Coefficient k of a b.
inline void product(arb_t out, arb_srcptr a, arb_srcptr b, slong k, slong prec) {
    arb_dot(out, nullptr, 0, a, 1, b + k, -1, k + 1, prec);
}
/// out + coefficient k of a b (out may not alias a or b).
inline void add_product(arb_t out, arb_srcptr a, arb_srcptr b, slong k, slong prec) {
    arb_dot(out, out, 0, a, 1, b + k, -1, k + 1, prec);
}
/// q[k] = coefficient k of a / b, from a_k, b_0..b_k and q_0..q_{k-1} (q may alias a).
inline void quotient(arb_ptr q, arb_srcptr a, arb_srcptr b, slong k, slong prec) {
    if (k == 0) {
        arb_div(q, a, b, prec);
        return;
    }
    arb_ball t;
    arb_dot(t.x, a + k, 1, b + 1, 1, q + k - 1, -1, k, prec);
    arb_div(q + k, t.x, b, prec);
}

/// sin u and cos u as series; ju[j] = j u_j.
class sin_cos {
  public:
    explicit sin_cos(slong order = 0) : s(order + 1), c(order + 1), ju(order + 1) {}
    void next(arb_srcptr u, slong k, slong prec) {
        if (k == 0) {
            arb_sin_cos(s[0], c[0], u, prec);
            return;
        }
        arb_mul_si(ju[k], u + k, k, prec);
        arb_dot(s[k], nullptr, 0, ju[1], 1, c[k - 1], -1, k, prec);
        arb_div_si(s[k], s[k], k, prec);
        arb_dot(c[k], nullptr, 1, ju[1], 1, s[k - 1], -1, k, prec);
        arb_div_si(c[k], c[k], k, prec);
    }
    ball_vector s, c, ju;
};

}  // namespace series

/// The right-hand side f of an autonomous system, as series: coefficient(x, k, out) writes
/// coefficient k of f(x(t)) into out[0..n) from the jet's coefficients 0..k (it may keep
/// auxiliary series between the calls k = 0, 1, ... of one expansion, which always start at 0).
class ball_vector_field {
  public:
    virtual ~ball_vector_field() = default;
    virtual slong dimension() const = 0;
    /// Component groups for the step-size control: components of a group share one scale (the
    /// largest magnitude in the group).
    virtual slong group_of(slong component) const = 0;
    /// Prepares the auxiliary series for expansions up to `order`.
    virtual void reserve(slong order) = 0;
    virtual void coefficient(const ball_jet& x, slong k, arb_ptr out, slong prec) = 0;
};

/// Fills jet coefficients 0..jet.order() of the solution through y (jet_i,0 = y_i).
void expand(ball_vector_field& f, arb_srcptr y, ball_jet& jet, slong prec);

/// Counts of the rigorous integration.
struct rigorous_statistics {
    long steps = 0;
    long rejected = 0;  ///< steps halved (a-priori enclosure or remainder)
    int order = 0;
};

/// Integrates y (in place, n = f.dimension() balls) over a time `duration` (a ball with a
/// non-negative lower bound): adaptive exact steps, then the last step of ball length, so that the
/// result contains x(t) for every start in y and every t in duration. Order p of the series; the
/// tolerance per step is 2^-prec relative to each group's scale. Returns false (y undefined) when
/// the a-priori enclosure cannot be found (a step halved 40 times) or a ball is not finite.
bool integrate_rigorous(ball_vector_field& f, arb_ptr y, const arb_t duration, slong order,
                        slong prec, rigorous_statistics* stats = nullptr);

/// The Jorba-Zou order for 2^-prec: ceil(prec ln 2 / 2) + 1.
slong rigorous_order_for(slong prec);

}  // namespace flipflux::certified_detail
