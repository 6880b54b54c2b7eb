// Flip detection: crossings of a trajectory with a dividing curve (paper Sec. 5.2), for any curve
// satisfying the `dividing_curve` concept (model/dividing_curve.hpp): the upright arm, the
// approximate saddle curve, the saddle orbit (orbits/).
//
// For arm 2 the curve is th2 = pi + h(th1), for arm 1 th1 = pi + h(th2), angles modulo 2 pi. With
// (s, f) the (other, flip) angle the detector follows the crossing function
//     phi(t) = f(t) - pi - h(red(s(t))),   red(s) = s - 2 pi round((s - c) / 2 pi),
// c the centre of h's domain [s_lo, s_hi]; a crossing is a time where phi passes a level 2 pi k
// (any integer k: angles are not reduced inside a step, and the reduction of the state's angles
// between steps shifts phi by exact multiples of 2 pi, which the detector carries over, so no
// crossing is lost or counted twice at a step boundary). A crossing counts in (t0, t1] when the
// indicator [phi >= 2 pi k] changes. Outside a restricted domain (a saddle orbit between its
// turning points) h is continued by its end values and a crossing counts only if red(s) lies in
// [s_lo, s_hi]: beyond the turning points the curve is energetically inaccessible.
//
// Per step, in order of cost:
//   0. the lanes' quiet test, once for all detectors of a trajectory: the prefilter of step 1
//      with the largest bound of the detectors, on a wider range (the RK lanes': step_is_quiet,
//      from the angles and their rates at the step's ends; the Taylor lanes': ranges_are_quiet,
//      on their polynomial ranges); a quiet step is not shown to the detectors at all
//      (skip_step): most steps for curves with |h| < pi;
//   1. the cheap test: first the prefilter of the flip angle f alone (within the bound on |h| of
//      pi), then the same with h's bounds over the step's range of s (offset_bounds: a table of
//      h's bounds on 64 bins of its domain) -- phi's range lies in f's range minus pi minus h's
//      -- then phi and phi' = f' - h'(s) s' at the step's end (from the state and the
//      right-hand side, which the integrator has already evaluated), the cubic Hermite
//      interpolant of (phi, phi') at both ends and its interior extrema give the range of phi;
//      widened by a margin (a quarter of the variation of the data plus an eighth of the cubic's
//      largest second-derivative term), it must contain a level for the step to be examined;
//   2. the examination: where the dense output bounds its angles over the step
//      (step_interpolant::angle_bounds, a proof for its polynomial: the RK lanes' dense_range),
//      phi's range from those bounds (widened to the step's end states) and offset_bounds (h's
//      bounds, sampled with a safety factor) must contain a level, or no indicator changes;
//      then phi' on the dense output at 1/4, 1/2, 3/4 of the step and at the cubic's
//      critical points; each sign change of phi' is refined by TOMS 748 root finding to a
//      critical point of phi, splitting the step into monotone pieces; in each piece every level
//      whose indicator changes is located on the dense output to a relative time tolerance of
//      ~4 ulp: by Newton's method with the dense output's own derivative, kept in the bracket
//      (level_root), where the dense output has one (step_interpolant::angles_and_rates), by
//      TOMS 748 otherwise. Direction: +1 when phi increases (the flip angle passes the curve in
//      the positive sense).
// Grazing crossings (an extremum of phi just beyond a level, both step ends on the same side) are
// found at step 2: two crossings, as they physically are. Assumption (documented in
// docs/theory.md#ensembles): phi' does not change sign twice between two of the sample points,
// i.e. phi has no pair of extrema within a quarter step -- steps resolve the motion; and, as for
// the flip angle in the prefilter, the other angle s stays within its widened cubic Hermite range
// over the step (step 1's test with h's bounds over that range).
// examined_steps() counts the steps that reach step 2, those its proof then passes over included.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/model/dividing_curve.hpp"

namespace flipflux {

/// One crossing of a dividing curve.
struct crossing {
    double time;    ///< when
    int direction;  ///< +1: the flip angle passes the curve increasing, -1: decreasing
    double s;       ///< the other angle there (reduced around the curve's domain)
};

/// The dense output of one integration step, as the detectors see it.
class step_interpolant {
  public:
    /// The pendulum state (th1, th2, l1, l2) at t in [t0, t1] (angles as at the step's start).
    virtual std::array<double, 4> state(double t) const = 0;
    /// Optional: bounds r[i] = {lo, hi} of angle i (th1, th2) of state(t) over the whole step,
    /// every value state() returns in [t0, t1] included (rounding too); false when the
    /// interpolant has none (the detectors then sample it). The detectors widen them to the
    /// step's end states (step_view's x0, x1). The RK lanes': explicit_rk's dense_range.
    virtual bool angle_bounds(std::array<std::array<double, 2>, 2>& r) const {
        (void)r;
        return false;
    }
    /// Optional: the angles (th1, th2) of state(t) (the same bits) in q and their rates in t on
    /// this interpolant (its derivative, not Hamilton's equations) in dq, for Newton's method on
    /// the level crossings; false when the interpolant has none (the detectors then bracket).
    virtual bool angles_and_rates(double t, std::array<double, 2>& q,
                                  std::array<double, 2>& dq) const {
        (void)t, (void)q, (void)dq;
        return false;
    }

