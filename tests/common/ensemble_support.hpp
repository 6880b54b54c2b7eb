// Helpers shared by the ensemble tests: the configuration density integrated over parts of the
// configuration space (for the sampler's marginals), built on the independent quadrature of
// ensemble_reference.hpp (independent of prediction/).
#pragma once

#include <array>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <functional>
#include <numbers>

#include "ensemble_reference.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "pendulums.hpp"
#include "support.hpp"

namespace flipflux::test {

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
