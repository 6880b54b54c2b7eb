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

#include <array>
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/prediction/phase_volume.hpp"

namespace flipflux::detail {

template <class Real>
struct angle_support {
    Real energy;
    Real w_this, w_other;
    Real theta_full;                        ///< t = pi on [0, theta_full]
    Real theta_edge;                        ///< t = 0 beyond theta_edge
    Real full_supplement, edge_supplement;  ///< pi - theta_full, pi - theta_edge (accurate)
    Real above_other;                       ///< E - 2 w_other
    Real below_this;                        ///< 2 w_this - E

    /// The support at E: the distances of E to the levels 2 w_other, 2 w_this and E_max are
    /// energy_level::above, exact when E and the model come from decimal texts. They set where
    /// the support's edges are and, near a level, the square-root branch points of the
    /// half-width ~sqrt(distance) from the integration path (singularity_distances), where the
    /// graded quadrature concentrates its nodes. No distance is rounded to the level: Omega's
    /// derivative is log-singular at a saddle (~330 at E = 2 + 1e-14 for the paper's pendulum),
    /// so moving E by up to 16 eps E_max onto the level, as an earlier version did, moved Omega by
    /// 15x its error estimate in double and quad.
    angle_support(const double_pendulum<Real>& model, const energy_level<Real>& E,
                  configuration_angle which)
        : energy(E.value) {
        const auto& k = model.coefficients();
        const bool first = which == configuration_angle::theta1;
        w_this = first ? k.alpha : k.beta;
        w_other = first ? k.beta : k.alpha;
        // 2 alpha is arm 1's saddle level, 2 beta arm 2's
        above_other = E.above(model.saddle_level(first ? arm::two : arm::one));
        below_this = E.below(model.saddle_level(first ? arm::one : arm::two));
        // sin^2(theta_full/2) = (E - 2 w_other)/(2 w_this), cos^2(...) = (E_max - E)/(2 w_this)
        half_angles(above_other, E.below(model.maximum_level()), theta_full, full_supplement);
        // sin^2(theta_edge/2) = E/(2 w_this), cos^2(...) = (2 w_this - E)/(2 w_this)
        half_angles(energy, below_this, theta_edge, edge_supplement);
    }

    /// theta in [0, pi] with sin^2(theta/2) = p/(2 w_this), cos^2(theta/2) = q/(2 w_this)
    /// (p + q = 2 w_this), and pi - theta, each from the smaller of p and q (no cancellation).
    void half_angles(const Real& p, const Real& q, Real& theta, Real& supplement) const {
        using std::asin;
        using std::sqrt;
        if (!(p > 0)) {
            theta = 0;
            supplement = pi<Real>();
        } else if (!(q > 0)) {
            theta = pi<Real>();
            supplement = 0;
        } else if (p <= q) {
            theta = 2 * asin(sqrt(p / (2 * w_this)));
            supplement = pi<Real>() - theta;
        } else {
            supplement = 2 * asin(sqrt(q / (2 * w_this)));
            theta = pi<Real>() - supplement;
        }
    }

    /// sin((theta + th)/2) for th = theta + d (d may be negative), from the supplement when theta
    /// is near pi (then (theta + th)/2 is near pi too and its sine small).
    Real sine_of_mean(const Real& theta, const Real& supplement, const Real& d) const {
        using std::sin;
        return theta <= half_pi<Real>() ? sin(theta + d / 2) : sin(supplement - d / 2);
    }

    /// rem(th) for 0 <= th <= pi, given d_edge = theta_edge - th.
    Real rem(const Real& d_edge) const {
        using std::sin;
        if (theta_edge < pi<Real>()) {
            return 2 * w_this * sin(d_edge / 2) *
                   sine_of_mean(theta_edge, edge_supplement, -d_edge);
        }
        // E >= 2 w_this: rem = (E - 2 w_this) + 2 w_this cos^2(th/2), cos(th/2) = sin(d_edge/2)
        // with d_edge = pi - th here: from the distance, accurate where th is near pi
        const Real c = sin(d_edge / 2);
        return 2 * w_this * c * c - below_this;
    }

    /// gap(th) = 2 w_other - rem(th) for 0 <= th <= pi, given d_full = th - theta_full.
    Real gap(const Real& th, const Real& d_full) const {
        using std::sin;
        if (theta_full > 0) {
            return 2 * w_this * sin(d_full / 2) * sine_of_mean(theta_full, full_supplement, d_full);
        }
        const Real s = sin(th / 2);  // E <= 2 w_other: gap = (2 w_other - E) + 2 w_this sin^2
        return 2 * w_this * s * s - above_other;
    }

    /// The half-width t(th) for 0 <= th <= pi, given d_edge = theta_edge - th and
    /// d_full = th - theta_full (distances accurate to full relative precision near 0).
    Real half_width(const Real& th, const Real& d_edge, const Real& d_full) const {
        using std::atan2;
        using std::sqrt;
        if (theta_edge < pi<Real>() && !(d_edge > 0)) return Real(0);
        if (theta_full > 0 && !(d_full > 0)) return pi<Real>();
        const Real r = rem(d_edge), g = gap(th, d_full);
        if (!(r > 0)) return Real(0);
        if (!(g > 0)) return pi<Real>();
        return 2 * atan2(sqrt(r), sqrt(g));
    }
};

/// Distances of the nearest singularities of the marginal beyond the ends of its middle piece
/// [a, b] (a = theta_full, b <= theta_edge), for tanh_sinh_integrate_graded: the mirror images
/// of the support's edges (t has square-root branch points there) or, when an edge is absent,
/// the complex zero of rem or gap closest to the end.
template <class Real>
std::array<Real, 2> singularity_distances(const angle_support<Real>& sup, const Real& b) {
    using std::sqrt;
    std::array<Real, 2> r{Real(0), Real(0)};
    if (sup.theta_full > 0) {
        r[0] = 2 * sup.theta_full;  // the zero of gap at -theta_full
    } else if (sup.above_other < 0) {
        r[0] = sqrt(-2 * sup.above_other / sup.w_this);  // gap ~ (2w_o - E) + w_t th^2/2
    }
    if (b == sup.theta_edge) {
        if (sup.theta_edge < pi<Real>()) {
            r[1] = 2 * sup.edge_supplement;  // the zero of rem at 2 pi - theta_edge
        } else if (sup.below_this < 0) {
            r[1] = sqrt(-2 * sup.below_this / sup.w_this);  // rem ~ (E - 2w_t) + ...
        }
    }
    return r;
}

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
