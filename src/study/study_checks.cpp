// The checks of a study request before anything runs (src/study/study_checks.hpp).
#include "study_checks.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <system_error>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/study/settings.hpp"

namespace flipflux::detail {
namespace {

/// What one energy's ensemble holds in memory, bounded up front (core/limits.hpp): every
/// trajectory's record (with its per-criterion vectors, its node in the map of finished
/// trajectories and its index in the work list) and, with a sample interval, its samples.
void check_sizes(const simulation_request& request, const ensemble_options& o) {
    if (request.bins > max_bins)
        throw input_error::about("bins", "'" + std::to_string(request.bins) +
                                             "' is too many histogram bins (at most " +
                                             std::to_string(max_bins) + ")");
    (void)checked_threads(static_cast<std::uint64_t>(std::max(o.threads, 0)), "threads");
    const double record = trajectory_record_bytes(request.criteria.size());
    const double n = static_cast<double>(o.trajectories);
    const std::string field =
        request.estimator == rate_estimator::short_trajectories ? "short_time" : "trajectories";
    const std::string value = request.estimator == rate_estimator::short_trajectories
                                  ? to_decimal(request.short_time)
                                  : std::to_string(o.trajectories);
    check_memory(field, value, n * record, std::to_string(o.trajectories) + " trajectory records");
    if (o.sample_interval > 0) {
        const double samples = std::floor(o.time / o.sample_interval) + 2;
        check_memory("sample_interval", to_decimal(o.sample_interval),
                     n * samples * sizeof(std::array<double, 5>),
                     "the sampled states of " + std::to_string(o.trajectories) + " trajectories");
    }
}

}  // namespace

/// The request checked (every option, the short estimator's budget turned into trajectories) and
/// the CSV directory checked (not created): the ensemble options every energy runs with (energy set
/// per energy).
ensemble_options checked_options(const simulation_request& request, const process_group& group) {
    ensemble_options o = request.options;
    o.method = resolved_method(o.method, o.rtol);  // outputs name the concrete integrator
    if (request.energies.empty()) throw input_error::about("energy", "no energy given");
    if (request.criteria.empty()) throw input_error::about("criteria", "no criterion given");
    if (o.sample_interval != 0 && request.csv_dir.empty() && !request.sink)
        throw input_error::about(
            "sample_interval",
            "'" + to_shortest_decimal(o.sample_interval) +
                "' needs a CSV directory, csv_dir (the sampled trajectories are written there)");
    if (o.sample_interval != 0 && (!request.checkpoint.empty() || group.size() > 1))
        throw input_error::about(
            "sample_interval", "'" + to_shortest_decimal(o.sample_interval) +
                                   "' cannot be combined with a checkpoint or MPI (samples are not "
                                   "checkpointed or gathered)");
    if (!(request.reference_time >= 0) || !std::isfinite(request.reference_time))
        throw input_error::about("reference_time", "'" +
                                                       to_shortest_decimal(request.reference_time) +
                                                       "' is invalid (must be finite and >= 0)");
    if (!(request.max_seconds >= 0) || !std::isfinite(request.max_seconds))
        throw input_error::about("max_seconds", "'" + to_shortest_decimal(request.max_seconds) +
                                                    "' is invalid (CPU seconds: finite and >= 0; "
                                                    "0: no bound)");
    if (!(request.checkpoint_interval >= 0))
        throw input_error::about(
            "checkpoint_interval",
            "'" + to_shortest_decimal(request.checkpoint_interval) + "' is invalid (must be >= 0)");
    if (request.estimator == rate_estimator::short_trajectories) {
        if (!std::isfinite(request.short_time) || !(request.short_time > 0))
            throw input_error::about("short_time", "'" + to_shortest_decimal(request.short_time) +
                                                       "' is invalid (must be finite and > 0)");
        if (!(o.time > 0) || o.trajectories == 0) validate(o);
        if (request.short_time > o.time)
            throw input_error::about("short_time", "'" + to_shortest_decimal(request.short_time) +
                                                       "' is longer than the budget's trajectory "
                                                       "length, time = " +
                                                       to_decimal(o.time));
        const double n = std::ceil(static_cast<double>(o.trajectories) * o.time /
                                   request.short_time * (1 - 1e-15));
        if (!(n <= 1e12))
            throw input_error::about("short_time", "'" + to_shortest_decimal(request.short_time) +
                                                       "' gives too many trajectories");
        o.trajectories = static_cast<std::uint64_t>(std::max(1.0, n));
        o.time = request.short_time;
    }
    o.atol = effective_atol(o);
    if (request.replicates == 0 || request.replicates > max_replicates)
        throw input_error::about("replicates", "'" + std::to_string(request.replicates) +
                                                   "' is invalid (must be 1 to " +
                                                   std::to_string(max_replicates) + ")");
    if (request.replicates > 1) {
        if (o.trajectories > std::numeric_limits<std::uint64_t>::max() / request.replicates)
            throw input_error::about(
                "replicates", "'" + std::to_string(request.replicates) + "' replicates of " +
                                  std::to_string(o.trajectories) + " trajectories are too many");
        o.trajectories *= request.replicates;
    }
    if (!request.initial_states.empty()) {
        if (request.initial_states.size() != request.energies.size())
            throw std::invalid_argument("simulate: initial_states needs one list per energy");
        if (request.replicates != 1 || request.estimator != rate_estimator::long_trajectories)
            throw input_error::about("initial_states",
                                     "given initial states need one replicate and the long "
                                     "estimator");
        for (const auto& list : request.initial_states)
            if (!list || list->size() != o.trajectories)
                throw input_error::about("initial_states", "every energy needs trajectories = " +
                                                               std::to_string(o.trajectories) +
                                                               " initial states");
    }
    check_sizes(request, o);
    // checked, not created: a refused request leaves no folder (the CSVs create it when written)
    const std::filesystem::path& dir = request.csv_dir;
    if (!dir.empty() && group.rank() == 0) {
        check_output_folder(dir, "csv_dir");
        if (!request.checkpoint.empty()) {
            namespace fs = std::filesystem;
            std::error_code ec;
            const fs::path c = fs::weakly_canonical(fs::absolute(request.checkpoint, ec), ec);
            const fs::path d = fs::weakly_canonical(fs::absolute(dir, ec), ec);
            if (c == d)
                throw input_error::about("checkpoint", "'" + request.checkpoint.string() +
                                                           "' is the CSV directory csv_dir");
            if (c.parent_path() == d && c.extension() == ".csv")
                throw input_error::about(
                    "checkpoint", "'" + request.checkpoint.string() +
                                      "' is a CSV name in the CSV directory csv_dir, where the "
                                      "ensemble's CSVs are written: choose another name");
        }
    }
    if (!request.checkpoint.empty() && group.rank() == 0)
        check_output_file(request.checkpoint, "checkpoint");
    return o;
}

}  // namespace flipflux::detail
