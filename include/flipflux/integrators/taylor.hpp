// Taylor-series arithmetic and a fixed-order Taylor integrator for autonomous systems x' = f(x),
// generic over the real type (docs/theory.md#the-taylor-integrator).
//
// Series arithmetic (automatic differentiation; Jorba & Zou, "A software package for the numerical
// integration of ODEs by means of high-order Taylor methods", Exp. Math. 14 (2005), Sec. 2; Moore,
// "Interval Analysis", 1966): a series u(t) = sum_k u_k t^k is the vector of its coefficients.
// Coefficient k of
//     a b:          sum_{j=0..k} a_j b_{k-j}
//     q = a / b:    q_k = (a_k - sum_{j=1..k} b_j q_{k-j}) / b_0            (from b q = a)
//     s = sin u, c = cos u (k >= 1; from s' = u' c, c' = -u' s):
//                   s_k = (1/k) sum_{j=1..k} j u_j c_{k-j},  c_k = -(1/k) sum_{j=1..k} j u_j
//                   s_{k-j}
//     e = exp u:    e_k = (1/k) sum_{j=1..k} j u_j e_{k-j}                  (from e' = u' e)
// each needs only the coefficients 0..k of its arguments (0..k-1 of its own), so the coefficients
// of the solution of x' = f(x) follow one order at a time: x_{k+1} = f_k / (k + 1), f_k the
// coefficient k of f(x(t)), which the caller's functor computes from x_0..x_k.
//
// The step (Jorba & Zou, Sec. 3): order p = ceil(-ln(tol) / 2) + 1 (minimises the work per unit
// time when the cost of a step grows like p^2; grows with the digits: 17 at double, 38 at quad,
// ~126 at 110 digits), step h = min_{j in {p-1, p}} (tol / ||x_j||)^(1/j) exp(-0.7 / (p - 1)),
// ||.|| the max norm weighted by the caller's componentwise scales. With h ~ rho / e^2 (rho the
// radius of convergence) the truncated terms sum to about tol / 6.
//
// Dense output: the step's Taylor polynomial (evaluate(t), Horner) is the solution on the step.
//
// NOTE: in the fixed-step use (integrate()), h and the order are the caller's: the result is then
// a smooth function of the initial state and of h (an adaptive step sequence is not), which
// shooting methods need. taylor_steps_for_tolerance() chooses the equal steps once, from an
// adaptive pass.
//
// Graded precision (mp; at quad the same argument gives the saddle flow's double tail,
// orbits/saddle_taylor.hpp): a term c_k h^k of the step is ~ e^(-2k) of the state (h ~ rho / e^2),
// so coefficient k needs only ~ 2 (p - 1 - k) / ln 2 bits relative to itself, plus guard bits,
// to keep its share of the step's error at the tolerance. Every coefficient k of the jet and of a
// flow's auxiliary series is rounded to that precision (coefficient_precision::trim; at most the
// working precision), and a product of a convolution for coefficient k reads only its factors'
// leading p_k + 64 bits: the products, which dominate the cost, then cost ~ 1/6 of the uniform
// precision's (docs/theory.md#the-taylor-integrator; ~2x faster orbits at mp:300, ~10 % at
// mp:100, where MPFR's cost per operation dominates). Operations between two
// trimmed coefficients (and unary ones on one: -x, abs(x)) go through the backend (sub, scale,
// divide, negate, working below), never through Boost's operators: those would change the
// process-wide default precision while they run (tests/quantities/test_precision_invariance.cpp).
//
// Domain and errors: any f analytic along the solution; a non-finite coefficient fails the step
// (reported, never thrown). Order in [1, max_taylor_order], else std::invalid_argument.
#pragma once

#include <mpfr.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/multiprecision/number.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/mpfr_number.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"

