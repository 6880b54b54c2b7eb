// Adaptive explicit Runge-Kutta integrators with dense output, in double precision:
//   dormand_prince_5   Dormand & Prince (1980) 5(4), FSAL, 4th-order dense output (Shampine 1986)
//                      -- the method of MATLAB's ode45 and Hairer's DOPRI5;
//   dormand_prince_853 Hairer's DOP853: 8th order, error estimator combining 5th and 3rd-order
//                      embedded formulas, 7th-order dense output from 3 extra stages
//                      (Hairer, Norsett & Wanner, Solving ODEs I, 2nd ed., Sec. II.10).
// They integrate x' = f(t, x) for x in R^N forward in time and know nothing of pendulums.
//
// Error control (Hairer's, as in DOPRI5/DOP853): a step is accepted when
//     err = || e_i / sc_i ||_rms <= 1,   sc_i = atol + rtol * max(|x_i(t)|, |x_i(t+h)|),
// over the first `controlled_components` components (all by default). Leaving components out
// lets auxiliary equations (e.g. variational equations) ride along without changing the steps of
// the primary solution: the primary components are then bit-identical with or without them.
// Step-size update h_new = h * clamp(0.9 * err^(-1/q) [* err_old^beta], fac_min, fac_max), with
// q = 5, beta = 0.04 (PI control), fac in [0.2, 10] for DOPRI5 and q = 8, beta = 0, fac in
// [1/3, 6] for DOP853 (Hairer's defaults; err^(-1/8) as three square roots, not pow). The local
// error per unit step is thus kept near rtol relative to the state; the global error of a
// non-chaotic problem grows roughly linearly in time and is proportional to rtol (verified in
// tests/integrators/test_explicit_rk.cpp).
//
// Dense output: after each accepted step, dense(t) for t in [t_previous(), t()] evaluates the
// continuous extension: DOPRI5's is free (uses the step's stages), DOP853's needs 3 more
// evaluations of f, done once per step on the first call. Interpolation error: O(h^5) (DOPRI5)
// and O(h^8) (DOP853) per step, i.e. of the order of the step's local error.
//
// Outcomes are data (rk_status), not exceptions: a non-finite right-hand side or a step size that
// underflows stops the integration with a status.
//
// NOTE: the coefficients are double literals (DOP853's are irrational, published to 30 digits):
// these methods are for double only (static_assert). Higher precisions use the Gauss-Legendre
// integrator (integrators/gauss_legendre.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "flipflux/core/names.hpp"
#include "flipflux/integrators/dormand_prince_tableaux.hpp"

namespace flipflux {

/// Options of an explicit Runge-Kutta integration.
struct rk_options {
    double rtol = 1e-10;                    ///< relative tolerance (> 0)
    double atol = 1e-10;                    ///< absolute tolerance per component (> 0)
    std::size_t controlled_components = 0;  ///< error norm over the first this many (0 = all)
    double initial_step = 0;                ///< 0: Hairer's automatic starting step
    double max_step = std::numeric_limits<double>::infinity();
    double fixed_step = 0;  ///< > 0: no error control, steps of this size (tests)
};

enum class rk_status {
    ok,                   ///< the step was accepted
    step_size_underflow,  ///< the step size fell below 16 ulp of t: the problem is too
                          ///< stiff/singular
    non_finite,           ///< the right-hand side produced NaN or infinity
};

template <>
struct enum_table<rk_status> {
    static constexpr std::string_view noun = "an integration status";
    static constexpr std::array<std::pair<rk_status, std::string_view>, 3> entries{
        {{rk_status::ok, "ok"},
         {rk_status::step_size_underflow, "step size underflow"},
         {rk_status::non_finite, "non-finite right-hand side"}}};
};

/// An adaptive embedded Runge-Kutta integrator of x' = f(t, x), x in R^N, with dense output.
/// F: callable as `std::array<double, N> f(double t, const std::array<double, N>& x)`.
/// Usage: construct, initialize(t0, x0), then step(t_end) repeatedly until t() == t_end; after
/// each accepted step, dense(t) interpolates on [t_previous(), t()].
template <class Method, std::size_t N, class F>
class explicit_rk {
  public:
    using state = std::array<double, N>;

