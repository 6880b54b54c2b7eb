// Adaptive 61-point Gauss-Kronrod quadrature (Boost.Math) behind flipflux's quadrature API.
// Boost computes the nodes of non-built-in types once, in function-local statics (thread-safe
// initialisation; each flipflux real type has a fixed precision, so the cache is always valid).
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <stdexcept>

#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"

namespace flipflux {

template <class Real>
quadrature_result<Real> gauss_kronrod_integrate(function_ref<Real(const Real&)> f, const Real& a,
                                                const Real& b,
                                                const quadrature_options<Real>& opt) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    if (!isfinite(a) || !isfinite(b) || a > b) {
        throw std::domain_error("gauss_kronrod_integrate: needs finite bounds with a <= b");
    }
    quadrature_result<Real> r;
    if (a == b) return r;
    std::size_t evaluations = 0;
    auto g = [&](const Real& x) -> Real {
        ++evaluations;
        return f(x);
    };
    Real error = 0, l1 = 0;
    r.value = boost::math::quadrature::gauss_kronrod<Real, 61>::integrate(
        g, a, b, static_cast<unsigned>(opt.max_depth), opt.relative_tolerance, &error, &l1);
    r.error_estimate = error + epsilon<Real>() * l1;
    r.l1_norm = l1;
    r.evaluations = evaluations;
    return r;
}

template quadrature_result<inst_real> gauss_kronrod_integrate<inst_real>(
    function_ref<inst_real(const inst_real&)>, const inst_real&, const inst_real&,
    const quadrature_options<inst_real>&);

}  // namespace flipflux