  protected:
    ~step_interpolant() = default;
};

/// The examinations' samples of one step at 1/4, 1/2 and 3/4 of it (flip_detector's step 2): the
/// dense output's state and the angular velocities there, computed by the first detector that
/// examines the step and reused by the others of its trajectory (the same bits: the same dense
/// output at the same times). Lives for one step (step_view::samples).
class step_samples {
  public:
    struct sample {
        std::array<double, 4> x;
        std::array<double, 2> w;
    };
    /// Sample q (0, 1, 2) at time t (the same t for every caller in the step).
    const sample& at(int q, double t, const step_interpolant& dense, const pendulum_flow& flow) {
        const auto k = static_cast<std::size_t>(q);
        if (!have_[k]) {
            s_[k].x = dense.state(t);
            s_[k].w = flow.velocities(s_[k].x);
            have_[k] = true;
        }
        return s_[k];
    }

    /// The dense output's bounds of the angles over the step (step_interpolant::angle_bounds),
    /// asked of it once per step; null when it has none.
    const std::array<std::array<double, 2>, 2>* angle_bounds(const step_interpolant& dense) {
        if (!bounds_asked_) {
            bounds_known_ = dense.angle_bounds(bounds_);
            bounds_asked_ = true;
        }
        return bounds_known_ ? &bounds_ : nullptr;
    }