namespace flipflux {

inline constexpr int max_taylor_order = 100000;

namespace taylor {

namespace detail {
/// A thread's scratch number for mul_add / mul_sub at MPFR precisions: a product rounded to the
/// accumulator's precision costs less than mpfr_fma's exact one (whose temporary is allocated at
/// the sum of the operands' precisions on every call once they differ).
inline mpfr_ptr scratch(mpfr_prec_t p) {
    thread_local mpfr_number s;
    return s.at(p);
}
/// x, or a read-only view of its leading `limbs` limbs (x truncated: MPFR keeps the mantissa's
/// most significant limb last) when it has more: a product rounded to p bits needs only
/// ~p + 64 bits of each factor, and its cost is the product of the factors' limb counts.
inline mpfr_srcptr leading_limbs(mpfr_srcptr x, mp_size_t limbs, __mpfr_struct& view) {
    const auto n = static_cast<mp_size_t>((mpfr_get_prec(x) + GMP_NUMB_BITS - 1) / GMP_NUMB_BITS);
    if (n <= limbs || !mpfr_regular_p(x)) return x;
    view._mpfr_prec = static_cast<mpfr_prec_t>(limbs) * GMP_NUMB_BITS;
    view._mpfr_sign = x->_mpfr_sign;
    view._mpfr_exp = x->_mpfr_exp;
    view._mpfr_d = x->_mpfr_d + (n - limbs);
    return &view;
}
/// t = a b rounded to t's precision p, from the factors' leading p + 64 bits.
inline void truncated_product(mpfr_ptr t, mpfr_srcptr a, mpfr_srcptr b) {
    const auto limbs =
        static_cast<mp_size_t>((mpfr_get_prec(t) + 64 + GMP_NUMB_BITS - 1) / GMP_NUMB_BITS);
    __mpfr_struct va, vb;
    mpfr_mul(t, leading_limbs(a, limbs, va), leading_limbs(b, limbs, vb), MPFR_RNDN);
}
}  // namespace detail

/// acc += a b (for MPFR: the product rounded to acc's precision, then the sum; for the other
/// Boost.Multiprecision types fused, without a temporary).
template <class Real>
inline void mul_add(Real& acc, const Real& a, const Real& b) {
    if constexpr (has_variable_precision_v<Real>) {
        mpfr_ptr t = detail::scratch(mpfr_get_prec(acc.backend().data()));
        detail::truncated_product(t, a.backend().data(), b.backend().data());
        mpfr_add(acc.backend().data(), acc.backend().data(), t, MPFR_RNDN);
    } else if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_multiply_add;
        eval_multiply_add(acc.backend(), a.backend(), b.backend());
    } else {
        acc += a * b;
    }
}
/// acc -= a b.
template <class Real>
inline void mul_sub(Real& acc, const Real& a, const Real& b) {
    if constexpr (has_variable_precision_v<Real>) {
        mpfr_ptr t = detail::scratch(mpfr_get_prec(acc.backend().data()));
        detail::truncated_product(t, a.backend().data(), b.backend().data());
        mpfr_sub(acc.backend().data(), acc.backend().data(), t, MPFR_RNDN);
    } else if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_multiply_subtract;
        eval_multiply_subtract(acc.backend(), a.backend(), b.backend());
    } else {
        acc -= a * b;
    }
}

/// out = a - b, rounded to out's precision (no change of the default precision).
template <class Real>
inline void sub(Real& out, const Real& a, const Real& b) {
    if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_subtract;
        eval_subtract(out.backend(), a.backend(), b.backend());
    } else {
        out = a - b;
    }
}
/// x = -x.
template <class Real>
inline void negate(Real& x) {
    if constexpr (boost::multiprecision::is_number<Real>::value)
        x.backend().negate();
    else
        x = -x;
}
/// x *= n.
template <class Real>
inline void scale(Real& x, long n) {
    if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_multiply;
        eval_multiply(x.backend(), n);
    } else {
        x *= n;
    }
}
/// x /= n.
template <class Real>
inline void divide(Real& x, long n) {
    if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_divide;
        eval_divide(x.backend(), n);
    } else {
        x /= n;
    }
}
/// x /= d, rounded to x's precision.
template <class Real>
inline void divide(Real& x, const Real& d) {
    if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_divide;
        eval_divide(x.backend(), d.backend());
    } else {
        x /= d;
    }
}
/// x at the working precision (a trimmed coefficient as the argument of a Boost function).
template <class Real>
inline Real working(const Real& x) {
    Real r = 0;
    if constexpr (boost::multiprecision::is_number<Real>::value) {
        using boost::multiprecision::default_ops::eval_add;
        eval_add(r.backend(), x.backend());
    } else {
        r = x;
    }
    return r;
}

