// The ensemble's Taylor integrator (integration_method::taylor): adaptive-step Taylor series of
// the pendulum's flow in double precision, several trajectories per thread in the lanes of SIMD
// vectors (pendulum_taylor.hpp), with the ensemble's detectors, energy check, drift, samples and
// chaos indicator (ensemble.hpp); docs/theory.md#the-ensembles-taylor-integrator.
//
// Order and step (Jorba & Zou 2005, Sec. 3, as integrators/taylor.hpp): p = ceil(-ln(rtol) / 2) + 1
// (13 at rtol 1e-10, 20 at rtol = epsilon), and
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

/// The order of the ensemble's Taylor integrator at relative tolerance `rtol`.
int ensemble_taylor_order(double rtol);

/// The smallest rtol the Taylor integrator accepts: epsilon (its order is then 20).
inline constexpr double min_taylor_rtol = std::numeric_limits<double>::epsilon();

namespace detail {

/// One thread's detectors, per lane.
using lane_detectors = std::array<std::vector<flip_detector_base*>, 8>;

/// One thread's share of a Taylor ensemble: `count` (4 or 8) trajectories in lockstep, the next
/// index taken from next_index whenever one finishes; `deliver` gets each finished (or
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
