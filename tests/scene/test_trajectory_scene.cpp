// A scene's [[trajectory]] (one trajectory and its flip events, the report's trajectory figures)
// and the [[ensemble]] keys atol and chaos_threshold (the report's sensitivity studies): the
// schema's refusals, and the files written.
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "flipflux/io/csv.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

std::string scene_error_of(const std::string& text) {
    try {
        (void)make_plan(parse_scene(text, "t.toml"));
    } catch (const scene_error& e) {
        return e.what();
    }
    return "accepted";
}

TEST(TrajectoryScene, BadKeysNameTheLine) {
    const std::string head = "[scene]\noutput = \"" + ::testing::TempDir() + "\"\n";
    const std::string t = head + "[[trajectory]]\n";
    EXPECT_EQ(scene_error_of(t + "time = 3\n"),
              "t.toml:3: trajectory[0].state: is required: [theta1, theta2, l1, l2]");
    EXPECT_EQ(scene_error_of(t + "state = [1, 2, 3]\n"),
              "t.toml:4: trajectory[0].state: expected an array of 4 numbers");
    EXPECT_EQ(scene_error_of(t + "state = [1, 2, 3, \"x\"]\n"),
              "t.toml:4: trajectory[0].state: 'x' is not a finite decimal number");
    EXPECT_EQ(scene_error_of(t + "state = [1, 2, 3, 4]\ntime = 0\n"),
              "t.toml:5: trajectory[0].time: '0' must be > 0");
    EXPECT_EQ(scene_error_of(t + "state = [1, 2, 3, 4]\ncriteria = [\"sideways\"]\n"),
              "t.toml:5: trajectory[0].criteria: 'sideways' is not a criterion (upright, "
              "approx, saddle)");
    EXPECT_EQ(scene_error_of(t + "state = [0, 0, 0, 0]\nname = \"a\"\n[[trajectory]]\n"
                                 "state = [0, 0, 0, 0]\nname = \"a\"\n"),
              "t.toml:8: trajectory[1].name: 'a' is already the name of the trajectory at line "
              "3 (their outputs would overwrite each other)");
    // the work bound of ensembles applies: 1e9 time units cannot finish
    EXPECT_NE(scene_error_of(t + "state = [1, 2, 0.5, 0.5]\ntime = 1e9\n")
                  .find("t.toml:3: trajectory[0].time: "),
              std::string::npos);
    const std::string e = head + "[[ensemble]]\nenergies = [3]\n";
    EXPECT_EQ(scene_error_of(e + "atol = -1e-6\n"),
              "t.toml:5: ensemble[0].atol: '-1e-06' must be >= 0 (0: equal to rtol)");
    EXPECT_EQ(scene_error_of(e + "chaos_threshold = 0\n"),
              "t.toml:5: ensemble[0].chaos_threshold: '0' is invalid (must be > 0)");
    const scene s =
        parse_scene(t + "state = [0.5, 2.8, \"0.46561367198671955\", 0.25]\n", "t.toml");
    ASSERT_EQ(s.trajectories.size(), 1u);
    EXPECT_EQ(s.trajectories[0].name, "trajectory1");
    EXPECT_EQ(s.trajectories[0].state,
              (std::vector<std::string>{"0.5", "2.8", "0.46561367198671955", "0.25"}));
    EXPECT_EQ(s.trajectories[0].arms, (std::vector<int>{1, 2}));
}

// The events of the scene's trajectory against the reference route at mp:40 (docs/validating.md,
// itself checked against an independent mpmath Taylor integration): the double trajectory at
// rtol 1e-12 is accurate to ~1e-13 at these times (measured in tests/study/test_trajectory.cpp),
// so 1e-11 is a bound with a margin of 20 that a wrong event (another time, arm or curve) breaks.
TEST(TrajectoryScene, WritesStatesAndEventsAndTheEnsembleTolerances) {
    forget_saddle_orbits();
    const fs::path out =
        fs::path(::testing::TempDir()) / ("flipflux_trajectory_scene_" + std::to_string(getpid()));
    fs::remove_all(out);
    const scene s = parse_scene(
        "[scene]\noutput = \"" + out.string() +
            "\"\n[[trajectory]]\nname = \"ex\"\nstate = [2.5, 3.0, 1.2, 1.0]\ntime = 3\n"
            "sample_interval = 1\ncriteria = [\"upright\", \"approx\"]\n"
            "[[ensemble]]\nname = \"ode45\"\ncriteria = [\"upright\"]\nenergies = [5]\n"
            "trajectories = 4\ntime = 2\nrtol = 1e-3\natol = 1e-6\nintegrator = \"dopri5\"\n"
            "chaos = true\nchaos_threshold = 0.2\n",
        "t.toml");
    const plan p = make_plan(s);
    ASSERT_EQ(p.count(plan_step::kind::trajectory), 1u);
    std::ostringstream log;
    run_options o;
    o.threads = 1;
    const run_counters c = execute_plan(s, p, log, o);
    EXPECT_EQ(c.trajectories, 4u + 1u);
    const csv_table ev = read_csv(out / "trajectory-ex-events.csv");
    ASSERT_EQ(ev.header, (std::vector<std::string>{"time", "arm", "criterion", "direction"}));
    const std::vector<std::tuple<double, std::string, std::string>> want{
        {0.176003333789106331620869900361778495381336, "2", "upright"},
        {0.523421024948778113516877008721281567201856, "2", "approx"},
        {2.11031210618144195108113544804946600895821, "1", "approx"},
        {2.11580343100204428548395606041050571490213, "1", "upright"}};
    ASSERT_EQ(ev.rows.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
        EXPECT_NEAR(std::stod(ev.rows[i].fields[0]), std::get<0>(want[i]), 1e-11) << i;
        EXPECT_EQ(ev.rows[i].fields[1], std::get<1>(want[i]));
        EXPECT_EQ(ev.rows[i].fields[2], std::get<2>(want[i]));
        EXPECT_EQ(ev.rows[i].fields[3], "1");
    }
    const csv_table st = read_csv(out / "trajectory-ex.csv");
    ASSERT_EQ(st.rows.size(), 4u);  // t = 0, 1, 2, 3
    EXPECT_EQ(st.rows[0].fields, (std::vector<std::string>{"0", "2.5", "3", "1.2", "1", "0"}));
    EXPECT_EQ(st.rows[3].fields[0], "3");
    for (const auto& row : st.rows)  // |H - H0| within the energy check's bound 64 (2 rtol) E
        EXPECT_LT(std::fabs(std::stod(row.fields[5])), 64 * 2e-12 * 6.2);
    const auto run = nlohmann::json::parse(read_text(out / "run.json"));
    EXPECT_EQ(run["trajectories"][0]["events_count"], 4);
    EXPECT_EQ(run["trajectories"][0]["energy"], "6.1345422401344294");  // docs/validating.md
    // the ensemble's tolerances and threshold as given (the JSON's shortest decimals of doubles)
    const auto ens = nlohmann::json::parse(read_text(out / "ensemble-ode45.json"));
    EXPECT_EQ(ens["method"], "dopri5");
    EXPECT_EQ(ens["rtol"], to_decimal(1e-3));
    EXPECT_EQ(ens["atol"], to_decimal(1e-6));
    EXPECT_EQ(ens["chaos"]["threshold"], to_decimal(0.2));
    fs::remove_all(out);
}

}  // namespace
}  // namespace flipflux::test