/// Graded precision on (the default) or off (every coefficient at the working precision: the
/// baseline of bench_orbit_integrators and the reference of the tests; at quad it also turns the
/// saddle flow's double tail on or off, orbits/saddle_taylor.hpp). Process-wide.
inline std::atomic<bool>& graded_precision() {
    static std::atomic<bool> on{true};
    return on;
}

/// While one lives, graded_precision() is `on` (then restored): e.g. tests of the recurrences at
/// orders far below the working precision's, whose coefficients must all be exact.
class graded_precision_scope {
  public:
    explicit graded_precision_scope(bool on) : saved_(graded_precision().exchange(on)) {}
    ~graded_precision_scope() { graded_precision().store(saved_); }
    graded_precision_scope(const graded_precision_scope&) = delete;
    graded_precision_scope& operator=(const graded_precision_scope&) = delete;

  private:
    bool saved_;
};

/// The precision of each coefficient k = 0..order of an order-p expansion (see the file
/// comment): min(working, max(guard, ceil(2 (p - 1 - k) / ln 2) + guard)) bits, guard = 64; for
/// the fixed-precision types (and with graded_precision() off) every coefficient keeps the
/// working precision.
template <class Real>
class coefficient_precision {
  public:
    static constexpr long guard_bits = 64;
    coefficient_precision() = default;
    explicit coefficient_precision(int order) {
        if constexpr (has_variable_precision_v<Real>) {
            if (!graded_precision().load()) return;
            const long full = binary_digits<Real>();
            bits_.resize(static_cast<std::size_t>(order + 1));
            for (int k = 0; k <= order; ++k) {
                const double need = 2.0 * (order - 1 - k) / std::log(2.0);
                bits_[static_cast<std::size_t>(k)] =
                    std::clamp(static_cast<long>(std::ceil(need)) + guard_bits, guard_bits, full);
            }
        } else {
            (void)order;
        }
    }
    /// Rounds coefficient k to its precision.
    void trim(Real& x, int k) const {
        if constexpr (has_variable_precision_v<Real>) {
            if (bits_.empty()) return;
            const auto b = static_cast<mpfr_prec_t>(bits_[static_cast<std::size_t>(k)]);
            if (mpfr_get_prec(x.backend().data()) != b)
                mpfr_prec_round(x.backend().data(), b, MPFR_RNDN);
        } else {
            (void)x, (void)k;
        }
    }
    /// x = 0 at coefficient k's precision (an accumulator for coefficient k).
    void zero(Real& x, int k) const {
        if constexpr (has_variable_precision_v<Real>) {
            if (!bits_.empty()) {
                const auto b = static_cast<mpfr_prec_t>(bits_[static_cast<std::size_t>(k)]);
                if (mpfr_get_prec(x.backend().data()) != b) mpfr_set_prec(x.backend().data(), b);
                mpfr_set_zero(x.backend().data(), 1);
                return;
            }
        } else {
            (void)k;
        }
        x = 0;
    }

  private:
    std::vector<long> bits_;
};

/// Coefficient k of a b into out: sum_{j=0..k} a_j b_{k-j}.
template <class Real>
inline void product(const std::vector<Real>& a, const std::vector<Real>& b, int k, Real& out) {
    out = 0;
    for (int j = 0; j <= k; ++j)
        mul_add(out, a[static_cast<std::size_t>(j)], b[static_cast<std::size_t>(k - j)]);
}

/// Coefficient k of q = a / b into q[k], from a_k, b_0..b_k and q_0..q_{k-1}.
template <class Real>
inline void quotient(const std::vector<Real>& a, const std::vector<Real>& b, std::vector<Real>& q,
                     int k) {
    const auto K = static_cast<std::size_t>(k);
    q[K] = a[K];
    for (int j = 1; j <= k; ++j)
        mul_sub(q[K], b[static_cast<std::size_t>(j)], q[static_cast<std::size_t>(k - j)]);
    divide(q[K], b[0]);
}

