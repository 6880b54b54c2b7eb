// Scene execution: outputs are written, unrequested work is skipped (counted), saddle orbits are
// continued once and then read back bit-identically from the disk cache.
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipflux/core/decimal.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/quantities/registry.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path d = fs::path(::testing::TempDir()) /
                       ("flipflux_scene_" + name + "_" + std::to_string(getpid()));
    fs::remove_all(d);
    return d;
}

scene scene_in(const fs::path& out, const std::string& body) {
    return parse_scene("[scene]\nname = \"t\"\noutput = \"" + out.string() + "\"\n" + body,
                       "t.toml");
}

// An [[ensemble]] table: criteria as TOML array items ("\"upright\""), energies as a TOML
// array's items, then any further keys (each ending in a newline).
std::string ensemble_table(const std::string& name, const std::string& criteria,
                           const std::string& energies, int trajectories, int time,
                           const std::string& more = "") {
    return "[[ensemble]]\nname = \"" + name + "\"\ncriteria = [" + criteria + "]\nenergies = [" +
           energies + "]\ntrajectories = " + std::to_string(trajectories) +
           "\ntime = " + std::to_string(time) + "\n" + more;
}

run_counters run(const scene& s, const fs::path& cache = {}) {
    std::ostringstream log;
    run_options o;
    o.cache_dir = cache;
    o.threads = 1;
    return execute_plan(s, make_plan(s), log, o);
}

TEST(Execute, UprightPredictionsSolveNoOrbitAndIntegrateNothing) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("upright");
    const scene s = scene_in(out,
                             "[predictions]\nquantities = [\"omega\", \"rate-upright\"]\n"
                             "arms = [1, 2]\nenergies = [3, 5, 7]\n");
    const run_counters c = run(s);
    EXPECT_EQ(c.orbit_solves, 0u);
    EXPECT_EQ(c.orbit_cache_hits, 0u);
    EXPECT_EQ(c.trajectories, 0u);
    // omega at 3 energies, rate-upright for both arms at 3 energies (0 below arm 1's saddle, 4)
    EXPECT_EQ(c.quantity_evaluations, 3u + 3u + 3u);
    const auto rows = read_csv(out / "predictions.csv");
    ASSERT_EQ(rows.rows.size(), 9u);
    // the executor's values are the registry's, digit for digit
    const double_pendulum<double> model;
    for (const auto& r : rows.rows) {
        const auto& q = find_quantity(r.fields.at(0));
        const arm a = r.fields.at(1) == "1" ? arm::one : arm::two;
        const double e = parse_real<double>(r.fields.at(2), "energy");
        EXPECT_EQ(r.fields.at(3), to_decimal(q.evaluate(model, a, e, "").value))
            << r.fields.at(0) << " " << e;
    }
    const auto run_json = nlohmann::json::parse(read_text(out / "run.json"));
    EXPECT_EQ(run_json["predictions"]["skipped"].size(), 0u);
    EXPECT_EQ(run_json["model"]["coefficients"]["alpha"], "2");
    fs::remove_all(out);
}

