// A complete Monte Carlo study as `flipflux simulate` and scenes run it: for each energy an
// ensemble with every requested criterion and its statistics against the prediction
// (ensemble/statistics.hpp), and over the energies the IQI and PQI per regime; the result is data
// (study/study_result.hpp), written as JSON and CSV by study/study_files.hpp. Every input is
// checked and every curve (saddle orbits included) built before any trajectory is integrated;
// runs resume from checkpoints (study/checkpoint.hpp) and spread over MPI processes.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/study/study_result.hpp"

namespace flipflux {

/// The processes of a distributed run (MPI in the CLI; the library knows no MPI). Every
/// process calls simulate() with the same request; trajectories are dealt out by index, the
/// results gathered to rank 0, which alone returns the report and writes files.
class process_group {
  public:
    virtual ~process_group() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Rank 0's `text`, on every rank.
    virtual std::string broadcast(const std::string& text) = 0;
    /// On rank 0: every rank's `text`, by rank; elsewhere: empty.
    virtual std::vector<std::string> gather(const std::string& text) = 0;
    /// Whether `flag` is true on any rank (on every rank).
    virtual bool any(bool flag) = 0;
};

/// Progress of a study: trajectories finished (including those read from a checkpoint) of the
/// total over all energies.
struct simulation_progress {
    std::uint64_t done = 0, total = 0, resumed = 0;  ///< resumed: read from the checkpoint
    std::size_t energy = 0, energies = 0;            ///< the energy being simulated
};

/// The value a study stores in its stop flag when it reaches simulation_request::max_seconds:
/// simulation_interrupted::signal() then returns it (a signal's number is positive).
inline constexpr int cpu_bound_stop = -1;

/// Thrown by simulate() when options.stop was set: finished trajectories are in the checkpoint.
class simulation_interrupted : public std::runtime_error {
  public:
    simulation_interrupted(const std::string& what, int signal, std::uint64_t saved,
                           std::string kept = {})
        : std::runtime_error(what), signal_(signal), saved_(saved), kept_(std::move(kept)) {}
    int signal() const { return signal_; }  ///< the value options.stop held
    std::uint64_t saved() const { return saved_; }
    /// What the checkpoint keeps, without the cause ("2 energies complete and 37 trajectories of
    /// E = 4.5 saved in 'FILE'"; empty without a checkpoint): for a caller's own message.
    const std::string& kept() const { return kept_; }

  private:
    int signal_;
    std::uint64_t saved_;
    std::string kept_;
};

/// Where a study's per-energy results go as each energy completes: the CSV files of a directory
/// (csv_directory_sink, study/study_files.hpp: the command line and scenes) or memory (the Python
/// module's arrays). Called on rank 0 only, one energy at a time.
class energy_sink {
  public:
    virtual ~energy_sink() = default;
    /// Whether energy `label`'s results are still there: asked of the energies a checkpoint holds
    /// as complete (their trajectories are not in it); false integrates the energy again.
    virtual bool has(const std::string& label) const = 0;
    /// One completed energy: its trajectories and its statistics.
    virtual void put(const ensemble_result& ensemble, const energy_result& summary) = 0;
};

struct simulation_request {
    arm flip_arm = arm::two;
    std::vector<std::string> criteria;  ///< names (criteria.hpp), each at most once
    /// (label, value): the label names the energy in the report and in file names
    std::vector<std::pair<std::string, double>> energies;
    ensemble_options options;  ///< options.energy is set per energy
    /// R >= 1 independent replicates of options.trajectories trajectories each: the study
    /// integrates R x trajectories (indices first_index + k N ... for replicate k) and reports
    /// every statistic pooled and with its spread over the replicates (study_result::replicates).
    std::size_t replicates = 1;
    std::size_t bins = 0;  ///< histogram bins (0: square-root rule)
    /// The per-energy results' destination (energy_sink); null: the CSV files of csv_dir, when
    /// it is set (a csv_directory_sink made by simulate), else none.
    energy_sink* sink = nullptr;
    std::filesystem::path csv_dir;  ///< empty: no CSV output
    /// With csv_dir: also write residence_E<label>_<criterion>.csv, every crossing time and the
    /// residence time since the previous one (the largest files by far: ~10 MB per criterion and
    /// energy at N = 100, T = 10,000). The residence statistics are in the result either way.
    bool residence_times = true;
    /// Non-empty: resume from / save to this checkpoint (study/checkpoint.hpp).
    std::filesystem::path checkpoint;
    double checkpoint_interval = 2;  ///< seconds between appends of finished trajectories
    /// > 0: the CPU seconds (the process's, every thread) the integration may take; at the bound
    /// the study stops as at an interrupt (finished trajectories stay in the checkpoint, and a
    /// rerun resumes from it) and throws simulation_interrupted with signal() == cpu_bound_stop.
    /// 0: no bound.
    double max_seconds = 0;
    bool timing = true;  ///< report "seconds" and "threads" (they vary run to run)
    rate_estimator estimator = rate_estimator::long_trajectories;
    double short_time = 20;  ///< trajectory length of the short estimator
    /// > 0: the quality indices also give the PQI expected at this trajectory length
    /// (quality_indices::pqi_reference), e.g. the paper's T = 10000 for a shorter run.
    double reference_time = 0;
    process_group* group = nullptr;  ///< null: a single process
    /// Per energy of `energies` (empty: every energy sampled): the given initial states of its
    /// options.trajectories trajectories (ensemble_options::initial_states; replicates 1).
    std::vector<std::shared_ptr<const std::vector<phase_point<double>>>> initial_states;
    /// Called (serialised, on rank 0) after each finished trajectory.
    std::function<void(const simulation_progress&)> progress;
};

/// What one trajectory's record holds in memory while its energy runs (without flips or
/// samples): the bound of core/limits.hpp's check_memory for `criteria` criteria.
double trajectory_record_bytes(std::size_t criteria);

/// Runs the study. Throws input_error for bad input (naming the field) before integrating, and
/// simulation_interrupted when options.stop is set during the run. With a process group, only
/// rank 0 returns the result (the others return nothing). Each energy's results go to the
/// request's sink (or the CSV files of csv_dir) as it completes.
std::optional<study_result> simulate(const double_pendulum<double>& model,
                                     const simulation_request& request);

/// Several studies on one set of trajectories: trajectory i at energy E is integrated once and
/// counts the crossings of every criterion of every study that has E (each (arm, criterion) once),
/// e.g. both arms' studies of the paper above the second saddle energy. Each study's result is
/// what simulate(model, requests[p]) returns, bit for bit (the trajectories depend on (seed, E, i)
/// only, and a detector never changes its trajectory). The requests differ only in arm,
/// criteria, energies, bins, csv_dir, residence_times and reference_time (std::invalid_argument
/// otherwise); the first one's checkpoint, progress and process group serve the run (the
/// checkpoint holds every study, study/checkpoint.hpp). With a process group, rank 0 returns the
/// results, in the order of the requests.
std::optional<std::vector<study_result>> simulate(const double_pendulum<double>& model,
                                                  const std::vector<simulation_request>& requests);

}  // namespace flipflux
