// One trajectory with its flip events by the reference route, Gauss-Legendre with events polished
// to full precision, in any precision (include/flipflux/study/trajectory.hpp explains the method).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/convert.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/integrators/taylor.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_taylor.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/trajectory.hpp"
#include "trajectory_checks.hpp"

namespace flipflux {
namespace {

/// A criterion's curve at Real with its name.
template <class Real>
struct curve_at {
    arm flip_arm;
    std::string name;
    std::function<Real(const Real&)> offset, slope;
    Real lo, hi;
};

/// The criteria's curves at the energy; the ones that cannot flip are listed in `skipped`.
template <class Real>
std::vector<curve_at<Real>> curves(const double_pendulum<Real>& model,
                                   const trajectory_request<Real>& q, const Real& energy,
                                   std::vector<std::string>& skipped) {
    std::vector<curve_at<Real>> out;
    for (const arm a : detail::ordered_arms(q.arms))
        for (const std::string& name : q.criteria) {
            const Real threshold = model.saddle_energy(a);
            if (!(energy > threshold)) {
                skipped.push_back(detail::below_threshold(a, name, energy, threshold));
                continue;
            }
            try {
                any_curve<Real> c = criterion(name).curve(model, a, energy);
                out.push_back({c.flip_arm, name, std::move(c.offset), std::move(c.slope),
                               c.domain[0], c.domain[1]});
            } catch (const criterion_unavailable& e) {
                skipped.push_back("arm " + to_string(a) + " " + name + ": " + e.detail());
            }
        }
    return out;
}

/// The crossing function phi = f - pi - h(red(s)) of a curve at a state, its time derivative,
/// and whether red(s) lies in the curve's domain (a crossing counts only there).
template <class Real>
struct crossing_value {
    Real phi, rate;
    bool inside;
};

/// The crossing function at x given dx = model.rhs(x) (the samples of a step share it between
/// curves).
template <class Real>
crossing_value<Real> crossing_function(const curve_at<Real>& c, const phase_point<Real>& x,
                                       const phase_point<Real>& dx) {
    using boost::multiprecision::round;
    using std::round;
    const Real two_pi = 2 * pi<Real>();
    const auto sf = curve_coordinates(c.flip_arm, x[0], x[1]);
    const Real centre = (c.lo + c.hi) / 2;
    const Real red = sf[0] - two_pi * Real(round((sf[0] - centre) / two_pi));
    const bool inside = red >= c.lo && red <= c.hi;
    const Real s = inside ? red : (red < c.lo ? c.lo : c.hi);
    const auto rates = curve_coordinates(c.flip_arm, dx[0], dx[1]);
    return {sf[1] - pi<Real>() - c.offset(s), rates[1] - (inside ? c.slope(s) * rates[0] : Real(0)),
            inside};
}

template <class Real>
crossing_value<Real> crossing_function(const double_pendulum<Real>& model, const curve_at<Real>& c,
                                       const phase_point<Real>& x) {
    return crossing_function(c, x, model.rhs(x));
}

/// floor(phi / 2 pi): the level below phi.
template <class Real>
long level_below(const Real& phi) {
    using boost::multiprecision::floor;
    using std::floor;
    return static_cast<long>(floor(phi / (2 * pi<Real>())));
}

/// Stages and steps: the local error (s!)^4 / ((2s)!)^2 (h Lambda)^(2s+1) below eps / 1000 at
/// h Lambda = 1/8, Lambda >= 1 + the largest angular velocity at the energy + the natural
/// frequency.
template <class Real>
std::pair<int, long> stages_and_steps(const double_pendulum<Real>& model, const Real& energy,
                                      const Real& time) {
    const auto& k = model.coefficients();
    const double A = static_cast<double>(k.A), B = static_cast<double>(k.B);
    const double lambda_min = static_cast<double>(mass_eigenvalue_range(k)[0]);
    const double e = std::max(0.0, static_cast<double>(energy));
    const double Lambda =
        1 + std::sqrt(2 * e / lambda_min) +
        std::sqrt(static_cast<double>(k.alpha) / A + static_cast<double>(k.beta) / B);
    const double digits = -std::log10(static_cast<double>(std::numeric_limits<Real>::epsilon()));
    int s = 2;
    auto log_error = [](int st) {
        return (4 * std::lgamma(st + 1.0) - 2 * std::lgamma(2 * st + 1.0)) / std::log(10.0) +
               (2 * st + 1) * std::log10(1.0 / 8);
    };
    while (s < max_gauss_legendre_stages && log_error(s) > -(digits + 3))
        ++s;
    const double n = std::ceil(static_cast<double>(time) * Lambda * 8);
    if (!(n <= 1e9))
        throw input_error::about("time", "'" + to_shortest_decimal(time) + "' is too long");
    return {s, std::max(1L, static_cast<long>(n))};
}

/// One step's events: the crossing function on the collocation polynomial at 16 points and at
/// its extrema, every level change in a monotone piece, each root polished by Newton on phi with
/// Gauss-Legendre steps of the exact length from the step's start.
template <class Real, class F, class Stepper>
void step_events(const double_pendulum<Real>& model, const std::vector<curve_at<Real>>& list,
                 const F& f, const Stepper& gl, const phase_point<Real>& x0,
                 const phase_point<Real>& x1, const Real& t0, const Real& h,
                 std::vector<flip_event<Real>>& events) {
    constexpr int samples = 16;
    const Real eps = std::numeric_limits<Real>::epsilon();
    using std::abs;
    auto state_at = [&](const Real& theta) {
        if (theta == 0) return x0;
        if (theta == 1) return x1;
        return gl.collocation(x0, theta);
    };
    if (list.empty()) return;  // every criterion below its threshold: nothing to sample
    // the samples' states and right-hand sides, once for every curve
    std::array<phase_point<Real>, samples + 1> xs, dxs;
    std::array<Real, samples + 1> theta;
    for (int k = 0; k <= samples; ++k) {
        theta[k] = Real(k) / samples;
        xs[k] = state_at(theta[k]);
        dxs[k] = model.rhs(xs[k]);
    }
    for (const curve_at<Real>& c : list) {
        std::array<Real, samples + 1> phi, rate;
        for (int k = 0; k <= samples; ++k) {
            const crossing_value<Real> v = crossing_function(c, xs[k], dxs[k]);
            phi[k] = v.phi;
            rate[k] = v.rate;
        }
        // the cheap exit: no level between the sampled values, phi' of one sign
        // (then phi is monotone and stays between its end values)
        bool one_sign = true;
        for (int k = 1; k <= samples; ++k)
            one_sign = one_sign && ((rate[k] > 0) == (rate[0] > 0)) && rate[k] != 0;
        const long lmin = level_below(*std::min_element(phi.begin(), phi.end()));
        const long lmax = level_below(*std::max_element(phi.begin(), phi.end()));
        if (one_sign && lmin == lmax) continue;
        // the extrema: where phi' changes sign, by bisection on the collocation polynomial
        std::vector<std::pair<Real, Real>> points;  // (theta, phi), increasing theta
        for (int k = 0; k <= samples; ++k) {
            points.emplace_back(theta[k], phi[k]);
            if (k == samples || (rate[k] > 0) == (rate[k + 1] > 0)) continue;
            Real a = theta[k], b = theta[k + 1];
            const bool rising = rate[k] > 0;
            for (int it = 0; it < 200 && b - a > 64 * eps; ++it) {
                const Real m = (a + b) / 2;
                (crossing_function(model, c, state_at(m)).rate > 0) == rising ? a = m : b = m;
            }
            const Real m = (a + b) / 2;
            points.emplace_back(m, crossing_function(model, c, state_at(m)).phi);
        }
        for (std::size_t p = 1; p < points.size(); ++p) {
            const long la = level_below(points[p - 1].second), lb = level_below(points[p].second);
            if (la == lb) continue;
            const bool up = lb > la;
            for (long level = up ? la + 1 : la; up ? level <= lb : level > lb;
                 level += up ? 1 : -1) {
                const Real target = 2 * pi<Real>() * Real(level);
                // a state on the curve at the trajectory's start is not a crossing, in either
                // direction (crossings are counted in (0, T]; the ensemble route's rule)
                if (t0 == 0 && p == 1 && points[0].second == target) continue;
                // bracket on the collocation polynomial, then Newton with exact-length steps
                Real a = points[p - 1].first, b = points[p].first;
                for (int it = 0; it < 200 && b - a > 64 * eps; ++it) {
                    const Real m = (a + b) / 2;
                    ((crossing_function(model, c, state_at(m)).phi >= target) == up ? b : a) = m;
                }
                const Real located = h * (a + b) / 2;
                Real tau = located;
                Stepper refine = gl;
                crossing_value<Real> v{};
                // Newton on the exact-length steps, kept within the monotone piece and within
                // 1e-6 h of the polynomial's root (which is right to far better)
                const Real piece_lo = h * points[p - 1].first, piece_hi = h * points[p].first;
                bool newton = true;
                for (int it = 0; it < 12; ++it) {
                    phase_point<Real> y = x0;
                    if (!refine.restep(f, y, tau)) {
                        newton = false;
                        break;
                    }
                    v = crossing_function(model, c, y);
                    const Real delta = (v.phi - target) / v.rate;
                    const Real next = tau - delta;
                    if (!(abs(next - located) <= h / 1000000 && next >= piece_lo &&
                          next <= piece_hi)) {
                        newton = false;
                        break;
                    }
                    tau = next;
                    if (abs(delta) <= 4 * eps * (abs(t0) + abs(tau))) break;
                }
                if (newton) {
                    if (v.inside)
                        events.push_back({t0 + tau, c.flip_arm, c.name, v.rate > 0 ? 1 : -1});
                    continue;
                }
                // Newton failed: either a graze (an extremum of phi within rounding of the
                // level, where phi' vanishes and the crossing time is only determined to about
                // the square root of the precision: both crossings of the pair are kept, at the
                // polynomial's roots, so that their count stays even) or no root at all (phi
                // jumps where red(s) passes the end of a restricted curve's domain, outside it:
                // phi differs across the polynomial's bracket by far more than rounding).
                const crossing_value<Real> va = crossing_function(model, c, state_at(a));
                const crossing_value<Real> vb = crossing_function(model, c, state_at(b));
                const Real ra = abs(va.rate), rb = abs(vb.rate);
                const Real rate = ra > rb ? ra : rb;
                const Real continuous = 1024 * eps * (1 + abs(target)) + 4 * rate * h * (b - a);
                if (!(abs(vb.phi - va.phi) <= continuous)) continue;
                if (crossing_function(model, c, state_at((a + b) / 2)).inside)
                    events.push_back({t0 + located, c.flip_arm, c.name, up ? 1 : -1});
            }
        }
    }
}

/// The Taylor route's step as step_events sees it: the step's Taylor polynomial (accurate to the
/// tolerance over the whole step) is both the dense output and the exact re-step from its start.
/// The recurrences are those of the saddle orbits (orbits/saddle_taylor.hpp) in the arm-2 saddle
/// frame, a shift of theta2 by pi, without the orbits' action component.
template <class Real>
struct taylor_step {
    const taylor_integrator<Real, 4>* ti = nullptr;
    Real h{0};
    phase_point<Real> at(const Real& t) const {
        const auto y = ti->evaluate(t);
        return {y[0], y[1] + pi<Real>(), y[2], y[3]};
    }
    phase_point<Real> collocation(const phase_point<Real>&, const Real& theta) const {
        return at(theta * h);
    }
    template <class F>
    bool restep(const F&, phase_point<Real>& y, const Real& tau) const {
        y = at(tau);
        return true;
    }
};

/// The start shared by the high-precision routes: the request checked, the energy, the work
/// bound (the same as the ensemble route's: a trajectory that could not finish is refused) and
/// the dividing curves to watch.
template <class Real>
std::vector<curve_at<Real>> start_record(const double_pendulum<Real>& model,
                                         const trajectory_request<Real>& q,
                                         trajectory_record<Real>& out) {
    detail::check_trajectory_request(q);
    out.energy = model.hamiltonian(q.state);
    check_trajectory_work(double_pendulum<double>(convert_parameters<double>(model.parameters())),
                          static_cast<double>(out.energy), static_cast<double>(q.time), "time",
                          static_cast<double>(std::numeric_limits<Real>::epsilon()));
    return curves(model, q, out.energy, out.skipped);
}

/// Appends the state x at time t, with its energy error, to the record.
template <class Real>
void record_state(const double_pendulum<Real>& model, trajectory_record<Real>& out, const Real& t,
                  const phase_point<Real>& x) {
    out.states.push_back({t, x[0], x[1], x[2], x[3], model.hamiltonian(x) - out.energy});
}

/// The end shared by the high-precision routes: the final state x at q.time and the events in
/// time order.
template <class Real>
void finish_record(const double_pendulum<Real>& model, const trajectory_request<Real>& q,
                   const phase_point<Real>& x, trajectory_record<Real>& out) {
    record_state(model, out, q.time, x);
    std::stable_sort(
        out.events.begin(), out.events.end(),
        [](const flip_event<Real>& a, const flip_event<Real>& b) { return a.time < b.time; });
}

}  // namespace

template <class Real>
trajectory_record<Real> taylor_trajectory(const double_pendulum<Real>& model,
                                          const trajectory_request<Real>& q) {
    trajectory_record<Real> out;
    const std::vector<curve_at<Real>> list = start_record(model, q, out);
    const Real tol = std::numeric_limits<Real>::epsilon();
    const int order = taylor_order_for(tol);
    const saddle_frame<Real> frame(model, arm::two);
    saddle_taylor_flow<Real, 0, false> flow(frame, order);
    taylor_integrator<Real, 4> ti(order);
    auto f = [&model](const phase_point<Real>& x, phase_point<Real>& dx) { dx = model.rhs(x); };
    using std::abs;
    record_state(model, out, Real(0), q.state);
    long next_sample = 1;
    std::array<Real, 4> y{q.state[0], q.state[1] - pi<Real>(), q.state[2], q.state[3]};
    phase_point<Real> x = q.state;
    Real t0 = 0;
    constexpr long max_steps = 1000000000;  // as the Gauss-Legendre route's bound
    while (t0 < q.time) {
        if (out.steps >= max_steps)
            throw std::runtime_error("trajectory: more than 1e9 Taylor steps");
        if (!ti.expand(flow, y))
            throw std::runtime_error("trajectory: a Taylor expansion is not finite at t = " +
                                     to_decimal(t0));
        std::array<Real, 4> scale;
        for (std::size_t i = 0; i < 4; ++i)
            scale[i] = 1 + abs(y[i]);
        Real h = ti.step_size(tol, scale);
        const bool last = t0 + h >= q.time;
        if (last) h = q.time - t0;
        const taylor_step<Real> step{&ti, h};
        const phase_point<Real> x0 = x;
        y = ti.evaluate(h);
        x = step.at(h);
        const Real t1 = last ? q.time : t0 + h;
        ++out.steps;
        const Real drift = abs(model.hamiltonian(x) - out.energy);
        if (drift > out.max_energy_drift) out.max_energy_drift = drift;
        step_events(model, list, f, step, x0, x, t0, h, out.events);
        while (q.sample_interval > 0) {
            const Real ts = q.sample_interval * next_sample;
            if (ts > t1 || ts >= q.time) break;
            record_state(model, out, ts, step.at(ts - t0));
            ++next_sample;
        }
        t0 = t1;
    }
    out.route = "taylor (order " + std::to_string(order) + ", " + std::to_string(out.steps) +
                " Jorba-Zou steps, events located on each step's polynomial)";
    finish_record(model, q, x, out);
    return out;
}

template <class Real>
trajectory_record<Real> reference_trajectory(const double_pendulum<Real>& model,
                                             const trajectory_request<Real>& q) {
    trajectory_record<Real> out;
    const std::vector<curve_at<Real>> list = start_record(model, q, out);
    const auto [stages, steps] = stages_and_steps(model, out.energy, q.time);
    out.route = "gauss-legendre (" + std::to_string(stages) + " stages, " + std::to_string(steps) +
                " steps, events polished by Newton)";
    const Real h = q.time / steps;
    auto f = [&model](const phase_point<Real>& x, phase_point<Real>& dx) { dx = model.rhs(x); };
    gauss_legendre<Real, 4> gl(stages);
    using std::abs;
    record_state(model, out, Real(0), q.state);
    long next_sample = 1;
    phase_point<Real> x = q.state;
    for (long k = 0; k < steps; ++k) {
        const phase_point<Real> x0 = x;
        const Real t0 = h * k, t1 = k + 1 == steps ? q.time : h * (k + 1);
        if (!gl.step(f, x, h))
            throw std::runtime_error("trajectory: a Gauss-Legendre step did not converge at t = " +
                                     to_decimal(t0));
        ++out.steps;
        const Real drift = abs(model.hamiltonian(x) - out.energy);
        if (drift > out.max_energy_drift) out.max_energy_drift = drift;
        step_events(model, list, f, gl, x0, x, t0, h, out.events);
        while (q.sample_interval > 0) {
            const Real ts = q.sample_interval * next_sample;
            if (ts > t1 || ts >= q.time) break;
            gauss_legendre<Real, 4> refine = gl;
            phase_point<Real> y = x0;
            if (!refine.restep(f, y, ts - t0))
                throw std::runtime_error("trajectory: a sampling step did not converge");
            record_state(model, out, ts, y);
            ++next_sample;
        }
    }
    finish_record(model, q, x, out);
    return out;
}

template <class Real>
trajectory_record<Real> integrate_trajectory(const double_pendulum<Real>& model,
                                             const trajectory_request<Real>& q) {
    if constexpr (std::is_same_v<Real, double>)
        return ensemble_trajectory(model, q);
    else  // the same digits as Gauss-Legendre (the golden trajectories: mp:100 Taylor against
          // mp:50 Gauss-Legendre to 50 digits), 10-20x faster at quad and mp:100
        return taylor_trajectory(model, q);
}

template trajectory_record<inst_real> integrate_trajectory<inst_real>(
    const double_pendulum<inst_real>&, const trajectory_request<inst_real>&);
template trajectory_record<inst_real> reference_trajectory<inst_real>(
    const double_pendulum<inst_real>&, const trajectory_request<inst_real>&);
template trajectory_record<inst_real> taylor_trajectory<inst_real>(
    const double_pendulum<inst_real>&, const trajectory_request<inst_real>&);

}  // namespace flipflux