/// sin u and cos u as series, with j u_j kept for the recurrences.
template <class Real>
struct sin_cos_series {
    std::vector<Real> s, c, ju;             ///< sin u, cos u, ju[j - 1] = j u_j
    coefficient_precision<Real> precision;  ///< of s and c (none: the working precision)
    explicit sin_cos_series(int order = 0, bool graded = false) {
        resize(order);
        if (graded) precision = coefficient_precision<Real>(order);
    }
    void resize(int order) {
        const auto n = static_cast<std::size_t>(order + 1);
        s.assign(n, Real(0));
        c.assign(n, Real(0));
        ju.assign(n, Real(0));
    }
    /// Coefficient k of sin u and cos u from u_0..u_k (and this series' 0..k-1).
    void next(const std::vector<Real>& u, int k) {
        using std::cos;
        using std::sin;
        const auto K = static_cast<std::size_t>(k);
        if (k == 0) {
            const Real u0 = working(u[0]);
            s[0] = sin(u0);
            c[0] = cos(u0);
            precision.trim(s[0], 0);
            precision.trim(c[0], 0);
            return;
        }
        ju[K - 1] = u[K];
        scale(ju[K - 1], k);
        s[K] = 0;
        c[K] = 0;
        for (int j = 1; j <= k; ++j) {
            const Real& v = ju[static_cast<std::size_t>(j - 1)];
            mul_add(s[K], v, c[static_cast<std::size_t>(k - j)]);
            mul_sub(c[K], v, s[static_cast<std::size_t>(k - j)]);
        }
        divide(s[K], k);
        divide(c[K], k);
        precision.trim(s[K], k);
        precision.trim(c[K], k);
    }
};

/// The first n + 1 coefficients of a b, a / b, sin/cos u and exp u (whole series; for tests and
/// one-off use).
template <class Real>
std::vector<Real> series_product(const std::vector<Real>& a, const std::vector<Real>& b) {
    std::vector<Real> out(a.size() < b.size() ? a.size() : b.size());
    for (std::size_t k = 0; k < out.size(); ++k)
        product(a, b, static_cast<int>(k), out[k]);
    return out;
}
template <class Real>
std::vector<Real> series_quotient(const std::vector<Real>& a, const std::vector<Real>& b) {
    if (b.empty() || b[0] == 0)
        throw std::invalid_argument("series_quotient: the divisor's constant term is 0");
    std::vector<Real> q(a.size() < b.size() ? a.size() : b.size());
    for (std::size_t k = 0; k < q.size(); ++k)
        quotient(a, b, q, static_cast<int>(k));
    return q;
}
template <class Real>
sin_cos_series<Real> series_sin_cos(const std::vector<Real>& u) {
    sin_cos_series<Real> sc(static_cast<int>(u.size()) - 1);
    for (std::size_t k = 0; k < u.size(); ++k)
        sc.next(u, static_cast<int>(k));
    return sc;
}
template <class Real>
std::vector<Real> series_exp(const std::vector<Real>& u) {
    using std::exp;
    std::vector<Real> e(u.size(), Real(0));
    if (u.empty()) return e;
    e[0] = exp(u[0]);
    for (std::size_t k = 1; k < u.size(); ++k) {
        for (std::size_t j = 1; j <= k; ++j) {
            Real v = u[j];
            v *= static_cast<long>(j);
            mul_add(e[k], v, e[k - j]);
        }
        e[k] /= static_cast<long>(k);
    }
    return e;
}

}  // namespace taylor

/// Jorba-Zou order for a tolerance: ceil(-ln(tol) / 2) + 1 (at least 2). A tolerance that would
/// need more than max_taylor_order (mp:N beyond about 86,800 digits) is input_error about the
/// precision, not a failure inside the integrator.
template <class Real>
int taylor_order_for(const Real& tolerance) {
    using std::log;
    const double l = -static_cast<double>(log(tolerance));
    const double p = std::ceil(l / 2) + 1;
    if (!(p <= max_taylor_order))
        throw input_error::about("precision",
                                 "its tolerance needs a Taylor series of order " +
                                     std::to_string(static_cast<long long>(std::min(p, 1e18))) +
                                     ", more than the " + std::to_string(max_taylor_order) +
                                     " the Taylor routes allow (mp:N up to about 86800 digits)");
    return p < 2 ? 2 : static_cast<int>(p);
}

