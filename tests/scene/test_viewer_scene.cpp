// A scene's [viewer]: the schema's checks, the plan (the viewer's orbits are continued by the
// orbit-family steps, so the viewer solves nothing itself), and the page written.
#include <filesystem>
#include <sstream>

#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

std::string scene_error_of(const std::string& text) {
    try {
        (void)parse_scene(text, "v.toml");
    } catch (const scene_error& e) {
        return e.what();
    }
    return "accepted";
}

TEST(ViewerScene, BadKeysNameTheLine) {
    const std::string head = "[scene]\noutput = \"o\"\n[viewer]\n";
    EXPECT_EQ(scene_error_of(head + "grid = 120\n"),
              "v.toml:4: viewer.grid: 120 is not 1 more than a multiple of 6 (the grid's nodes "
              "fall on the multiples of pi/2)");
    EXPECT_EQ(scene_error_of(head + "energies_per_arm = 0\n"),
              "v.toml:4: viewer.energies_per_arm: 0 is out of range [1, 1000]");
    EXPECT_EQ(scene_error_of(head + "arms = [3]\n"), "v.toml:4: viewer.arms: an arm is 1 or 2");
    EXPECT_EQ(scene_error_of(head + "energies = 3\n"), "v.toml:4: viewer.energies: unknown key");
    const scene s = parse_scene(head, "v.toml");
    ASSERT_TRUE(s.viewer.has_value());
    EXPECT_EQ(s.viewer->arms, (std::vector<int>{1, 2}));
    EXPECT_EQ(s.viewer->energies_per_arm, 30);
}

TEST(ViewerScene, PlanContinuesTheFamilyAndThePageIsWritten) {
    forget_saddle_orbits();
    const fs::path out =
        fs::path(::testing::TempDir()) / ("flipflux_viewer_scene_" + std::to_string(getpid()));
    fs::remove_all(out);
    const scene s = parse_scene("[scene]\noutput = \"" + out.string() +
                                    "\"\n[viewer]\narms = [2]\nenergies_per_arm = 1\n"
                                    "samples = 9\ngrid = 7\n",
                                "v.toml");
    const plan p = make_plan(s);
    ASSERT_EQ(p.steps.size(), 2u);
    EXPECT_EQ(p.steps[0].what, plan_step::kind::orbit_family);
    EXPECT_EQ(p.steps[0].energies, (std::vector<std::string>{"4"}));
    EXPECT_EQ(p.steps[1].what, plan_step::kind::viewer);
    std::ostringstream log;
    run_options o;
    o.threads = 1;
    const run_counters c = execute_plan(s, p, log, o);
    EXPECT_EQ(c.orbit_solves, 1u);  // by the family step; the viewer found it in the memo
    const std::string page = read_text(out / "viewer.html");
    EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
    EXPECT_NE(page.find("\"families\":[{\"arm\":2,"), std::string::npos);
    EXPECT_NE(page.find("\"energy\":4,"), std::string::npos);
    EXPECT_NE(read_text(out / "run.json").find("\"viewer\""), std::string::npos);
    fs::remove_all(out);
}

}  // namespace
}  // namespace flipflux::test