TEST(Execute, SaddleFamilyIsSolvedOnceThenReadFromTheCache) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("saddle"), cache = fresh_dir("cache");
    const scene s = scene_in(out,
                             "[predictions]\nquantities = [\"flux-saddle\", \"period\"]\n"
                             "energies = [3, 3.5]\n"
                             "[orbits]\narms = [2]\nenergies = [3, 3.5]\ncurve_samples = 5\n");
    const run_counters first = run(s, cache);
    EXPECT_EQ(first.orbit_solves, 2u);  // one family, two orbits, shared by both outputs
    EXPECT_EQ(first.orbit_cache_hits, 0u);
    const std::string predictions = read_text(out / "predictions.csv");
    const std::string orbits = read_text(out / "orbits-arm2.csv");

    forget_saddle_orbits();  // a new process: only the disk cache remains
    fs::remove_all(out);
    const run_counters second = run(s, cache);
    EXPECT_EQ(second.orbit_solves, 0u);
    EXPECT_EQ(second.orbit_cache_hits, 2u);
    EXPECT_EQ(read_text(out / "predictions.csv"), predictions);  // bit-identical through the cache
    EXPECT_EQ(read_text(out / "orbits-arm2.csv"), orbits);

    // independent reference: scipy DOP853 at rtol 1e-13 with a shooting on (beta, T) gives, for
    // the egalitarian pendulum at E = 3, F = 5.61072094322671 and T = 5.97481755607803
    const auto rows = read_csv(out / "predictions.csv");
    ASSERT_EQ(rows.rows.size(), 4u);
    EXPECT_EQ(rows.rows[0].fields.at(0), "flux-saddle");
    EXPECT_NEAR(parse_real<double>(rows.rows[0].fields.at(3), "f"), 2 * 5.61072094322671, 1e-11);
    EXPECT_NEAR(parse_real<double>(rows.rows[2].fields.at(3), "T"), 5.97481755607803, 1e-11);
    // the curve samples lie on the energy surface's boundary at their ends (turning points)
    const auto curve = read_csv(out / "orbit-curves-arm2.csv");
    ASSERT_EQ(curve.rows.size(), 10u);
    const double_pendulum<double> model;
    const double v_end = model.potential(parse_real<double>(curve.rows[0].fields.at(1), "t1"),
                                         parse_real<double>(curve.rows[0].fields.at(2), "t2"));
    EXPECT_NEAR(v_end, 3.0, 1e-9);

    // issue 20: an edited entry (period 7.5, action -1) was used and published. Edited without
    // resealing it fails the checksum; resealed it fails the physical checks; both are
    // recomputed, counted and the outputs are the same as solved
    std::vector<fs::path> entries;
    for (const auto& f : fs::recursive_directory_iterator(cache))
        if (f.is_regular_file()) entries.push_back(f.path());
    ASSERT_EQ(entries.size(), 2u);
    for (std::size_t i = 0; i < entries.size(); ++i) {
        auto j = nlohmann::ordered_json::parse(read_text(entries[i]));
        j["period"] = "7.5";
        j["action"] = "-1";
        std::ofstream(entries[i]) << (i == 0 ? j.dump() : seal_orbit_record(j.dump()));
    }
    forget_saddle_orbits();
    const run_counters edited = run(s, cache);
    EXPECT_EQ(edited.orbit_cache_hits, 0u);
    EXPECT_EQ(edited.orbit_cache_rejected, 2u);
    EXPECT_EQ(edited.orbit_solves, 2u);
    EXPECT_EQ(read_text(out / "predictions.csv"), predictions);
    EXPECT_EQ(
        nlohmann::json::parse(read_text(out / "run.json"))["counters"]["orbit_cache_rejected"], 2);

    // a corrupted cache entry is recomputed, not trusted
    for (const auto& f : fs::recursive_directory_iterator(cache))
        if (f.is_regular_file()) std::ofstream(f.path()) << "{not json";
    forget_saddle_orbits();
    const run_counters third = run(s, cache);
    EXPECT_EQ(third.orbit_solves, 2u);
    EXPECT_EQ(third.orbit_cache_rejected, 2u);
    EXPECT_EQ(read_text(out / "predictions.csv"), predictions);

    // an entry that is not a regular file (a folder, a link to a device, a link loop) was an
    // "internal error" or a hang: it is recomputed and left as it is (the result not cached)
    {
        std::vector<fs::path> files;
        for (const auto& f : fs::recursive_directory_iterator(cache))
            if (f.is_regular_file()) files.push_back(f.path());
        ASSERT_EQ(files.size(), 2u);
        fs::remove(files[0]);
        fs::create_directory(files[0]);
        fs::remove(files[1]);
        fs::create_symlink("/dev/zero", files[1]);
        forget_saddle_orbits();
        const run_counters odd = run(s, cache);
        EXPECT_EQ(odd.orbit_solves, 2u);
        EXPECT_EQ(odd.orbit_cache_rejected, 2u);
        EXPECT_EQ(read_text(out / "predictions.csv"), predictions);
        EXPECT_TRUE(fs::is_directory(files[0]));
        EXPECT_TRUE(fs::is_symlink(files[1]));
        fs::remove(files[0]);
        fs::remove(files[1]);
    }

    // a folder where the scene writes a file, and a temporary file of a killed process: the
    // folder is refused before anything is computed, the temporary file removed
    {
        fs::remove(out / "predictions.csv");
        fs::create_directory(out / "predictions.csv");
        forget_saddle_orbits();
        EXPECT_THROW(check_existing_output(s), scene_error);  // --dry-run's check, the same
        try {
            (void)run(s, cache);
            ADD_FAILURE() << "a folder predictions.csv was accepted";
        } catch (const scene_error& e) {
            // the plan's check of every output path (scene_outputs), before the run's own
            EXPECT_NE(std::string(e.what()).find("predictions.csv' is a folder, where the run "
                                                 "writes a file"),
                      std::string::npos)
                << e.what();
        }
        fs::remove(out / "predictions.csv");
        // pid 2^22 + 1 is above Linux's pid_max limit: no process has it
        std::ofstream(out / "run.json.tmp.4194305") << "{";
        check_existing_output(s);  // --dry-run removes nothing
        EXPECT_TRUE(fs::exists(out / "run.json.tmp.4194305"));
        (void)run(s, cache);
        EXPECT_FALSE(fs::exists(out / "run.json.tmp.4194305"));
        EXPECT_EQ(read_text(out / "predictions.csv"), predictions);
    }

    // an output directory that cannot be created is refused before anything is computed
    const fs::path file = out / "predictions.csv";
    const scene blocked = scene_in(file / "sub",
                                   "[predictions]\nquantities = [\"omega\"]\n"
                                   "energies = [3]\n");
    std::ostringstream log;
    try {
        (void)execute_plan(blocked, plan{}, log, {});
        ADD_FAILURE() << "not refused";
    } catch (const scene_error& e) {
        EXPECT_NE(std::string(e.what()).find("t.toml:3: scene.output: '"), std::string::npos)
            << e.what();
    }
    fs::remove_all(out);
    fs::remove_all(cache);
}

