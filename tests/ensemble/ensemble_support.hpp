// Helpers shared by the ensemble tests: random admissible pendulums, the non-egalitarian
// pendulum used throughout, and the configuration density integrated over parts of the
// configuration space (for the sampler's marginals), built on the independent quadrature of
// verification/ensemble_reference.hpp (independent of prediction/).
#pragma once

#include <array>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <functional>
#include <numbers>

#include "../../verification/ensemble_reference.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "support.hpp"

namespace flipflux::test {

/// Random admissible parameters: point masses or rigid links.
inline physical_parameters<double> random_parameters(random_reals& rnd, bool rigid) {
    physical_parameters<double> p;
    p.m1 = rnd(0.2, 3);
    p.m2 = rnd(0.2, 3);
    p.L1 = rnd(0.3, 2);
    p.L2 = rnd(0.3, 2);
    p.a1 = rigid ? rnd(0.1, 1.5) : p.L1;
    p.a2 = rigid ? rnd(0.1, 1.5) : p.L2;
    p.I1 = rigid ? rnd(0, 0.5) : 0.0;
    p.I2 = rigid ? rnd(0, 0.5) : 0.0;
    p.g = rnd(0.5, 10);
    return p;
}

/// A non-egalitarian pendulum (rigid links, unequal masses and lengths, g != 1).
inline physical_parameters<double> lopsided_parameters() {
    physical_parameters<double> p;
    p.m1 = 0.7;
    p.m2 = 1.3;
    p.L1 = 0.8;
    p.L2 = 1.2;
    p.a1 = 0.5;
    p.a2 = 0.65;
    p.I1 = 0.04;
    p.I2 = 0.09;
    p.g = 1.5;
    return p;
}

using verification::integrate;

/// Half-width of the accessible interval of th with 2 k sin^2(th/2) < E_rest (pi if all).
inline double accessible_half_width(double rest, double k) {
    if (rest <= 0) return 0;
    const double r = rest / (2 * k);
    return r >= 1 ? std::numbers::pi : 2 * std::asin(std::sqrt(r));
}

/// int over th2 in [lo, hi] of sqrt(det M(th1, th2)) Theta(E - V): the configuration density
/// integrated over part of a vertical line (the accessible set in th2 is |th2| < m(th1)).
inline double density_line_th2(const double_pendulum<double>& m, double E, double th1, double lo,
                               double hi) {
    const auto& k = m.coefficients();
    const double w =
        accessible_half_width(E - 2 * k.alpha * std::pow(std::sin(th1 / 2), 2), k.beta);
    const double a = std::max(lo, -w), b = std::min(hi, w);
    return integrate([&](double t2) { return std::sqrt(m.mass_determinant(th1, t2)); }, a, b, 0);
}
inline double density_line_th1(const double_pendulum<double>& m, double E, double th2, double lo,
                               double hi) {
    const auto& k = m.coefficients();
    const double w =
        accessible_half_width(E - 2 * k.beta * std::pow(std::sin(th2 / 2), 2), k.alpha);
    const double a = std::max(lo, -w), b = std::min(hi, w);
    return integrate([&](double t1) { return std::sqrt(m.mass_determinant(t1, th2)); }, a, b, 0);
}

/// Outer integral over [a, b] of a line integral whose accessible width has square-root kinks:
/// the interval is split at the points where the width reaches the bin edges.
inline double integrate_with_breaks(const std::function<double(double)>& f, double a, double b,
                                    std::vector<double> breaks) {
    breaks.push_back(a);
    breaks.push_back(b);
    std::sort(breaks.begin(), breaks.end());
    double s = 0;
    for (std::size_t i = 1; i < breaks.size(); ++i) {
        const double lo = std::max(a, breaks[i - 1]), hi = std::min(b, breaks[i]);
        if (hi > lo) s += integrate(f, lo, hi, 12, 1e-11);
    }
    return s;
}

/// th1 where the accessible th2-width equals w (solving 2 alpha sin^2(th1/2) = E - 2 beta
/// sin^2(w/2)), as +-; empty when none.
inline std::vector<double> width_breaks_th1(const double_pendulum<double>& m, double E, double w) {
    const auto& k = m.coefficients();
    const double rest = E - 2 * k.beta * std::pow(std::sin(w / 2), 2);
    if (rest <= 0 || rest >= 2 * k.alpha) return {};
    const double t = 2 * std::asin(std::sqrt(rest / (2 * k.alpha)));
    return {-t, t};
}
inline std::vector<double> width_breaks_th2(const double_pendulum<double>& m, double E, double w) {
    const auto& k = m.coefficients();
    const double rest = E - 2 * k.alpha * std::pow(std::sin(w / 2), 2);
    if (rest <= 0 || rest >= 2 * k.beta) return {};
    const double t = 2 * std::asin(std::sqrt(rest / (2 * k.beta)));
    return {-t, t};
}

}  // namespace flipflux::test