/// A Taylor integrator of fixed order for a state of N reals. The functor f is called as
/// f(jet, k, fk) for k = 0, 1, .., order - 1 in that order from each expansion point: given the
/// coefficients 0..k of every component (jet[i][0..k]), it writes coefficient k of x'(t) into
/// fk (it may keep auxiliary series of its own between the calls of one expansion). Not
/// thread-safe; one object per thread.
template <class Real, std::size_t N>
class taylor_integrator {
  public:
    using state = std::array<Real, N>;
    using jet_type = std::array<std::vector<Real>, N>;

    explicit taylor_integrator(int order) : order_(order), precision_(order) {
        if (order < 1 || order > max_taylor_order)
            throw std::invalid_argument("taylor_integrator: order " + std::to_string(order) +
                                        " outside [1, " + std::to_string(max_taylor_order) + "]");
        for (auto& v : jet_)
            v.assign(static_cast<std::size_t>(order + 1), Real(0));
        for (Real& v : carry_)
            v = 0;
    }

    int order() const { return order_; }
    const jet_type& jet() const { return jet_; }

    /// The Taylor coefficients 0..order of the solution through x; false if one is not finite.
    template <class F>
    bool expand(F& f, const state& x) {
        using boost::multiprecision::isfinite;
        using std::isfinite;
        for (std::size_t i = 0; i < N; ++i) {
            jet_[i][0] = x[i];
            precision_.trim(jet_[i][0], 0);
        }
        for (int k = 0; k < order_; ++k) {
            f(static_cast<const jet_type&>(jet_), k, fk_);
            const auto K = static_cast<std::size_t>(k + 1);
            for (std::size_t i = 0; i < N; ++i) {
                jet_[i][K] = fk_[i];
                taylor::divide(jet_[i][K], k + 1);
                precision_.trim(jet_[i][K], k + 1);
            }
        }
        bool finite = true;
        for (std::size_t i = 0; i < N; ++i)
            finite = finite && isfinite(jet_[i][static_cast<std::size_t>(order_)]);
        return finite;
    }

    /// The last expansion's polynomial at t (dense output; t = 0 gives its expansion point).
    state evaluate(const Real& t) const {
        state out;
        for (std::size_t i = 0; i < N; ++i)
            out[i] = horner(jet_[i], t, 0);
        return out;
    }

    /// Jorba-Zou step size of the last expansion for tolerance tol, the coefficients weighted by
    /// 1 / scale (componentwise).
    Real step_size(const Real& tol, const state& scale) const {
        using std::exp;
        using std::pow;
        Real h = std::numeric_limits<Real>::max();
        for (int j = order_ - 1; j <= order_; ++j) {
            if (j < 1) continue;
            Real n = 0;
            for (std::size_t i = 0; i < N; ++i) {
                using std::abs;
                // (at the working precision: the coefficient may be rounded, see the file comment)
                const Real v =
                    abs(taylor::working(jet_[i][static_cast<std::size_t>(j)])) / scale[i];
                if (v > n) n = v;
            }
            if (n == 0) continue;
            const Real r = pow(tol / n, Real(1) / j);
            if (r < h) h = r;
        }
        const int p = order_ > 2 ? order_ : 2;
        return h * exp(Real(-7) / (10 * (p - 1)));
    }

    /// One step of size h (expand at x, then x = x(h) with compensated summation); false and x
    /// unchanged if a coefficient is not finite.
    template <class F>
    bool step(F& f, state& x, const Real& h, integration_statistics* stats = nullptr) {
        if (!expand(f, x)) return false;
        for (std::size_t i = 0; i < N; ++i) {
            Real inc = horner(jet_[i], h, 1);
            inc *= h;
            inc += carry_[i];
            const Real x1 = x[i] + inc;
            carry_[i] = (x[i] - x1) + inc;
            x[i] = x1;
        }
        if (stats) {
            ++stats->steps;
            stats->rhs_evaluations += order_;
        }
        return true;
    }

