// Symplectic Gauss-Legendre implicit Runge-Kutta methods (s stages, order 2s) for autonomous
// systems x' = f(x), generic over the real type.
//
// Method (Hairer, Lubich, Wanner, "Geometric Numerical Integration", II.1.3 and VIII.6):
//     Z_i = h sum_j a_ij f(x + Z_j),   i = 1..s        (stage equations)
//     x1  = x + h sum_j b_j f(x + Z_j) = x + sum_i d_i Z_i,   d = b^T A^{-1},
// with nodes c_i = (1 + xi_i) / 2, xi_i the roots of the Legendre polynomial P_s, weights
// b_i = 1 / ((1 - xi_i^2) P_s'(xi_i)^2) and a_ij = int_0^{c_i} l_j(t) dt (l_j the Lagrange basis on
// the nodes). The method is the collocation method at the Gauss points: symplectic, symmetric
// (time-reversible), of order 2s, and exact differentiation commutes with it (the method applied
// to the variational equations gives the exact Jacobian of the numerical flow).
//
// NOTE: the tableau is computed in Real (Newton on P_s from a double first guess, iterated to the
// type's precision) and cached per type; flipflux's MPFR types have a fixed precision, so a cache
// keyed by type is keyed by precision (see core/real.hpp).
//
// The stage equations are solved by fixed-point iteration started from the extrapolated
// collocation polynomial of the previous step (Hairer et al. VIII.6.1). The iteration runs until
// the weighted increment is below epsilon or stops decreasing at the rounding floor; a step whose
// iteration has not converged after digits + 10 sweeps (the count a contraction factor of 1/2
// would need from an O(1) start) is reported as failed, never silently accepted. integrate()
// then splits that step into two halves. The update x1 = x + sum d_i Z_i is accumulated with
// compensated summation, so that rounding errors grow like a random walk (Brouwer's law).
//
// Domain and errors: any autonomous f with f(x, dx) writing x' into dx; h may be negative
// (backward integration); stages in [1, max_gauss_legendre_stages], else std::invalid_argument.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/real.hpp"

namespace flipflux {

inline constexpr int max_gauss_legendre_stages = 64;

/// The Butcher tableau of the s-stage Gauss-Legendre method, with the derived coefficients the
/// integrator uses.
template <class Real>
struct gauss_legendre_tableau {
    int stages = 0;
    std::vector<Real> roots;  ///< roots of P_s on [-1, 1], increasing
    std::vector<Real> c;      ///< nodes c_i = (1 + root_i) / 2
    std::vector<Real> b;      ///< weights (sum 1)
    std::vector<Real> a;      ///< A, row-major s x s
    std::vector<Real> d;      ///< d = b^T A^{-1}: x1 = x + sum_i d_i Z_i
    std::vector<Real> e;      ///< extrapolation, row-major: next step's Z_i ~ sum_j e_ij Z_j
    Real A(int i, int j) const { return a[static_cast<std::size_t>(i * stages + j)]; }
};

/// The cached tableau of the `stages`-stage method in Real (thread-safe). Throws
/// std::invalid_argument for stages outside [1, max_gauss_legendre_stages].
template <class Real>
const gauss_legendre_tableau<Real>& gauss_legendre_tableau_of(int stages);

/// Builds the tableau afresh (what the cache stores); exposed for the tests.
template <class Real>
gauss_legendre_tableau<Real> make_gauss_legendre_tableau(int stages);

#define FLIPFLUX_GL_EXTERN(R)                                                           \
    extern template const gauss_legendre_tableau<R>& gauss_legendre_tableau_of<R>(int); \
    extern template gauss_legendre_tableau<R> make_gauss_legendre_tableau<R>(int);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_GL_EXTERN)
#undef FLIPFLUX_GL_EXTERN

/// Counters of an integration.
struct integration_statistics {
    long steps = 0;                ///< accepted steps (a split step counts once per piece)
    long split_steps = 0;          ///< steps whose stage iteration failed and were halved
    long stage_iterations = 0;     ///< fixed-point sweeps, summed over steps
    int max_stage_iterations = 0;  ///< worst single step
    long rhs_evaluations = 0;
};

/// Outcome of integrate(): success, or the stage iteration could not converge even after
/// splitting a step `max_split_depth` times.
struct integration_result {
    bool success = true;
    integration_statistics statistics;
};

/// An s-stage Gauss-Legendre integrator for a state of N reals. Not thread-safe (it keeps the
/// previous step's stages for the starting guess); use one object per thread.
template <class Real, std::size_t N>
class gauss_legendre {
  public:
    using state = std::array<Real, N>;
    static constexpr int max_split_depth = 12;