TEST(Execute, OrbitIntegratorAppliesToFamiliesTablesAndQuantities) {
    // [scene] orbit_integrator = "taylor" at double (where Gauss-Legendre is the default): the
    // family is solved once by Taylor series, the quantity reuses it, and the values agree with
    // the default route's to the orbit's accuracy
    forget_saddle_orbits();
    const fs::path out = fresh_dir("integrator");
    const scene s = scene_in(out,
                             "orbit_integrator = \"taylor\"\n"
                             "[predictions]\nquantities = [\"period\"]\nenergies = [3]\n"
                             "[orbits]\narms = [2]\nenergies = [3]\n");
    const run_counters c = run(s);
    EXPECT_EQ(c.orbit_solves, 1u);
    const auto rows = read_csv(out / "predictions.csv");
    ASSERT_EQ(rows.rows.size(), 1u);
    EXPECT_NE(rows.rows[0].fields.at(5).find("Taylor"), std::string::npos)
        << rows.rows[0].fields.at(5);
    const auto table = read_csv(out / "orbits-arm2.csv");
    ASSERT_EQ(table.rows.size(), 1u);
    EXPECT_EQ(table.rows[0].fields.at(0), "3");  // the scene's text, not a rounded binary
    EXPECT_EQ(table.rows[0].fields.at(1), rows.rows[0].fields.at(3));
    const double T = parse_real<double>(rows.rows[0].fields.at(3), "T");
    EXPECT_NEAR(T, 5.97481755607803, 1e-11);  // scipy DOP853 reference (see above)
    // curve_flux (the curve-flux quadrature over the orbit's curve) against flux = 2 F
    const double flux = parse_real<double>(table.rows[0].fields.at(3), "flux");
    const double through = parse_real<double>(table.rows[0].fields.at(4), "curve_flux");
    EXPECT_NEAR(through / flux, 1.0, 1e-11);
    EXPECT_NEAR(flux, 2 * parse_real<double>(table.rows[0].fields.at(2), "action"), 1e-14 * flux);
    fs::remove_all(out);
    try {
        (void)scene_in(out, "orbit_integrator = \"rk4\"\n");
        ADD_FAILURE() << "an unknown integrator was accepted";
    } catch (const scene_error& e) {
        EXPECT_NE(std::string(e.what()).find("orbit_integrator"), std::string::npos) << e.what();
    }
}

