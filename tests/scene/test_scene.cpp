// Scene files: every error names file, line and key; grids expand exactly; plans contain exactly
// the work the requested outputs need.
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

const char* minimal = R"([scene]
name = "t"
output = "out/t"
)";

std::string error_of(const std::string& text) {
    try {
        (void)parse_scene(text, "s.toml");
    } catch (const scene_error& e) {
        return e.what();
    }
    return "";
}

TEST(Scene, ParsesAMinimalScene) {
    const scene s = parse_scene(minimal, "s.toml");
    EXPECT_EQ(s.name, "t");
    EXPECT_EQ(s.output, "out/t");
    EXPECT_EQ(s.prec, precision{real_kind::double_});
    EXPECT_FALSE(s.predictions.has_value());
    EXPECT_TRUE(s.ensembles.empty());
}

TEST(Scene, ErrorsNameFileLineAndKey) {
    const std::pair<std::string, std::string> cases[] = {
        {std::string(minimal) + "bogus = 1\n", "s.toml:4: scene.bogus: unknown key"},
        {std::string(minimal) + "[extra]\nx = 1\n", "s.toml:4: extra: unknown key"},
        {"[scene]\nname = \"t\"\noutput = \"o\"\nprecison = \"quad\"\n",
         "s.toml:4: scene.precison: unknown key"},
        {"[scene]\nname = 3\noutput = \"o\"\n", "s.toml:2: scene.name: expected a string"},
        {"[scene]\noutput = \"o\"\nprecision = \"mp:5000000\"\n", "s.toml:3: scene.precision:"},
        {"[scene]\nname = \"t\"\n", "s.toml:1: scene.output: is required"},
        {"[scene]\noutput = \"o\"\n[model]\nm1 = \"abc\"\n", "s.toml:4: model.m1: 'abc' is not"},
        {"[scene]\noutput = \"o\"\n[model]\nm1 = -1\n", "s.toml:3: model: m1: '-1' is invalid"},
        {"[scene]\noutput = \"o\"\n[predictions]\nquantities = [\"omega\"]\narms = [3]\n"
         "energies = [3]\n",
         "s.toml:5: predictions.arms: an arm is 1 or 2"},
        {"[scene]\noutput = \"o\"\n[predictions]\nquantities = [\"omega\"]\n",
         "predictions.energies: is required"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ntrajectories = 0\n",
         "s.toml:5: ensemble[0].trajectories: '0' is invalid (expected a positive integer)"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\nseed = -1\n",
         "s.toml:5: ensemble[0].seed: '-1' is invalid (expected a non-negative integer)"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\nreplicates = 1001\n",
         "s.toml:5: ensemble[0].replicates: '1001' is too many (at most 1000)"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ntrajectories = 1000000001\n",
         "s.toml:5: ensemble[0].trajectories: '1000000001' is too many (at most 1000000000"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ntrajectories = 1e2\n",
         "s.toml:5: ensemble[0].trajectories: expected an integer, got a float"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\nseed = \"5\"\n",
         "s.toml:5: ensemble[0].seed: expected an integer, got a string"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\nchaos = 1\n",
         "s.toml:5: ensemble[0].chaos: expected true or false, got an integer"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\nintegrator = 5\n",
         "s.toml:5: ensemble[0].integrator: expected a string, got an integer"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ntime = [1]\n",
         "s.toml:5: ensemble[0].time: expected a number, got an array"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ncriteria = [\"up\"]\n",
         "s.toml:5: ensemble[0].criteria: 'up' is not a criterion"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = [3]\ntime = -2\n",
         "s.toml:5: ensemble[0].time: '-2' is invalid (must be > 0)"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = { from = 2, to = 3 }\n",
         "ensemble[0].energies.step: is required"},
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = { from = 2, to = 3, step = 1, x = 1 "
         "}\n",
         "s.toml:4: ensemble[0].energies.x: unknown key"},
        // a grid's rule is checked where its line is known (before: no file or line)
        {"[scene]\noutput = \"o\"\n[[ensemble]]\nenergies = { from = 2, to = 3, step = 0.3 }\n",
         "s.toml:4: ensemble[0].energies: to - from = 1 is not a multiple of step = 0.3"},
        {"[scene]\noutput = \"o\"\nname = \n", "s.toml:3: malformed TOML"},
        {"[scene]\noutput = \"o\"\n[accuracy]\nmax_seconds = 0\n",
         "s.toml:4: accuracy.max_seconds: '0' must be finite and > 0"},
        {"[scene]\noutput = \"o\"\n[accuracy]\nmax_seconds = \"1e400\"\n",
         "s.toml:4: accuracy.max_seconds: '1e400' must be finite and > 0"},
        {"[scene]\noutput = \"o\"\n[golden]\nmax_seconds = -1\n",
         "s.toml:4: golden.max_seconds: '-1' must be finite and >= 0 (0: no bound)"},
    };
    for (const auto& [text, expected] : cases) {
        const std::string e = error_of(text);
        EXPECT_NE(e.find(expected), std::string::npos)
            << "got: " << e << "\nexpected: " << expected;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
}

TEST(Scene, GridsExpandInTheWorkingPrecision) {
    energy_grid g;
    g.from = "2.05", g.to = "5.95", g.step = "0.05";
    const auto e = energies_of<quad>(g, "energies");
    ASSERT_EQ(e.size(), 79u);
    EXPECT_EQ(e.front().value, quad(205) / 100);
    EXPECT_EQ(e.back().value, quad(595) / 100);
    // every point is the decimal meant, correctly rounded: no accumulated rounding
    EXPECT_EQ(e[20].value, quad(305) / 100);
    const auto texts = energy_texts(g, "energies");
    EXPECT_EQ(texts[1], "2.1");
    EXPECT_EQ(texts[20], "3.05");
    EXPECT_EQ(energies_of<double>(g, "energies")[1].value, 2.1);
    in_mp(50,
          [&] { EXPECT_EQ(energies_of<mp>(g, "energies")[77].value, parse_real<mp>("5.9", "x")); });
    energy_grid bad;
    bad.from = "2", bad.to = "3.01", bad.step = "0.1";
    EXPECT_THROW(energies_of<double>(bad, "energies"), scene_error);
    bad.to = "1";
    EXPECT_THROW(energies_of<double>(bad, "energies"), scene_error);
    bad.to = "3", bad.step = "0";
    EXPECT_THROW(energies_of<double>(bad, "energies"), scene_error);
}

TEST(Plan, UprightOnlyNeedsNoSaddleOrbit) {
    const scene s =
        parse_scene(std::string(minimal) +
                        "[predictions]\nquantities = [\"rate-upright\"]\narms = [1, 2]\n"
                        "energies = { from = 2.5, to = 5.5, step = 0.5 }\n"
                        "[[ensemble]]\ncriteria = [\"upright\"]\nenergies = [3, 5]\n",
                    "s.toml");
    const plan p = make_plan(s);
    EXPECT_EQ(p.count(plan_step::kind::orbit_family), 0u);
    EXPECT_EQ(p.count(plan_step::kind::predictions), 1u);
    EXPECT_EQ(p.count(plan_step::kind::ensemble), 1u);
}

TEST(Plan, SaddleQuantitiesNeedTheFamilyAtTheirEnergiesOnly) {
    const scene s =
        parse_scene(std::string(minimal) +
                        "[predictions]\nquantities = [\"rate-saddle\"]\narms = [1]\n"
                        "energies = { from = 3, to = 7, step = 0.5 }\n"
                        "[[ensemble]]\narm = 2\ncriteria = [\"saddle\"]\nenergies = [3]\n",
                    "s.toml");
    const plan p = make_plan(s);
    ASSERT_EQ(p.count(plan_step::kind::orbit_family), 2u);
    // arm 1: saddle at 4, maximum at 6: 4.5, 5, 5.5 only
    const auto& arm1 = p.steps[0];
    EXPECT_EQ(arm1.arm, 1);
    EXPECT_EQ(arm1.energies, (std::vector<std::string>{"4.5", "5", "5.5"}));
    EXPECT_EQ(p.steps[1].arm, 2);
    EXPECT_EQ(p.steps[1].energies, std::vector<std::string>{"3"});
}

TEST(Plan, PredictionOnlySceneRunsNoSimulation) {
    const scene s = parse_scene(
        std::string(minimal) + "[predictions]\nquantities = [\"omega\"]\nenergies = [3]\n",
        "s.toml");
    const plan p = make_plan(s);
    EXPECT_EQ(p.count(plan_step::kind::ensemble), 0u);
    EXPECT_EQ(p.count(plan_step::kind::orbit_family), 0u);
}

// atol = 0 means rtol (study/settings.hpp's trajectory_key): two ensembles that differ only in
// writing it out integrate the same trajectories, once; another seed does not share them.
TEST(Plan, EnsemblesWithTheSameEffectiveToleranceShareTrajectories) {
    const auto ensemble = [](const std::string& name, const std::string& extra) {
        return "[[ensemble]]\nname = \"" + name +
               "\"\nenergies = [3]\ntrajectories = 4\ntime = 5\nrtol = 1e-10\n" + extra;
    };
    const scene s =
        parse_scene(std::string(minimal) + ensemble("a", "atol = 0\n") +
                        ensemble("b", "atol = 1e-10\n") + ensemble("c", "atol = 1e-10\nseed = 5\n"),
                    "s.toml");
    const plan p = make_plan(s);
    ASSERT_EQ(p.count(plan_step::kind::ensemble), 2u);
    for (const plan_step& step : p.steps) {
        if (step.what != plan_step::kind::ensemble) continue;
        EXPECT_EQ(step.ensemble_indices.size(), step.ensemble_indices.front() == 0 ? 2u : 1u);
    }
}

}  // namespace
}  // namespace flipflux::test
