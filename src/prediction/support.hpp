// Internal to src/prediction: the geometry of the allowed region V <= E seen from one angle.
//
// V = 2 w_this sin^2(th/2) + 2 w_other sin^2(th_o/2) with (w_this, w_other) = (alpha, beta) for
// th = th1 and (beta, alpha) for th = th2. At fixed th the other angle is allowed on
// |th_o| <= t(th), where 2 w_other sin^2(t/2) = rem(th) := E - 2 w_this sin^2(th/2):
//     t = 0 for |th| >= theta_edge   (sin^2(theta_edge/2) = E / (2 w_this), or pi if E >= 2 w_this)
//     t = pi for |th| <= theta_full  (sin^2(theta_full/2) = (E - 2 w_other)/(2 w_this), 0 if
//                                     E <= 2 w_other, pi if E >= E_max)
// In between t = 2 atan2(sqrt(rem), sqrt(gap)), gap := 2 w_other - rem, and both rem and gap are
// evaluated from the distances to theta_edge and theta_full as products of sines
// (sin^2 a - sin^2 b = sin(a - b) sin(a + b)), so that neither loses digits near its zero.
#pragma once

#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/prediction/phase_volume.hpp"

namespace flipflux::detail {

template <class Real>
struct angle_support {
    Real energy;
    Real w_this, w_other;
    Real theta_full;  ///< t = pi on [0, theta_full]
    Real theta_edge;  ///< t = 0 beyond theta_edge

    angle_support(const double_pendulum<Real>& model, const Real& E, configuration_angle which)
        : energy(E) {
        using std::asin;
        using std::sqrt;
        const auto& k = model.coefficients();
        w_this = which == configuration_angle::theta1 ? k.alpha : k.beta;
        w_other = which == configuration_angle::theta1 ? k.beta : k.alpha;
        const Real above_other = E - 2 * w_other;  // E minus the energy that frees th_o entirely
        theta_full = above_other <= 0            ? Real(0)
                     : above_other >= 2 * w_this ? pi<Real>()
                                                 : 2 * asin(sqrt(above_other / (2 * w_this)));
        theta_edge = E <= 0            ? Real(0)
                     : E >= 2 * w_this ? pi<Real>()
                                       : 2 * asin(sqrt(E / (2 * w_this)));
    }

    /// rem(th) for 0 <= th <= pi, given d_edge = theta_edge - th (used when theta_edge < pi).
    Real rem(const Real& th, const Real& d_edge) const {
        using std::cos;
        using std::sin;
        if (theta_edge < pi<Real>())
            return 2 * w_this * sin(d_edge / 2) * sin((theta_edge + th) / 2);
        const Real c = cos(th / 2);  // E >= 2 w_this: rem = (E - 2 w_this) + 2 w_this cos^2(th/2)
        return (energy - 2 * w_this) + 2 * w_this * c * c;
    }

    /// gap(th) = 2 w_other - rem(th) for 0 <= th <= pi, given d_full = th - theta_full.
    Real gap(const Real& th, const Real& d_full) const {
        using std::sin;
        if (theta_full > 0) return 2 * w_this * sin(d_full / 2) * sin((th + theta_full) / 2);
        const Real s = sin(th / 2);  // E <= 2 w_other: gap = (2 w_other - E) + 2 w_this sin^2
        return (2 * w_other - energy) + 2 * w_this * s * s;
    }

    /// The half-width t(th) for 0 <= th <= pi, given d_edge = theta_edge - th and
    /// d_full = th - theta_full (distances accurate to full relative precision near 0).
    Real half_width(const Real& th, const Real& d_edge, const Real& d_full) const {
        using std::atan2;
        using std::sqrt;
        if (theta_edge < pi<Real>() && !(d_edge > 0)) return Real(0);
        if (theta_full > 0 && !(d_full > 0)) return pi<Real>();
        const Real r = rem(th, d_edge), g = gap(th, d_full);
        if (!(r > 0)) return Real(0);
        if (!(g > 0)) return pi<Real>();
        return 2 * atan2(sqrt(r), sqrt(g));
    }
};

/// |theta| reduced to [0, pi] (the marginals are even and 2 pi-periodic).
template <class Real>
Real folded_angle(const Real& theta) {
    using std::abs;
    using std::fmod;
    if (abs(theta) <= pi<Real>()) return abs(theta);
    Real x = fmod(abs(theta), two_pi<Real>());  // in [0, 2 pi)
    return x > pi<Real>() ? two_pi<Real>() - x : x;
}

}  // namespace flipflux::detail
