// Tanh-sinh quadrature (Boost.Math) behind flipflux's quadrature API: one integrator per thread,
// endpoint distances passed to the integrand, error estimates floored at the rounding level.
// NOTE: Boost 1.74 declares tanh_sinh::integrate "-> decltype(...) const", which makes the return
// type const, not the member function: the integrator must be non-const.
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/version.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

#include "convergence.hpp"
#include "flipflux/core/budget.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"

namespace flipflux {
namespace {

/// Levels the tanh-sinh rule may add (Boost's default).
constexpr std::size_t tanh_sinh_levels = 15;

template <class Real>
boost::math::quadrature::tanh_sinh<Real>& thread_integrator() {
    using std::ldexp;
    if constexpr (!has_variable_precision_v<Real>) {
        thread_local boost::math::quadrature::tanh_sinh<Real> integrator(tanh_sinh_levels);
        return integrator;
    } else {
        // NOTE: one integrator per working precision (its abscissas are built in it).
        // Boost 1.74's default minimum complement (4 * min_value) is 2^-(2^30) for MPFR and
        // overflows itrunc; 2^-(4 digits + 64) lies far below every weight that matters.
        thread_local std::map<int, std::unique_ptr<boost::math::quadrature::tanh_sinh<Real>>>
            integrators;
        const int bits = binary_digits<Real>();
        auto& slot = integrators[bits];
        if (!slot)
            slot = std::make_unique<boost::math::quadrature::tanh_sinh<Real>>(
                tanh_sinh_levels, ldexp(Real(1), -(4 * bits + 64)));
        return *slot;
    }
}

}  // namespace

template <class Real>
Real default_quadrature_tolerance() {
    using std::pow;
    return pow(epsilon<Real>(), Real(2) / 3);
}

template <class Real>
Real default_kronrod_tolerance() {
    using std::pow;
    return pow(epsilon<Real>(), Real(3) / 4);
}

template <class Real>
quadrature_result<Real> tanh_sinh_integrate(endpoint_integrand<Real> f, const Real& a,
                                            const Real& b, const quadrature_options<Real>& opt) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    if (!isfinite(a) || !isfinite(b) || a > b) {
        throw std::domain_error("tanh_sinh_integrate: needs finite bounds with a <= b");
    }
    quadrature_result<Real> r;
    if (a == b) return r;
    const Real width = b - a;
    std::size_t evaluations = 0;
    // Boost passes the signed complement: a - x (< 0) in the left half, b - x in the right half.
    auto g = [&](const Real& x, const Real& xc) -> Real {
        ++evaluations;
        check_cpu_budget();
        if (xc < 0) return f(x, -xc, width + xc);
        return f(x, width - xc, xc);
    };
    Real error = 0, l1 = 0;
    std::size_t levels = 0;
    const Real tolerance =
        opt.relative_tolerance > 0 ? opt.relative_tolerance : default_quadrature_tolerance<Real>();
    r.value = thread_integrator<Real>().integrate(g, a, b, tolerance, &error, &l1, &levels);
    // NOTE: Boost 1.74 maps [a, b] to [-1, 1] and scales the integral and L1 back by (b - a) / 2,
    // but not the level difference `error` (boostorg/math issue 449, fixed after 1.74): unscaled,
    // it made the estimate of a piece of width w wrong by about (w / 2)^(3/2) -- 1e11 times too
    // large on the tiny pieces of a graded integral or a tiny allowed region (Omega at E = 1e-15:
    // a relative estimate of 1.2e-4 for a value good to 2e-16), and too small beyond a width of 2,
    // where the convergence test below also compared it with a scaled L1.
#if BOOST_VERSION <= 107400
    error *= width / 2;
#endif
    // Converged: the last two levels agree to the tolerance. Boost also stops, before that, when
    // the level differences have grown twice after level 4 and returns the level before the last
    // growth with its difference d. Measured (Omega, E = 2.05 at double: d = 5e-11 L1, the
    // returned value good to 4e-17): the growth comes from finer levels' abscissas next to an
    // endpoint singularity, where the integrand's rounding is amplified, while the levels up to
    // the returned one converged as usual; the convergence model then holds for it. Only where
    // such a stop leaves d above sqrt(tolerance) L1 (convergence had not begun), or the rule ran
    // out of levels, is d itself the estimate.
    using std::sqrt;
    const bool converged = l1 > 0 && (error <= tolerance * l1 ||
                                      (levels < tanh_sinh_levels && error <= sqrt(tolerance) * l1));
    r.error_estimate =
        (converged ? detail::converged_error(error, l1) : error) + epsilon<Real>() * l1;
    r.l1_norm = l1;
    r.levels = levels;
    r.evaluations = evaluations;
    return r;
}

