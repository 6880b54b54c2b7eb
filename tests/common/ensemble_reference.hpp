// An independent reference for the ensemble verifications: the phase volume and the flux
// through a configuration-space curve by adaptive Gauss-Kronrod quadrature, written here from the
// derivation in docs/theory.md#ensembles (not from prediction/):
//     Omega(E) = 2 pi int int sqrt(det M) Theta(E - V) dth1 dth2,
//     f(E) = 4 int ds sqrt(2 K_+) q(s),   K = E - V on the curve,
//     q = sqrt(A + 2 C c h' + B h'^2) (arm 2: th1 = s, th2 = pi + h(s)),
//     q = sqrt(B + 2 C c h' + A h'^2) (arm 1: th2 = s, th1 = pi + h(s)), c = cos(th1 - th2).
// Accuracy ~1e-9 relative: far below the statistical errors it is compared with.
#pragma once

#include <algorithm>
#include <array>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux::verification {

inline double integrate(const std::function<double(double)>& f, double a, double b,
                        unsigned depth = 15, double tol = 1e-12) {
    if (!(b > a)) return 0;
    return boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b, depth, tol);
}

/// Omega(E): for each th1 the accessible th2 form |th2| < w(th1), integrated by a 31-point rule
/// (smooth integrand); the outer integral is split where w reaches 0 or pi.
inline double phase_volume(const double_pendulum<double>& m, double E) {
    const double pi = std::numbers::pi;
    const auto& k = m.coefficients();
    auto width = [&](double rest, double c) {
        if (rest <= 0) return 0.0;
        const double r = rest / (2 * c);
        return r >= 1 ? pi : 2 * std::asin(std::sqrt(r));
    };
    auto line = [&](double t1) {
        const double w = width(E - 2 * k.alpha * std::pow(std::sin(t1 / 2), 2), k.beta);
        return integrate([&](double t2) { return std::sqrt(m.mass_determinant(t1, t2)); }, -w, w,
                         0);
    };
    std::vector<double> breaks{-pi, pi};
    for (double rest : {E, E - 2 * k.beta}) {
        if (rest > 0 && rest < 2 * k.alpha) {
            const double t = 2 * std::asin(std::sqrt(rest / (2 * k.alpha)));
            breaks.push_back(-t);
            breaks.push_back(t);
        }
    }
    std::sort(breaks.begin(), breaks.end());
    double s = 0;
    for (std::size_t i = 1; i < breaks.size(); ++i)
        s += integrate(line, breaks[i - 1], breaks[i], 12, 1e-11);
    return 2 * pi * s;
}

/// The bidirectional flux through `curve` at energy E.
template <class Curve>
double curve_flux(const double_pendulum<double>& m, const Curve& curve, double E) {
    const auto& k = m.coefficients();
    const arm a = curve.flip_arm();
    auto integrand = [&](double s) {
        const double f = std::numbers::pi + curve.offset(s), hp = curve.slope(s);
        const double th1 = a == arm::two ? s : f, th2 = a == arm::two ? f : s;
        const double K = E - m.potential(th1, th2);
        if (K <= 0) return 0.0;
        const double c = std::cos(th1 - th2);
        const double q = a == arm::two ? k.A + 2 * k.C * c * hp + k.B * hp * hp
                                       : k.B + 2 * k.C * c * hp + k.A * hp * hp;
        return 4 * std::sqrt(2 * K) * std::sqrt(q);
    };
    const std::array<double, 2> d = curve.domain();
    const int pieces = 64;
    double s = 0;
    for (int i = 0; i < pieces; ++i)
        s += integrate(integrand, d[0] + (d[1] - d[0]) * i / pieces,
                       d[0] + (d[1] - d[0]) * (i + 1) / pieces, 12, 1e-11);
    return s;
}

}  // namespace flipflux::verification
