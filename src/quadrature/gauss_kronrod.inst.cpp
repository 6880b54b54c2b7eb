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
    const Real tolerance =
        opt.relative_tolerance > 0 ? opt.relative_tolerance : default_kronrod_tolerance<Real>();
    r.value = boost::math::quadrature::gauss_kronrod<Real, 61>::integrate(
        g, a, b, static_cast<unsigned>(opt.max_depth), tolerance, &error, &l1);
    r.error_estimate = error + epsilon<Real>() * l1;
    r.l1_norm = l1;
    r.evaluations = evaluations;
    return r;
}

template <class Real>
quadrature_result<Real> gauss_kronrod_fixed(function_ref<Real(const Real&)> f, const Real& a,
                                            const Real& b, std::size_t panels) {
    using boost::math::quadrature::gauss;
    using boost::math::quadrature::gauss_kronrod;
    using std::abs;
    if (!(a <= b) || panels == 0) {
        throw std::domain_error("gauss_kronrod_fixed: needs a <= b and panels > 0");
    }
    const auto& x = gauss_kronrod<Real, 61>::abscissa();
    const auto& wk = gauss_kronrod<Real, 61>::weights();
    const auto& wg = gauss<Real, 30>::weights();
    quadrature_result<Real> r;
    const Real half = (b - a) / (2 * panels);
    for (std::size_t p = 0; p < panels; ++p) {
        const Real centre = a + (2 * p + 1) * half;
        Real kronrod = wk[0] * f(centre), gauss_sum = 0;
        Real l1 = abs(kronrod);
        for (std::size_t i = 1; i < x.size(); ++i) {
            const Real fp = f(centre + half * x[i]), fm = f(centre - half * x[i]);
            kronrod += wk[i] * (fp + fm);
            l1 += wk[i] * (abs(fp) + abs(fm));
            // Boost's 30-point Gauss rule (even order) sits on the odd indices
            if (i % 2 == 1) gauss_sum += wg[i / 2] * (fp + fm);
        }
        r.value += half * kronrod;
        r.error_estimate += half * abs(kronrod - gauss_sum);
        r.l1_norm += half * l1;
    }
    r.evaluations = panels * (2 * x.size() - 1);
    r.error_estimate += epsilon<Real>() * r.l1_norm;
    return r;
}

template <class Real>
std::size_t kronrod_panels(const Real& length, const Real& strip_half_width,
                           std::size_t max_panels) {
    using std::ceil;
    using std::pow;
    if (!(length > 0)) return 1;
    if (!(strip_half_width > 0)) return 0;
    const Real rho = pow(epsilon<Real>(), Real(-1) / 90);
    // Bernstein ellipse through i d for the panel [-h, h]: rho = d/h + sqrt(1 + (d/h)^2)
    const Real half_width = 2 * rho * strip_half_width / (rho * rho - 1);
    const Real n = ceil(length / (2 * half_width));
    if (n > max_panels) return 0;
    return n < 1 ? 1 : static_cast<std::size_t>(n);
}

template quadrature_result<inst_real> gauss_kronrod_fixed<inst_real>(
    function_ref<inst_real(const inst_real&)>, const inst_real&, const inst_real&, std::size_t);
template std::size_t kronrod_panels<inst_real>(const inst_real&, const inst_real&, std::size_t);
template quadrature_result<inst_real> gauss_kronrod_integrate<inst_real>(
    function_ref<inst_real(const inst_real&)>, const inst_real&, const inst_real&,
    const quadrature_options<inst_real>&);

}  // namespace flipflux
