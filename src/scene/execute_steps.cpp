// Scene steps that write outside the ensembles' data: golden data, the accuracy report, the
// report generator, and the checks of the output directories (execute_steps.hpp).
#include "execute_steps.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>

#include "flipflux/output/accuracy_markdown.hpp"
#include "flipflux/output/golden_files.hpp"
#include "flipflux/quantities/accuracy.hpp"
#include "flipflux/quantities/golden.hpp"

namespace flipflux {

namespace scene_steps {

namespace {

/// How the run was started, as generated files record it: the caller's command and the scene.
std::string scene_command(const context& ctx) {
    const std::string& run = ctx.options.words.run_scene;
    return (run.empty() ? std::string("scene") : run) + " " + ctx.s.file.string();
}

}  // namespace

// ---- golden data, accuracy, report ----------------------------------------------------------

void run_golden(context& ctx) {
    const golden_spec& g = *ctx.s.golden;
    if (ctx.s.custom_model) {
        throw scene_error(ctx.s.file.string() + ":" + std::to_string(g.line) +
                          ": golden: golden data is defined for the default (egalitarian) "
                          "pendulum; remove [model] or [golden]");
    }
    golden_options options;
    options.quantities = g.quantities;
    options.value_precision = g.value_precision;
    options.jobs = ctx.options.threads > 0 ? ctx.options.threads : 2;
    options.max_seconds = std::strtod(g.max_seconds.c_str(), nullptr);
    std::size_t skipped = 0;
    options.skipped = [&](const std::string& what) {
        ++skipped;
        ctx.log << "  golden: skipped " << what << "\n";
    };
    std::size_t last = 0;
    options.progress = [&](const golden_row&, std::size_t done, std::size_t total) {
        if (done == total || done >= last + 50) {
            ctx.log << "  golden rows " << done << "/" << total << "\n";
            last = done;
        }
    };
    const auto rows = generate_golden(options);
    const std::filesystem::path dir = g.dir;
    std::filesystem::create_directories(dir);
    write_file_atomically(dir / "golden.csv", golden_csv(rows));
    write_file_atomically(dir / "provenance.json",
                          golden_provenance(scene_command(ctx), rows.size(),
                                            options.value_precision, ctx.options.words));
    ctx.counters.files.push_back((dir / "golden.csv").string());
    ctx.counters.files.push_back((dir / "provenance.json").string());
    ctx.log << "  wrote " << (dir / "golden.csv").string() << " (" << rows.size() << " rows)\n";
    ctx.summary["golden"] = {{"dir", g.dir}, {"rows", rows.size()}, {"skipped", skipped}};
}

void run_accuracy(context& ctx) {
    const accuracy_spec& a = *ctx.s.accuracy;
    std::string appendix;  // read first: a missing file is an error before minutes of measuring
    for (const std::string& file : a.appendices) {
        try {
            appendix += "\n" + read_input_file(file, "accuracy.appendices");
        } catch (const input_error& e) {
            throw scene_error(ctx.s.file.string() + ":" + std::to_string(a.line) +
                              ": accuracy.appendices: " + e.detail());
        }
    }
    accuracy_options options;
    options.quantities = a.quantities;
    options.precisions = a.precisions;
    options.max_seconds = std::strtod(a.max_seconds.c_str(), nullptr);
    options.threads = ctx.options.threads > 0 ? ctx.options.threads : 2;
    options.progress = [&](const std::string& line) { ctx.log << "  " << line << "\n"; };
    const auto entries = measure_accuracy(options);
    const std::string md =
        accuracy_markdown(entries, options, scene_command(ctx), ctx.options.words) + appendix;
    const std::filesystem::path out = a.out;
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    write_file_atomically(out, md);
    ctx.counters.files.push_back(out.string());
    ctx.log << "  wrote " << out.string() << "\n";
    ctx.summary["accuracy"] = {{"file", a.out}};
}

void run_report(context& ctx, double seconds_so_far) {
    const report_spec& r = *ctx.s.report;
    // run.json first: the report reads it
    ctx.summary["seconds"] = seconds_so_far;
    ctx.summary["cpu_seconds"] = process_cpu_seconds() - ctx.cpu_start;
    ctx.write("run.json", ctx.summary.dump(2) + "\n");
    const std::filesystem::path& script = ctx.options.report_script;
    if (script.empty() || !std::filesystem::is_regular_file(script))
        throw std::runtime_error(
            "report: the report generator make_report.py was not found" +
            (script.empty() ? std::string() : " at '" + script.string() + "'") +
            " (it is installed beside the executable: share/flipflux/report/)");
    const std::string command = "python3 '" + script.string() + "' --run-dir '" +
                                ctx.s.output.string() + "' --out '" + r.dir + "'" + [&] {
                                    std::string others;
                                    for (const std::string& d : r.other_runs)
                                        others += " --other-run-dir '" + d + "'";
                                    return others;
                                }();
    ctx.log << "  " << command << "\n";
    ctx.log.flush();
    const int status = std::system(command.c_str());
    // exit status 2: the generator refused its input (a dirty work tree, a malformed run
    // directory) and said why on stderr, in one line each: a user's error, not an internal one
    if (status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 2)
        throw input_error("report: make_report.py refused to write '" + r.dir +
                          "' (its reason is above); the run's results are in '" +
                          ctx.s.output.string() + "': rerun the report alone with " + command);
    if (status != 0)  // the environment's failure (exit status 1), not an internal error
        throw output_error("report: make_report.py failed (" +
                           (status != -1 && WIFEXITED(status)
                                ? "exit status " + std::to_string(WEXITSTATUS(status))
                                : std::string("status ") + std::to_string(status)) +
                           "; its reason is above); the run's results are in '" +
                           ctx.s.output.string() + "': rerun the report alone with " + command);
    ctx.summary["report"] = {{"dir", r.dir}};
}

/// Creates `dir` (and its parents) and checks that a file can be created in it; throws
/// scene_error naming the scene's file, line and key otherwise.
void create_output_dir(const scene& s, const std::filesystem::path& dir, int line,
                       const std::string& key) {
    const std::string where =
        s.file.string() + ":" + std::to_string(line) + ": " + key + ": '" + dir.string() + "' ";
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
        throw scene_error(where + "cannot be created (" +
                          (ec ? ec.message() : std::string("not a directory")) + ")");
    const std::filesystem::path probe =
        dir / (".flipflux-write-test-" + std::to_string(::getpid()));
    std::ofstream test(probe);
    const bool writable = static_cast<bool>(test << "x");
    test.close();
    std::filesystem::remove(probe, ec);
    if (!writable) throw scene_error(where + "is not writable");
}

/// The scene's output directory, before anything is computed. Its files are *.csv, *.json and
/// *.checkpoint directly in it: a folder (or anything but a file) in such a place would fail its
/// write late, after the computation. With `remove_stale`, dead processes' temporary files of
/// them are removed.
void check_output_entries(const scene& s, bool remove_stale) {
    const std::string where = s.file.string() + ":" + std::to_string(s.output_line) +
                              ": scene.output: '" + s.output.string() + "' ";
    const auto ours = [](const std::filesystem::path& p) {
        const std::string ext = p.extension().string();
        return ext == ".csv" || ext == ".json" || ext == ".checkpoint";
    };
    std::error_code ec;
    std::vector<std::filesystem::path> stale;
    for (const auto& e : std::filesystem::directory_iterator(s.output, ec)) {
        std::error_code fe;
        // NAME.tmp.PID of write_file_atomically for one of the scene's files, left by a process
        // that was killed: removed when PID no longer runs (nothing else is touched)
        const std::string name = e.path().filename().string();
        if (const std::size_t at = name.rfind(".tmp."); at != std::string::npos) {
            const std::string pid = name.substr(at + 5);
            if (ours(name.substr(0, at)) && !pid.empty() && pid.size() < 10 &&
                pid.find_first_not_of("0123456789") == std::string::npos &&
                std::filesystem::is_regular_file(e.path(), fe) &&
                ::kill(static_cast<pid_t>(std::stol(pid)), 0) != 0 && errno == ESRCH)
                stale.push_back(e.path());
            continue;
        }
        if (ours(e.path()) && !std::filesystem::is_regular_file(e.path(), fe))
            throw scene_error(where + "holds '" + e.path().filename().string() +
                              "', which is not a regular file, where the scene writes its files");
    }
    if (remove_stale)
        for (const std::filesystem::path& f : stale)
            std::filesystem::remove(f, ec);
}

/// The output directory is this scene's, or nobody's: another scene's run.json there means its
/// files would be mixed with this run's (a resumed run of this scene finds its own name).
void check_output_owner(const scene& s) {
    const std::filesystem::path file = s.output / "run.json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return;
    std::string text;
    try {
        text = read_input_file(file, "scene.output");
    } catch (const input_error&) {
        return;  // unreadable or huge: not a run.json this program wrote
    }
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("scene") || !j["scene"].is_string())
        return;  // not a run.json this program wrote: rewritten like any output
    const std::string owner = j["scene"].get<std::string>();
    if (owner != s.name)
        throw scene_error(s.file.string() + ":" + std::to_string(s.output_line) +
                          ": scene.output: '" + s.output.string() + "' holds the run of scene '" +
                          owner + "' (its run.json): choose another output, or remove it");
}

}  // namespace scene_steps

void check_existing_output(const scene& s) {
    std::error_code ec;
    if (!std::filesystem::is_directory(s.output, ec)) return;  // run creates it (make_plan checked)
    scene_steps::check_output_entries(s, false);
    scene_steps::check_output_owner(s);
}

}  // namespace flipflux