TEST(Execute, EnsembleEvaluatesOnlyTheListedCriteria) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("ensemble");
    const scene s = scene_in(out, ensemble_table("u", "\"upright\"", "4, 5", 8, 5) +
                                      ensemble_table("ua", "\"upright\", \"approx\"", "5", 8, 5));
    const run_counters c = run(s);
    EXPECT_EQ(c.orbit_solves, 0u);
    // the two ensembles have the same trajectories (seed, N, T, ...): integrated once, at E = 4
    // and 5, E = 5's counting the flips of both ensembles' criteria
    EXPECT_EQ(c.trajectories, 8u * 2);
    EXPECT_EQ(c.curve_criteria, 1u);  // approx at E = 5 only
    // the short estimator spends the same budget on trajectories of length 20 (its default)
    const scene sh = scene_in(
        out, ensemble_table("short", "\"upright\"", "5", 4, 50, "estimator = \"short\"\n"));
    EXPECT_EQ(run(sh).trajectories, 10u);  // ceil(4 x 50 / 20)
    const auto u = nlohmann::json::parse(read_text(out / "ensemble-u.json"));
    ASSERT_EQ(u["energies"].size(), 2u);
    EXPECT_EQ(u["energies"][0]["criteria"].size(), 1u);
    EXPECT_TRUE(u["energies"][0]["criteria"].contains("upright"));
    // the pendulum, as `flipflux simulate` writes it (the scene's file did not say which)
    EXPECT_EQ(u["model"]["m1"], "1");
    EXPECT_EQ(u["model"]["coefficients"]["A"], "2");
    EXPECT_FALSE(fs::exists(out / "ensemble-u+ua.checkpoint"));  // removed once complete
    fs::remove_all(out);
}

// A stop the caller asked for (run_options::stop, a signal's number) before the run began: the
// run computes and writes nothing, and says so with the signal and how to resume.
TEST(Execute, AStopAskedForBeforeTheFirstStepComputesNothing) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("stopped");
    const scene s = scene_in(out,
                             "[predictions]\nquantities = [\"omega\"]\narms = [2]\n"
                             "energies = [4]\n" +
                                 ensemble_table("u", "\"upright\"", "5", 8, 5));
    std::atomic<int> stop{SIGINT};
    std::ostringstream log;
    run_options o;
    o.threads = 1;
    o.stop = &stop;
    try {
        execute_plan(s, make_plan(s), log, o);
        ADD_FAILURE() << "the run did not stop";
    } catch (const simulation_interrupted& e) {
        EXPECT_EQ(e.signal(), SIGINT);
        EXPECT_EQ(std::string(e.what()),
                  "interrupted before its first step; rerun the same command to resume");
    }
    EXPECT_FALSE(fs::exists(out / "predictions.csv"));
    EXPECT_FALSE(fs::exists(out / "ensemble-u.json"));
    EXPECT_FALSE(fs::exists(out / "run.json"));
    fs::remove_all(out);
}

// A checkpoint left in the output directory that is not this ensemble's (corrupt, or another
// run's: the scene was edited since) is refused naming the scene's file, line and ensemble, and
// what to do; it is not the command line's --checkpoint, which `run` does not have.
TEST(Execute, AForeignCheckpointIsRefusedNamingTheScenesEnsemble) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("foreign");
    const scene s = scene_in(out, ensemble_table("u", "\"upright\"", "5", 8, 5));
    fs::create_directories(out);
    std::ofstream(out / "ensemble-u.checkpoint") << "not a checkpoint\n";
    try {
        run(s);
        ADD_FAILURE() << "the foreign checkpoint was accepted";
    } catch (const input_error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find("t.toml:4: ensemble 'u': its checkpoint '" +
                            (out / "ensemble-u.checkpoint").string() + "' "),
                  0u)
            << what;
        EXPECT_NE(what.find("is not a flipflux checkpoint"), std::string::npos) << what;
        EXPECT_NE(what.find("; delete the file to start the ensemble afresh"), std::string::npos)
            << what;
        EXPECT_EQ(e.field(), "");
    }
    EXPECT_FALSE(fs::exists(out / "ensemble-u.json"));
    fs::remove_all(out);
}

