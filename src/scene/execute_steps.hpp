// Scene execution's shared state and the steps that write outside the ensembles' data (private to
// src/scene): golden data, the accuracy report, the report generator, and the checks of the
// output directories. execute.cpp runs the plan; execute_steps.cpp holds these steps.
#pragma once

#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "flipflux/core/budget.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/scene/plan.hpp"

namespace flipflux::scene_steps {

using json = nlohmann::ordered_json;

/// One run of a plan: the scene, where progress goes, the caller's options and what was written.
struct context {
    const scene& s;
    std::ostream& log;
    const run_options& options;
    run_counters counters;
    json summary = json::object();
    double cpu_start = process_cpu_seconds();  ///< the run's start, for run.json's cpu_seconds
    /// false on the ranks other than 0 of an MPI run: they compute what the ensembles need and
    /// write nothing (join_ensembles)
    bool writes = true;
    /// What the ensembles poll to stop (run_options::stop or the run's CPU bound; null: nothing).
    const std::atomic<int>* stop = nullptr;
    /// The ensemble steps' checkpoints, removed once the whole run is complete (a stopped run's
    /// rerun restores its finished ensembles from them).
    std::vector<std::filesystem::path> checkpoints{};

    void write(const std::filesystem::path& name, const std::string& content) {
        if (!writes) return;
        const auto path = s.output / name;
        write_file_atomically(path, content);
        counters.files.push_back(path.string());
        log << "  wrote " << path.string() << "\n";
    }
};

/// [golden]: the golden rows and their provenance in golden.dir.
void run_golden(context& ctx);

/// [accuracy]: the measured accuracy table, with its appendices, in accuracy.out.
void run_accuracy(context& ctx);

/// [report]: run.json (seconds_so_far so far), then tools/report/make_report.py on the run.
void run_report(context& ctx, double seconds_so_far);

/// Creates `dir` (and its parents) and checks that a file can be created in it; throws
/// scene_error naming the scene's file, line and key otherwise.
void create_output_dir(const scene& s, const std::filesystem::path& dir, int line,
                       const std::string& key);

/// The scene's output directory, before anything is computed: its places for files are free of
/// folders; with `remove_stale`, dead processes' temporary files of them are removed.
void check_output_entries(const scene& s, bool remove_stale);

/// The output directory is this scene's, or nobody's (another scene's run.json: scene_error).
void check_output_owner(const scene& s);

}  // namespace flipflux::scene_steps