    explicit gauss_legendre(int stages)
        : t_(&gauss_legendre_tableau_of<Real>(stages)),
          z_(static_cast<std::size_t>(stages)),
          zn_(static_cast<std::size_t>(stages)),
          fz_(static_cast<std::size_t>(stages)),
          lag_(static_cast<std::size_t>(stages)) {
        for (Real& v : carry_)
            v = 0;
    }

    int stages() const { return t_->stages; }
    int order() const { return 2 * t_->stages; }
    const gauss_legendre_tableau<Real>& tableau() const { return *t_; }
    /// Fixed-point sweeps allowed per step: digits + 10.
    static int max_iterations() { return binary_digits<Real>() + 10; }

    /// Forgets the previous step (its stages seed the next step's iteration) and the rounding
    /// carry of compensated summation. Call when x is changed from outside.
    void forget() {
        have_history_ = false;
        for (Real& v : carry_)
            v = 0;
    }

    /// One step of size h, x updated in place. Returns false and leaves x unchanged when the stage
    /// iteration does not converge.
    template <class F>
    bool step(const F& f, state& x, const Real& h, integration_statistics* stats = nullptr) {
        integration_statistics local;
        integration_statistics& s = stats ? *stats : local;
        const int ns = t_->stages;
        // starting guess: the previous collocation polynomial extrapolated, or an Euler slope
        if (have_history_ && h == h_prev_) {
            for (int i = 0; i < ns; ++i)
                for (std::size_t k = 0; k < N; ++k) {
                    Real v = 0;
                    for (int j = 0; j < ns; ++j)
                        v += t_->e[static_cast<std::size_t>(i * ns + j)] * z_[j][k];
                    zn_[i][k] = v;
                }
            for (int i = 0; i < ns; ++i)
                z_[i] = zn_[i];
        } else {
            euler_guess(f, x, h, s);
        }
        return solve_and_update(f, x, h, s);
    }

    /// Steps from the same initial state as the last (successful) step, with a new step size h:
    /// the stage iteration starts from the last step's collocation polynomial evaluated at the new
    /// nodes, which makes a sequence of steps of nearby sizes from one point (root finding in the
    /// step size) cheap. Without a last step this is step(). The caller must pass the last step's
    /// initial state, not its result.
    template <class F>
    bool restep(const F& f, state& x, const Real& h, integration_statistics* stats = nullptr) {
        integration_statistics local;
        integration_statistics& s = stats ? *stats : local;
        for (Real& v : carry_)
            v = 0;
        if (!have_history_ || h_prev_ == 0) {
            euler_guess(f, x, h, s);
            return solve_and_update(f, x, h, s);
        }
        const int ns = t_->stages;
        const Real r = h / h_prev_;
        // Z_i = u(c_i r) - x with u(t) = x + sum_j Z_j lt_j(t), lt_j the Lagrange basis on
        // {0, c_1, .., c_s} for node c_j
        for (int i = 0; i < ns; ++i) {
            const Real t = t_->c[i] * r;
            for (int j = 0; j < ns; ++j) {
                Real l = t / t_->c[j];
                for (int m = 0; m < ns; ++m)
                    if (m != j) l *= (t - t_->c[m]) / (t_->c[j] - t_->c[m]);
                lag_[static_cast<std::size_t>(j)] = l;
            }
            for (std::size_t k = 0; k < N; ++k) {
                Real v = 0;
                for (int j = 0; j < ns; ++j)
                    v += lag_[static_cast<std::size_t>(j)] * z_[j][k];
                zn_[i][k] = v;
            }
        }
        for (int i = 0; i < ns; ++i)
            z_[i] = zn_[i];
        return solve_and_update(f, x, h, s);
    }

    /// The collocation polynomial of the last successful step at the fraction theta of it
    /// (u(0) = x0, the step's initial state, which the caller passes): accurate to order s + 1,
    /// enough to locate events; polish them with restep() from x0 (full order 2 s).
    state collocation(const state& x0, const Real& theta) const {
        const int ns = t_->stages;
        state u = x0;
        for (int j = 0; j < ns; ++j) {
            Real l = theta / t_->c[j];
            for (int m = 0; m < ns; ++m)
                if (m != j) l *= (theta - t_->c[m]) / (t_->c[j] - t_->c[m]);
            for (std::size_t k = 0; k < N; ++k)
                u[k] += l * z_[static_cast<std::size_t>(j)][k];
        }
        return u;
    }

    /// `steps` steps of size h from x (in place); observe(k, x) after step k = 1..steps (a step
    /// that had to be split is observed once, at its end). Each call starts afresh (forget()).
    template <class F, class Observer>
    integration_result integrate(const F& f, state& x, const Real& h, long steps,
                                 Observer&& observe) {
        forget();
        integration_result r;
        for (long k = 1; k <= steps; ++k) {
            check_cpu_budget();
            if (!step(f, x, h, &r.statistics)) {
                ++r.statistics.split_steps;
                if (!split_step(f, x, h, 1, r.statistics)) {
                    r.success = false;
                    return r;
                }
                forget_history_only();
            }
            observe(k, static_cast<const state&>(x));
        }
        return r;
    }
    template <class F>
    integration_result integrate(const F& f, state& x, const Real& h, long steps) {
        return integrate(f, x, h, steps, [](long, const state&) {});
    }

