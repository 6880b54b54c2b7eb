// Issue 20 (hardening), scenes: ensemble names stay one path component and unique, duplicate arms,
// quantities and energies are refused, and the plan (what --dry-run runs) refuses everything that
// run would refuse without computing: energies below an arm's saddle, a model outside the working
// precision's range, a report without inputs, unknown golden quantities, rtol below what double
// can meet, more trajectories than memory holds, an output directory that cannot be written.
// Every refusal names file, line and key in one line.
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "flipflux/core/limits.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

const std::string head = "[scene]\nname = \"t\"\noutput = \"out/t\"\n";

/// The message of the scene_error that parsing (and planning) `text` throws; "" if none.
std::string refusal(const std::string& text) {
    try {
        (void)make_plan(parse_scene(text, "s.toml"));
    } catch (const scene_error& e) {
        return e.what();
    }
    return "";
}

void expect_refused(const std::string& text, const std::string& expected) {
    const std::string e = refusal(text);
    EXPECT_NE(e.find(expected), std::string::npos) << "got: " << e << "\nexpected: " << expected;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

std::string ensemble(const std::string& name) {
    return "[[ensemble]]\nname = \"" + name + "\"\nenergies = [5]\ncriteria = [\"upright\"]\n";
}

TEST(SceneLimits, EnsembleNamesThatLeaveTheOutputDirectoryAreRefused) {
    for (const std::string bad : {"../../../../x", "a/b", "..", ".hidden", "", "a b", "x\\\\y"})
        expect_refused(head + ensemble(bad), "s.toml:5: ensemble[0].name: '");
    expect_refused(head + ensemble(std::string(max_ensemble_name + 1, 'x')),
                   "is not a valid ensemble name");
    EXPECT_EQ(refusal(head + ensemble("arm2_E5-6.0")), "");
    EXPECT_EQ(refusal(head + ensemble(std::string(max_ensemble_name, 'x'))), "");
}

TEST(SceneLimits, TwoEnsemblesWithOneNameAreRefused) {
    expect_refused(
        head + ensemble("a") + ensemble("b") + ensemble("a"),
        "s.toml:13: ensemble[2].name: 'a' is already the name of the ensemble at line 4");
    // the default names count too
    expect_refused(head + "[[ensemble]]\nenergies = [5]\n" + ensemble("ensemble1"),
                   "ensemble[1].name: 'ensemble1' is already");
}

TEST(SceneLimits, DuplicateArmsQuantitiesAndEnergiesAreRefused) {
    expect_refused(head + "[predictions]\nquantities = [\"omega\", \"omega\"]\nenergies = [3]\n",
                   "s.toml:5: predictions.quantities: 'omega' is given twice");
    expect_refused(
        head + "[predictions]\nquantities = [\"omega\"]\narms = [2, 2]\nenergies = [3]\n",
        "s.toml:6: predictions.arms: arm 2 is given twice");
    expect_refused(head + "[predictions]\nquantities = [\"omega\"]\nenergies = [3, 4, \"3.0\"]\n",
                   "s.toml:4: predictions.energies: E = 3.0 is given twice (as '3')");
    expect_refused(head + "[orbits]\nenergies = [3, 3]\n", "orbits.energies: E = 3 is given twice");
    // compared in the working precision: distinct in mp:40, one number in double
    const std::string mp = "[scene]\nname = \"t\"\noutput = \"out/t\"\nprecision = \"mp:40\"\n";
    const std::string close =
        "[predictions]\nquantities = [\"omega\"]\n"
        "energies = [\"3\", \"3.0000000000000000000001\"]\n";
    EXPECT_EQ(refusal(mp + close), "");
    expect_refused(head + close,
                   "predictions.energies: E = 3.0000000000000000000001 is given twice");
    expect_refused(head + "[[ensemble]]\nenergies = [5, 5e0]\n",
                   "ensemble[0].energies: E = 5 is given twice");
    expect_refused(head + "[[ensemble]]\nenergies = [5]\ncriteria = [\"upright\", \"upright\"]\n",
                   "ensemble[0].criteria: 'upright' is given twice");
    expect_refused(head + "[golden]\nquantities = [\"omega\", \"omega\"]\n",
                   "golden.quantities: 'omega' is given twice");
}

TEST(SceneLimits, DryRunRefusesWhatRunWouldRefuse) {
    // arm 1's saddle energy is 2 alpha = 4 for the egalitarian pendulum
    expect_refused(head + "[[ensemble]]\narm = 1\nenergies = [3]\n",
                   "s.toml:4: ensemble[0].energies: E = 3 is at or below arm 1's saddle energy 4");
    // the saddle orbit's family ends at the potential's maximum E_max = 6: refused in the plan,
    // naming the scene's key (not the command line's option), before any step runs
    expect_refused(head + "[[ensemble]]\nenergies = [3, 7]\ncriteria = [\"upright\", \"saddle\"]\n",
                   "s.toml:4: ensemble[0].energies: '7' is at or above the maximum energy 6, where "
                   "criterion 'saddle' of arm 2 has no saddle orbit");
    expect_refused(head + "[model]\nm2 = 1e300\n", "s.toml:4: model: m2: '1e+300' is outside");
    expect_refused(head + "[report]\ndir = \"r\"\n",
                   "s.toml:4: report: the report needs something to report");
    expect_refused(head + "[golden]\nquantities = [\"bogus\"]\n", "s.toml:4: golden.quantities: ");
    expect_refused(head + "[accuracy]\nquantities = [\"bogus\"]\n",
                   "s.toml:4: accuracy.quantities: ");
    expect_refused(head + "[model]\nm2 = 2\n[golden]\n", "golden: golden data is defined");
    expect_refused(head + "[[ensemble]]\nenergies = [5]\nrtol = 1e-19\n",
                   "s.toml:6: ensemble[0].rtol: '1e-19' is below what double precision can meet");
}

TEST(SceneLimits, TrajectoriesBeyondMemoryAreRefusedInThePlan) {
    ::setenv("FLIPFLUX_MEMORY_LIMIT", "1000000", 1);  // 1 MB: a few thousand records
    expect_refused(head + "[[ensemble]]\nenergies = [5]\ntrajectories = 1000000\n",
                   "s.toml:4: ensemble[0].trajectories: '1000000' would need about");
    EXPECT_EQ(refusal(head + "[[ensemble]]\nenergies = [5]\ntrajectories = 100\n"), "");
    ::unsetenv("FLIPFLUX_MEMORY_LIMIT");
    // the schema's own bound, 1e9 trajectories, is refused on a machine with less than ~0.5 TB
    const std::string huge =
        refusal(head + "[[ensemble]]\nenergies = [5]\ntrajectories = 1000000000\n");
    if (memory_budget_bytes() < 1e11) {
        EXPECT_NE(huge.find("would need about"), std::string::npos) << huge;
    }
}

TEST(SceneLimits, OutputDirectoriesThatCannotBeWrittenAreRefusedBeforeComputing) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                      ("flipflux_limits_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::filesystem::path file = dir / "a-file";
    std::ofstream(file) << "x";
    auto with_output = [](const std::string& out) {
        return "[scene]\nname = \"t\"\noutput = \"" + out +
               "\"\n[predictions]\nquantities = " + "[\"omega\"]\nenergies = [3]\n";
    };
    expect_refused(with_output(file.string()), "s.toml:3: scene.output: '");
    expect_refused(with_output((file / "sub").string()), "is a file");
    expect_refused(with_output(dir.string() + "/" + std::string(300, 'n')), "longer than");
    // also as root, whom access() lets "write" /proc (issue 20's probe campaign: the dry run
    // accepted what run then refused): the plan creates and removes a folder there
    expect_refused(with_output("/proc/x"), "s.toml:3: scene.output: '/proc/x' cannot be created");
    EXPECT_EQ(refusal(with_output((dir / "new" / "deeper").string())), "");
    EXPECT_FALSE(std::filesystem::exists(dir / "new"));  // the check creates nothing
    expect_refused(head + "[predictions]\nquantities = [\"omega\"]\nenergies = [3]\n[report]\n" +
                       "dir = \"" + file.string() + "\"\n",
                   "report.dir: '");
    std::filesystem::remove_all(dir);
}

// Review of issue 20's merge: a short-estimator ensemble whose time is below the short
// trajectories' length passed the dry run, then failed after the scene's earlier steps had run.
TEST(SceneLimits, ShortEstimatorWithATimeBelowItsTrajectoriesIsRefusedInThePlan) {
    expect_refused(head + "[[ensemble]]\nenergies = [5]\nestimator = \"short\"\ntime = 10\n",
                   "s.toml:4: ensemble[0].time: '10' is shorter than the short estimator's");
    EXPECT_EQ(refusal(head + "[[ensemble]]\nenergies = [5]\nestimator = \"short\"\ntime = 40\n"),
              "");
}

// Issue 20's probe campaign: [orbits] energies outside an arm's saddle-orbit family (above E_max,
// below the arm's saddle: a grid shared by both arms) were dropped without a word; run.json now
// lists each with the reason.
TEST(SceneLimits, ProbeOrbitEnergiesWithoutAnOrbitAreListedInRunJson) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                      ("flipflux_orbit_skip_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "s.toml") << "[scene]\nname = \"t\"\noutput = \"" << (dir / "out").string()
                                  << "\"\n[orbits]\narms = [1, 2]\nenergies = [1.5, 6.5]\n";
    const command_result r = run_flipflux("run " + (dir / "s.toml").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string run = read_text(dir / "out" / "run.json");
    for (const std::string e :
         {"\"arm\": \"1\",\n        \"energy\": \"1.5\",\n        \"reason\": \"outside the arm's "
          "saddle-orbit family (4, 6)\"",
          "\"arm\": \"1\",\n        \"energy\": \"6.5\"",
          "\"arm\": \"2\",\n        \"energy\": \"6.5\",\n        \"reason\": \"outside the arm's "
          "saddle-orbit family (2, 6)\""})
        EXPECT_NE(run.find(e), std::string::npos) << e << "\nin\n" << run;
    std::filesystem::remove_all(dir);
}

// The island census (issue 41): a census shares no trajectory with the ensemble it tests (its
// seed differs from that ensemble's and from those sharing its trajectories), names an existing
// ensemble of its arm, classifies (chaos = true) and has energies among the tested ones'; a
// classification check names a census and re-integrates its trajectories (same seed).
TEST(SceneLimits, ACensusMustBeIndependentOfTheEnsembleItTests) {
    const auto ens = [](const std::string& name, const std::string& extra) {
        return "[[ensemble]]\nname = \"" + name + "\"\nenergies = [5, 5.5]\ncriteria = " +
               "[\"upright\"]\nchaos = true\ntrajectories = 10\n" + extra;
    };
    const std::string tested = ens("a", "seed = 1\n");
    EXPECT_EQ(refusal(head + tested + ens("c", "seed = 2\ncensus_of = \"a\"\n")), "");
    expect_refused(head + tested + ens("c", "seed = 1\ncensus_of = \"a\"\n"),
                   "ensemble[1].seed: '1' is the seed of ensemble 'a': a census must share no "
                   "trajectory");
    expect_refused(head + tested + ens("c", "seed = 2\ncensus_of = \"b\"\n"),
                   "ensemble[1].census_of: 'b' names no other ensemble");
    expect_refused(head + tested + ens("c", "seed = 2\narm = 1\ncensus_of = \"a\"\n"),
                   "the census counts arm 1, ensemble 'a' arm 2");
    expect_refused(head + tested +
                       "[[ensemble]]\nname = \"c\"\nenergies = [4.5]\nchaos = true\nseed = "
                       "2\ncensus_of = \"a\"\n",
                   "E = 4.5 is not an energy of ensemble 'a'");
    // a check of the census: the census's seed, at most its trajectories
    const std::string census = ens("c", "seed = 2\ncensus_of = \"a\"\n");
    EXPECT_EQ(refusal(head + tested + census +
                      ens("k", "seed = 2\ntime = 50000\nclassification_check_of = \"c\"\n")),
              "");
    expect_refused(head + tested + census + ens("k", "seed = 3\nclassification_check_of = \"c\"\n"),
                   "ensemble[2].classification_check_of: a classification check re-integrates");
    expect_refused(head + tested + census + ens("k", "seed = 1\nclassification_check_of = \"a\"\n"),
                   "'a' is not a census");
    expect_refused(head + ens("a", "replicates = 0\n"), "replicates");
}

}  // namespace
}  // namespace flipflux::test