// Two scenes with one output directory mixed their files (an audit found scene A's
// orbits-arm2.csv beside scene B's run.json): another scene's run.json there is refused before
// anything is computed; the same scene runs there again.
TEST(Execute, AnotherScenesOutputDirectoryIsRefused) {
    const fs::path out = fresh_dir("owner");
    const std::string body = "[predictions]\nquantities = [\"omega\"]\nenergies = [3]\n";
    (void)run(scene_in(out, body));
    (void)run(scene_in(out, body));  // the same scene again
    const scene other = parse_scene(
        "[scene]\nname = \"other\"\noutput = \"" + out.string() + "\"\n" + body, "b.toml");
    // --dry-run refuses it too (check_existing_output), and the scene itself passes
    EXPECT_THROW(check_existing_output(other), scene_error);
    EXPECT_NO_THROW(check_existing_output(scene_in(out, body)));
    try {
        (void)run(other);
        ADD_FAILURE() << "scene 'other' wrote into scene 't''s directory";
    } catch (const scene_error& e) {
        EXPECT_NE(std::string(e.what()).find("b.toml:3: scene.output: '" + out.string() +
                                             "' holds the run of scene 't'"),
                  std::string::npos)
            << e.what();
    }
    fs::remove_all(out);
}

// Every crossing time (residence_E<E>_<criterion>.csv, the largest output by far) is written only
// for an ensemble that asks for it, also when it shares its trajectories with one that does not;
// the residence statistics are in every ensemble's JSON, and the file holds exactly the gaps they
// count. run.json carries the marks the report chooses by.
TEST(Execute, CrossingTimesAreWrittenOnlyWhereAsked) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("residence");
    const scene s = scene_in(out, ensemble_table("plain", "\"upright\"", "5", 4, 20) +
                                      ensemble_table("times", "\"upright\"", "5", 4, 20,
                                                     "residence_times = true\nhistogram = true\n"));
    const run_counters c = run(s);
    EXPECT_EQ(c.trajectories, 4u);  // one set of trajectories for both
    EXPECT_TRUE(fs::exists(out / "ensemble-plain" / "trajectories_E5.csv"));
    EXPECT_FALSE(fs::exists(out / "ensemble-plain" / "residence_E5_upright.csv"));
    const fs::path times = out / "ensemble-times" / "residence_E5_upright.csv";
    ASSERT_TRUE(fs::exists(times));
    const std::string text = read_text(times);
    for (const char* name : {"plain", "times"}) {
        const auto j =
            nlohmann::json::parse(read_text(out / (std::string("ensemble-") + name + ".json")));
        const auto& upright = j["energies"][0]["criteria"]["upright"];
        const std::uint64_t gaps = upright["residence_times"]["count"].get<std::uint64_t>();
        EXPECT_GT(gaps, 4u) << name;  // E = 5, T = 20: several flips per trajectory
        EXPECT_EQ(static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n')), gaps + 1)
            << name;  // a header, one row per gap
    }
    const auto runs = nlohmann::json::parse(read_text(out / "run.json"));
    ASSERT_EQ(runs["ensembles"].size(), 2u);
    EXPECT_FALSE(runs["ensembles"][0]["residence_times"].get<bool>());
    EXPECT_FALSE(runs["ensembles"][0]["histogram"].get<bool>());
    EXPECT_TRUE(runs["ensembles"][1]["residence_times"].get<bool>());
    EXPECT_TRUE(runs["ensembles"][1]["histogram"].get<bool>());
    fs::remove_all(out);
}

TEST(Execute, SaddleCriterionEnsembleUsesTheFamily) {
    forget_saddle_orbits();
    const fs::path out = fresh_dir("saddle_ensemble");
    const scene s =
        scene_in(out, "[predictions]\nquantities = [\"rate-saddle\"]\nenergies = [5]\n" +
                          ensemble_table("s", "\"saddle\"", "5", 4, 2));
    const run_counters c = run(s);
    EXPECT_EQ(c.orbit_solves,
              1u);  // the family's one orbit; the predictions and the criterion reuse it
    EXPECT_EQ(c.curve_criteria, 1u);
    fs::remove_all(out);
}