    explicit explicit_rk(F f, rk_options options = {}) : f_(std::move(f)), opt_(options) {
        if (!(opt_.rtol > 0) || !(opt_.atol > 0) || !std::isfinite(opt_.rtol) ||
            !std::isfinite(opt_.atol))
            throw std::invalid_argument("explicit_rk: rtol and atol must be finite and > 0");
        if (opt_.controlled_components == 0 || opt_.controlled_components > N)
            opt_.controlled_components = N;
        if (!(opt_.max_step > 0)) throw std::invalid_argument("explicit_rk: max_step must be > 0");
    }

    /// Starts (or restarts) at (t0, x0).
    void initialize(double t0, const state& x0) {
        t_ = t_prev_ = t0;
        x_ = x_prev_ = x0;
        fx_ = f_prev_ = eval(t0, x0);
        h_last_ = 0;
        facold_ = 1e-4;
        last_rejected_ = false;
        dense_ready_ = false;
        h_ = opt_.fixed_step > 0     ? opt_.fixed_step
             : opt_.initial_step > 0 ? opt_.initial_step
                                     : initial_step();
        h_ = std::min(h_, opt_.max_step);
    }

    /// Takes one accepted step towards t_end (> t()), landing exactly on t_end when it is reached.
    rk_status step(double t_end) {
        for (;;) {
            rk_status status = rk_status::ok;
            if (!begin_step(t_end, status)) return status;
            for_each_stage([&]<int s>() { this->template stage<s>(); });
            const int r = end_step(status);
            if (r > 0) return rk_status::ok;
            if (r < 0) return status;
        }
    }

    // ---- phased stepping: step() as begin_step, stage(1) ... stage(stages - 1), end_step. Several
    // integrators advanced in lockstep, stage by stage, give the processor independent chains of
    // work (the stages of one step depend on each other); each integrator's arithmetic is exactly
    // that of step().

    /// Starts a trial step towards t_end (> t()). False (with `status`) when the step size
    /// underflowed.
    bool begin_step(double t_end, rk_status& status) {
        if (!(t_end > t_))
            throw std::invalid_argument("explicit_rk::step: t_end must lie after t()");
        double h = h_;
        bool last = false;
        if (t_ + 1.01 * h >= t_end) {
            h = t_end - t_;
            last = true;
        }
        if (!(h > 16 * std::numeric_limits<double>::epsilon() * std::abs(t_)) && !last) {
            status = rk_status::step_size_underflow;
            return false;
        }
        trial_h_ = h;
        trial_last_ = last;
        trial_end_ = t_end;
        copy(fx_.data(), k_[0]);
        return true;
    }

    /// Stage s (1 <= s < stages) of the trial step. The stage index is a template argument: the
    /// tableau row is then unrolled with its zero coefficients dropped.
    template <int s>
    void stage() {
        static_assert(s >= 1 && s < S);
        double y[N];
        stage_point_ct<s>(trial_h_, x_.data(), y);
        if constexpr (s == S - 1) copy(y, x_new_.data());
        eval_into(t_ + Method::c[s] * trial_h_, y, k_[s]);
    }

    /// The stages evaluated by the caller, several integrators at once, lane-major (vectors whose
    /// lanes are the integrators): stage s's point is stage_sum<s> from x(), derivative() (stage
    /// 0) and trial_step(), the same operations as stage<s>(), so the same bits. The caller hands
    /// over the trial step's end (the last stage's point) and f there with set_trial_end, which
    /// counts the stages' evaluations, and the stages in between with set_stage only where the
    /// dense output is used (after an accepted step, before dense()); the error norm and the
    /// step-size factor come with end_step (error_sums, error_norms, step_factors).
    double trial_step() const { return trial_h_; }
    /// Where the trial step ends: t() after it, if accepted.
    double trial_end_time() const { return trial_last_ ? trial_end_ : t_ + trial_h_; }
    void set_trial_end(const double* y, const double* f) {
        copy(y, x_new_.data());
        copy(f, k_[S - 1]);
        evaluations_ += S - 1;
    }
    void set_stage(int s, const double* f) { copy(f, k_[s]); }

