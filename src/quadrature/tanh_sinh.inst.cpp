// Tanh-sinh quadrature (Boost.Math) behind flipflux's quadrature API: one integrator per thread,
// endpoint distances passed to the integrand, error estimates floored at the rounding level.
// NOTE: Boost 1.74 declares tanh_sinh::integrate "-> decltype(...) const", which makes the return
// type const, not the member function: the integrator must be non-const.
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

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
    r.error_estimate = error + epsilon<Real>() * l1;
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
    // offsets from a of the break points: the a-side grading, then the b-side one
    std::vector<Real> left{Real(0)}, right;
    if (r_a > finest && 4 * r_a < width) {
        for (Real x = r_a; x < width / 2; x *= 4)
            left.push_back(x);
    }
    if (r_b > finest && 4 * r_b < width) {
        for (Real x = r_b; x < width / 2; x *= 4)
            right.push_back(x);  // distances from b
    }
    std::vector<Real> offsets = left;  // increasing offsets from a; b-side as width - distance
    for (auto it = right.rbegin(); it != right.rend(); ++it) {
        const Real o = width - *it;
        if (o > offsets.back()) offsets.push_back(o);
    }
    quadrature_result<Real> total;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
        const bool last = i + 1 == offsets.size();
        const Real lo = a + offsets[i];
        const Real hi = last ? b : a + offsets[i + 1];
        const Real from_a = offsets[i];  // exact 0 on the first piece
        const Real to_end = last ? Real(0) : Real(width - offsets[i + 1]);  // exact 0 on the last
        auto g = [&](const Real& x, const Real& da, const Real& db) -> Real {
            return f(x, from_a + da, to_end + db);
        };
        total += tanh_sinh_integrate<Real>(g, lo, hi, opt);
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
