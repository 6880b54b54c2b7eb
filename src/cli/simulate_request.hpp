// `flipflux simulate`'s options and their checked translation into a simulation_request
// (study/simulation.hpp), shared by the command (simulate_command.cpp) and the Python module
// (python/_flipflux.cpp), so that both accept the same input and refuse it with the same message.
#pragma once

#include <cstdint>
#include <string>

#include "common.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/settings.hpp"
#include "flipflux/study/simulation.hpp"

namespace flipflux::cli {

/// A setting's default on the command line (study/settings.hpp's table).
inline std::string cli_default(std::string_view field) {
    return setting_default(run_setting_named(field), settings_surface::command_line);
}

/// The options of `flipflux simulate` as given (decimal text); defaults from the settings table.
struct simulate_state {
    std::string energy,
        arm_text = cli_default("arm"), criteria = cli_default("criteria"), trajectories, time,
        seed = cli_default("seed"), rtol = cli_default("rtol"), threads = cli_default("threads"),
        csv_dir, method = cli_default("method"), chaos_threshold = cli_default("chaos_threshold"),
        first_index = cli_default("first_index"), bins = cli_default("bins"),
        sample_interval = cli_default("sample_interval"), checkpoint,
        checkpoint_interval = cli_default("checkpoint_interval"),
        max_seconds = cli_default("max_seconds"), estimator = cli_default("estimator"),
        short_time = cli_default("short_time"), reference_time = cli_default("reference_time"),
        replicates = cli_default("replicates"), initial_states, write_initial_states;
    bool no_chaos = false, progress = false, no_timing = false;
    model_options model;
};

/// The request the options describe (options.stop and group unset): study/settings.hpp's
/// builder; throws input_error naming the offending option.
simulation_request make_request(const simulate_state& s);

}  // namespace flipflux::cli
