// One trajectory from a given canonical state, with its flip events: what `flipflux trajectory`
// writes for simulator authors to check their integrator and flip detector against.
//
// The state is (th1, th2, l1, l2): angles from the downward vertical, conjugate momenta
// l = dL/d(th dot). A flip event is a crossing of a criterion's dividing curve
// (model/dividing_curve.hpp) by the arm's flip angle, counted as the flip detector counts it
// (ensemble/flip_detector.hpp: the crossing function phi = f - pi - h(red(s)) passing a level
// 2 pi k, inside the curve's domain); direction +1 when the flip angle increases through it. The
// criteria's curves are those of the trajectory's energy H(x0) (the saddle orbit depends on it);
// a criterion whose curve does not exist at that energy (below the arm's saddle energy; the saddle
// orbit above E_max) cannot flip and is listed in `skipped`.
//
// Two routes:
//   - the ensemble's (double only): DOP853 or DOPRI5 with the energy check and the ensemble's
//     detectors: exactly what `simulate` does to each of its trajectories; the default at double;
//   - the reference route (any precision; the default at quad and mp:N): the s-stage
//     Gauss-Legendre method (symplectic, order 2 s) with equal steps h = T / n, s and n chosen
//     from the precision so that the local error (s!)^4 / ((2 s)!)^2 (h Lambda)^(2 s + 1) is far
//     below epsilon (Lambda a bound on the angular velocities at the energy). Per step the
//     crossing function is sampled on the step's collocation polynomial (16 points), its extrema
//     found where phi' changes sign (so two crossings inside one step, a grazing flip, are
//     found), every level change bracketed, and each crossing time then polished by Newton's
//     method on phi with Gauss-Legendre steps of the exact length from the step's start (full
//     order: the collocation polynomial itself is only of order s + 1), kept within the
//     crossing's monotone piece. Where Newton fails (a graze closer to the level than the
//     precision resolves: phi' vanishes there), both crossings of the pair are kept at the
//     polynomial's roots, so that their count stays even; where phi jumps (a restricted curve's
//     domain end) there is no crossing. Sample states are taken the same way. Angles are never
//     reduced, so the states are unwrapped.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "flipflux/core/real.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

template <class Real>
struct trajectory_request {
    phase_point<Real> state{};
    Real time{0};                       ///< integrate over [0, time], time > 0
    std::vector<std::string> criteria;  ///< names (study/criteria.hpp), each at most once
    std::vector<arm> arms;              ///< whose flips are detected, each at most once
    Real sample_interval{0};            ///< > 0: the state every interval (0: only t = 0, T)
    double rtol = 1e-12;  ///< the ensemble route's tolerance (atol = rtol); ignored by the other
    integration_method method = integration_method::dop853;  ///< the ensemble route's method
    /// The ensemble route's Taylor order (method taylor); 0: ensemble_taylor_order's choice.
    int taylor_order = 0;
};

template <class Real>
struct flip_event {
    Real time{0};
    arm flip_arm = arm::two;
    std::string criterion;
    int direction = 0;  ///< +1: the flip angle increases through the curve, -1: decreases
};

template <class Real>
struct trajectory_record {
    Real energy{0};                        ///< H(x0)
    std::vector<flip_event<Real>> events;  ///< in time order (ties: arm 1 first, then criteria)
    /// (t, th1, th2, l1, l2, H - H(x0)): t = 0, every sample time, and t = T; angles unwrapped
    std::vector<std::array<Real, 6>> states;
    Real max_energy_drift{0};  ///< over the step ends
    long steps = 0;
    /// "ensemble (dop853, rtol 1e-12)", "ensemble (taylor, order 20, rtol 3e-11)" or
    /// "gauss-legendre ..."
    std::string route;
    std::vector<std::string> skipped;  ///< "arm A criterion C: why" for criteria that cannot flip
};

/// The request's own checks (state, time, sample interval, rtol, criteria, arms), as
/// integrate_trajectory makes them before integrating: for a plan that must refuse what the run
/// would (scene `[[trajectory]]`). Throws input_error about the request's field.
void check_trajectory_request(const trajectory_request<double>& q);

/// Integrates the trajectory by the precision's default route (double: the ensemble's; quad and
/// mp:N: the Taylor route, with the Gauss-Legendre reference route as its independent check).
/// Throws input_error (naming the field: state, time, criteria, arms, sample_interval, rtol) for
/// bad input, and std::runtime_error when the integration fails.
template <class Real>
trajectory_record<Real> integrate_trajectory(const double_pendulum<Real>& model,
                                             const trajectory_request<Real>& request);

/// The reference route (Gauss-Legendre with events polished to full precision), at any
/// precision, double included.
template <class Real>
trajectory_record<Real> reference_trajectory(const double_pendulum<Real>& model,
                                             const trajectory_request<Real>& request);

/// The ensemble's route (double only).
trajectory_record<double> ensemble_trajectory(const double_pendulum<double>& model,
                                              const trajectory_request<double>& request);

/// The Taylor route (an independent high-precision route, `flipflux trajectory --route taylor`):
/// the Taylor-series integrator of the saddle orbits (integrators/taylor.hpp, the recurrences of
/// orbits/saddle_taylor.hpp), order ceil(-ln(eps) / 2) + 1, adaptive Jorba-Zou steps to the
/// working precision's epsilon (relative to 1 + |x|), the events located on each step's Taylor
/// polynomial, which is the solution to that tolerance over the whole step (the same location
/// code as the Gauss-Legendre route, with the polynomial as both dense output and re-step). Much
/// cheaper than Gauss-Legendre at many digits. Throws as reference_trajectory.
template <class Real>
trajectory_record<Real> taylor_trajectory(const double_pendulum<Real>& model,
                                          const trajectory_request<Real>& request);

#define FLIPFLUX_TRAJECTORY_EXTERN(R)                                                           \
    extern template trajectory_record<R> integrate_trajectory<R>(const double_pendulum<R>&,     \
                                                                 const trajectory_request<R>&); \
    extern template trajectory_record<R> reference_trajectory<R>(const double_pendulum<R>&,     \
                                                                 const trajectory_request<R>&); \
    extern template trajectory_record<R> taylor_trajectory<R>(const double_pendulum<R>&,        \
                                                              const trajectory_request<R>&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_TRAJECTORY_EXTERN)
#undef FLIPFLUX_TRAJECTORY_EXTERN

}  // namespace flipflux
