// Dividing curves in configuration space: the flip criteria of the paper (Sec. 3) as curves.
//
// A curve for flips of arm `a` gives the flip angle as pi plus an offset h of the other angle s:
//     arm 2:  theta2 = pi + h(theta1)        arm 1:  theta1 = pi + h(theta2)
// (angles modulo 2 pi). The three criteria of the paper are
//     upright arm              h = 0                      (paper eq. crit:up)
//     approximate saddle orbit h = A sin s                (paper eq. crit:approx; A = 2 - sqrt 2
//     for
//                                                          arm 2 of the egalitarian pendulum)
//     saddle orbit             h = the orbit's curve      (orbits/, an interpolant on the orbit's
//                                                          turning-point interval)
// For general parameters A is the slope of the saddle's centre mode: with direction (a1, a2) in
// (theta1, theta2), arm 2 (saddle (0, pi)): A = a2/a1; arm 1 (saddle (pi, 0)): A = a1/a2.
//
// The `dividing_curve` concept is what the flux integral (prediction/), the flip detector
// (ensemble/) and the saddle-orbit interpolant (orbits/) agree on:
//     arm flip_arm() const;                      which arm's flips the curve counts
//     Real offset(const Real& s) const;          h(s)
//     Real slope(const Real& s) const;           h'(s)
//     std::array<Real, 2> domain() const;        the s-interval where h is defined; outside it the
//                                                curve is energetically inaccessible (e.g. beyond a
//                                                saddle orbit's turning points), [-pi, pi] for
//                                                curves defined everywhere (then h is 2
//                                                pi-periodic)
#pragma once

#include <array>
#include <concepts>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/model/critical_points.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

template <class C, class Real>
concept dividing_curve = requires(const C& c, const Real& s) {
    { c.flip_arm() } -> std::same_as<arm>;
    { c.offset(s) } -> std::convertible_to<Real>;
    { c.slope(s) } -> std::convertible_to<Real>;
    { c.domain() } -> std::convertible_to<std::array<Real, 2>>;
};

/// The upright-arm criterion: the flip angle equals pi.
template <class Real>
struct upright_curve {
    arm a = arm::two;
    arm flip_arm() const { return a; }
    Real offset(const Real&) const { return Real(0); }
    Real slope(const Real&) const { return Real(0); }
    std::array<Real, 2> domain() const { return {-pi<Real>(), pi<Real>()}; }
};

/// The approximate saddle-orbit criterion: the flip angle equals pi + amplitude sin(s).
template <class Real>
struct sine_curve {
    arm a = arm::two;
    Real amplitude{0};
    arm flip_arm() const { return a; }
    Real offset(const Real& s) const {
        using std::sin;
        return from_sincos(sin(s), Real(0))[0];
    }
    Real slope(const Real& s) const {
        using std::cos;
        return from_sincos(Real(0), cos(s))[1];
    }
    /// h(s) and h'(s) from sin s and cos s, for a caller that computes them together (the
    /// ensemble's flip detector, with its inline sin/cos).
    std::array<Real, 2> from_sincos(const Real& sin_s, const Real& cos_s) const {
        return {amplitude * sin_s, amplitude * cos_s};
    }
    std::array<Real, 2> domain() const { return {-pi<Real>(), pi<Real>()}; }
};

/// The approximate saddle curve of `a`, its amplitude the slope of the saddle's centre mode.
template <class Real>
sine_curve<Real> approximate_saddle_curve(const double_pendulum<Real>& model, arm a) {
    const critical_point<Real> saddle = flip_saddle(model, a);
    const auto& d = saddle.modes[0].direction;  // the oscillatory (centre) mode
    return {a, a == arm::two ? d[1] / d[0] : d[0] / d[1]};
}

/// Splits a configuration into (s, flip angle) for arm a: arm 2 -> (th1, th2), arm 1 -> (th2, th1).
template <class Real>
std::array<Real, 2> curve_coordinates(arm a, const Real& th1, const Real& th2) {
    return a == arm::two ? std::array<Real, 2>{th1, th2} : std::array<Real, 2>{th2, th1};
}

}  // namespace flipflux
