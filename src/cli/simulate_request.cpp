// `flipflux simulate`'s options checked and translated (simulate_request.hpp).
#include "simulate_request.hpp"

#include "flipflux/core/limits.hpp"

#include <algorithm>
#include <charconv>

namespace flipflux::cli {

std::uint64_t parse_unsigned(const std::string& text, const std::string& option, bool positive) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || (positive && v == 0))
        throw input_error(option + ": '" + text + "' is invalid (expected " +
                          (positive ? "a positive" : "a non-negative") + " integer)");
    return v;
}

double parse_positive(const std::string& text, const std::string& option) {
    const double v = parse_real<double>(text, option);
    if (!(v > 0)) throw input_error(option + ": '" + text + "' is invalid (must be > 0)");
    return v;
}

simulation_request make_request(const simulate_state& s) {
    simulation_request q;
    q.flip_arm = parse_arm(s.arm_text);
    q.energies = parse_energy_list(s.energy);
    q.criteria = parse_criterion_list(s.criteria);
    ensemble_options& o = q.options;
    o.trajectories = parse_unsigned(s.trajectories, "--trajectories", true);
    q.replicates = parse_unsigned(s.replicates, "--replicates", true);
    if (q.replicates > max_replicates)
        throw input_error("--replicates: '" + s.replicates + "' is too many (at most " +
                          std::to_string(max_replicates) + ")");
    o.time = parse_positive(s.time, "--time");
    o.seed = parse_unsigned(s.seed, "--seed", false);
    o.first_index = parse_unsigned(s.first_index, "--first-index", false);
    o.rtol = parse_positive(s.rtol, "--rtol");
    o.threads = checked_threads(parse_unsigned(s.threads, "--threads", false), "--threads");
    o.method = resolved_method(parse_name<integration_method>(s.method, "--method"), o.rtol);
    if (const std::string p = rtol_problem(o.rtol, s.rtol, o.method); !p.empty())
        throw input_error("--rtol: " + p);
    o.chaos = !s.no_chaos;
    o.chaos_threshold = parse_positive(s.chaos_threshold, "--chaos-threshold");
    o.sample_interval = parse_real<double>(s.sample_interval, "--sample-interval");
    q.bins = parse_unsigned(s.bins, "--bins", false);
    q.csv_dir = s.csv_dir;
    q.checkpoint = s.checkpoint;
    q.checkpoint_interval = parse_real<double>(s.checkpoint_interval, "--checkpoint-interval");
    q.estimator = parse_name<rate_estimator>(s.estimator, "--estimator");
    q.short_time = parse_positive(s.short_time, "--short-time");
    q.reference_time = parse_real<double>(s.reference_time, "--reference-time");
    q.timing = !s.no_timing;
    return q;
}

}  // namespace flipflux::cli