  private:
    void forget_history_only() { have_history_ = false; }

    template <class F>
    void euler_guess(const F& f, const state& x, const Real& h, integration_statistics& s) {
        f(x, fz_[0]);
        ++s.rhs_evaluations;
        for (int i = 0; i < t_->stages; ++i)
            for (std::size_t k = 0; k < N; ++k)
                z_[i][k] = t_->c[i] * h * fz_[0][k];
    }

    /// The fixed-point iteration from the guess in z_, then x1 = x + sum d_i Z_i.
    template <class F>
    bool solve_and_update(const F& f, state& x, const Real& h, integration_statistics& s) {
        const int ns = t_->stages;
        using std::abs;
        const Real eps = std::numeric_limits<Real>::epsilon();
        const Real floor = 1024 * eps;
        Real previous = std::numeric_limits<Real>::max();
        bool converged = false;
        int it = 0;
        for (it = 1; it <= max_iterations(); ++it) {
            for (int i = 0; i < ns; ++i) {
                for (std::size_t k = 0; k < N; ++k)
                    y_[k] = x[k] + z_[i][k];
                f(y_, fz_[i]);
            }
            s.rhs_evaluations += ns;
            Real delta = 0;
            bool finite = true;
            for (int i = 0; i < ns; ++i) {
                for (std::size_t k = 0; k < N; ++k) {
                    Real v = 0;
                    for (int j = 0; j < ns; ++j)
                        v += t_->A(i, j) * fz_[j][k];
                    v *= h;
                    const Real diff = abs(v - z_[i][k]);
                    if (!(diff == diff) || !(abs(v) < std::numeric_limits<Real>::max())) {
                        finite = false;
                    } else if (diff != 0) {
                        const Real term = diff / (abs(x[k]) + abs(v));
                        if (term > delta) delta = term;
                    }
                    z_[i][k] = v;
                }
            }
            if (!finite) break;
            // NOTE: converged at epsilon, or when the increment stops shrinking at the rounding
            // floor (it cannot shrink further); a stall above the floor keeps iterating.
            if (delta <= eps || (delta >= previous && delta <= floor)) {
                converged = true;
                break;
            }
            previous = delta;
        }
        s.stage_iterations += it;
        if (it > s.max_stage_iterations) s.max_stage_iterations = it;
        if (!converged) {
            have_history_ = false;
            return false;
        }
        // x1 = x + sum d_i Z_i, compensated
        for (std::size_t k = 0; k < N; ++k) {
            Real inc = carry_[k];
            for (int i = 0; i < ns; ++i)
                inc += t_->d[i] * z_[i][k];
            const Real x1 = x[k] + inc;
            carry_[k] = (x[k] - x1) + inc;
            x[k] = x1;
        }
        have_history_ = true;
        h_prev_ = h;
        ++s.steps;
        return true;
    }

    template <class F>
    bool split_step(const F& f, state& x, const Real& h, int depth, integration_statistics& s) {
        if (depth > max_split_depth) return false;
        const Real half = h / 2;
        for (int piece = 0; piece < 2; ++piece) {
            if (!step(f, x, half, &s)) {
                if (!split_step(f, x, half, depth + 1, s)) return false;
            }
        }
        return true;
    }

    const gauss_legendre_tableau<Real>* t_;
    std::vector<state> z_, zn_, fz_;
    std::vector<Real> lag_;
    state y_{}, carry_{};
    bool have_history_ = false;
    Real h_prev_{0};
};

/// How many equal steps of one method reach a requested accuracy over `duration`.
template <class Real>
struct step_count_estimate {
    long steps = 0;             ///< recommended number of steps
    Real error_estimate{0};     ///< estimated weighted max error of the endpoint with `steps`
    double observed_order = 0;  ///< order seen between the pilot runs (2 s when asymptotic)
    bool asymptotic = false;    ///< the pilot runs were in the asymptotic regime (or at roundoff)
};