    /// y = base + h sum_{j < s} a[s][j] k[j] with the tableau row known at compile time (zero
    /// terms dropped), in the order of stage<s>(), for T double or a vector of lanes (each lane
    /// the same operations as a double).
    /// (always_inline throughout, no lambda: inlined into a caller compiled for AVX2 or AVX-512,
    /// all of it is compiled for that instruction set.)
    template <int s, class T, class Stages>
    [[gnu::always_inline]] static void stage_sum(const T& h, const T* base, const Stages& k, T* y) {
        static_assert(s >= 1 && s < S);
        for (std::size_t i = 0; i < N; ++i)
            y[i] = base[i];
        add_stage_terms<s, 0>(h, k, y);
    }

    /// Calls fn.template operator()<s>() for s = 1, ..., stages - 1 in order.
    template <class Fn>
    static void for_each_stage(Fn&& fn) {
        [&]<int... s>(std::integer_sequence<int, s...>) {
            (fn.template operator()<s + 1>(), ...);
        }
        (std::make_integer_sequence<int, S - 1>{});
    }

    /// Ends the trial step: 1 accepted, 0 rejected (retry with the new step size), -1 failed
    /// (`status` says why).
    int end_step(rk_status& status) {
        const double err = error_norm(trial_h_, x_.data(), x_new_.data(), k_, opt_);
        return end_step(status, err, step_factor(err));
    }
    /// end_step with the error norm and its step-size factor computed by the caller (error_sums
    /// on vectors whose lanes are several integrators, from their start, end point and stages,
    /// then error_norm_from and step_factor per lane: the same bits).
    int end_step(rk_status& status, double err, double factor) {
        return end_step(status, err, factor, [this] { return !check_ || check_(x_, x_new_); });
    }
    /// ... and with the step check given by the caller (check(): true passes; called only where
    /// set_step_check's would be), in place of set_step_check's.
    template <class Check>
    int end_step(rk_status& status, double err, double factor, Check&& check) {
        const double h = trial_h_;
        const double tiny = 16 * std::numeric_limits<double>::epsilon() * std::abs(t_);
        if (opt_.fixed_step > 0 || err <= 1) {
            if (opt_.fixed_step > 0 || check()) {
                accept(h, err, factor, trial_end_time());
                return 1;
            }
            // the error estimate passed but the step check failed: halve and retry
            ++rejected_;
            ++check_rejections_;
            last_rejected_ = true;
            h_ = 0.5 * h;
            if (!(h_ > tiny)) {
                status = rk_status::step_size_underflow;
                return -1;
            }
            return 0;
        }
        ++rejected_;
        last_rejected_ = true;
        if (!std::isfinite(err)) {
            h_ = h * 0.1;
            if (!(h_ > tiny)) {
                status = rk_status::non_finite;
                return -1;
            }
            return 0;
        }
        // err > 1 here, so factor = safety * error_power(err)
        h_ = h * std::max(Method::fac_min, factor);
        if (!(h_ > tiny)) {
            status = rk_status::step_size_underflow;
            return -1;
        }
        return 0;
    }

    /// An optional acceptance test applied after the error test: check(x_old, x_new) == false
    /// rejects the step, which is retried with half its size. For invariants the error
    /// estimate does not see, e.g. a conserved quantity that must not jump: embedded error
    /// estimates occasionally pass a step whose true error is orders of magnitude larger
    /// (DOP853's err5^2 / sqrt(err5^2 + 0.01 err3^2) when the 5th-order estimate happens to
    /// be small in every component). Not applied with fixed_step.
    void set_step_check(std::function<bool(const state&, const state&)> check) {
        check_ = std::move(check);
    }
    /// Steps rejected by the step check (included in rejected_steps()).
    long check_rejections() const { return check_rejections_; }

    /// Integrates to t_end, calling observer(*this) after every accepted step.
    template <class Observer>
    rk_status integrate(double t_end, Observer&& observer) {
        while (t_ < t_end) {
            const rk_status s = step(t_end);
            if (s != rk_status::ok) return s;
            observer(*this);
        }
        return rk_status::ok;
    }

