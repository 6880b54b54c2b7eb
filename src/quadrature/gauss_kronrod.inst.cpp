// 61-point Gauss-Kronrod quadrature: the rule (nodes and weights in the working precision) and the
// adaptive and fixed-panel integrators built on it (quadrature/quadrature.hpp).
//
// The fixed-precision types take Boost.Math's tabulated rule. For mp the rule is computed in the
// working precision (Gauss nodes: zeros of P_30; Kronrod nodes: zeros of the Stieltjes polynomial
// E_31; weights as in Boost's gauss_kronrod_detail, Patterson 1968) and cached per precision:
// Boost's own tables for variable-precision types are function-local statics, frozen at the
// precision of their first use. The adaptive recursion is Boost's gauss_kronrod::integrate
// (bisection while the Kronrod-Gauss difference exceeds both the relative tolerance and the
// halved absolute tolerance), kept here so that it runs on the precision-keyed rule.
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/legendre.hpp>
#include <boost/math/special_functions/legendre_stieltjes.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"

namespace flipflux {
namespace {

constexpr unsigned kronrod_points = 61;
constexpr unsigned gauss_order = (kronrod_points - 1) / 2;  // 30

template <class Real>
gauss_kronrod_rule<Real> tabulated_rule() {
    using boost::math::quadrature::gauss;
    using boost::math::quadrature::gauss_kronrod;
    const auto& x = gauss_kronrod<Real, kronrod_points>::abscissa();
    const auto& wk = gauss_kronrod<Real, kronrod_points>::weights();
    const auto& wg = gauss<Real, gauss_order>::weights();
    gauss_kronrod_rule<Real> r;
    r.abscissa.assign(x.begin(), x.end());
    r.kronrod_weights.assign(wk.begin(), wk.end());
    r.gauss_weights.assign(wg.begin(), wg.end());
    return r;
}

template <class Real>
gauss_kronrod_rule<Real> computed_rule() {
    using boost::math::legendre_p;
    using boost::math::legendre_p_prime;
    gauss_kronrod_rule<Real> r;
    const std::vector<Real> gauss_nodes = boost::math::legendre_p_zeros<Real>(gauss_order);
    const boost::math::legendre_stieltjes<Real> stieltjes(gauss_order + 1);
    // the Kronrod nodes: 0 and one zero of E_31 between consecutive Gauss nodes (and above the
    // last). NOTE: legendre_stieltjes::zeros() does not converge for a run-time-precision type in
    // Boost 1.74 (its Newton step stops ~1e-5 off); a safeguarded Newton iteration here.
    r.abscissa.push_back(Real(0));
    for (std::size_t k = 0; k < gauss_nodes.size(); ++k) {
        Real lo = gauss_nodes[k], hi = k + 1 < gauss_nodes.size() ? gauss_nodes[k + 1] : Real(1);
        const bool rising = stieltjes(lo) < 0;
        Real x = (lo + hi) / 2;
        for (int i = 0; i < 10000; ++i) {
            const Real e = stieltjes(x);
            if (e == 0) break;
            ((e < 0) == rising ? lo : hi) = x;  // keep the sign change bracketed
            Real next = x - e / stieltjes.prime(x);
            if (!(next > lo && next < hi)) next = (lo + hi) / 2;
            using std::abs;
            const bool converged = abs(next - x) <= 4 * epsilon<Real>() * abs(x);
            x = next;
            if (converged) break;
        }
        r.abscissa.push_back(gauss_nodes[k]);
        r.abscissa.push_back(x);
    }
    r.kronrod_weights.assign(r.abscissa.size(), Real(0));
    for (std::size_t i = 0; i < r.abscissa.size(); ++i) {
        const Real& x = r.abscissa[i];
        if (i % 2 == 1) {  // a Gauss node (the order is even: 0 is a Kronrod node)
            const Real dp = legendre_p_prime(gauss_order, x);
            const Real gauss_weight = 2 / ((1 - x * x) * dp * dp);
            r.gauss_weights.push_back(gauss_weight);
            r.kronrod_weights[i] =
                gauss_weight + Real(2) / (Real(gauss_order + 1) * dp * stieltjes(x));
        } else {
            r.kronrod_weights[i] =
                Real(2) / (Real(gauss_order + 1) * legendre_p(gauss_order, x) * stieltjes.prime(x));
        }
    }
    return r;
}

/// The Kronrod sum, the Gauss sum's difference from it (floored at 2 eps |K|) and the L1 sum of
/// f over [-1, 1] (Boost's integrate_non_adaptive_m1_1).
template <class Real, class F>
Real kronrod_on_unit(const gauss_kronrod_rule<Real>& rule, F&& f, Real& error, Real& l1) {
    using std::abs;
    const auto& x = rule.abscissa;
    const auto& wk = rule.kronrod_weights;
    const auto& wg = rule.gauss_weights;
    Real fp = f(Real(0));
    Real kronrod = fp * wk[0], gauss = 0;
    l1 = abs(kronrod);
    for (std::size_t i = 1; i < x.size(); i += 2) {
        fp = f(x[i]);
        const Real fm = f(-x[i]);
        kronrod += (fp + fm) * wk[i];
        l1 += (abs(fp) + abs(fm)) * wk[i];
        gauss += (fp + fm) * wg[i / 2];
    }
    for (std::size_t i = 2; i < x.size(); i += 2) {
        fp = f(x[i]);
        const Real fm = f(-x[i]);
        kronrod += (fp + fm) * wk[i];
        l1 += (abs(fp) + abs(fm)) * wk[i];
    }
    const Real difference = abs(kronrod - gauss), floor = abs(kronrod * epsilon<Real>() * Real(2));
    error = difference > floor ? difference : floor;
    return kronrod;
}

/// Boost's recursive_adaptive_integrate on the rule.
template <class Real, class F>
Real adaptive(const gauss_kronrod_rule<Real>& rule, F& f, const Real& tolerance, const Real& a,
              const Real& b, unsigned levels, Real abs_tol, Real& error, Real& l1) {
    using std::abs;
    check_cpu_budget();
    const Real mean = (b + a) / 2, scale = (b - a) / 2;
    Real local_error;
    Real estimate =
        scale * kronrod_on_unit(
                    rule, [&](const Real& x) { return f(scale * x + mean); }, local_error, l1);
    const Real abs_tol1 = abs(Real(estimate * tolerance));
    if (abs_tol == 0) abs_tol = abs_tol1;
    if (levels > 0 && abs_tol1 < local_error && abs_tol < local_error) {
        const Real mid = (a + b) / 2;
        Real right_error, right_l1;
        estimate = adaptive(rule, f, tolerance, a, mid, levels - 1, abs_tol / 2, error, l1);
        estimate +=
            adaptive(rule, f, tolerance, mid, b, levels - 1, abs_tol / 2, right_error, right_l1);
        error += right_error;
        l1 += right_l1;
        return estimate;
    }
    l1 *= scale;
    error = local_error;
    return estimate;
}

}  // namespace

template <class Real>
const gauss_kronrod_rule<Real>& gauss_kronrod_61() {
    if constexpr (!has_variable_precision_v<Real>) {
        static const gauss_kronrod_rule<Real> rule = tabulated_rule<Real>();
        return rule;
    } else {
        static std::mutex mutex;
        static std::map<int, std::unique_ptr<const gauss_kronrod_rule<Real>>> rules;
        const std::lock_guard<std::mutex> lock(mutex);
        auto& slot = rules[binary_digits<Real>()];
        if (!slot) slot = std::make_unique<const gauss_kronrod_rule<Real>>(computed_rule<Real>());
        return *slot;
    }
}

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
    r.value = adaptive(gauss_kronrod_61<Real>(), g, tolerance, a, b,
                       static_cast<unsigned>(opt.max_depth), Real(0), error, l1);
    r.error_estimate = error + epsilon<Real>() * l1;
    r.l1_norm = l1;
    r.evaluations = evaluations;
    return r;
}

template <class Real>
quadrature_result<Real> gauss_kronrod_fixed(function_ref<Real(const Real&)> f, const Real& a,
                                            const Real& b, std::size_t panels) {
    using std::abs;
    if (!(a <= b) || panels == 0) {
        throw std::domain_error("gauss_kronrod_fixed: needs a <= b and panels > 0");
    }
    const gauss_kronrod_rule<Real>& rule = gauss_kronrod_61<Real>();
    const auto& x = rule.abscissa;
    const auto& wk = rule.kronrod_weights;
    const auto& wg = rule.gauss_weights;
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
            // the 30-point Gauss rule (even order) sits on the odd indices
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

template const gauss_kronrod_rule<inst_real>& gauss_kronrod_61<inst_real>();
template quadrature_result<inst_real> gauss_kronrod_fixed<inst_real>(
    function_ref<inst_real(const inst_real&)>, const inst_real&, const inst_real&, std::size_t);
template std::size_t kronrod_panels<inst_real>(const inst_real&, const inst_real&, std::size_t);
template quadrature_result<inst_real> gauss_kronrod_integrate<inst_real>(
    function_ref<inst_real(const inst_real&)>, const inst_real&, const inst_real&,
    const quadrature_options<inst_real>&);

}  // namespace flipflux
