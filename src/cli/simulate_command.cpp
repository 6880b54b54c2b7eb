// flipflux simulate: Monte Carlo ensembles (paper Sec. 5-6), a thin layer over
// study/simulation.hpp: parses the options and prints the study's JSON report (with the model).
// Also the run-time machinery of long runs:
//   - MPI: when launched by mpirun (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK in the
//     environment) MPI is initialised and the ranks share the trajectories (simulation.hpp's
//     process_group); rank 0 prints the report. Otherwise MPI is not touched at all.
//   - SIGINT/SIGTERM: a flag the integrators poll once per step; in-flight trajectories are
//     abandoned, finished ones are in the checkpoint, the exit status is 128 + the signal.
//   - a progress bar on stderr (a terminal, or --progress).
#include <unistd.h>

#include <atomic>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "common.hpp"
#include "flipflux/ensemble/replicate_check.hpp"
#include "flipflux/ensemble/sampler.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_files.hpp"
#include "flipflux/validation/candidate_pendulum.hpp"
#include "mpi_group.hpp"
#include "progress.hpp"
#include "simulate_request.hpp"

namespace flipflux::cli {
namespace {

/// --initial-states: the file's energies and states replace --energy and --trajectories (one
/// replicate); its `# pendulum:` line, if any, must name the model options' pendulum.
void use_initial_states(const simulate_state& s, const double_pendulum<double>& model,
                        simulation_request& q, bool both, bool root) {
    if (const std::optional<declared_pendulum> d = read_declared_pendulum(s.initial_states)) {
        try {  // a declared value no pendulum has is refused as such, not asked for
            (void)make_model<double>(d->parameters);
        } catch (const input_error& e) {
            throw input_error("--initial-states: " + d->where + ": pendulum: " + e.what());
        }
        if (!same_parameters(d->parameters, s.model))
            throw input_error("--initial-states: " + d->where + ": the pendulum " +
                              parameters_text(d->parameters) + " is not the model options' (" +
                              parameters_text(s.model) + "): give its parameters");
    }
    const std::vector<initial_state_set> sets = read_initial_states(s.initial_states, model);
    std::size_t repeated = 0;
    for (const initial_state_set& set : sets) {
        repeated += set.repeated;
        // where no flip is possible: the file's line, not an option the user did not give
        double threshold = std::numeric_limits<double>::infinity();
        for (const arm a : {arm::one, arm::two}) {
            if (!both && a != q.flip_arm) continue;
            double t = 0;
            for (const std::string& c : q.criteria)
                t = std::max(t, criterion_threshold(model, a, c));
            threshold = std::min(threshold, t);
        }
        if (!(set.energy > threshold))
            throw input_error("--initial-states: " + s.initial_states + ":" +
                              std::to_string(set.lines.front()) + ": E = " + set.label +
                              " is at or below the threshold " + to_decimal(threshold) +
                              (both ? " of both arms" : " of arm " + to_string(q.flip_arm)) +
                              " (no flips possible)");
    }
    if (repeated > 0 && root)
        std::fprintf(stderr,
                     "flipflux: note: --initial-states: %zu rows repeat a state of their energy "
                     "(a paired file lists each trajectory per arm): each state is integrated "
                     "once\n",
                     repeated);
    if (q.replicates != 1)
        throw input_error("--replicates: not with --initial-states (one set of trajectories)");
    q.energies.clear();
    q.initial_states.clear();
    for (const initial_state_set& set : sets) {
        if (set.states.size() != sets.front().states.size())
            throw input_error("--initial-states: '" + s.initial_states + "' has " +
                              std::to_string(set.states.size()) + " states at E = " + set.label +
                              " but " + std::to_string(sets.front().states.size()) + " at E = " +
                              sets.front().label + ": every energy needs the same number");
        q.energies.emplace_back(set.label, set.energy);
        q.initial_states.push_back(
            std::make_shared<const std::vector<phase_point<double>>>(set.states));
    }
    q.options.trajectories = sets.front().states.size();
}

/// --write-initial-states: a writable file that is not another output of the run.
void check_initial_states_output(const simulate_state& s) {
    namespace fs = std::filesystem;
    const std::string& f = s.write_initial_states;
    if (f.empty()) throw input_error("--write-initial-states: '' is not a file name");
    check_output_file(f, "--write-initial-states");
    std::error_code ec;
    const fs::path w = fs::weakly_canonical(fs::absolute(f, ec), ec);
    for (const auto& [option, other] : {std::pair{"--checkpoint", &s.checkpoint},
                                        std::pair{"--initial-states", &s.initial_states}})
        if (!other->empty() && w == fs::weakly_canonical(fs::absolute(*other, ec), ec))
            throw input_error("--write-initial-states: '" + f + "' is also the " + option +
                              " file");
    if (!s.csv_dir.empty() && w.extension() == ".csv") {
        const fs::path d = fs::weakly_canonical(fs::absolute(s.csv_dir, ec), ec);
        for (fs::path p = w.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path())
            if (p == d)
                throw input_error("--write-initial-states: '" + f +
                                  "' is a CSV name inside --csv-dir, where the ensemble's CSVs "
                                  "are written: choose another name or folder");
    }
}

/// --arm both: a study per arm on one set of trajectories; an arm counts only at the energies
/// above its criteria's thresholds (a note names the others), as a scene's ensembles do.
std::vector<simulation_request> both_arms(const double_pendulum<double>& model,
                                          const simulation_request& q, bool root) {
    std::vector<simulation_request> out;
    std::vector<std::string> notes;
    std::vector<int> counted(q.energies.size(), 0);  // arms counting at each energy
    for (const arm a : {arm::one, arm::two}) {
        simulation_request r = q;
        r.flip_arm = a;
        r.energies.clear();
        r.initial_states.clear();
        if (!q.csv_dir.empty()) r.csv_dir = q.csv_dir / ("arm" + to_string(a));
        if (!out.empty()) r.progress = nullptr;
        double threshold = 0;
        for (const std::string& c : q.criteria)
            threshold = std::max(threshold, criterion_threshold(model, a, c));
        std::string skipped;
        for (std::size_t k = 0; k < q.energies.size(); ++k) {
            if (q.energies[k].second > threshold) {
                ++counted[k];
                r.energies.push_back(q.energies[k]);
                if (!q.initial_states.empty()) r.initial_states.push_back(q.initial_states[k]);
            } else {
                skipped += (skipped.empty() ? "" : ",") + q.energies[k].first;
            }
        }
        if (!skipped.empty())  // noted only when some arm counts (else one error line)
            notes.push_back("flipflux: note: --arm both: arm " + to_string(a) +
                            " is not counted at E = " + skipped + " (at or below its threshold " +
                            to_decimal(threshold) + ": no flips possible)\n");
        if (!r.energies.empty()) out.push_back(std::move(r));
    }
    // an energy neither arm counts is refused, as a single arm's run refuses its own
    for (std::size_t k = 0; k < q.energies.size(); ++k)
        if (counted[k] == 0)
            throw input_error("--energy: '" + q.energies[k].first +
                              "' lies at or below both arms' thresholds (no flips possible)");
    if (root)
        for (const std::string& n : notes)
            std::fputs(n.c_str(), stderr);
    if (out.front().flip_arm != arm::one) out.front().progress = q.progress;
    return out;
}

/// --write-initial-states: every trajectory's initial state, given or sampled.
std::string initial_states_text(const simulate_state& s, const double_pendulum<double>& model,
                                const simulation_request& q) {
    std::vector<initial_state_set> sets;
    const std::uint64_t n = q.options.trajectories * q.replicates;
    for (std::size_t k = 0; k < q.energies.size(); ++k) {
        ensemble_options o = q.options;
        o.energy = q.energies[k].second;
        o.initial_states = q.initial_states.empty() ? nullptr : q.initial_states[k];
        const microcanonical_sampler sampler(model, o.energy);
        initial_state_set set{q.energies[k].first, o.energy, {}, {}};
        for (std::uint64_t i = 0; i < n; ++i)
            set.states.push_back(initial_state_of(sampler, o, o.first_index + i));
        sets.push_back(std::move(set));
    }
    return "# pendulum: " + parameters_text(s.model) + "\n" +
           initial_states_csv(sets, q.options.first_index);
}

void run(const simulate_state& s) {
    std::unique_ptr<mpi_group> mpi;
    if (launched_by_mpirun()) mpi = open_mpi_group();
    const bool root = !mpi || mpi->rank() == 0;
    try {
        const double_pendulum<double> model = make_model<double>(s.model);
        const bool given = !s.initial_states.empty(), both = s.arm_text == "both";
        if (given && !s.energy.empty())
            throw input_error("--energy: not with --initial-states (its file gives the energies)");
        if (given && !s.trajectories.empty())
            throw input_error(
                "--trajectories: not with --initial-states (one trajectory per state)");
        if (!given && s.energy.empty())
            throw input_error("--energy is required (or --initial-states FILE)");
        if (!given && s.trajectories.empty())
            throw input_error("--trajectories is required (or --initial-states FILE)");
        simulate_state one = s;
        if (both) one.arm_text = "1";
        if (given) one.energy = "1", one.trajectories = "1";  // replaced by the file's
        simulation_request q = make_request(one);
        if (given) use_initial_states(s, model, q, both, root);
        if (!s.write_initial_states.empty() && root) check_initial_states_output(s);
        q.options.stop = &stop_signal();
        q.group = mpi.get();
        progress_bar bar(s.progress);
        if (root && bar.active())
            q.progress = [&bar](const simulation_progress& p) { show_study_progress(bar, p); };
        const signal_guard guard;
        std::optional<study_result> result;
        std::optional<std::vector<study_result>> results;
        try {
            if (both) {
                // one set of trajectories, both arms' criteria (as a scene's ensembles do)
                std::vector<simulation_request> qs = both_arms(model, q, root);
                results = simulate(model, qs);
                if (results) result = results->front();
            } else {
                result = simulate(model, q);
            }
        } catch (const simulation_interrupted& e) {
            bar.finish();
            if (e.signal() == cpu_bound_stop)  // the run's own bound: an error naming it
                throw input_error(std::string("--max-seconds: ") + e.what());
            if (root) std::fprintf(stderr, "flipflux: %s\n", e.what());
            exit_status() = 128 + (e.signal() > 0 ? e.signal() : SIGINT);
            return;
        }
        bar.finish();
        std::vector<const study_result*> all;
        if (results)
            for (const study_result& r : *results)
                all.push_back(&r);
        else if (result)
            all.push_back(&*result);
        for (const study_result* r : all)
            for (const energy_result& e : r->energies)
                if (e.failed_trajectories > 0)  // excluded from the statistics (docs/limits.md)
                    std::fprintf(stderr,
                                 "flipflux: warning: E = %s: %llu of %llu trajectories failed "
                                 "(the integration stopped before T) and are excluded from the "
                                 "statistics (\"failed_trajectories\" in the report)\n",
                                 e.label.c_str(),
                                 static_cast<unsigned long long>(e.failed_trajectories),
                                 static_cast<unsigned long long>(r->options.trajectories));
        for (const study_result* r :
             all)  // the heavy-tail check (docs/theory.md, "Replicate errors")
            for (const energy_result& e : r->energies)
                for (const criterion_result& c : e.criteria) {
                    const criterion_statistics& st = c.statistics;
                    if (st.replicate_rates.empty()) continue;
                    const std::size_t R = st.replicate_rates.size();
                    const double ratio =
                        replicate_standard_error(st.replicate_rates) / st.rates.standard_error;
                    if (!replicate_error_ratio_flagged(ratio, R)) continue;
                    const std::array<double, 2> range = replicate_error_ratio_range(R);
                    std::fprintf(stderr,
                                 "flipflux: warning: E = %s, %s: the replicate error is %.3gx the "
                                 "per-trajectory standard error, outside [%.2g, %.3g], where "
                                 "%.4g %% of the ratios of %zu replicates fall when that error is "
                                 "right: %s (\"replicates\" in the report)\n",
                                 e.label.c_str(), st.criterion.c_str(), ratio, range[0], range[1],
                                 100 * (1 - replicate_check_false_alarm), R,
                                 ratio > range[1]
                                     ? "heavy tails or rare islands; trust the replicate error"
                                     : "the replicates agree more closely than their trajectories' "
                                       "spread allows; take the per-trajectory error as the "
                                       "floor");
                }
        if (result && !s.write_initial_states.empty())
            write_file_atomically(s.write_initial_states, initial_states_text(s, model, q));
        if (result && both) {
            json out{{"command", "simulate"}, {"arm", "both"}, {"studies", json::array()}};
            for (const study_result& r : *results)
                out["studies"].push_back(study_json(r));
            out["model"] = parameters_json(model);
            print(out.dump(2) + "\n");
        } else if (result) {
            json out = study_json(*result);
            out["model"] = parameters_json(model);
            print(out.dump(2) + "\n");
        }
    } catch (const std::exception& e) {
        if (!mpi || mpi->size() == 1) throw;
        // another rank may wait in a collective: report and end the whole job
        const auto* bad_input = dynamic_cast<const input_error*>(&e);
        const bool io = dynamic_cast<const output_error*>(&e) != nullptr ||
                        dynamic_cast<const convergence_error*>(&e) != nullptr;
        if (root || bad_input == nullptr)
            std::fprintf(stderr, "flipflux: %s%s\n",
                         bad_input || io ? "error: " : "internal error: ",
                         bad_input ? error_text(*bad_input).c_str() : one_line(e.what()).c_str());
        std::fflush(stderr);
        mpi->abort(bad_input ? 2 : 1);
    }
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<simulate_state>();
    CLI::App* sub = app.add_subcommand(
        "simulate",
        "Monte Carlo ensemble at one or more energies: microcanonical initial conditions, "
        "trajectories (DOP853, DOPRI5 or Taylor at double), flips of each criterion, statistics as "
        "JSON "
        "(and CSV with --csv-dir). Default rtol 1e-10, where `trajectory` uses 1e-12: a "
        "statistic of many trajectories is insensitive to it (the rates' integration bias at "
        "1e-10 is far below their statistical error), one trajectory compared event by event "
        "is not; set --rtol to match either.");
    sub->add_option("--energy", s->energy,
                    "energy E, a list E1,E2,... or a range FROM:TO:STEP (inclusive; TO - FROM a "
                    "multiple of STEP) [required unless --initial-states]");
    sub->add_option("--arm", s->arm_text,
                    "the arm whose flips are counted: 1, 2 or both (one set of trajectories, "
                    "both arms' criteria: a report per arm under \"studies\", CSVs in "
                    "--csv-dir/arm1 and arm2)")
        ->capture_default_str();
    sub->add_option("--initial-states", s->initial_states,
                    "integrate these initial states instead of sampling (CSV: energy, theta1, "
                    "theta2, l1, l2, as --write-initial-states writes, e.g. another simulator's "
                    "own sample): the file gives the energies and the trajectories");
    sub->add_option("--write-initial-states", s->write_initial_states,
                    "write every trajectory's initial state (CSV: trajectory, energy, theta1, "
                    "theta2, l1, l2, every digit) for another simulator to integrate: the paired "
                    "check (validate --ensemble --paired, docs/validating.md)");
    sub->add_option("--criteria", s->criteria,
                    "comma-separated flip criteria: " + criterion_name_list())
        ->capture_default_str();
    sub->add_option("--replicates", s->replicates,
                    "independent replicates of --trajectories each (trajectories in index "
                    "blocks, distinct random streams): every statistic pooled and with its "
                    "spread over the replicates, verdicts from that spread (1 to 1000)")
        ->capture_default_str();
    sub->add_option("--trajectories", s->trajectories,
                    "number of trajectories per energy (> 0) [required unless --initial-states]");
    sub->add_option("--time", s->time, "integration time T per trajectory (> 0)")->required();
    sub->add_option("--seed", s->seed, "random seed (non-negative integer)")->capture_default_str();
    sub->add_option("--first-index", s->first_index,
                    "index of the first trajectory (split runs across processes)")
        ->capture_default_str();
    sub->add_option("--rtol", s->rtol,
                    "relative (and absolute) tolerance of the integrator (trajectory's default is "
                    "1e-12: see above)")
        ->capture_default_str();
    sub->add_option(
           "--method", s->method,
           "integrator: dop853, dopri5, taylor (adaptive-order Taylor series in SIMD lanes; rtol "
           "down to eps) or auto (taylor below rtol 1e-10, else dop853; the output names "
           "the choice)")
        ->capture_default_str();
    sub->add_option("--threads", s->threads, "OpenMP threads (0: all available)")
        ->capture_default_str();
    sub->add_option("--chaos-threshold", s->chaos_threshold,
                    "Lyapunov threshold for 'chaotic', in units of sqrt(alpha/A)")
        ->capture_default_str();
    sub->add_flag("--no-chaos", s->no_chaos,
                  "skip the variational equations (no chaotic/regular classification)");
    sub->add_option("--bins", s->bins, "histogram bins (0: square-root rule)")
        ->capture_default_str();
    sub->add_option("--sample-interval", s->sample_interval,
                    "store every trajectory's state at this time interval (needs --csv-dir)")
        ->capture_default_str();
    sub->add_option("--csv-dir", s->csv_dir,
                    "write per-trajectory rates, residence times and histograms as CSV here");
    sub->add_option("--checkpoint", s->checkpoint,
                    "save finished trajectories to FILE and resume from it (same command)");
    sub->add_option("--checkpoint-interval", s->checkpoint_interval,
                    "seconds between checkpoint appends (0: after every trajectory)")
        ->capture_default_str();
    sub->add_option("--max-seconds", s->max_seconds,
                    "CPU seconds (every thread's) the integration may take (0: no bound): at the "
                    "bound the run stops as at Ctrl-C, its finished trajectories kept in "
                    "--checkpoint (the same command resumes), exit status 2")
        ->capture_default_str();
    sub->add_option("--estimator", s->estimator,
                    "long: the given trajectories x time; short: the same budget in "
                    "trajectories of length --short-time")
        ->capture_default_str();
    sub->add_option("--short-time", s->short_time, "trajectory length of --estimator short")
        ->capture_default_str();
    sub->add_option("--reference-time", s->reference_time,
                    "also estimate the PQI for trajectories of this length (S scaled by "
                    "sqrt(time / reference); 0: not)")
        ->capture_default_str();
    sub->add_flag("--progress", s->progress,
                  "progress bar on stderr (default: only when stderr is a terminal)");
    sub->add_flag("--no-timing", s->no_timing,
                  "leave out seconds/threads/processes (output identical across runs)");
    add_model_options(*sub, s->model);
    sub->callback([s, sub] {
        for (const char* o : {"--write-initial-states", "--initial-states"})
            if (sub->get_option(o)->count() > 0 &&
                (o[2] == 'w' ? s->write_initial_states : s->initial_states).empty())
                throw input_error(std::string(o) + ": '' is not a file name");
        run(*s);
    });
});

}  // namespace
}  // namespace flipflux::cli
