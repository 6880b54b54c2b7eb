// 1-D quadrature with error estimates, and the nested (2-D) route built on it.
//
//   tanh_sinh_integrate      double-exponential rule (Boost.Math tanh_sinh; Mori 1985, Bailey et
//                            al. 2005): converges at its full rate for integrands analytic inside
//                            the interval with algebraic endpoint behaviour (sqrt(x - a), ...).
//                            The integrand receives the distances to both endpoints, x - a and
//                            b - x, to full relative accuracy even where x itself has rounded
//                            onto the endpoint: integrands like sqrt(K(x)) with K(a) = 0 evaluate
//                            K from the distance without cancellation.
//   gauss_kronrod_integrate  adaptive 61-point Gauss-Kronrod (Boost.Math's rule and recursion), for
//   smooth
//                            integrands; an independent rule for cross-checks.
//   nested_integrate         the outer integral (tanh-sinh) of inner integrals supplied as
//                            quadrature_results; inner error estimates are propagated.
//
// Results carry {value, error_estimate, l1_norm, levels, evaluations}. error_estimate is absolute:
// for tanh-sinh, from the difference d of the last two refinement levels by the convergence
// model d (d / l1_norm)^(1/2) (each level squares the relative error once converged; the power
// 3/2 leaves room for a late start: tanh_sinh.inst.cpp), d itself when the rule did not converge;
// for Gauss-Kronrod the Kronrod-Gauss difference summed over panels; both plus the rounding level
// eps * l1_norm. tests/prediction/test_error_estimates.cpp checks that the estimates of Omega and
// the upright flux bound the actual errors and lie within 100x of them at double and quad.
//
// Precision: the integrators are built in Real (abscissas and weights in the working precision;
// no double constants). For mp the tanh-sinh rule is constructed with an explicit minimum
// complement 2^-(4 digits + 64) (Boost 1.74's default, 4 * min_value, overflows itrunc).
// Caches: one tanh-sinh integrator per thread and working precision; one Gauss-Kronrod rule per
// type and working precision (gauss_kronrod_61), so no cache is reused at another precision.
// Threads: a tanh_sinh object is not thread-safe while it lazily adds levels (TOOLCHAIN.md), so
// each thread owns its own (thread_local); all functions here may be called concurrently.
#pragma once

#include <cstddef>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "flipflux/core/real.hpp"

namespace flipflux {

/// A non-owning reference to a callable (like C++26 std::function_ref): cheap to pass by value,
/// valid only while the referenced callable lives. Lets the integrators live in compiled
/// translation units (one per real type) while taking any lambda.
template <class Signature>
class function_ref;

template <class R, class... Args>
class function_ref<R(Args...)> {
  public:
    template <class F>
    requires(!std::is_same_v<std::remove_cvref_t<F>, function_ref> &&
             std::is_invocable_r_v<R, F&, Args...>) function_ref(F&& f)
    noexcept  // NOLINT: implicit by design
        : object_(const_cast<void*>(static_cast<const void*>(&f))),
          call_([](void* o, Args... a) -> R {
              return (*static_cast<std::remove_reference_t<F>*>(o))(std::forward<Args>(a)...);
          }) {}
    R operator()(Args... a) const { return call_(object_, std::forward<Args>(a)...); }

  private:
    void* object_;
    R (*call_)(void*, Args...);
};

template <class Real>
struct quadrature_result {
    Real value{0};                ///< the integral
    Real error_estimate{0};       ///< estimated absolute error (conservative, see above)
    Real l1_norm{0};              ///< integral of |f|; l1_norm / |value| is the condition number
    std::size_t levels = 0;       ///< tanh-sinh refinement levels (0 for Gauss-Kronrod)
    std::size_t evaluations = 0;  ///< integrand evaluations

