// The first phase of simulate() (src/study/simulation.cpp): every input of a request checked
// before any trajectory is integrated.
#pragma once

#include "flipflux/study/simulation.hpp"

namespace flipflux::detail {

/// The request checked (every option, the short estimator's budget turned into trajectories; the
/// CSV directory and checkpoint checked, not created): the ensemble options every energy runs
/// with (energy set per energy). Throws input_error naming the field.
ensemble_options checked_options(const simulation_request& request, const process_group& group);

}  // namespace flipflux::detail
