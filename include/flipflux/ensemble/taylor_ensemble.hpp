// The ensemble's Taylor integrator (integration_method::taylor): adaptive-step Taylor series of
// the pendulum's flow in double precision, several trajectories per thread in the lanes of SIMD
// vectors (pendulum_taylor.hpp), with the ensemble's detectors, energy check, drift, samples and
// chaos indicator (ensemble.hpp); docs/theory.md#the-ensembles-taylor-integrator.
//
// Step (Jorba & Zou 2005, Sec. 3, as integrators/taylor.hpp), at the order p of
// ensemble_taylor_order (below):
//     h = min_{j in {p-1, p}} (tol / ||x_j||)^(1/j) exp(-0.7 / (p - 1)),
//     tol = max(atol, rtol ||x_0||),
// ||.|| the max norm over (th1, th2, l1, l2); the tangent vector rides along uncontrolled. The
// step's Taylor polynomial is its dense output: the detectors locate crossings on it. A step that
// changes H by more than energy_jump_factor (atol + rtol |E|) plus a rounding allowance of 64 eps
// (1 + |E|) is retried with half its size (the same polynomial, evaluated nearer its centre).
//
// Lanes: within a thread up to 8 trajectories (AVX-512) or 4 compute their jets together in
// vectors; every operation is lane-wise, so a trajectory's result is the same bits for any
// instruction set, thread count, schedule or process split (tested).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"

namespace flipflux {

/// The order of the ensemble's Taylor integrator at relative tolerance `rtol` (clamped to
/// [min_taylor_rtol, 0.1]), with or without the tangent vector: the order of least modelled cost
/// per unit time. A step of order p costs kappa + p^2 (the jet's convolutions grow as p^2; kappa,
/// in the same unit, is what a step costs besides them: step end, energy check, detectors) and
/// its size grows with the order as rtol^(1/p) (the step rule above: h ~ (tol / ||x_p||)^(1/p)),
/// so the cost per time unit is c(p) = (kappa + p^2) e^(L/p), L = -ln(rtol). Its logarithmic
/// derivative 2p / (kappa + p^2) - L / p^2 changes sign once (where 2 p^3 = L (p^2 + kappa)), so
/// c has one minimum over the integers in [min_taylor_order, ensemble_taylor_max_order]: that p.
/// Jorba & Zou's p ~ L/2 is the case kappa = 0; this integrator's steps do enough besides their
/// jets (kappa = taylor_step_overhead, measured: docs/scale.md, bench/taylor_order.cpp) that its
/// order is higher: 20 rather than 13 at rtol 5e-11, 22 (the cap) rather than 20 at epsilon.
int ensemble_taylor_order(double rtol, bool tangent);

/// The order the Taylor integrator uses for `o`: o.taylor_order, or when that is 0 the automatic
/// order at o.rtol, with the tangent vector when o.chaos (outputs name it: simulate's JSON and
/// checkpoint header, the trajectory route).
int ensemble_taylor_order(const ensemble_options& o);

/// kappa of ensemble_taylor_order, in units of one term p^2 of the jet's cost: without the
/// tangent vector, and with it (its jet costs about three times the state's, so its other work
/// weighs less). Calibrated by bench/taylor_order.cpp's scans of the order at four tolerances
/// (bench/results/taylor_order_zen5.txt): the cost per time unit is flat within a few per cent
/// around the orders these give.
inline constexpr double taylor_step_overhead = 256;
inline constexpr double taylor_step_overhead_tangent = 90;

/// The lowest order the integrator accepts (its step rule uses the coefficients p - 1 and p).
inline constexpr int min_taylor_order = 2;

/// The smallest rtol the Taylor integrator accepts: epsilon.
inline constexpr double min_taylor_rtol = std::numeric_limits<double>::epsilon();

namespace detail {

/// One thread's detectors, per lane (the Taylor lanes take at most 8).
using lane_detectors = std::array<std::vector<flip_detector_base*>, max_thread_lanes>;

/// One thread's share of a Taylor ensemble: `count` (at most 8 are taken) trajectories in lockstep,
/// the next index taken from next_index whenever one finishes; `deliver` gets each finished (or
/// abandoned) one.
void run_taylor_lanes(const double_pendulum<double>& model, const ensemble_options& o,
                      const microcanonical_sampler& sampler, lane_detectors& detectors,
                      vector_isa isa, std::size_t count,
                      const std::function<bool(std::uint64_t&)>& next_index,
                      const std::function<void(trajectory_result&)>& deliver);

/// One trajectory by the Taylor integrator (the same bits as in an ensemble).
trajectory_result taylor_trajectory(const double_pendulum<double>& model,
                                    const phase_point<double>& x0, const ensemble_options& o,
                                    std::uint64_t index,
                                    const std::vector<flip_detector_base*>& detectors);

}  // namespace detail
}  // namespace flipflux