    /// The continuous extension of the last accepted step at t in [t_previous(), t()].
    state dense(double t) {
        if (!dense_ready_) prepare_dense();
        const double th = h_last_ == 0 ? 0 : (t - t_prev_) / h_last_;
        const double th1 = 1 - th;
        state y;
        double* yp = y.data();
        const double* x0 = x_prev_.data();
        for (std::size_t i = 0; i < N; ++i) {
            // y0 + th (r0 + th1 (r1 + th (r2 + th1 (r3 + th (r4 + th1 (r5 + th r6))))))
            double acc = rc_[Method::dense_terms - 1][i];
            for (int j = Method::dense_terms - 2; j >= 0; --j)
                acc = rc_[j][i] + ((j % 2 == 0) ? th1 : th) * acc;
            yp[i] = x0[i] + th * acc;
        }
        return y;
    }

    /// Components 0 ... n - 1 of dense(t) (the same bits) in y and their rates (the derivative
    /// in t of the continuous extension itself) in dy.
    void dense_and_rate(double t, std::size_t n, double* y, double* dy) {
        if (!dense_ready_) prepare_dense();
        const double th = h_last_ == 0 ? 0 : (t - t_prev_) / h_last_;
        const double th1 = 1 - th;
        const double per_t = h_last_ == 0 ? 0 : 1 / h_last_;
        for (std::size_t i = 0; i < n; ++i) {
            // dense()'s nesting, each factor's derivative in th alongside (th1' = -1, th' = 1)
            double acc = rc_[Method::dense_terms - 1][i], dacc = 0;
            for (int j = Method::dense_terms - 2; j >= 0; --j) {
                const bool even = j % 2 == 0;
                dacc = (even ? -acc : acc) + (even ? th1 : th) * dacc;
                acc = rc_[j][i] + (even ? th1 : th) * acc;
            }
            y[i] = x_prev_[i] + th * acc;
            dy[i] = (acc + th * dacc) * per_t;
        }
    }

