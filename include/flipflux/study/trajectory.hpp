// One trajectory from a given canonical state, with its flip events: what `flipflux trajectory`
// writes for simulator authors to check their integrator and flip detector against.
//
// The state is (th1, th2, l1, l2): angles from the downward vertical, conjugate momenta
// l = dL/d(th dot). At double the trajectory is integrated by the ensemble's integrator
// (DOP853 or DOPRI5 with the energy check) and its flips found by the ensemble's detectors
// (ensemble/flip_detector.hpp): it is exactly what `simulate` does to each of its trajectories.
// A flip event is a crossing of a criterion's dividing curve by the arm's flip angle; direction
// +1 when the flip angle increases through it. The criteria's curves are those of the trajectory's
// energy H(x0) (the saddle orbit depends on it); a criterion whose curve is not accessible at that
// energy (below the arm's saddle energy) cannot flip and is listed in `skipped`.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"

namespace flipflux {

struct trajectory_request {
    phase_point<double> state{};
    double time = 0;                    ///< integrate over [0, time], time > 0
    std::vector<std::string> criteria;  ///< names (study/criteria.hpp), each at most once
    std::vector<arm> arms;              ///< whose flips are detected, each at most once
    double sample_interval = 0;         ///< > 0: the state every interval (0: only t = 0, T)
    double rtol = 1e-12;                ///< of the integrator (atol = rtol)
    integration_method method = integration_method::dop853;
};

struct flip_event {
    double time = 0;
    arm flip_arm = arm::two;
    std::string criterion;
    int direction = 0;  ///< +1: the flip angle increases through the curve, -1: decreases
};

struct trajectory_record {
    double energy = 0;  ///< H(x0)
    std::vector<flip_event>
        events;  ///< in time order (ties: arm 1 first, then the criteria's order)
    /// (t, th1, th2, l1, l2, H - H(x0)): t = 0, every sample time, and t = T; angles unwrapped
    std::vector<std::array<double, 6>> states;
    double max_energy_drift = 0;  ///< over every step end
    long steps = 0, rejected_steps = 0;
    rk_status status = rk_status::ok;
    std::vector<std::string> skipped;  ///< "arm A criterion C: why" for criteria that cannot flip
};

/// Integrates the trajectory. Throws input_error (naming the field: state, time, criteria, arms,
/// sample_interval, rtol) for bad input, and std::runtime_error when the integration fails.
trajectory_record integrate_trajectory(const double_pendulum<double>& model,
                                       const trajectory_request& request);

}  // namespace flipflux
