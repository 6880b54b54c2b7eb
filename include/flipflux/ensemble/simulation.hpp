// A complete Monte Carlo study as `flipflux simulate` and scenes run it: for each energy an
// ensemble with every requested criterion, its statistics (ensemble/statistics.hpp) as a JSON
// report, optional CSVs, and over the energies the IQI and PQI per regime. Every input is checked
// and every curve (saddle orbits included) built before any trajectory is integrated.
//
// JSON: {"command", "arm", "trajectories", "first_index", "time", "seed", "method", "rtol",
// "atol", "chaos": {indicator, threshold, threshold_rate, classification_reliable},
// "energies": [{energy, seconds, threads, steps_per_trajectory, failed_trajectories,
// max_energy_drift, criteria: {name: {predicted_rate, prediction_method, mean_rate, std,
// standard_error, z_score, flips, chaotic_fraction, max_energy_drift, chaotic: {...},
// residence_times: {...}, rate_histogram: {...}}}}], "quality": {name: {all_trajectories,
// chaotic_trajectories}}, "regimes"}; every real number a decimal string with all digits of
// double (null where undefined, e.g. a z-score without prediction).
// CSV (in csv_dir, each file written atomically), per energy label L and criterion C:
// trajectories_EL.csv (index, lyapunov, chaotic, max_energy_drift, steps, status, flips_C,
// rate_C...), residence_EL_C.csv (trajectory, crossing_time, residence_time),
// rate_histogram_EL_C.csv and residence_histogram_EL_C.csv (bin_lower, bin_upper, count,
// density), samples_EL.csv with options.sample_interval > 0 (trajectory, t, theta1, theta2, l1,
// l2).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"

namespace flipflux {

struct simulation_request {
    arm flip_arm = arm::two;
    std::vector<std::string> criteria;  ///< names (criteria.hpp), each at most once
    /// (label, value): the label names the energy in the report and in file names
    std::vector<std::pair<std::string, double>> energies;
    ensemble_options options;       ///< options.energy is set per energy
    std::size_t bins = 0;           ///< histogram bins (0: square-root rule)
    std::filesystem::path csv_dir;  ///< empty: no CSV output
};

/// Runs the study. Throws input_error for bad input (naming the option) before integrating.
nlohmann::ordered_json simulate(const double_pendulum<double>& model,
                                const simulation_request& request);

/// "5", "2.5,3,3.5" or "FROM:TO:STEP" items (inclusive range, values rounded to 15 digits), in
/// order; throws input_error naming `option`.
std::vector<std::pair<std::string, double>> parse_energy_list(
    const std::string& text, const std::string& option = "--energy");

/// Comma-separated criterion names, each known and at most once; throws input_error naming
/// `option`.
std::vector<std::string> parse_criterion_list(const std::string& text,
                                              const std::string& option = "--criteria");

}  // namespace flipflux