/// Chooses the number of equal steps over `duration` for which the endpoint's error, weighted
/// componentwise by 1/scale_k, is about `tolerance`. Pilot runs with n, 2n and 4n steps
/// (n doubled until the observed order is near 2s or the differences reach rounding) fix the
/// error constant; the recommendation is n_needed = 4n (e(4n) / tolerance)^(1/2s), times a safety
/// factor 1.15, never fewer than `min_steps`. With steps far too long the implicit stages can
/// converge to another solution of their equations, the same for n, 2n and 4n steps (and 8n),
/// and such runs agree with each other at any order while all of them are wrong: a run that had
/// to split a step gives no verdict, and a triple's verdict stands only when the next one
/// (2n, 4n, 8n) gives a verdict too.
template <class Real, std::size_t N, class F>
step_count_estimate<Real> steps_for_tolerance(const F& f, const std::array<Real, N>& x0,
                                              const Real& duration, const Real& tolerance,
                                              int stages, const std::array<Real, N>& scale,
                                              long min_steps = 4) {
    using std::abs;
    using std::log2;
    using std::pow;
    gauss_legendre<Real, N> gl(stages);
    const int order = gl.order();
    using state = std::array<Real, N>;
    // the runs so far, by step count (each run once)
    std::vector<std::pair<long, std::optional<state>>> runs;
    auto run = [&](long n) -> const std::optional<state>& {
        for (const auto& r : runs)
            if (r.first == n) return r.second;
        state x = x0;
        std::optional<state> out;
        // (a run whose stage iteration failed somewhere and split that step is not one of n
        // equal steps, and its steps are too long for the implicit stages: no verdict from it)
        const integration_result r = gl.integrate(f, x, duration / n, n);
        if (r.success && r.statistics.split_steps == 0) out = x;
        runs.emplace_back(n, std::move(out));
        return runs.back().second;
    };
    auto distance = [&](const state& a, const state& b) {
        Real d = 0;
        for (std::size_t k = 0; k < N; ++k) {
            const Real v = abs(a[k] - b[k]) / scale[k];
            if (v > d) d = v;
        }
        return d;
    };
    const Real eps = std::numeric_limits<Real>::epsilon();
    // The verdict of the runs with n, 2n and 4n steps (nullopt: none yet).
    auto verdict = [&](long n) -> std::optional<step_count_estimate<Real>> {
        // (copies: run() may reallocate `runs`)
        const std::optional<state> x1 = run(n), x2 = run(2 * n), x4 = run(4 * n);
        if (!x1 || !x2 || !x4) return std::nullopt;
        step_count_estimate<Real> est;
        const Real e1 = distance(*x1, *x4), e2 = distance(*x2, *x4);
        const Real roundoff = 64 * eps * std::sqrt(static_cast<double>(4 * n));
        if (e2 <= roundoff) {  // 2n already at the rounding floor
            est.asymptotic = true;
            est.steps = e1 <= roundoff ? n : 2 * n;
            est.error_estimate = e1 <= roundoff ? e1 : e2;
            est.observed_order = order;
            if (est.steps < min_steps) est.steps = min_steps;
            return est;
        }
        // NOTE: an unstable flow amplifies rounding errors, so the differences can stall at a
        // floor far above eps: small differences that stop shrinking are that floor, not a
        // pre-asymptotic regime (which has large differences)
        if (e1 < Real(1) / 1000 && e2 * 4 >= e1) {
            est.asymptotic = true;
            est.steps = 2 * n < min_steps ? min_steps : 2 * n;
            est.error_estimate = e1 > e2 ? e1 : e2;
            est.observed_order = static_cast<double>(log2(e1 / e2));
            return est;
        }
        const double p = static_cast<double>(log2(e1 / e2));
        // asymptotic when the error ratio shows the method's order (within [-1.5, +3])
        if (p >= order - 1.5 && p <= order + 3) {
            est.asymptotic = true;
            est.observed_order = p;
            // e(4n) ~ e2 / 2^order; error(n') = e(4n) (4n / n')^order
            const Real e4 = e2 / pow(Real(2), order);
            const Real ratio = e4 / tolerance;
            double needed = 4.0 * static_cast<double>(n) *
                            static_cast<double>(pow(ratio, Real(1) / order)) * 1.15;
            long m = static_cast<long>(std::ceil(needed));
            if (m < min_steps) m = min_steps;
            est.steps = m;
            est.error_estimate = e4 * pow(Real(4 * n) / m, order);
            return est;
        }
        return std::nullopt;
    };
    step_count_estimate<Real> est;
    long n = min_steps > 0 ? min_steps : 1;
    using boost::multiprecision::isfinite;
    using std::isfinite;
    bool finite = isfinite(duration);
    for (const Real& v : x0)
        finite = finite && isfinite(v);
    // NOTE: at most 2^20 times the first pilot's steps: beyond that the problem is not one of
    // step size (the estimate is then reported as not asymptotic)
    for (int attempt = 0; finite && attempt < 20; ++attempt, n *= 2) {
        const auto v = verdict(n);
        if (v && verdict(2 * n)) return *v;
    }
    est.steps = 4 * (n / 2);
    est.asymptotic = false;
    return est;
}

}  // namespace flipflux