  private:
    std::array<sample, 3> s_;  // sample q is set where have_[q] (not zeroed: one per step)
    std::array<bool, 3> have_{};
    std::array<std::array<double, 2>, 2> bounds_{};
    bool bounds_asked_ = false, bounds_known_ = false;
};

/// What a detector is told about one accepted step.
struct step_view {
    double t0, t1;
    const std::array<double, 4>& x0;  ///< state at t0
    const std::array<double, 4>& f0;  ///< Hamilton's equations at x0
    const std::array<double, 4>& x1;  ///< state at t1 (angles continuous with x0)
    const std::array<double, 4>& f1;  ///< Hamilton's equations at x1
    const step_interpolant& dense;
    /// Optional (null: the detector computes it): per angle (th1, th2), a range [lo, hi] of the
    /// angle over the step for the prefilter (a detector reads both: its flip angle and its
    /// curve's s), shared by the detectors of one trajectory: the RK lanes' is the widened range
    /// of the cubic Hermite interpolant,
    /// flip_angle_range of (the angle, its rate) at the step's start and end (the same bits as
    /// each detector computing it); the Taylor lanes' a bound of the step's polynomial itself
    /// (pendulum_taylor.hpp: taylor_angle_range).
    const std::array<std::array<double, 2>, 2>* angle_ranges = nullptr;
    /// Optional (null: each detector evaluates its own): the step's shared examination samples.
    step_samples* samples = nullptr;
};

namespace detail {

inline double hermite(double p0, double p1, double m0, double m1, double u) {
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 +
           (u3 - u2) * m1;
}

// Roots in (0, 1) of the derivative of the cubic Hermite interpolant,
// a u^2 + b u + c with a = 6 (p0 - p1) + 3 (m0 + m1), b = -6 (p0 - p1) - 4 m0 - 2 m1, c = m0.
inline int cubic_critical_points(double p0, double p1, double m0, double m1,
                                 std::array<double, 2>& out) {
    const double a = 6 * (p0 - p1) + 3 * (m0 + m1);
    const double b = -6 * (p0 - p1) - 4 * m0 - 2 * m1;
    const double c = m0;
    int n = 0;
    auto keep = [&](double u) {
        if (u > 0 && u < 1) out[n++] = u;
    };
    const double scale = std::abs(a) + std::abs(b) + std::abs(c);
    if (scale == 0) return 0;
    if (std::abs(a) <= 1e-12 * scale) {
        if (b != 0) keep(-c / b);
        return n;
    }
    const double disc = b * b - 4 * a * c;
    if (disc < 0) return 0;
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    keep(q / a);
    if (q != 0) keep(c / q);
    if (n == 2 && out[0] > out[1]) std::swap(out[0], out[1]);
    return n;
}

// |x| for T double (std::abs) or lane by lane of a vector of doubles with the same bits (the sign
// bit cleared). (Out-parameters here and below: a function returning a vector by value would
// have an ABI that depends on the instruction set, which GCC warns of.)
template <class T>
[[gnu::always_inline]] inline void abs_into(const T& x, T& r) {
    if constexpr (std::is_floating_point_v<T>) {
        r = std::abs(x);
    } else {
        using bits = decltype(x < x);  // the signed 64-bit integers of the vector's lanes
        r = reinterpret_cast<T>(reinterpret_cast<bits>(x) &
                                std::numeric_limits<std::int64_t>::max());
    }
}

// The prefilter's margin of the cubic Hermite interpolant of (p, m) on the step, before its
// rounding term: a quarter of the variation of the data plus an eighth of the cubic's largest
// second-derivative term (hermite_range's and step_is_quiet's, one formula). For T double or a
// vector of doubles whose lanes are several steps, each lane the same bits as a double's (the
// larger of the two terms by std::max's rule, a < b ? b : a).
template <class T>
[[gnu::always_inline]] inline void hermite_margin(const T& p0, const T& p1, const T& m0,
                                                  const T& m1, T& margin) {
    T d2a, d2b, dp, am0, am1;
    abs_into(6 * (p1 - p0) - 4 * m0 - 2 * m1, d2a);
    abs_into(-6 * (p1 - p0) + 2 * m0 + 4 * m1, d2b);
    abs_into(p1 - p0, dp);
    abs_into(m0, am0);
    abs_into(m1, am1);
    margin = 0.25 * (dp + am0 + am1) + 0.125 * (d2a < d2b ? d2b : d2a);
}
inline double hermite_margin(double p0, double p1, double m0, double m1) {
    double margin = 0;
    hermite_margin(p0, p1, m0, m1, margin);
    return margin;
}

// The range of the cubic Hermite interpolant of (p, m) on the step, widened by hermite_margin
// and a rounding term; with `critical`, its interior critical points there and their number
// returned (without, the number of those it needed: 0 when its range is its ends').
inline int hermite_range(double p0, double p1, double m0, double m1, double& lo, double& hi,
                         std::array<double, 2>* critical = nullptr) {
    lo = std::min(p0, p1);
    hi = std::max(p0, p1);
    std::array<double, 2> crit{};
    int ncrit = 0;
    // The cubic lies in the hull of its Bezier points p0, p0 + m0 / 3, p1 - m1 / 3, p1: when the
    // inner two lie between the ends, so does the cubic, and its range is that of the ends (the
    // critical points are needed only when the caller asks for them).
    const double b1 = p0 + m0 * (1.0 / 3), b2 = p1 - m1 * (1.0 / 3);
    if (critical != nullptr || !(b1 >= lo && b1 <= hi && b2 >= lo && b2 <= hi)) {
        ncrit = cubic_critical_points(p0, p1, m0, m1, crit);
        for (int i = 0; i < ncrit; ++i) {
            const double c = hermite(p0, p1, m0, m1, crit[i]);
            lo = std::min(lo, c);
            hi = std::max(hi, c);
        }
    }
    const double margin = hermite_margin(p0, p1, m0, m1) +
                          64 * std::numeric_limits<double>::epsilon() * (1 + std::abs(hi));
    lo -= margin;
    hi += margin;
    if (critical) *critical = crit;
    return ncrit;
}

// within_reach's test in two parts: the ends a, b scaled to levels (for T double or lane by lane
// of a vector of doubles, the same bits), then reaches_level(a, b).
template <class T>
[[gnu::always_inline]] inline void reach_ends(const T& lo, const T& hi, double bound, T& a, T& b) {
    constexpr double pi = std::numbers::pi, inv_two_pi = 1 / (2 * std::numbers::pi);
    a = (lo - (bound + pi)) * inv_two_pi;
    b = (hi + (bound - pi)) * inv_two_pi;
}

/// Whether [a, b] (reach_ends' ends, in units of levels) holds an integer: ceil(a) <= floor(b),
/// true when either end is not a number (a range that is not a number reaches every level). The
/// one form of the prefilters' test, for within_reach, step_is_quiet and the lanes' quiet test
/// (flip_detector::step's test of phi's own Hermite range is a different one: false for NaN).
inline bool reaches_level(double a, double b) {
    return !(std::ceil(a) > std::floor(b));
}

/// The prefilter's test: whether a flip angle ranging over [lo, hi] in a step comes within
/// `bound` of pi (mod 2 pi), i.e. [lo - (bound + pi), hi + (bound - pi)] holds a level 2 pi n (the
/// ends scaled by 1 / (2 pi) rather than divided: a rounding's difference, far inside the ranges'
/// widening). Monotone in lo, hi and bound, rounding included: a wider range or a larger bound
/// never reaches fewer levels.
inline bool within_reach(double lo, double hi, double bound) {
    double a = 0, b = 0;
    reach_ends(lo, hi, bound, a, b);
    return reaches_level(a, b);
}

// step_is_quiet's test of one flip angle, for T double or a vector of doubles whose lanes are
// several steps (each lane the same bits as a double's): the reach_ends a, b of the angle's range
// (p0 to p1, rates w0 and w1, step h) against `bound`; the step is quiet in this angle when
// !reaches_level(a, b).
template <class T>
[[gnu::always_inline]] inline void quiet_reach(double bound, const T& h, const T& p0, const T& p1,
                                               const T& w0, const T& w1, T& a, T& b) {
    constexpr double slack = 1e-9;
    const T m0 = h * w0, m1 = h * w1;
    const T b1 = p0 + m0 / 3, b2 = p1 - m1 / 3;
    // std::min's and std::max's rules (b < a ? b : a, a < b ? b : a), lane by lane
    const T lo01 = p1 < p0 ? p1 : p0, lo12 = b2 < b1 ? b2 : b1;
    const T hi01 = p0 < p1 ? p1 : p0, hi12 = b1 < b2 ? b2 : b1;
    const T lo = lo12 < lo01 ? lo12 : lo01, hi = hi01 < hi12 ? hi12 : hi01;
    T margin, alo, ahi;
    hermite_margin(p0, p1, m0, m1, margin);
    abs_into(lo, alo);
    abs_into(hi, ahi);
    margin = margin + 64 * std::numeric_limits<double>::epsilon() * (1 + alo + ahi) + slack;
    reach_ends(lo - margin, hi + margin, bound, a, b);
}

}  // namespace detail

/// The prefilter's range of angle i (0: th1, 1: th2) over a step of length h from (x0, w0) to
/// (x1, w1), w the angular velocities: step_view::angle_ranges.
inline std::array<double, 2> flip_angle_range(int i, double h, const std::array<double, 4>& x0,
                                              const std::array<double, 4>& w0,
                                              const std::array<double, 4>& x1,
                                              const std::array<double, 4>& w1) {
    std::array<double, 2> r{};
    detail::hermite_range(x0[i], x1[i], h * w0[i], h * w1[i], r[0], r[1]);
    return r;
}

/// Whether a step is quiet: every detector whose flip angle is i and whose prefilter bound is at
/// most bound[i] (flip_detector_base::prefilter_bound; negative: angle i is not tested) would
/// skip it at its prefilter, so that none need see it (flip_detector_base::skip_step). A wider,
/// cheaper form of the detectors' own prefilter, from the same data (the angle and its rate at
/// the step's start and end): the cubic Hermite interpolant's Bezier hull (which contains its
/// range) widened by hermite_range's margin (its rounding term taken over the hull) and 1e-9 rad,
/// against the widest bound. Every step called quiet is one each detector's prefilter skips.
inline bool step_is_quiet(const std::array<double, 2>& bound, double h,
                          const std::array<double, 4>& x0, const std::array<double, 4>& w0,
                          const std::array<double, 4>& x1, const std::array<double, 4>& w1) {
    for (std::size_t k = 0; k < 2; ++k) {
        if (bound[k] < 0) continue;
        double a = 0, b = 0;
        detail::quiet_reach(bound[k], h, x0[k], x1[k], w0[k], w1[k], a, b);
        if (detail::reaches_level(a, b)) return false;
    }
    return true;
}

/// step_is_quiet for lanes that have each flip angle's range over the step already (the Taylor
/// lanes' taylor_angle_range, step_view::angle_ranges): the detectors' own test with the widest
/// bound, so every step called quiet is one each detector's prefilter skips.
inline bool ranges_are_quiet(const std::array<double, 2>& bound,
                             const std::array<std::array<double, 2>, 2>& ranges) {
    for (std::size_t i = 0; i < 2; ++i)
        if (bound[i] >= 0 && detail::within_reach(ranges[i][0], ranges[i][1], bound[i]))
            return false;
    return true;
}

/// Type-erased detector interface: the ensemble runs any set of criteria chosen at run time.
class flip_detector_base {
  public:
    virtual ~flip_detector_base() = default;
    virtual std::unique_ptr<flip_detector_base> clone() const = 0;
    virtual arm flip_arm() const = 0;
    /// Starts a trajectory at state x0 with right-hand side f0.
    virtual void start(const std::array<double, 4>& x0, const std::array<double, 4>& f0) = 0;
    /// Appends the crossings in the step to `out` (in time order) and returns how many. A
    /// crossing belongs to the step in which the indicator [phi >= level] changes.
    virtual int step(const step_view& v, std::vector<crossing>& out) = 0;
    /// The state's angles at the step end were shifted by (d1, d2), multiples of 2 pi.
    virtual void shift(double d1, double d2) = 0;
    /// Number of steps that needed the dense-output examination (a cost diagnostic; those the
    /// dense output's bounds then pass over included).
    virtual long examined_steps() const = 0;
    /// The prefilter's bound on |h|: a crossing needs the flip angle within it of pi (mod 2 pi)
    /// somewhere in the step (step_is_quiet).
    virtual double prefilter_bound() const = 0;
    /// A step the lane found quiet (step_is_quiet) passed without step(): the same outcome as
    /// step() (which would skip it).
    void skip_step() {
        start_valid_ = false;
        at_start_ = false;
    }