TEST(Execute, DryRunComputesNothingAndErrorsNameTheKey) {
    const fs::path dir = fresh_dir("cli");
    fs::create_directories(dir);
    const fs::path out = dir / "out";
    {
        std::ofstream f(dir / "s.toml");
        f << "[scene]\noutput = \"" << out.string()
          << "\"\n[predictions]\nquantities = [\"rate-saddle\"]\nenergies = [3]\n";
    }
    const auto dry = run_flipflux("run --dry-run " + (dir / "s.toml").string());
    EXPECT_EQ(dry.status, 0);
    EXPECT_NE(dry.out.find("saddle-orbit family of arm 2"), std::string::npos);
    EXPECT_FALSE(fs::exists(out));
    {
        std::ofstream f(dir / "bad.toml");
        f << "[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ntrajectories = 0\n";
    }
    const auto bad = run_flipflux("run " + (dir / "bad.toml").string());
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("bad.toml:5: ensemble[0].trajectories"), std::string::npos) << bad.err;
    fs::remove_all(dir);
}

// The report generator is found at run time beside the executable (share/flipflux/report/, as
// the build tree and `cmake --install` lay it out) or through $FLIPFLUX_REPORT_SCRIPT, never at a
// source path compiled in: an executable without one refuses a scene with a report before
// computing anything.
TEST(Execute, ReportGeneratorIsFoundBesideTheExecutable) {
    const fs::path dir = fresh_dir("report_lookup");
    fs::create_directories(dir / "bin");
    const fs::path exe = dir / "bin" / "flipflux";
    fs::copy_file(FLIPFLUX_EXE, exe);
    const fs::path out = dir / "out";
    {
        std::ofstream f(dir / "s.toml");
        f << "[scene]\noutput = \"" << out.string()
          << "\"\n[predictions]\nquantities = [\"omega\"]\nenergies = [3]\n[report]\ndir = \""
          << (dir / "report").string() << "\"\n";
    }
    const std::string scene = (dir / "s.toml").string();
    const std::string err = (dir / "err.txt").string();
    // alone: refused, exit status 2, nothing computed
    int status = std::system(("env -u FLIPFLUX_REPORT_SCRIPT " + exe.string() + " run --no-cache " +
                              scene + " >/dev/null 2>" + err)
                                 .c_str());
    EXPECT_EQ(WEXITSTATUS(status), 2);
    EXPECT_NE(read_text(err).find("report generator make_report.py is not installed"),
              std::string::npos)
        << read_text(err);
    EXPECT_FALSE(fs::exists(out / "predictions.csv"));
    // beside it, as installed (bin/../share/flipflux/report/): found and run
    const fs::path script = dir / "share" / "flipflux" / "report" / "make_report.py";
    fs::create_directories(script.parent_path());
    {
        std::ofstream f(script);
        f << "import sys, os\nout = sys.argv[sys.argv.index('--out') + 1]\n"
             "os.makedirs(out, exist_ok=True)\nopen(os.path.join(out, 'ran'), 'w').write('yes')\n";
    }
    status = std::system(("env -u FLIPFLUX_REPORT_SCRIPT " + exe.string() + " run --no-cache " +
                          scene + " >/dev/null 2>" + err)
                             .c_str());
    EXPECT_EQ(WEXITSTATUS(status), 0) << read_text(err);
    EXPECT_EQ(read_text(dir / "report" / "ran"), "yes");
    EXPECT_TRUE(fs::exists(out / "predictions.csv"));
    fs::remove_all(dir);
}

TEST(Execute, AccuracyAppendixMustExistBeforeAnythingIsMeasured) {
    const fs::path out = fresh_dir("accuracy");
    const scene s = scene_in(out, "[accuracy]\nout = \"" + (out / "a.md").string() +
                                      "\"\nappendices = [\"/nonexistent/bench.md\"]\n");
    try {
        (void)run(s);
        ADD_FAILURE() << "no error";
    } catch (const scene_error& e) {
        EXPECT_NE(std::string(e.what()).find("t.toml:4: accuracy.appendices: "
                                             "'/nonexistent/bench.md' does not exist"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(fs::exists(out / "a.md"));
    fs::remove_all(out);
}

TEST(Execute, GoldenNeedsTheDefaultPendulum) {
    const fs::path out = fresh_dir("golden");
    const scene s =
        scene_in(out, "[model]\nm1 = 2\n[golden]\ndir = \"" + (out / "g").string() + "\"\n");
    EXPECT_THROW((void)run(s), scene_error);
    EXPECT_FALSE(fs::exists(out / "g" / "golden.csv"));
    fs::remove_all(out);
}

}  // namespace
}  // namespace flipflux::test
