// flipflux run [--dry-run] SCENE: compute what a scene file asks for, and nothing else.
// --max-seconds S bounds the run's CPU time; at the bound, or at SIGINT/SIGTERM, it stops with its
// ensembles' finished trajectories and finished ensemble steps in their checkpoints, and the same
// command resumes (exit status 2 at the bound, 128 + the signal otherwise). Each ensemble step
// shows a progress bar on stderr (a terminal, or --progress).
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "common.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "mpi_group.hpp"
#include "progress.hpp"

namespace flipflux::cli {
namespace {

/// The report generator: $FLIPFLUX_REPORT_SCRIPT, else share/flipflux/report/make_report.py
/// beside the executable (build tree) or in ../share (installed); empty when none exists.
std::filesystem::path find_report_script() {
    if (const char* env = std::getenv("FLIPFLUX_REPORT_SCRIPT"); env && *env) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(env, ec))
            throw input_error("FLIPFLUX_REPORT_SCRIPT: '" + std::string(env) +
                              "' is not a file (the report generator make_report.py)");
        return env;
    }
    return find_share_path("report/make_report.py");
}

struct run_state {
    std::string file;
    bool dry_run = false;
    std::string cache_dir;
    bool no_cache = false;
    int threads = 0;
    double checkpoint_interval = 2;
    double max_seconds = 0;
    bool progress = false;
};

void run_scene(const run_state& s, process_group* group);

/// The message of a run stopped at its bound (naming --max-seconds) or by a signal.
std::string stopped_text(const simulation_interrupted& e) {
    return e.signal() == cpu_bound_stop ? std::string("--max-seconds: ") + e.what() : e.what();
}
/// Its exit status: 2 at the bound (as bad input), else 128 + the signal.
int stopped_status(const simulation_interrupted& e) {
    return e.signal() == cpu_bound_stop ? 2 : 128 + (e.signal() > 0 ? e.signal() : SIGINT);
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<run_state>();
    CLI::App* sub = app.add_subcommand(
        "run", "Run a scene file (TOML, see docs/scenes.md): compute exactly what it requests");
    sub->add_option("scene", s->file, "the scene file")->required();
    sub->add_flag("--dry-run", s->dry_run, "print the plan without computing anything");
    sub->add_option("--cache-dir", s->cache_dir,
                    "saddle-orbit cache (default: $FLIPFLUX_CACHE_DIR, $XDG_CACHE_HOME/flipflux "
                    "or ~/.cache/flipflux)");
    sub->add_flag("--no-cache", s->no_cache, "neither read nor write the saddle-orbit cache");
    sub->add_option("--threads", s->threads, "OpenMP threads (0: all available)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--checkpoint-interval", s->checkpoint_interval,
                    "seconds between checkpoint appends of an ensemble's finished trajectories "
                    "(0: after every one)")
        ->capture_default_str();
    sub->add_option("--max-seconds", s->max_seconds,
                    "CPU seconds the run may take (0: no bound); at the bound it stops as at "
                    "SIGINT, keeping its ensembles' finished trajectories, and the same command "
                    "resumes")
        ->capture_default_str();
    sub->add_flag("--progress", s->progress,
                  "a progress bar of each ensemble step on stderr (default: only when stderr is a "
                  "terminal)");
    sub->callback([s] {
        if (!(s->checkpoint_interval >= 0) || !std::isfinite(s->checkpoint_interval)) {
            throw input_error("--checkpoint-interval: '" + to_decimal(s->checkpoint_interval) +
                              "' is invalid (must be a finite number >= 0)");
        }
        if (!(s->max_seconds >= 0))
            throw input_error("--max-seconds: '" + to_decimal(s->max_seconds) +
                              "' is invalid (must be >= 0; 0: no bound)");
        (void)checked_threads(static_cast<std::uint64_t>(s->threads), "--threads");
        // mpirun -np N flipflux run SCENE: the ensembles' trajectories spread over the ranks,
        // everything else computed and written by rank 0 (run_options::group)
        std::unique_ptr<mpi_group> mpi;
        if (!s->dry_run && launched_by_mpirun()) mpi = open_mpi_group();
        if (mpi && mpi->size() > 1) {
            try {
                run_scene(*s, mpi.get());
            } catch (const simulation_interrupted& e) {
                // every rank stops in the same ensemble step (its collective agrees) or rank 0
                // alone between steps: rank 0 says why and ends the whole job; the others give it
                // the time to (their abort would end it first, unsaid)
                if (mpi->rank() == 0) {
                    std::fprintf(stderr, "flipflux: %s%s\n",
                                 e.signal() == cpu_bound_stop ? "error: " : "",
                                 stopped_text(e).c_str());
                    std::fflush(stderr);
                } else {
                    std::this_thread::sleep_for(std::chrono::seconds(5));
                }
                mpi->abort(stopped_status(e));
            } catch (const std::exception& e) {
                // another rank may wait in a collective: report (rank 0, or any rank's internal
                // error) and end the whole job
                const auto* bad_input = dynamic_cast<const input_error*>(&e);
                const bool io = dynamic_cast<const output_error*>(&e) != nullptr ||
                                dynamic_cast<const convergence_error*>(&e) != nullptr;
                if (mpi->rank() == 0 || bad_input == nullptr)
                    std::fprintf(
                        stderr, "flipflux: %s%s\n",
                        bad_input || io ? "error: " : "internal error: ",
                        bad_input ? error_text(*bad_input).c_str() : one_line(e.what()).c_str());
                std::fflush(stderr);
                mpi->abort(bad_input ? 2 : 1);
            }
            return;
        }
        try {
            run_scene(*s, nullptr);
        } catch (const simulation_interrupted& e) {
            if (e.signal() == cpu_bound_stop) throw input_error(stopped_text(e));
            std::fprintf(stderr, "flipflux: %s\n", stopped_text(e).c_str());
            exit_status() = stopped_status(e);
        }
    });
});