  protected:
    bool start_valid_ = false;  ///< start_ (the derived detector's phi at t0) is current
    bool at_start_ = false;     ///< no step since start(): the next one begins the trajectory
};

template <class Curve>
requires dividing_curve<Curve, double>
class flip_detector final : public flip_detector_base {
  public:
    flip_detector(Curve curve, const pendulum_flow& flow)
        : curve_(std::move(curve)), flow_(flow), arm_(curve_.flip_arm()) {
        const std::array<double, 2> d = curve_.domain();
        lo_ = d[0];
        hi_ = d[1];
        if (!(lo_ < hi_) || !std::isfinite(lo_) || !std::isfinite(hi_) ||
            hi_ - lo_ > two_pi * (1 + 1e-12))
            throw std::invalid_argument(
                "flip_detector: the curve's domain must be an interval "
                "of length at most 2 pi");
        centre_ = (lo_ + hi_) / 2;
        full_ = hi_ - lo_ >= two_pi * (1 - 1e-12);
        // a bound on |h| for the prefilter: the maximum over 513 points, widened by 10 % and
        // 0.05 rad (h is smooth on its domain and constant beyond; see step())
        double hmax = 0;
        for (int i = 0; i <= 512; ++i)
            hmax = std::max(
                hmax,
                std::abs(static_cast<double>(curve_.offset(lo_ + (hi_ - lo_) * (i / 512.0)))));
        offset_bound_ = hmax == 0 ? 0.0 : 1.1 * hmax + 0.05;
        flat_ = hmax == 0 && full_;
        if (!flat_) offset_table_ = std::make_shared<const offset_table>(curve_, lo_, hi_);
    }

