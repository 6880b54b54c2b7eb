// The formats of a study's results (study/study_result.hpp): its JSON report and the per-energy
// CSV files. Every real number is a decimal string with all the digits of double (null where
// undefined, e.g. a z-score without prediction).
//
// JSON: {"command": "simulate", "arm", "trajectories", "first_index", "time", "seed", "method",
// "rtol", "atol", "estimator", ["budget": {trajectories, time}: per replicate], ["replicates":
// {count, trajectories_each, rule}], "chaos": {indicator, threshold,
// threshold_rate, classification_reliable}, "energies": [{energy, [seconds, threads,
// processes], steps_per_trajectory, failed_trajectories, energy_check_rejections,
// max_energy_drift, criteria: {name: {predicted_rate, prediction_method, mean_rate, std,
// standard_error, z_score, flips, chaotic_fraction, max_energy_drift, chaotic: {trajectories,
// mean_rate, std, standard_error, z_score}, residence_times: {count, min, q0.001, q0.01, median,
// mean}, rate_histogram: {lower, upper, bin_width, counts}, max_rate}}, paired_differences:
// [{criteria: [first, second], mean, std, standard_error}]}], "quality": {name:
// {all_trajectories, chaotic_trajectories: [{regime, energies, IQI, PQI, IQI_sd, PQI_sd,
// noise_floor, rms_S, ["reference": {time, PQI, PQI_sd}]}]}}, "regimes": [{regime, lower,
// upper}], "agreement": {name: {all_trajectories, chaotic_trajectories: {energies, chi2, worst_z,
// max_relative_deviation}}}, "prediction_differences": [{criteria: [first, second], energies,
// rms_relative}]} (fields as in study_result.hpp and ensemble/statistics.hpp, fractions not %).
//
// CSV (in a directory, each file written atomically), per energy label L and criterion C:
// trajectories_EL.csv (index, lyapunov, chaotic, max_energy_drift, steps,
// energy_check_rejections, status, flips_C, rate_C...), residence_EL_C.csv (trajectory,
// crossing_time, residence_time), rate_histogram_EL_C.csv and residence_histogram_EL_C.csv
// (bin_lower, bin_upper, count, density), samples_EL.csv when trajectories were sampled
// (trajectory, t, theta1, theta2, l1, l2).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_result.hpp"

namespace flipflux {

/// The JSON report of a study.
nlohmann::ordered_json study_json(const study_result& result);

/// A column of an energy's table: integers, reals (written with every digit of double; NaN as an
/// empty cell where nan_is_empty: not computed) or texts. One of the three vectors holds it.
struct table_column {
    enum class kind { integer, real, text };
    std::string name;
    kind type = kind::real;
    bool nan_is_empty = false;
    std::vector<std::uint64_t> integers;
    std::vector<double> reals;
    std::vector<std::string> texts;
    std::size_t size() const;
};

/// One table of an energy's results: `name` is its CSV file's stem (trajectories_E<label>, ...:
/// the list above), the columns those of the file, in order.
struct energy_table {
    std::string name;
    std::vector<table_column> columns;
    std::size_t rows() const;
};

/// The tables of one energy: its trajectories (the ensemble) and its statistics (`summary`); with
/// residence_times also every crossing time (residence_E<label>_<criterion>).
std::vector<energy_table> energy_tables(const ensemble_result& ensemble,
                                        const energy_result& summary, bool residence_times);

/// The same tables handed to f one at a time, in that order (one in memory at a time).
void for_each_energy_table(const ensemble_result& ensemble, const energy_result& summary,
                           bool residence_times, const std::function<void(energy_table&&)>& f);

/// A table as CSV: the header, then one line per row.
std::string csv_text(const energy_table& table);

/// The file sink: each energy's tables as <dir>/<name>.csv, each written atomically (output_error
/// naming the path when one cannot be).
class csv_directory_sink : public energy_sink {
  public:
    csv_directory_sink(std::filesystem::path dir, bool residence_times)
        : dir_(std::move(dir)), residence_times_(residence_times) {}
    bool has(const std::string& label) const override;
    void put(const ensemble_result& ensemble, const energy_result& summary) override;

  private:
    std::filesystem::path dir_;
    bool residence_times_;
};

/// The initial states of an ensemble (simulate --write-initial-states and --initial-states; the
/// paired check with another simulator, docs/validating.md): CSV trajectory,energy,theta1,theta2,
/// l1,l2, one row per trajectory (trajectory its index, energy the label), every digit of double.
struct initial_state_set {
    std::string label;  ///< the energy's text (the first row's, for rows of the same value)
    double energy = 0;
    std::vector<phase_point<double>> states;
    std::vector<int> lines;    ///< each state's line in the file (0 when not read from one)
    std::size_t repeated = 0;  ///< rows repeating a state of this energy (read once)
};

/// The columns of an initial state in a CSV (energy, theta1, theta2, l1, l2; -1 when missing).
struct initial_state_columns {
    int energy = -1;
    std::array<int, 4> state{-1, -1, -1, -1};
    explicit initial_state_columns(const csv_table& t);
    bool complete() const;
};

/// One row's energy (> 0) and state, H = E to a relative 1e-8; throws input_error "<at>..."
/// (`at` is "FILE:LINE: ") naming the field. Shared by every reader of initial states.
std::pair<double, phase_point<double>> read_initial_state(const csv_row& row,
                                                          const initial_state_columns& c,
                                                          const double_pendulum<double>& model,
                                                          const std::string& at);

/// The rows of `sets`, header first (no comment lines).
std::string initial_states_csv(const std::vector<initial_state_set>& sets,
                               std::uint64_t first_index = 0);

/// Reads an initial-states file (columns energy, theta1, theta2, l1, l2; others ignored; `#`
/// comment lines skipped), grouped by energy value in order of first appearance; a row repeating
/// a state of its energy (a paired file lists each trajectory once per arm) is counted in
/// `repeated`, not read again. Every state must have H = E to a relative 1e-8 (another pendulum
/// or energy otherwise). Throws input_error "FILE:LINE: ..." for anything malformed.
std::vector<initial_state_set> read_initial_states(const std::filesystem::path& file,
                                                   const double_pendulum<double>& model);

}  // namespace flipflux
