// The run settings (study/settings.hpp): one table of defaults, one builder that names an
// offending setting as its caller's surface does, one rule for which studies share trajectories.
#include <gtest/gtest.h>

#include <map>

#include "flipflux/core/error.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/settings.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

std::string message_of(const settings_text& t, settings_surface s) {
    try {
        (void)make_simulation_request(t, s);
    } catch (const input_error& e) {
        return e.what();
    }
    return "";
}

const settings_text minimal{{"trajectories", "4"}, {"time", "10"}};

TEST(Settings, EachSurfaceNamesTheOffendingSettingItsOwnWay) {
    settings_text t = minimal;
    t["rtol"] = "-1";
    EXPECT_EQ(message_of(t, settings_surface::command_line),
              "--rtol: '-1' is invalid (must be > 0)");
    EXPECT_EQ(message_of(t, settings_surface::scene), "rtol: '-1' is invalid (must be > 0)");
    EXPECT_EQ(message_of(t, settings_surface::python), "rtol: '-1' is invalid (must be > 0)");
    t = minimal;
    t["method"] = "rk4";
    EXPECT_EQ(message_of(t, settings_surface::command_line).rfind("--method: 'rk4'", 0), 0u);
    EXPECT_EQ(message_of(t, settings_surface::scene).rfind("integrator: 'rk4'", 0), 0u);
    EXPECT_EQ(message_of(t, settings_surface::python).rfind("method: 'rk4'", 0), 0u);
    t = minimal;
    t["chaos_threshold"] = "0";
    EXPECT_EQ(message_of(t, settings_surface::command_line).rfind("--chaos-threshold: '0'", 0), 0u);
    t = minimal;
    t["atol"] = "-1e-6";
    EXPECT_EQ(message_of(t, settings_surface::scene),
              "atol: '-1e-6' must be >= 0 (0: equal to rtol)");
    t["atol"] = "-0";  // a negative zero is refused too
    EXPECT_EQ(message_of(t, settings_surface::scene), "atol: '-0' must be >= 0 (0: equal to rtol)");
    t = minimal;
    t["reference_time"] = "-0";
    EXPECT_EQ(message_of(t, settings_surface::scene).rfind("reference_time: '-0' is invalid", 0),
              0u);
}

TEST(Settings, DefaultsComeFromTheTablePerSurface) {
    const simulation_request cli = make_simulation_request(minimal, settings_surface::command_line);
    const simulation_request scene = make_simulation_request(minimal, settings_surface::scene);
    EXPECT_EQ(cli.options.seed, 0u);
    EXPECT_EQ(scene.options.seed, 1u);
    EXPECT_EQ(cli.options.rtol, 1e-10);
    EXPECT_EQ(cli.options.method, integration_method::dop853);  // auto at 1e-10
    EXPECT_TRUE(cli.options.chaos);
    EXPECT_FALSE(scene.options.chaos);
    EXPECT_EQ(cli.options.chaos_threshold, 0.05);
    EXPECT_EQ(cli.flip_arm, arm::two);
    // every registered criterion: the paper's three (and this binary's toys, test_criteria.cpp)
    EXPECT_EQ(cli.criteria, criterion_names());
    ASSERT_GE(cli.criteria.size(), 3u);
    EXPECT_EQ(std::vector<std::string>(cli.criteria.begin(), cli.criteria.begin() + 3),
              (std::vector<std::string>{"upright", "approx", "saddle"}));
    EXPECT_EQ(
        make_simulation_request({{"time", "1"}}, settings_surface::scene).options.trajectories,
        1000u);
    // a setting the command line lacks is named by its field (atol: scenes only)
    for (const run_setting& s : run_settings())
        EXPECT_EQ(setting_name(s, settings_surface::command_line),
                  s.option.empty() ? std::string(s.field) : std::string(s.option));
    settings_text tight = minimal;
    tight["rtol"] = "1e-12";
    EXPECT_EQ(make_simulation_request(tight, settings_surface::python).options.method,
              integration_method::taylor);  // auto below 1e-10
}