    std::unique_ptr<flip_detector_base> clone() const override {
        return std::make_unique<flip_detector>(*this);
    }
    arm flip_arm() const override { return arm_; }
    const Curve& curve() const { return curve_; }
    long examined_steps() const override { return examined_; }
    double prefilter_bound() const override { return offset_bound_; }

    void start(const std::array<double, 4>& x0, const std::array<double, 4>& f0) override {
        start_ = evaluate(x0, {f0[0], f0[1]});
        start_valid_ = true;
        at_start_ = true;
    }

    /// Bounds [hmin, hmax] of the curve's offset h over red(s) for s in [slo, shi], where red(s)
    /// lies in the domain (there only does a crossing count): the table's bounds (offset_table)
    /// over the bins that the pieces of [slo, shi] shifted by -2 pi, 0, 2 pi (after reduction)
    /// meet in the domain, widened by 1e-9 rad (red's rounding). False when no piece meets the
    /// domain: no crossing can count. A range of 2 pi or more (or not a number) gets the bounds
    /// over the whole domain. A curve with h = 0 everywhere (the upright arm) gives [0, 0].
    bool offset_bounds(double slo, double shi, double& hmin, double& hmax) const {
        constexpr double eps = 1e-9;
        if (flat_) {
            hmin = hmax = 0;
            return true;
        }
        const offset_table& t = *offset_table_;
        if (!(shi - slo < two_pi - 2 * eps)) {
            t.bounds(0, offset_table::bins - 1, hmin, hmax);
            return true;
        }
        const double r = reduce(slo);
        const double a = r - eps, b = r + (shi - slo) + eps;
        hmin = std::numeric_limits<double>::infinity();
        hmax = -hmin;
        bool any = false;
        for (int n = -1; n <= 1; ++n) {
            const double pa = std::max(a + n * two_pi, lo_), pb = std::min(b + n * two_pi, hi_);
            if (!(pa <= pb)) continue;
            any = true;
            double mn = 0, mx = 0;
            t.bounds(t.bin(pa), t.bin(pb), mn, mx);
            hmin = std::min(hmin, mn);
            hmax = std::max(hmax, mx);
        }
        return any;
    }

    void shift(double d1, double d2) override {
        // phi shifts with the flip angle; h(red(s)) is unchanged (red removes the s shift)
        start_.phi += arm_ == arm::two ? d2 : d1;
    }

    int step(const step_view& v, std::vector<crossing>& out) override {
        const bool first = at_start_;
        at_start_ = false;
        // the prefilter: a crossing needs the flip angle f within offset_bound_ of pi (mod 2 pi)
        // somewhere in the step; the cubic Hermite range of f (from f, f' at both ends), widened
        // by the margin of the main test below, is checked first, and the curve is not even
        // evaluated when it stays away (most steps for any curve with |h| < pi)
        {
            const int fi = arm_ == arm::two ? 1 : 0;
            double lo = 0, hi = 0;
            angle_range(v, fi, lo, hi);
            bool skip = !detail::within_reach(lo, hi, offset_bound_);
            if (!skip && !flat_) {
                // the same test with h's bounds over the step's range of s (offset_bounds) in
                // place of the bound on |h| over the whole domain
                double slo = 0, shi = 0;
                angle_range(v, 1 - fi, slo, shi);
                skip = !reaches(lo, hi, slo, shi);
            }
            if (!skip && !start_valid_) start_ = evaluate(v.x0, {v.f0[0], v.f0[1]});
            start_valid_ = !skip;  // when examined, start_ = end below
            if (skip) return 0;
        }
        const value end = evaluate(v.x1, {v.f1[0], v.f1[1]});
        const double h = v.t1 - v.t0;
        const double p0 = start_.phi, p1 = end.phi;
        const double m0 = h * start_.dphi, m1 = h * end.dphi;
        double lo = 0, hi = 0;
        hermite_range(p0, p1, m0, m1, lo, hi);
        int found = 0;
        if (std::ceil(lo * inv_two_pi) <= std::floor(hi * inv_two_pi)) {
            ++examined_;
            std::array<double, 2> crit{};
            const int ncrit = detail::cubic_critical_points(p0, p1, m0, m1, crit);
            found = examine(v, end, crit, ncrit, first, out);
        }
        start_ = end;
        return found;
    }