    /// Adds the result over an adjacent interval.
    quadrature_result& operator+=(const quadrature_result& o) {
        value += o.value;
        error_estimate += o.error_estimate;
        l1_norm += o.l1_norm;
        levels = levels > o.levels ? levels : o.levels;
        evaluations += o.evaluations;
        return *this;
    }
};

/// The default relative tolerance of tanh-sinh: eps^(2/3). The rule stops when two successive
/// levels agree to the tolerance; as each level roughly doubles the number of correct digits,
/// the last level is then accurate far beyond the tolerance. NOTE: sqrt(eps), Boost's default,
/// is not enough when the integrand has a near singularity (the doubling then starts late): the
/// phase volume of a pendulum with a light first link came out 3e-13 off in double.
template <class Real>
Real default_quadrature_tolerance();

/// The default relative tolerance of adaptive Gauss-Kronrod: eps^(3/4) (the Kronrod sum is
/// accurate to about the 3/2 power of the Kronrod-Gauss difference used as estimate).
template <class Real>
Real default_kronrod_tolerance();

template <class Real>
struct quadrature_options {
    Real relative_tolerance{0};  ///< 0: the rule's default (see above)
    std::size_t max_depth = 15;  ///< Gauss-Kronrod bisection depth (tanh-sinh: 15 levels, fixed)
};

/// f(x, x - a, b - x).
template <class Real>
using endpoint_integrand = function_ref<Real(const Real& x, const Real& to_a, const Real& to_b)>;

/// Integral of f over [a, b] (a < b, both finite) by tanh-sinh. a == b gives 0.
/// Throws std::domain_error for a > b or non-finite bounds, boost's evaluation_error when f
/// returns a non-finite value.
template <class Real>
quadrature_result<Real> tanh_sinh_integrate(endpoint_integrand<Real> f, const Real& a,
                                            const Real& b, const quadrature_options<Real>& = {});

/// Sum of tanh-sinh integrals over the consecutive intervals [p0, p1], [p1, p2], ... of the
/// increasing break points p (f sees the distances to the ends of its own piece).
template <class Real>
quadrature_result<Real> tanh_sinh_integrate_pieces(endpoint_integrand<Real> f,
                                                   const std::vector<Real>& breakpoints,
                                                   const quadrature_options<Real>& = {});

/// Integral over [a, b] by tanh-sinh on pieces graded geometrically (ratio 4) towards an end
/// whose integrand has a singularity just outside the interval, at distance r_a beyond a (r_b
/// beyond b): break points a + r_a, a + 4 r_a, ... up to the middle. Tanh-sinh converges at its
/// full rate only when the nearest singularity is not much closer to the interval than its
/// length; e.g. sqrt(K) near a pair of close zeros of K. f receives the distances to a and b
/// of the whole interval (to full relative accuracy near a and b). r = 0 (or r >= (b - a)/4):
/// no grading at that end.
template <class Real>
quadrature_result<Real> tanh_sinh_integrate_graded(endpoint_integrand<Real> f, const Real& a,
                                                   const Real& b, const Real& r_a, const Real& r_b,
                                                   const quadrature_options<Real>& = {});

/// Integral over [a, b] of an f analytic inside [a, b] and bounded, whose end behaviour is a power
/// series in sqrt(x - a) and sqrt(b - x) (square-root branch points at the ends), by the
/// substitution x = a + (b - a) sin^2(u/2), which makes the integrand analytic in u on [0, pi],
/// and nested Clenshaw-Curtis rules in u of 32, 64, ... up to max_intervals intervals (a power of
/// 2; each rule reuses the last one's nodes; f being bounded, the ends, where dx/du = 0,
/// contribute nothing: M - 1 evaluations). The
/// rules converge geometrically, at a rate set by f's complex singularity nearest to [a, b]: the
/// first rule that agrees with the one before to the tolerance (relative to the L1 norm) is
/// returned, its error estimate from their difference by tanh-sinh's convergence model
/// (tanh_sinh.inst.cpp); nothing is returned when none does, and the caller uses tanh-sinh. Far
/// fewer evaluations than tanh-sinh where the singularities are not close (Omega at quad: 127 or
/// 255; bench/results/omega_quad.txt has the times against tanh-sinh's).
template <class Real>
std::optional<quadrature_result<Real>> sine_squared_clenshaw_curtis(
    endpoint_integrand<Real> f, const Real& a, const Real& b, std::size_t max_intervals,
    const quadrature_options<Real>& = {});

/// The 61-point Gauss-Kronrod rule on [-1, 1] in the working precision, by symmetry: abscissa[i]
/// >= 0 ascending (abscissa[0] = 0), kronrod_weights[i] of +-abscissa[i], gauss_weights[i / 2] of
/// the 30-point Gauss rule at the odd indices i. Built once per type and precision; thread-safe.
template <class Real>
struct gauss_kronrod_rule {
    std::vector<Real> abscissa, kronrod_weights, gauss_weights;
};
template <class Real>
const gauss_kronrod_rule<Real>& gauss_kronrod_61();

/// Integral of a smooth f over [a, b] by adaptive 61-point Gauss-Kronrod.
template <class Real>
quadrature_result<Real> gauss_kronrod_integrate(function_ref<Real(const Real&)> f, const Real& a,
                                                const Real& b,
                                                const quadrature_options<Real>& = {});

/// Non-adaptive 61-point Gauss-Kronrod on `panels` equal panels of [a, b]: the fixed rule for
/// integrands whose strip of analyticity is known (choose panels with kronrod_panels). The error
/// estimate is the summed Kronrod-Gauss difference (the Kronrod sum is accurate to about its
/// 3/2 power); callers fall back to an adaptive rule when it exceeds their tolerance.
template <class Real>
quadrature_result<Real> gauss_kronrod_fixed(function_ref<Real(const Real&)> f, const Real& a,
                                            const Real& b, std::size_t panels);

/// Panels for gauss_kronrod_fixed over an interval of length `length` for an integrand analytic
/// in the strip |Im z| < strip_half_width: each panel's Bernstein ellipse reaches
/// rho = eps^(-1/90), where the 30-point Gauss error rho^-60 is eps^(2/3) and the Kronrod error
/// ~ eps. Returns 0 when more than max_panels would be needed (use an adaptive rule then).
template <class Real>
std::size_t kronrod_panels(const Real& length, const Real& strip_half_width,
                           std::size_t max_panels = 64);

/// The outer tanh-sinh integral over [a, b] (graded as tanh_sinh_integrate_graded with r_a, r_b)
/// of inner(x, x - a, b - x).value; the result's error estimate adds the outer estimate and the
/// largest relative inner estimate times the outer l1 norm; evaluations count the inner
/// integrands' evaluations.
template <class Real>
quadrature_result<Real> nested_integrate(
    function_ref<quadrature_result<Real>(const Real& x, const Real& to_a, const Real& to_b)> inner,
    const Real& a, const Real& b, const Real& r_a = Real(0), const Real& r_b = Real(0),
    const quadrature_options<Real>& outer = {});

#define FLIPFLUX_QUADRATURE_EXTERN(R)                                                             \
    extern template R default_quadrature_tolerance<R>();                                          \
    extern template R default_kronrod_tolerance<R>();                                             \
    extern template quadrature_result<R> tanh_sinh_integrate<R>(                                  \
        endpoint_integrand<R>, const R&, const R&, const quadrature_options<R>&);                 \
    extern template quadrature_result<R> tanh_sinh_integrate_pieces<R>(                           \
        endpoint_integrand<R>, const std::vector<R>&, const quadrature_options<R>&);              \
    extern template quadrature_result<R> tanh_sinh_integrate_graded<R>(                           \
        endpoint_integrand<R>, const R&, const R&, const R&, const R&,                            \
        const quadrature_options<R>&);                                                            \
    extern template std::optional<quadrature_result<R>> sine_squared_clenshaw_curtis<R>(          \
        endpoint_integrand<R>, const R&, const R&, std::size_t, const quadrature_options<R>&);    \
    extern template const gauss_kronrod_rule<R>& gauss_kronrod_61<R>();                           \
    extern template quadrature_result<R> gauss_kronrod_integrate<R>(                              \
        function_ref<R(const R&)>, const R&, const R&, const quadrature_options<R>&);             \
    extern template quadrature_result<R> gauss_kronrod_fixed<R>(function_ref<R(const R&)>,        \
                                                                const R&, const R&, std::size_t); \
    extern template std::size_t kronrod_panels<R>(const R&, const R&, std::size_t);               \
    extern template quadrature_result<R> nested_integrate<R>(                                     \
        function_ref<quadrature_result<R>(const R&, const R&, const R&)>, const R&, const R&,     \
        const R&, const R&, const quadrature_options<R>&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_QUADRATURE_EXTERN)
#undef FLIPFLUX_QUADRATURE_EXTERN

}  // namespace flipflux
