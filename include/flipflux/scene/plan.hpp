// The plan of a scene: exactly the computations its requested outputs need, in dependency order.
//
//   orbit family (arm a)   only when a saddle quantity (period, action, flux-saddle, rate-saddle,
//                          multiplier, stability-index) is requested for arm a or [orbits] or
//                          [viewer] asks for arm a (in the scene's precision), or when an ensemble
//                          of arm a counts the saddle criterion (in double); at the union of the
//                          energies those need inside (E_s, E_max). Read from the on-disk cache
//                          when there.
//   predictions            the requested quantities at the requested arms and energies
//   ensemble               one step per set of [[ensemble]]s whose trajectories are the same (same
//                          trajectories, time, seed, rtol, atol, integrator, estimator, chaos flag
//                          and threshold):
//                          each trajectory integrated once at the union of their energies, counting
//                          at each energy only the criteria the ensembles having it list
//   trajectory             one step per [[trajectory]]: one trajectory and its flip events (double)
//   viewer                 the saddle-orbit viewer page (its families are orbit-family steps above)
//   golden / accuracy / report
//
// `flipflux run --dry-run SCENE` prints the plan without computing anything.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "flipflux/output/command_words.hpp"
#include "flipflux/scene/scene.hpp"
#include "flipflux/study/simulation.hpp"

namespace flipflux {

struct plan_step {
    enum class kind {
        orbit_family,
        predictions,
        ensemble,
        trajectory,
        viewer,
        golden,
        accuracy,
        report
    };
    kind what;
    int arm = 0;                          ///< orbit families and ensembles
    std::vector<std::string> energies;    ///< decimal text, in order
    std::vector<std::string> quantities;  ///< predictions: "name@arm" per requested pair
    std::vector<std::string> criteria;    ///< ensembles
    std::size_t ensemble_index = 0;       ///< into scene::ensembles (trajectories: ::trajectories)
    std::string description;
    /// orbit families: the precision they are computed in (the scene's for predictions and
    /// [orbits]; double for the saddle criterion of ensembles)
    precision prec = precision{real_kind::double_};
    /// ensembles: every [[ensemble]] this step runs (ensemble_index first), on one set of
    /// trajectories
    std::vector<std::size_t> ensemble_indices;
};

struct plan {
    std::vector<plan_step> steps;
    /// Number of steps of a kind (for tests and the dry-run summary).
    std::size_t count(plan_step::kind k) const;
};

/// True for quantities that need the saddle orbit (the registry's needs_saddle_orbit; throws
/// input_error for an unknown name).
bool needs_saddle_orbit(const std::string& quantity);

/// Builds the plan; throws scene_error for an unknown quantity or an energy a requested quantity
/// does not admit.
plan make_plan(const scene& s);

/// The run settings of an [[ensemble]] as a study request, by study/settings.hpp's builder (a
/// scene's defaults; energies, criteria, arm, files and threads are the caller's). The plan's
/// sharing rule compares the trajectory_key of these requests.
simulation_request ensemble_settings(const ensemble_spec& x);

/// Writes the plan, one line per step.
void print_plan(const scene& s, const plan& p, std::ostream& out);

/// What a run did, counted (tests use this to prove unrequested work was skipped).
struct run_counters {
    std::size_t orbit_solves = 0;          ///< saddle orbits solved (cache misses)
    std::size_t orbit_cache_hits = 0;      ///< saddle orbits read from the cache
    std::size_t orbit_cache_rejected = 0;  ///< cache entries refused (corrupt, invalid): recomputed
    std::size_t quantity_evaluations = 0;  ///< registry evaluations
    std::size_t trajectories = 0;          ///< trajectories integrated
    std::size_t curve_criteria = 0;        ///< criteria evaluated that are curves (approx, saddle)
    std::vector<std::string> files;        ///< files written
};

class process_group;  // study/simulation.hpp

struct run_options {
    /// saddle-orbit cache directory; empty: no disk cache (the in-process memo still applies)
    std::filesystem::path cache_dir;
    int threads = 0;  ///< OpenMP threads for ensembles, golden data and accuracy (0: all)
    /// seconds between appends of finished trajectories to an ensemble's checkpoint (0: after
    /// every trajectory)
    double checkpoint_interval = 2;
    /// The report generator (tools/report/make_report.py) a [report] table runs; the command
    /// line finds it beside its executable (empty: a scene with a report is refused).
    std::filesystem::path report_script;
    /// Processes sharing the run (`mpirun -np N flipflux run SCENE`; null: one). The ensembles'
    /// trajectories are spread over them (study/simulation.hpp: the results are those of one
    /// process, bit for bit); everything else -- orbits, predictions, trajectories, files, the
    /// report -- is computed once, by rank 0. The other ranks join only the ensemble steps.
    process_group* group = nullptr;
    /// The caller's words for its commands in the files the scene generates (golden provenance,
    /// the accuracy report); the command line gives its own.
    command_words words;
    /// The CPU seconds the run may take (this process's, every thread; 0: no bound), from its
    /// start. Checked at every integrator step of an ensemble and between the plan's steps; at the
    /// bound the run stops as at `stop`: execute_plan throws simulation_interrupted with signal()
    /// cpu_bound_stop. An orbit family, predictions, a trajectory, the viewer's page and the orbit
    /// tables have the rest of it as the calling thread's CPU budget and stop inside (their work
    /// not kept); [golden], [accuracy] and [report] run to their end before the check ([golden]
    /// and [accuracy] have max_seconds of their own).
    double max_seconds = 0;
    /// The caller's stop flag (a signal's number; null: none), polled where max_seconds is: a
    /// non-zero value stops the run, execute_plan throwing simulation_interrupted with signal()
    /// that value. Either way the finished ensembles' results and the one in progress's finished
    /// trajectories stay in their checkpoints (ensemble-NAMES.checkpoint in the output directory,
    /// removed when the whole run completes), so that the same command resumes the run.
    const std::atomic<int>* stop = nullptr;
    /// Called as an ensemble step's trajectories finish (rank 0 only): the step's ensembles'
    /// names ("a" or "a+b", those sharing its trajectories) and the study's progress; null: none.
    std::function<void(const std::string& ensembles, const simulation_progress&)> progress;
};

/// The default cache directory: $FLIPFLUX_CACHE_DIR, else $XDG_CACHE_HOME/flipflux, else
/// $HOME/.cache/flipflux, else .flipflux-cache.
std::filesystem::path default_cache_dir();

/// The checks execute_plan makes of an existing output directory before computing anything (a
/// folder where the scene writes a file; another scene's run.json), for --dry-run: it creates and
/// removes nothing. Throws scene_error naming scene.output.
void check_existing_output(const scene& s);

/// Executes the plan, writing outputs under s.output (atomically); progress to `log`.
run_counters execute_plan(const scene& s, const plan& p, std::ostream& log,
                          const run_options& options = {});

}  // namespace flipflux