    /// `steps` steps of size h from x (in place); observe(k, x) after step k = 1..steps. The
    /// rounding carry starts at zero.
    template <class F, class Observer>
    integration_result integrate(F& f, state& x, const Real& h, long steps, Observer&& observe) {
        for (Real& v : carry_)
            v = 0;
        integration_result r;
        for (long k = 1; k <= steps; ++k) {
            check_cpu_budget();
            if (!step(f, x, h, &r.statistics)) {
                r.success = false;
                return r;
            }
            observe(k, static_cast<const state&>(x));
        }
        return r;
    }
    template <class F>
    integration_result integrate(F& f, state& x, const Real& h, long steps) {
        return integrate(f, x, h, steps, [](long, const state&) {});
    }

  private:
    /// sum_{k >= from} c_k t^(k - from).
    Real horner(const std::vector<Real>& c, const Real& t, int from) const {
        // (from the working precision: the coefficients may be trimmed)
        Real r = taylor::working(c[static_cast<std::size_t>(order_)]);
        for (int k = order_ - 1; k >= from; --k) {
            r *= t;
            r += c[static_cast<std::size_t>(k)];
        }
        return r;
    }

    int order_;
    taylor::coefficient_precision<Real> precision_;
    jet_type jet_;
    state fk_{}, carry_{};
};

/// Equal Taylor steps over `duration` for a tolerance: an adaptive pass (Jorba-Zou steps at
/// order taylor_order_for(tolerance)) gives the smallest step h_min along the way, the equal steps
/// are n = ceil(duration / h_min) (at least min_steps); the error estimate is the weighted max
/// distance at the end between the order-p and order-(p + 4) runs with those n steps (the latter
/// is the more accurate by a factor ~ e^-8). `make_f()` returns a fresh functor per run.
template <class Real, std::size_t N, class MakeF>
step_count_estimate<Real> taylor_steps_for_tolerance(const MakeF& make_f,
                                                     const std::array<Real, N>& x0,
                                                     const Real& duration, const Real& tolerance,
                                                     const std::array<Real, N>& scale,
                                                     long min_steps = 4) {
    using std::abs;
    using std::ceil;
    const int p = taylor_order_for(tolerance);
    step_count_estimate<Real> est;
    est.observed_order = p;
    {
        taylor_integrator<Real, N> ti(p);
        auto f = make_f(p);
        std::array<Real, N> x = x0;
        Real t = 0, hmin = abs(duration);
        // NOTE: at most 2^20 adaptive steps: beyond that the problem is not one of step size
        for (long i = 0; i < (1L << 20) && t < abs(duration); ++i) {
            check_cpu_budget();
            if (!ti.expand(f, x)) return est;
            Real h = ti.step_size(tolerance, scale);
            if (h < hmin) hmin = h;
            if (t + h > abs(duration)) h = abs(duration) - t;
            x = ti.evaluate(duration < 0 ? Real(-h) : h);
            t += h;
        }
        if (t < abs(duration)) return est;
        const Real n = ceil(abs(duration) / hmin);
        est.steps = static_cast<long>(n);
        if (est.steps < min_steps) est.steps = min_steps;
    }
    auto run = [&](int order, std::array<Real, N>& x) {
        taylor_integrator<Real, N> ti(order);
        auto f = make_f(order);
        x = x0;
        return ti.integrate(f, x, duration / est.steps, est.steps).success;
    };
    std::array<Real, N> xa, xb;
    if (!run(p, xa) || !run(p + 4, xb)) {
        est.steps = 0;
        return est;
    }
    Real d = 0;
    for (std::size_t k = 0; k < N; ++k) {
        const Real v = abs(xa[k] - xb[k]) / scale[k];
        if (v > d) d = v;
    }
    est.error_estimate = d;
    est.asymptotic = true;
    return est;
}

}  // namespace flipflux
