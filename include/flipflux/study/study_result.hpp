// What a Monte Carlo study (study/simulation.hpp) finds, as data: per energy and criterion the
// prediction and the ensemble's statistics against it (ensemble/statistics.hpp), and over the
// energies the quality indices per regime (paper Sec. 5.6). Formats live at the edge:
// study/study_files.hpp writes it as JSON and the per-energy CSVs, study/checkpoint.hpp stores
// completed energies exactly.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "flipflux/core/names.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/statistics.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

/// Estimators of the mean rate (docs/scale.md): `long` integrates `trajectories` trajectories
/// of length `time` (the paper's); `short` spends the same budget (trajectories x time units) on
/// ceil(trajectories * time / short_time) trajectories of length short_time. The crossing count
/// of the invariant ensemble is exact for any length, so both are unbiased.
enum class rate_estimator { long_trajectories, short_trajectories };
template <>
struct enum_table<rate_estimator> {
    static constexpr std::string_view noun = "an estimator";
    static constexpr std::array<std::pair<rate_estimator, std::string_view>, 2> entries{
        {{rate_estimator::long_trajectories, "long"},
         {rate_estimator::short_trajectories, "short"}}};
};

/// One criterion at one energy: its predicted rate (none for a criterion without one) and the
/// ensemble's statistics against it (statistics.criterion names the criterion).
struct criterion_result {
    std::optional<quantity_value<double>> prediction;
    criterion_statistics statistics;
};

/// The per-trajectory difference of the rates of two criteria at one energy (paired: the same
/// trajectories), e.g. approx - saddle: its mean, sd and standard error resolve differences far
/// below the standard error of either rate.
struct paired_difference {
    std::size_t first = 0, second = 0;  ///< criterion positions in the request, first < second
    summary_statistics difference;      ///< of rate(first) - rate(second) over the trajectories
};

/// One energy of a study.
struct energy_result {
    std::string label;  ///< the energy's decimal text, as requested
    double energy = 0;
    double seconds = 0;  ///< wall time of the energy (this run's, or the checkpoint's)
    /// CPU time of the energy, every thread of this process (rank 0's under MPI); NaN when it
    /// comes from a checkpoint written before it was recorded
    double cpu_seconds = 0;
    int threads = 0;    ///< threads of rank 0
    int processes = 1;  ///< MPI processes
    double steps_per_trajectory = 0;
    std::uint64_t failed_trajectories = 0;     ///< status not ok (ensemble/ensemble.hpp)
    std::int64_t energy_check_rejections = 0;  ///< steps rejected by the energy check, in total
    double max_energy_drift = 0;               ///< over all trajectories
    std::vector<criterion_result> criteria;    ///< in the order of the request
    std::vector<paired_difference> paired;     ///< every pair of criteria, (0,1), (0,2), (1,2)...
};

/// The quality indices of one criterion per regime, over all trajectories and over the chaotic
/// sub-ensemble (the paper's PQI tables use the chaotic trajectories).
struct criterion_quality {
    std::vector<quality_indices> all_trajectories, chaotic_trajectories;
};

/// How the simulated rates of one criterion agree with its predictions over the energies (those
/// with a prediction and a positive standard error): z = (mean - predicted) / standard error.
struct criterion_agreement {
    std::size_t energies = 0;
    double chi2 = 0;                    ///< sum of z^2 (about `energies` for a correct chain)
    double worst_z = 0;                 ///< the z of largest magnitude (NaN without energies)
    double max_relative_deviation = 0;  ///< max |mean / predicted - 1| (NaN without energies)
    /// With R > 1 replicates: the same with z = (mean - predicted) / replicate error (the
    /// jackknife over replicates, replicate_standard_error), over the energies where that error is
    /// positive. Such a z is Student-t with R - 1 degrees of freedom for a correct prediction, so
    /// chi2 is expected near energies (R - 1) / (R - 3) (expected_chi2; NaN for R <= 3).
    struct replicate_verdict {
        std::size_t energies = 0;
        double chi2 = 0, expected_chi2 = 0, worst_z = 0;
        /// each replicate's own sum of z^2 (its mean against its per-trajectory error)
        std::vector<double> chi2_of_replicates;
        /// The heavy-tail check: per energy, replicate error / per-trajectory standard error of
        /// the pooled mean (about 1 when the per-trajectory error is trustworthy): its largest
        /// and smallest value, and the energies where it lies outside
        /// replicate_error_ratio_range(R) (ensemble/replicate_check.hpp: a false alarm at 0.1 %
        /// of the energies when the per-trajectory error is right, whatever R).
        double max_error_ratio = 0, min_error_ratio = 0;
        std::size_t error_mismatches = 0;
    };
    std::optional<replicate_verdict> replicates;
};

/// The relative difference of two criteria's predicted rates over the study's energies (both
/// predicted): sqrt(mean (predicted(first) / predicted(second) - 1)^2). Deterministic.
struct prediction_difference {
    std::size_t first = 0, second = 0;
    std::size_t energies = 0;
    double rms_relative = 0;  ///< NaN without energies
};

/// A completed study.
struct study_result {
    arm flip_arm = arm::two;
    /// Independent replicates R: the trajectories, in index order, are R blocks of equal size
    /// (distinct Philox streams: trajectory i's numbers depend on (seed, E, i) only), each
    /// summarised on its own; options.trajectories is their total.
    std::size_t replicates = 1;
    std::vector<std::string> criteria;
    /// As integrated: the short estimator's trajectories and time; atol resolved; energy unset.
    ensemble_options options;
    rate_estimator estimator = rate_estimator::long_trajectories;
    std::uint64_t budget_trajectories = 0;  ///< the request's trajectories and time (the budget
    double budget_time = 0;                 ///< the short estimator spends)
    double chaos_threshold_rate = 0;        ///< the threshold as a rate (statistics.hpp)
    bool classification_reliable = false;   ///< whether T resolves the threshold
    bool timing = true;                     ///< whether seconds/threads/processes are reported
    double reference_time = 0;  ///< > 0: the PQI at this trajectory length is estimated too
    std::vector<energy_result> energies;
    std::vector<criterion_quality> quality;  ///< per criterion, in the order of `criteria`
    std::vector<energy_regime> regimes;      ///< the regimes of `quality` (paper_regimes)
    /// per criterion: over all trajectories and over the chaotic sub-ensemble
    struct agreement_of_criterion {
        criterion_agreement all_trajectories, chaotic_trajectories;
    };
    std::vector<agreement_of_criterion> agreement;
    std::vector<prediction_difference> prediction_differences;  ///< every pair of criteria
};

}  // namespace flipflux
