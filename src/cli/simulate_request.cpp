// `flipflux simulate`'s options checked and translated (simulate_request.hpp).
#include "simulate_request.hpp"

#include "flipflux/core/limits.hpp"

#include <algorithm>
#include <charconv>

namespace flipflux::cli {

simulation_request make_request(const simulate_state& s) {
    settings_text t{{"arm", s.arm_text},
                    {"energy", s.energy},
                    {"criteria", s.criteria},
                    {"trajectories", s.trajectories},
                    {"replicates", s.replicates},
                    {"time", s.time},
                    {"seed", s.seed},
                    {"first_index", s.first_index},
                    {"rtol", s.rtol},
                    {"threads", s.threads},
                    {"method", s.method},
                    {"chaos", s.no_chaos ? "false" : "true"},
                    {"chaos_threshold", s.chaos_threshold},
                    {"sample_interval", s.sample_interval},
                    {"bins", s.bins},
                    {"checkpoint_interval", s.checkpoint_interval},
                    {"max_seconds", s.max_seconds},
                    {"estimator", s.estimator},
                    {"short_time", s.short_time},
                    {"reference_time", s.reference_time}};
    simulation_request q = make_simulation_request(t, settings_surface::command_line);
    q.csv_dir = s.csv_dir;
    q.checkpoint = s.checkpoint;
    q.timing = !s.no_timing;
    return q;
}

}  // namespace flipflux::cli
