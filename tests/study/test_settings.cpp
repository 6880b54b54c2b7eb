// The run settings (study/settings.hpp): one table of defaults, one builder that names an
// offending setting as its caller's surface does, one rule for which studies share trajectories.
#include <gtest/gtest.h>

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
    EXPECT_EQ(cli.criteria, criterion_names());
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

}  // namespace
}  // namespace flipflux::test