template <class Real>
quadrature_result<Real> tanh_sinh_integrate_pieces(endpoint_integrand<Real> f,
                                                   const std::vector<Real>& p,
                                                   const quadrature_options<Real>& opt) {
    quadrature_result<Real> total;
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
        total += tanh_sinh_integrate<Real>(f, p[i], p[i + 1], opt);
    return total;
}

template <class Real>
quadrature_result<Real> tanh_sinh_integrate_graded(endpoint_integrand<Real> f, const Real& a,
                                                   const Real& b, const Real& r_a, const Real& r_b,
                                                   const quadrature_options<Real>& opt) {
    const Real width = b - a;
    // NOTE: no grading below the rounding level of the interval (nothing to resolve there)
    const Real finest = 64 * epsilon<Real>() * width;
    // The break points as pairs (distance from a, distance to b), each exact on its own side:
    // a break point r_b 4^k before b keeps its distance to b as computed, never as width minus
    // an offset, which near b = pi loses the distance's digits to the rounding of pi (a branch
    // point 1e-23 from pi at mp:30 then came out to 17 digits, and tanh-sinh ran to its last
    // level on every piece: 24 s where 6.5 s do now).
    struct break_point {
        Real from_a, to_b;
    };
    std::vector<break_point> points{{Real(0), width}};
    if (r_a > finest && 4 * r_a < width) {
        for (Real x = r_a; x < width / 2; x *= 4)
            points.push_back({x, Real(width - x)});
    }
    std::vector<Real> right;  // distances from b, increasing
    if (r_b > finest && 4 * r_b < width) {
        for (Real x = r_b; x < width / 2; x *= 4)
            right.push_back(x);
    }
    for (auto it = right.rbegin(); it != right.rend(); ++it)
        if (width - *it > points.back().from_a) points.push_back({Real(width - *it), *it});
    points.push_back({width, Real(0)});
    quadrature_result<Real> total;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const break_point &lo = points[i], &hi = points[i + 1];
        if (lo.from_a <= lo.to_b) {  // a piece that starts on a's side: in x itself
            const Real x_lo = a + lo.from_a;
            const Real x_hi = i + 2 == points.size() ? b : Real(a + hi.from_a);
            auto g = [&](const Real& x, const Real& da, const Real& db) -> Real {
                return f(x, lo.from_a + da, hi.to_b + db);
            };
            total += tanh_sinh_integrate<Real>(g, x_lo, x_hi, opt);
        } else {  // on b's side: in u = x - x_lo in [0, length], length from the exact distances
            const Real x_lo = b - lo.to_b, length = lo.to_b - hi.to_b;
            auto g = [&](const Real& u, const Real& du_lo, const Real& du_hi) -> Real {
                return f(x_lo + u, lo.from_a + du_lo, hi.to_b + du_hi);
            };
            total += tanh_sinh_integrate<Real>(g, Real(0), length, opt);
        }
    }
    return total;
}

template <class Real>
quadrature_result<Real> nested_integrate(
    function_ref<quadrature_result<Real>(const Real&, const Real&, const Real&)> inner,
    const Real& a, const Real& b, const Real& r_a, const Real& r_b,
    const quadrature_options<Real>& opt) {
    using std::abs;
    std::size_t evaluations = 0;
    Real worst_relative = 0;
    auto outer = [&](const Real& x, const Real& to_a, const Real& to_b) -> Real {
        const quadrature_result<Real> r = inner(x, to_a, to_b);
        evaluations += r.evaluations;
        if (r.l1_norm > 0) {
            const Real rel = r.error_estimate / r.l1_norm;
            if (rel > worst_relative) worst_relative = rel;
        }
        return r.value;
    };
    quadrature_result<Real> r = tanh_sinh_integrate_graded<Real>(outer, a, b, r_a, r_b, opt);
    r.error_estimate += worst_relative * r.l1_norm;
    r.evaluations = evaluations;
    return r;
}

#define FLIPFLUX_TANH_SINH_INSTANTIATE(R)                                                         \
    template R default_quadrature_tolerance<R>();                                                 \
    template R default_kronrod_tolerance<R>();                                                    \
    template quadrature_result<R> tanh_sinh_integrate<R>(endpoint_integrand<R>, const R&,         \
                                                         const R&, const quadrature_options<R>&); \
    template quadrature_result<R> tanh_sinh_integrate_pieces<R>(                                  \
        endpoint_integrand<R>, const std::vector<R>&, const quadrature_options<R>&);              \
    template quadrature_result<R> tanh_sinh_integrate_graded<R>(endpoint_integrand<R>, const R&,  \
                                                                const R&, const R&, const R&,     \
                                                                const quadrature_options<R>&);    \
    template quadrature_result<R> nested_integrate<R>(                                            \
        function_ref<quadrature_result<R>(const R&, const R&, const R&)>, const R&, const R&,     \
        const R&, const R&, const quadrature_options<R>&)
FLIPFLUX_TANH_SINH_INSTANTIATE(inst_real);

}  // namespace flipflux