void run_scene(const run_state& st, process_group* group) {
    const run_state* s = &st;
    {
        const scene sc = load_scene(s->file);
        const plan p = make_plan(sc);
        if (s->dry_run) check_existing_output(sc);  // what run would refuse, refused here too
        run_options options;
        options.words = cli_command_words();
        if (sc.report) {  // refused now rather than after the computation (and by --dry-run)
            options.report_script = find_report_script();
            if (options.report_script.empty())
                throw input_error(
                    "the scene has a [report] but the report generator make_report.py is not "
                    "installed beside this executable (share/flipflux/report/) and "
                    "FLIPFLUX_REPORT_SCRIPT is not set");
        }
        const bool root = group == nullptr || group->rank() == 0;
        if (root) print_plan(sc, p, std::cout);
        if (s->dry_run) return;
        options.threads = s->threads;
        options.group = group;
        options.checkpoint_interval = s->checkpoint_interval;
        options.max_seconds = s->max_seconds;
        options.stop = &stop_signal();
        if (!s->no_cache)
            options.cache_dir =
                s->cache_dir.empty() ? default_cache_dir() : std::filesystem::path(s->cache_dir);
        // each ensemble step's bar on stderr (rank 0): a new bar when another step reports
        std::unique_ptr<progress_bar> bar;
        std::string bar_of;
        if (root && progress_bar(s->progress).active())
            options.progress = [&](const std::string& ensembles, const simulation_progress& q) {
                if (!bar || ensembles != bar_of) {
                    if (bar) bar->finish();
                    bar = std::make_unique<progress_bar>(s->progress);
                    bar_of = ensembles;
                }
                show_study_progress(*bar, q, "ensemble " + ensembles);
            };
        std::ostringstream quiet;  // the other ranks' log
        const signal_guard guard;  // SIGINT, SIGTERM: the run stops as at its CPU bound
        run_counters c;
        try {
            c = execute_plan(sc, p, root ? std::cout : quiet, options);
        } catch (...) {
            if (bar) bar->finish();  // a terminal's open line ended before the message
            throw;
        }
        if (!root) return;
        std::cout << "saddle orbits solved " << c.orbit_solves << ", from cache "
                  << c.orbit_cache_hits
                  << (c.orbit_cache_rejected ? " (" + std::to_string(c.orbit_cache_rejected) +
                                                   " invalid cache entries recomputed)"
                                             : std::string())
                  << "; trajectories " << c.trajectories << "; curve criteria " << c.curve_criteria
                  << "\n";
    }
}

}  // namespace
}  // namespace flipflux::cli