  private:
    static constexpr double pi = std::numbers::pi;
    static constexpr double two_pi = 2 * std::numbers::pi;
    // The step tests' levels 2 pi k: lo and hi scaled by 1 / (2 pi) rather than divided (a
    // rounding's difference; both tests' ranges are widened by far more, so no crossing is lost).
    static constexpr double inv_two_pi = 1 / two_pi;

    struct value {
        double phi = 0, dphi = 0, s = 0;
    };
    struct point {
        double t, phi, dphi;
    };

    // red(s). Within 3.14 of the centre round() is 0 (its argument below 0.4998 in magnitude)
    // and s - 2 pi * 0 is s: the same value without the call.
    double reduce(double s) const {
        const double d = std::abs(s - centre_);
        if (full_ ? d <= pi : d < 3.14) return s;
        return s - two_pi * std::round((s - centre_) / two_pi);
    }

    // The curve at the state's angles: phi, s, and h'(s) (0 outside the domain).
    struct on_curve {
        double phi, s, slope;
    };
    on_curve locate(const std::array<double, 4>& x) const {
        const std::array<double, 2> q = curve_coordinates(arm_, x[0], x[1]);
        const double s = reduce(q[0]);
        const bool inside = s >= lo_ && s <= hi_;
        const double sc = inside ? s : std::clamp(s, lo_, hi_);
        double offset = 0, slope = 0;
        if constexpr (requires { curve_.from_sincos(sc, sc); }) {
            // h from sin s and cos s (the sine curve): the inline sin/cos, both at once
            double sn = 0, cs = 0;
            fast_sincos(sc, sn, cs);
            const std::array<double, 2> h = curve_.from_sincos(sn, cs);
            offset = h[0];
            slope = inside ? h[1] : 0.0;
        } else if constexpr (requires { curve_.offset_and_slope(sc); }) {
            // h and h' in one pass (the saddle curve: two Chebyshev sums side by side)
            const std::array<double, 2> h = curve_.offset_and_slope(sc);
            offset = h[0];
            slope = inside ? h[1] : 0.0;
        } else {
            offset = curve_.offset(sc);
            slope = inside ? double(curve_.slope(sc)) : 0.0;
        }
        return {q[1] - pi - offset, s, slope};
    }

    value evaluate(const std::array<double, 4>& x, const std::array<double, 2>& w) const {
        const on_curve c = locate(x);
        const std::array<double, 2> qd = curve_coordinates(arm_, w[0], w[1]);
        return {c.phi, qd[1] - c.slope * qd[0], c.s};
    }

    value evaluate(const step_samples::sample& p) const { return evaluate(p.x, p.w); }
    value evaluate_at(const step_view& v, double t) const {
        const std::array<double, 4> x = v.dense.state(t);
        return evaluate(x, flow_.velocities(x));
    }

    // phi (and s) on the dense output without phi' (the velocities): the level searches' function,
    // the same bits as evaluate_at's phi and s.
    on_curve locate_at(const step_view& v, double t) const { return locate(v.dense.state(t)); }

    static int hermite_range(double p0, double p1, double m0, double m1, double& lo, double& hi,
                             std::array<double, 2>* critical = nullptr) {
        return detail::hermite_range(p0, p1, m0, m1, lo, hi, critical);
    }
    static double hermite(double p0, double p1, double m0, double m1, double u) {
        return detail::hermite(p0, p1, m0, m1, u);
    }

    template <class G>
    double root(G&& g, double a, double b, double ga, double gb) const {
        if (ga == 0) return a;
        if (gb == 0) return b;
        std::uintmax_t iterations = 100;
        const auto r = boost::math::tools::toms748_solve(
            g, a, b, ga, gb, boost::math::tools::eps_tolerance<double>(50), iterations);
        return 0.5 * (r.first + r.second);
    }

    // A root of g in [a, b] (g(a), g(b) of opposite signs, g monotone there): Newton's method
    // with the interpolant's own derivative (g_and_rate), kept inside the shrinking bracket (a
    // step outside it bisects), to the tolerance of root()'s TOMS 748 (a relative change of at
    // most 2^-49); root() itself when the interpolant has no rates.
    template <class G, class GD>
    double level_root(G&& g, GD&& g_and_rate, double a, double b, double ga, double gb) const {
        if (ga == 0) return a;
        if (gb == 0) return b;
        constexpr double rel = 0x1p-49;
        double t = a + (b - a) * (ga / (ga - gb));  // the secant's root: inside [a, b]
        if (!(t > a && t < b)) t = 0.5 * (a + b);
        for (int it = 0; it < 100; ++it) {
            double gt = 0, dgt = 0;
            if (!g_and_rate(t, gt, dgt)) return root(g, a, b, ga, gb);
            if (gt == 0) return t;
            if ((gt < 0) == (ga < 0)) {
                a = t;
                ga = gt;
            } else {
                b = t;
                gb = gt;
            }
            const double tol = rel * std::max(std::abs(a), std::abs(b));
            double next = t - gt / dgt;
            // converged (next may round to t; kept in the bracket, so in the step)
            if (std::abs(next - t) <= tol) return std::clamp(next, a, b);
            if (!(next > a && next < b)) next = 0.5 * (a + b);  // dgt 0 or not a number too
            if (b - a <= tol) return 0.5 * (a + b);
            t = next;
        }
        return 0.5 * (a + b);
    }