TEST(Settings, TheTrajectoryKeyHoldsWhatDecidesTheTrajectories) {
    const auto key = [](settings_text t) {
        return trajectory_key_of(make_simulation_request(t, settings_surface::scene));
    };
    settings_text a = minimal, b = minimal;
    a["rtol"] = b["rtol"] = "1e-10";
    a["atol"] = "0";
    b["atol"] = "1e-10";  // atol 0 is rtol: the same trajectories
    EXPECT_EQ(key(a), key(b));
    b["chaos_threshold"] = "0.2";  // classifies, does not integrate
    b["reference_time"] = "10000";
    EXPECT_EQ(key(a), key(b));
    for (const auto& [field, value] :
         std::vector<std::pair<std::string, std::string>>{{"seed", "2"},
                                                          {"time", "11"},
                                                          {"trajectories", "5"},
                                                          {"replicates", "2"},
                                                          {"rtol", "1e-9"},
                                                          {"atol", "1e-12"},
                                                          {"method", "dopri5"},
                                                          {"chaos", "true"},
                                                          {"estimator", "short"}}) {
        settings_text c = a;
        c[field] = value;
        EXPECT_FALSE(key(a) == key(c)) << field;
    }
}

// The table's decides_trajectories flags and trajectory_key_of agree: changing a flagged setting
// (to another valid value) changes the key, changing any other leaves it.
TEST(Settings, TheKeyFollowsTheTablesFlags) {
    const std::map<std::string, std::string> other{{"energy", "3"},
                                                   {"arm", "1"},
                                                   {"criteria", "upright"},
                                                   {"replicates", "2"},
                                                   {"trajectories", "5"},
                                                   {"time", "11"},
                                                   {"seed", "2"},
                                                   {"first_index", "3"},
                                                   {"rtol", "1e-9"},
                                                   {"atol", "1e-12"},
                                                   {"method", "dopri5"},
                                                   {"threads", "1"},
                                                   {"chaos_threshold", "0.2"},
                                                   {"chaos", "true"},
                                                   {"bins", "5"},
                                                   {"sample_interval", "1"},
                                                   {"checkpoint_interval", "5"},
                                                   {"max_seconds", "60"},
                                                   {"estimator", "long"},
                                                   {"short_time", "30"},
                                                   {"reference_time", "100"}};
    settings_text base = minimal;
    base["estimator"] = "short";  // short_time decides the trajectories of the short estimator
    const trajectory_key k0 =
        trajectory_key_of(make_simulation_request(base, settings_surface::scene));
    for (const run_setting& s : run_settings()) {
        const auto alt = other.find(std::string(s.field));
        ASSERT_NE(alt, other.end()) << s.field << ": give the test another value of it";
        settings_text t = base;
        t[std::string(s.field)] = alt->second;
        const trajectory_key k =
            trajectory_key_of(make_simulation_request(t, settings_surface::scene));
        EXPECT_EQ(!(k == k0), s.decides_trajectories) << s.field;
    }
}

// The library structs' own member defaults (the C++ API: ensemble_options, simulation_request)
// are the table's command-line defaults, except the integrator: a struct names dop853 (the
// runner resolves auto by rtol, which at the default rtol 1e-10 is dop853 too).
TEST(Settings, TheLibraryStructsDefaultAsTheTable) {
    const simulation_request table = make_simulation_request(minimal, settings_surface::python);
    const simulation_request plain;
    EXPECT_EQ(plain.options.rtol, table.options.rtol);
    EXPECT_EQ(plain.options.atol, table.options.atol);
    EXPECT_EQ(plain.options.seed, table.options.seed);
    EXPECT_EQ(plain.options.first_index, table.options.first_index);
    EXPECT_EQ(plain.options.chaos, table.options.chaos);
    EXPECT_EQ(plain.options.chaos_threshold, table.options.chaos_threshold);
    EXPECT_EQ(plain.options.method, table.options.method);
    EXPECT_EQ(plain.options.sample_interval, table.options.sample_interval);
    EXPECT_EQ(plain.replicates, table.replicates);
    EXPECT_EQ(plain.bins, table.bins);
    EXPECT_EQ(plain.checkpoint_interval, table.checkpoint_interval);
    EXPECT_EQ(plain.estimator, table.estimator);
    EXPECT_EQ(plain.short_time, table.short_time);
    EXPECT_EQ(plain.reference_time, table.reference_time);
    EXPECT_EQ(plain.flip_arm, table.flip_arm);
}

}  // namespace
}  // namespace flipflux::test
