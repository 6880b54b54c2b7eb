// `flipflux simulate`'s options and their checked translation into a simulation_request
// (study/simulation.hpp), shared by the command (simulate_command.cpp) and the Python module
// (python/_flipflux.cpp), so that both accept the same input and refuse it with the same message.
#pragma once

#include <cstdint>
#include <string>

#include "common.hpp"
#include "flipflux/study/simulation.hpp"

namespace flipflux::cli {

/// The options of `flipflux simulate` as given (decimal text).
struct simulate_state {
    std::string energy,
        arm_text = "2", criteria = "upright,approx,saddle", trajectories, time, seed = "0",
        rtol = "1e-10", threads = "0", csv_dir, method = "auto", chaos_threshold = "0.05",
        first_index = "0", bins = "0", sample_interval = "0", checkpoint, checkpoint_interval = "2",
        estimator = "long", short_time = "20", reference_time = "0", replicates = "1",
        initial_states, write_initial_states;
    bool no_chaos = false, progress = false, no_timing = false;
    model_options model;
};

/// A non-negative (positive) integer; throws input_error naming `option` otherwise.
std::uint64_t parse_unsigned(const std::string& text, const std::string& option, bool positive);

/// A number > 0; throws input_error naming `option` otherwise.
double parse_positive(const std::string& text, const std::string& option);

/// The request the options describe (options.stop and group unset); throws input_error naming
/// the offending option.
simulation_request make_request(const simulate_state& s);

}  // namespace flipflux::cli