    int examine(const step_view& v, const value& end, const std::array<double, 2>& crit, int ncrit,
                bool first, std::vector<crossing>& out) {
        // the dense output's own bounds of the angles over the step, where it has them: phi
        // reaches no level there, so no indicator changes (the same outcome as the samples')
        std::array<std::array<double, 2>, 2> own{};
        const std::array<std::array<double, 2>, 2>* b =
            v.samples != nullptr ? v.samples->angle_bounds(v.dense)
                                 : (v.dense.angle_bounds(own) ? &own : nullptr);
        if (b != nullptr) {
            // widened to the step's end states, from which the ends' phi come (start_, end)
            const std::size_t fi = arm_ == arm::two ? 1 : 0, si = 1 - fi;
            auto lo = [&](std::size_t i) { return std::min({(*b)[i][0], v.x0[i], v.x1[i]}); };
            auto hi = [&](std::size_t i) { return std::max({(*b)[i][1], v.x0[i], v.x1[i]}); };
            if (!reaches(lo(fi), hi(fi), lo(si), hi(si))) return 0;
        }
        const double h = v.t1 - v.t0;
        // sample points: ends, quarters (tagged 0, 1, 2: shared through v.samples), cubic
        // critical points (tagged -1)
        std::array<std::pair<double, int>, 8> us{};
        int nu = 0;
        for (int q = 0; q < 3; ++q)
            us[nu++] = {0.25 * (q + 1), q};
        for (int i = 0; i < ncrit; ++i)
            us[nu++] = {crit[i], -1};
        std::sort(us.begin(), us.begin() + nu);
        std::array<point, 24> pts{};
        int np = 0;
        pts[np++] = {v.t0, start_.phi, start_.dphi};
        for (int i = 0; i < nu; ++i) {
            const double t = v.t0 + us[i].first * h;
            if (t <= pts[np - 1].t || t >= v.t1) continue;
            const value val = us[i].second >= 0 && v.samples != nullptr
                                  ? evaluate(v.samples->at(us[i].second, t, v.dense, flow_))
                                  : evaluate_at(v, t);
            pts[np++] = {t, val.phi, val.dphi};
        }
        pts[np++] = {v.t1, end.phi, end.dphi};
        // refine the critical points of phi between samples
        std::array<point, 24> mono{};
        int nm = 0;
        mono[nm++] = pts[0];
        for (int i = 1; i < np; ++i) {
            const point& a = pts[i - 1];
            const point& b = pts[i];
            if ((a.dphi < 0 && b.dphi > 0) || (a.dphi > 0 && b.dphi < 0)) {
                auto dphi = [&](double t) { return evaluate_at(v, t).dphi; };
                const double tc = root(dphi, a.t, b.t, a.dphi, b.dphi);
                if (tc > mono[nm - 1].t && tc < b.t) {
                    mono[nm++] = {tc, locate_at(v, tc).phi, 0.0};
                }
            }
            mono[nm++] = b;
        }
        // level crossings in each monotone piece
        int found = 0;
        for (int i = 1; i < nm; ++i) {
            const point& a = mono[i - 1];
            const point& b = mono[i];
            if (a.phi == b.phi) continue;
            const int dir = b.phi > a.phi ? 1 : -1;
            const double k_lo = std::ceil(std::min(a.phi, b.phi) / two_pi);
            const double k_hi = std::floor(std::max(a.phi, b.phi) / two_pi);
            for (double kk = 0; kk <= k_hi - k_lo; ++kk) {
                const double k = dir > 0 ? k_lo + kk : k_hi - kk;
                const double level = k * two_pi;
                if ((a.phi >= level) == (b.phi >= level)) continue;
                auto g = [&](double t) { return locate_at(v, t).phi - level; };
                auto g_and_rate = [&](double t, double& gt, double& dgt) {
                    std::array<double, 2> q{}, dq{};
                    if (!v.dense.angles_and_rates(t, q, dq)) return false;
                    const on_curve c = locate({q[0], q[1], 0.0, 0.0});
                    const std::array<double, 2> qd = curve_coordinates(arm_, dq[0], dq[1]);
                    gt = c.phi - level;
                    dgt = qd[1] - c.slope * qd[0];
                    return true;
                };
                // NOTE: tx == t0 is possible only when phi(t0) equals the level exactly and
                // leaves it downwards; the previous step saw no indicator change then (it ended
                // with phi at the level, indicator true). At the trajectory's start there is no
                // previous step: a state on the curve is not a crossing in either direction
                // (crossings are counted in (0, T]).
                const double tx = level_root(g, g_and_rate, a.t, b.t, a.phi - level, b.phi - level);
                if (first && tx == v.t0) continue;
                const double at_s = tx == v.t1 ? end.s : locate_at(v, tx).s;
                if (at_s < lo_ || at_s > hi_) continue;  // outside the curve's domain
                out.push_back({tx, dir, at_s});
                ++found;
            }
        }
        return found;
    }