    /// Bounds {lo, hi} of component i of dense(t) over the whole last accepted step. dense() is
    /// y0 + th r0 + th th1 r1 + th^2 th1 r2 + th^2 th1^2 P(th), th1 = 1 - th, P a polynomial in
    /// th and th1 with the coefficients r3, r4, ... (each term a product of factors in [0, 1]):
    /// the cubic's range (its ends and its interior extrema) widened by (|r3| + |r4| + ...) / 16
    /// and a rounding term (dense()'s own rounding included).
    std::array<double, 2> dense_range(std::size_t i) {
        if (!dense_ready_) prepare_dense();
        const double y0 = x_prev_[i], r0 = rc_[0][i], r1 = rc_[1][i], r2 = rc_[2][i];
        auto cubic = [&](double th) { return y0 + th * (r0 + (1 - th) * (r1 + th * r2)); };
        double lo = std::min(y0, y0 + r0), hi = std::max(y0, y0 + r0);
        // the cubic's derivative: (r0 + r1) + 2 (r2 - r1) th - 3 r2 th^2
        const double a = -3 * r2, b = 2 * (r2 - r1), c = r0 + r1;
        auto extremum = [&](double th) {
            if (th > 0 && th < 1) {
                const double v = cubic(th);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        };
        if (a == 0) {
            if (b != 0) extremum(-c / b);
        } else if (const double disc = b * b - 4 * a * c; disc >= 0) {
            const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
            extremum(q / a);
            if (q != 0) extremum(c / q);
        }
        double rest = 0;
        for (int j = 3; j < Method::dense_terms; ++j)
            rest += std::abs(rc_[j][i]);
        const double rounding = 64 * std::numeric_limits<double>::epsilon() *
                                (std::abs(y0) + std::abs(r0) + std::abs(r1) + std::abs(r2) + rest);
        const double widen = rest / 16 * (1 + 1e-12) + rounding;
        return {lo - widen, hi + widen};
    }

    /// Adds delta to the current state (and to the last step's start, keeping the dense output
    /// valid). Only for directions in which f is invariant (e.g. angles shifted by 2 pi).
    void translate(const state& delta) {
        for (std::size_t i = 0; i < N; ++i) {
            x_[i] += delta[i];
            x_prev_[i] += delta[i];
        }
    }

    /// Multiplies the components i >= first by `factor` everywhere (current state, last step,
    /// stages, dense output), e.g. to renormalise a tangent vector. Valid only for components
    /// whose equations are linear and homogeneous in themselves and do not feed back into the
    /// components below `first` (variational equations): then the integration continues exactly
    /// as if the tail had been scaled from the start.
    void rescale_tail(std::size_t first, double factor) {
        auto scale_tail = [&](double* v) {
            for (std::size_t i = first; i < N; ++i)
                v[i] *= factor;
        };
        scale_tail(x_.data());
        scale_tail(x_prev_.data());
        scale_tail(x_new_.data());
        scale_tail(fx_.data());
        scale_tail(f_prev_.data());
        for (auto& k : k_)
            scale_tail(k);
        for (auto& r : rc_)
            scale_tail(r);
    }

    double t() const { return t_; }
    double t_previous() const { return t_prev_; }
    const state& x() const { return x_; }
    const state& x_previous() const { return x_prev_; }
    const state& derivative() const { return fx_; }               ///< f(t, x)
    const state& derivative_previous() const { return f_prev_; }  ///< at the last step's start
    double last_step() const { return h_last_; }
    double next_step() const { return h_; }
    long accepted_steps() const { return accepted_; }
    long rejected_steps() const { return rejected_; }
    long evaluations() const { return evaluations_; }
    const F& rhs() const { return f_; }
    const rk_options& options() const { return opt_; }

  private:
    // NOTE: the inner loops index raw arrays (C-array tableaux and stage storage, pointers from
    // data()): the same code at -O2, and several times faster in the -O0 coverage build, where
    // every std::array::operator[] is a function call.
    static constexpr int S = Method::stages;
    static constexpr int SD = Method::stages + Method::dense_stages;

    // The square root, of a double or lane by lane of a vector of doubles (SSE2's, two lanes at
    // a time: correctly rounded, the same bits as std::sqrt).
    template <class T>
    [[gnu::always_inline]] static void sqrt_of(const T& x, T& r) {
        if constexpr (std::is_floating_point_v<T>) {
            r = std::sqrt(x);
        } else {
            using pair = double __attribute__((vector_size(16)));
            for (std::size_t l = 0; l < sizeof(T) / sizeof(double); l += 2) {
                const pair p = {x[l], x[l + 1]};
                const pair q = __builtin_ia32_sqrtpd(p);
                r[l] = q[0];
                r[l + 1] = q[1];
            }
        }
    }

  public:
    /// error_norms' and step_factors' square root by default (Root): sqrt_of, std::sqrt for a
    /// double and SSE2's two lanes at a time for a vector of any width. A caller compiled for
    /// wider vectors may pass its own Root (a static of(x, r) per vector type, correctly
    /// rounded, so the same bits): the ensemble's lanes use AVX's and AVX-512's there.
    struct default_root {
        template <class T>
        [[gnu::always_inline]] static void of(const T& x, T& r) {
            sqrt_of(x, r);
        }
    };

  private:
    static void copy(const double* from, double* to) {
        for (std::size_t i = 0; i < N; ++i)
            to[i] = from[i];
    }
    void eval_into(double t, const double* x, double* out) {
        ++evaluations_;
        state xs;
        copy(x, xs.data());
        const state f = f_(t, xs);
        copy(f.data(), out);
    }
    state eval(double t, const state& x) {
        ++evaluations_;
        return f_(t, x);
    }

    // Hairer's hinit: h with h^order * ||f''|| ~ 0.01, capped by 100 times the explicit-Euler
    // guess.
    double initial_step() {
        const std::size_t m = opt_.controlled_components;
        double d0 = 0, d1 = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const double sc = opt_.atol + opt_.rtol * std::abs(x_[i]);
            d0 += (x_[i] / sc) * (x_[i] / sc);
            d1 += (fx_[i] / sc) * (fx_[i] / sc);
        }
        d0 = std::sqrt(d0 / m);
        d1 = std::sqrt(d1 / m);
        double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        h0 = std::min(h0, opt_.max_step);
        state x1;
        for (std::size_t i = 0; i < N; ++i)
            x1[i] = x_[i] + h0 * fx_[i];
        const state f1 = eval(t_ + h0, x1);
        double d2 = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const double sc = opt_.atol + opt_.rtol * std::abs(x_[i]);
            d2 += ((f1[i] - fx_[i]) / sc) * ((f1[i] - fx_[i]) / sc);
        }
        d2 = std::sqrt(d2 / m) / h0;
        const double dm = std::max(d1, d2);
        const double h1 =
            dm <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / dm, 1.0 / Method::order);
        const double h = std::min(100 * h0, h1);
        return std::isfinite(h) && h > 0 ? h : 1e-6;
    }

    // stage_point with the row known at compile time (same arithmetic, zero terms dropped)
    template <int s>
    void stage_point_ct(double h, const double* base, double* y) const {
        stage_sum<s>(h, base, k_, y);
    }
    // the terms j, j + 1, ..., s - 1 of stage_sum<s>
    template <int s, int j, class T, class Stages>
    [[gnu::always_inline]] static void add_stage_terms(const T& h, const Stages& k, T* y) {
        constexpr double a = Method::a[s][j];
        if constexpr (a != 0) {
            for (std::size_t i = 0; i < N; ++i)
                y[i] += h * a * k[j][i];
        }
        if constexpr (j + 1 < s) add_stage_terms<s, j + 1>(h, k, y);
    }

    // y = base + h sum_{j < s} a[s][j] k_j
    void stage_point(int s, double h, const double* base, double* y) const {
        copy(base, y);
        for (int j = 0; j < s; ++j) {
            const double a = Method::a[s][j];
            if (a == 0) continue;
            const double* kj = k_[j];
            for (std::size_t i = 0; i < N; ++i)
                y[i] += h * a * kj[i];
        }
    }

  public:
    /// The embedded error estimate's norm over the controlled components (Hairer's: DOP853's
    /// |h| s5 / sqrt((s5 + 0.01 s3) m) with s5, s3 the sums of squares of the scaled 5th- and
    /// 3rd-order estimates, DOPRI5's RMS of h e / sc) from a step h
    /// with stages k from x0 to x1, in two parts: error_sums, the sums over components, for T
    /// double or a vector whose lanes are several integrators (vector operations then, each
    /// lane's the same as a double's), and error_norm_from, one integrator's norm from its sums.
    /// (always_inline: see stage_sum.)
    template <class T, class Stages>
    [[gnu::always_inline]] static void error_sums(const T& h, const T* x0, const T* x1,
                                                  const Stages& k, const rk_options& o, T& first,
                                                  T& second) {
        const std::size_t m = o.controlled_components;
        first = T{};  // DOP853: s5, s3; DOPRI5: the sum of squares of h e / sc, and 0
        second = T{};
        for (std::size_t i = 0; i < m; ++i) {
            T sc;
            if constexpr (std::is_floating_point_v<T>) {
                sc = o.atol + o.rtol * std::max(std::abs(x0[i]), std::abs(x1[i]));
            } else {
                // lane by lane the same: |-0| = -0 here gives the same scale (atol + rtol * -0),
                // and a < b ? b : a is std::max's rule
                const T a = x0[i] < T{} ? -x0[i] : x0[i], b = x1[i] < T{} ? -x1[i] : x1[i];
                sc = o.atol + o.rtol * (a < b ? b : a);
            }
            if constexpr (Method::order == 5) {
                T e{};
                error_terms<0>(k, i, e, e);
                const T r = h * e / sc;
                first += r * r;
            } else {
                T e5{}, e3{};
                error_terms<0>(k, i, e5, e3);
                e3 -= Method::bhh0 * k[0][i] + Method::bhh8 * k[8][i] + Method::bhh11 * k[11][i];
                first += (e5 / sc) * (e5 / sc);
                second += (e3 / sc) * (e3 / sc);
            }
        }
    }
    /// The step-size update's factor before the PI term and the clamp: safety * err^(-1/q + 0.75
    /// beta) at max(err, 1e-300) (the factor of a rejected step too, whose err exceeds 1), for T
    /// double or a vector whose lanes are several integrators (each lane's the same as a double's:
    /// correctly rounded square roots; DOPRI5's pow lane by lane).
    template <class T, class Root = default_root>
    [[gnu::always_inline]] static void step_factors(const T& err, T& factor) {
        const T tiny = T{} + 1e-300;
        const T e = err < tiny ? tiny : err;  // std::max(err, 1e-300)
        T p;
        error_power<T, Root>(e, p);
        factor = Method::safety * p;
    }
    static double step_factor(double err) {
        double factor;
        step_factors(err, factor);
        return factor;
    }
    /// The error norm from error_sums' sums, for T double or a vector of lanes (the same bits).
    template <class T, class Root = default_root>
    [[gnu::always_inline]] static void error_norms(const T& h, const T& first, const T& second,
                                                   const rk_options& o, T& err) {
        const auto m = static_cast<double>(o.controlled_components);
        if constexpr (Method::order == 5) {
            Root::of(first / m, err);
        } else {
            // as a double: 0 when both sums are, else |h| s5 / sqrt(m (s5 + 0.01 s3)), the
            // denominator 1 when it is not positive; lane by lane the same (|h| as in error_sums,
            // h > 0 anyway)
            const T one = T{} + 1.0;
            T deno = first + 0.01 * second;
            deno = deno > T{} ? deno : one;
            const T ah = h < T{} ? -h : h;
            T root;
            Root::of(deno * m, root);
            const T r = ah * first / root;
            // (nested selects: a vector's & of two comparisons compiles to a compare per lane)
            err = first == T{} ? (second == T{} ? T{} : r) : r;
        }
    }
    static double error_norm_from(double h, double first, double second, const rk_options& o) {
        double err;
        error_norms(h, first, second, o, err);
        return err;
    }

  private:
    // error_sums' sums over the stages, j = 0, 1, ... in order with the terms whose coefficient
    // is zero dropped at compile time (the same sums for finite stages: adding a product +-0 to
    // a sum that started at +0 leaves it as it is): DOPRI5's e in `a` (b aliases a), DOP853's
    // 5th-order e5 in `a` and its 3rd-order estimate's b (tableau row 12) in `b`.
    template <int j, class T, class Stages>
    [[gnu::always_inline]] static void error_terms(const Stages& k, std::size_t i, T& a, T& b) {
        if constexpr (Method::order == 5) {
            if constexpr (j < S) {
                if constexpr (constexpr double c = Method::e[j]; c != 0) a += c * k[j][i];
                error_terms<j + 1>(k, i, a, b);
            }
        } else if constexpr (j < 12) {
            if constexpr (constexpr double c = Method::e5[j]; c != 0) a += c * k[j][i];
            if constexpr (constexpr double c = Method::a[12][j]; c != 0) b += c * k[j][i];
            error_terms<j + 1>(k, i, a, b);
        }
    }
    template <class Stages>
    static double error_norm(double h, const double* x0, const double* x1, const Stages& k,
                             const rk_options& o) {
        double first, second;
        error_sums(h, x0, x1, k, o, first, second);
        return error_norm_from(h, first, second, o);
    }
    // err^(-1/q + 0.75 beta) of the step-size update; for DOP853 (q = 8, beta = 0) as
    // 1 / sqrt(sqrt(sqrt(err))): correctly rounded square roots, a few ulp from pow's value (the
    // factor is clamped to [1/3, 6] anyway) at a fifth of its cost.
    template <class T, class Root = default_root>
    [[gnu::always_inline]] static void error_power(const T& err, T& p) {
        if constexpr (Method::order == 8 && Method::beta == 0) {
            T r1, r2, r3;
            Root::of(err, r1);
            Root::of(r1, r2);
            Root::of(r2, r3);
            p = 1 / r3;
        } else if constexpr (std::is_floating_point_v<T>) {
            p = std::pow(err, -1.0 / Method::order + 0.75 * Method::beta);
        } else {
            for (std::size_t l = 0; l < sizeof(T) / sizeof(double); ++l) {
                double one;
                error_power(double(err[l]), one);
                p[l] = one;
            }
        }
    }

    void accept(double h, double err, double factor, double t_new) {
        ++accepted_;
        double fac = 1;
        if (opt_.fixed_step > 0) {
            h_ = opt_.fixed_step;
        } else {
            // PI control: h_new = h * safety * err^-(1/q - 0.75 beta) * err_old^beta
            fac = factor;
            if constexpr (Method::beta != 0) fac *= std::pow(facold_, Method::beta);
            fac = std::clamp(fac, Method::fac_min, Method::fac_max);
            facold_ = std::max(err, 1e-4);
            double h_new = h * fac;
            if (last_rejected_) h_new = std::min(h_new, h);
            h_ = std::min(h_new, opt_.max_step);
        }
        last_rejected_ = false;
        t_prev_ = t_;
        x_prev_ = x_;
        f_prev_ = fx_;
        t_ = t_new;
        x_ = x_new_;
        copy(k_[S - 1], fx_.data());
        h_last_ = h;
        dense_ready_ = false;
    }

    // The dense output's sums over the stages with the coefficients known at compile time (zero
    // terms dropped: the same sums, in the same order, for finite stages).
    template <int s>
    void dense_stage_point(double h, const double* base, double* y) const {
        for (std::size_t i = 0; i < N; ++i)
            y[i] = base[i];
        add_stage_terms<s, 0>(h, k_, y);
    }
    template <int n, int j = 0, class D>
    [[gnu::always_inline]] void dense_terms_sum(D d, std::size_t i, double& sum) const {
        if constexpr (j < n) {
            if constexpr (constexpr double dj = D{}(j); dj != 0) sum += dj * k_[j][i];
            dense_terms_sum<n, j + 1>(d, i, sum);
        }
    }
    template <int r>
    double dense_row_sum(std::size_t i) const {
        double sum = 0;
        dense_terms_sum<16>([](int j) { return Method::d[r][j]; }, i, sum);
        return sum;
    }

    void prepare_dense() {
        const double h = h_last_;
        const double* x0 = x_prev_.data();
        const double* x1 = x_.data();
        if constexpr (Method::order == 5) {
            // k_ holds the stages of the accepted step (k_[6] = f at its end).
            // Shampine's form: y0 + th (r0 + th1 (r1 + th (r2 + th1 r3))).
            for (std::size_t i = 0; i < N; ++i) {
                const double dx = x1[i] - x0[i];
                const double bspl = h * k_[0][i] - dx;
                rc_[0][i] = dx;
                rc_[1][i] = bspl;
                rc_[2][i] = dx - h * k_[6][i] - bspl;
                double sum = 0;
                dense_terms_sum<7>([](int j) { return Method::d[j]; }, i, sum);
                rc_[3][i] = h * sum;
            }
        } else {
            double y[N];
            [&]<int... s>(std::integer_sequence<int, s...>) {
                ((dense_stage_point<13 + s>(h, x0, y),
                  eval_into(t_prev_ + Method::c[13 + s] * h, y, k_[13 + s])),
                 ...);
            }
            (std::make_integer_sequence<int, 3>{});
            for (std::size_t i = 0; i < N; ++i) {
                const double dx = x1[i] - x0[i];
                rc_[0][i] = dx;
                rc_[1][i] = h * k_[0][i] - dx;
                rc_[2][i] = 2 * dx - h * (k_[12][i] + k_[0][i]);
                [&]<int... r>(std::integer_sequence<int, r...>) {
                    ((rc_[3 + r][i] = h * dense_row_sum<r>(i)), ...);
                }
                (std::make_integer_sequence<int, 4>{});
            }
        }
        dense_ready_ = true;
    }

    F f_;
    rk_options opt_;
    double t_ = 0, t_prev_ = 0, h_ = 0, h_last_ = 0, facold_ = 1e-4;
    double trial_h_ = 0, trial_end_ = 0;
    bool trial_last_ = false;
    bool last_rejected_ = false, dense_ready_ = false;
    state x_{}, x_prev_{}, x_new_{}, fx_{}, f_prev_{};
    double k_[SD][N] = {};
    double rc_[Method::dense_terms][N] = {};
    long accepted_ = 0, rejected_ = 0, evaluations_ = 0, check_rejections_ = 0;
    std::function<bool(const state&, const state&)> check_;

    static_assert(Method::stages + Method::dense_stages >= 7);
};

}  // namespace flipflux