    // The prefilter's range [lo, hi] of angle i over the step: the lane's (step_view::
    // angle_ranges) or, without, flip_angle_range's from the step's ends.
    static void angle_range(const step_view& v, int i, double& lo, double& hi) {
        const auto k = static_cast<std::size_t>(i);
        if (v.angle_ranges) {
            lo = (*v.angle_ranges)[k][0];
            hi = (*v.angle_ranges)[k][1];
        } else {
            const double h = v.t1 - v.t0;
            hermite_range(v.x0[k], v.x1[k], h * v.f0[k], h * v.f1[k], lo, hi);
        }
    }

    // Whether phi = f - pi - h(red(s)) can pass a level 2 pi k (with red(s) in the domain) while
    // the flip angle f stays in [flo, fhi] and the other angle s in [slo, shi]: a level in
    // [flo - pi - max h, fhi - pi - min h], widened by 1e-9 rad for rounding (a range that is not
    // a number reaches every level).
    bool reaches(double flo, double fhi, double slo, double shi) const {
        double hmin = 0, hmax = 0;
        if (!flat_ && !offset_bounds(slo, shi, hmin, hmax)) return false;
        constexpr double slack = 1e-9;
        return detail::within_reach(flo - hmax - slack, fhi - hmin + slack, 0.0);
    }

    // h's bounds on the domain's bins, for offset_bounds: on each of `bins` equal bins, h's least
    // and largest value at 17 equally spaced points, widened by 1.5 times the largest |h'| at
    // those points times half their spacing, and by 1e-9 (1 + |h|). Between two points h departs
    // from them by at most its largest slope there times half their spacing; that slope is
    // sampled, with a safety factor of 1.5 (h is smooth on its domain: a sine, or Chebyshev
    // series of a saddle orbit), so the bounds are not a proof;
    // over a run of bins by a sparse table (the bounds of 2^k bins from each bin: two look-ups).
    // Shared by a detector's clones.
    struct offset_table {
        static constexpr int bins = 64, levels = 7;  // 2^(levels - 1) = bins
        double lo = 0, width = 1, per_width = 1;
        std::array<std::array<std::array<double, 2>, bins>, levels> runs{};

        offset_table(const Curve& curve, double dlo, double dhi)
            : lo(dlo), width((dhi - dlo) / bins), per_width(bins / (dhi - dlo)) {
            constexpr int points = 16;
            for (int i = 0; i < bins; ++i) {
                double mn = std::numeric_limits<double>::infinity(), mx = -mn, slope = 0;
                for (int j = 0; j <= points; ++j) {
                    const double sj = j == points && i == bins - 1
                                          ? dhi
                                          : dlo + width * (i + j / static_cast<double>(points));
                    const double hj = static_cast<double>(curve.offset(sj));
                    mn = std::min(mn, hj);
                    mx = std::max(mx, hj);
                    slope = std::max(slope, std::abs(static_cast<double>(curve.slope(sj))));
                }
                const double widen = 1.5 * slope * (width / points) / 2 +
                                     1e-9 * (1 + std::max(std::abs(mn), std::abs(mx)));
                runs[0][static_cast<std::size_t>(i)] = {mn - widen, mx + widen};
            }
            for (std::size_t k = 1; k < levels; ++k)
                for (std::size_t i = 0; i + (std::size_t{1} << k) <= bins; ++i) {
                    const auto& x = runs[k - 1][i];
                    const auto& y = runs[k - 1][i + (std::size_t{1} << (k - 1))];
                    runs[k][i] = {std::min(x[0], y[0]), std::max(x[1], y[1])};
                }
        }
        // the bin of s in the domain
        int bin(double s) const {
            return std::clamp(static_cast<int>((s - lo) * per_width), 0, bins - 1);
        }
        // the bounds over bins i0..i1 (i0 <= i1)
        void bounds(int i0, int i1, double& mn, double& mx) const {
            const int n = i1 - i0 + 1;
            const int k = std::bit_width(static_cast<unsigned>(n)) - 1;
            const auto& x = runs[static_cast<std::size_t>(k)][static_cast<std::size_t>(i0)];
            const auto& y =
                runs[static_cast<std::size_t>(k)][static_cast<std::size_t>(i1 + 1 - (1 << k))];
            mn = std::min(x[0], y[0]);
            mx = std::max(x[1], y[1]);
        }
    };

    Curve curve_;
    pendulum_flow flow_;
    arm arm_;
    double lo_ = 0, hi_ = 0, centre_ = 0;
    bool full_ = true;
    bool flat_ = false;  ///< h = 0 on the whole circle (no offset_table)
    std::shared_ptr<const offset_table> offset_table_;
    value start_{};            ///< phi, phi' and s at the step's start (start_valid_)
    double offset_bound_ = 0;  ///< the prefilter's bound on |h|
    long examined_ = 0;
};

/// A detector for `curve` (deduces the curve type).
template <class Curve>
requires dividing_curve<Curve, double> std::unique_ptr<flip_detector_base> make_flip_detector(
    Curve curve, const pendulum_flow& flow) {
    return std::make_unique<flip_detector<Curve>>(std::move(curve), flow);
}

}  // namespace flipflux
