// The paired ensemble check (validation/paired_check.hpp) through the CLI: flipflux samples the
// states (simulate --write-initial-states), an independent route counts their flips (the Taylor
// integrator at quad, `trajectory --route taylor`), and `validate --ensemble --paired` accepts
// those counts; a wrong count on many stable trajectories fails naming the first one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::vector<std::string>> csv_rows(const fs::path& file) {
    std::vector<std::vector<std::string>> out;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream ss(line);
        for (std::string f; std::getline(ss, f, ',');)
            fields.push_back(f);
        out.push_back(fields);
    }
    return out;
}

TEST(PairedCheck, IndependentCountsOfTheSameStatesPassAndWrongOnesFail) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("paired_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const auto init = dir / "init.csv";
    const auto s = run_flipflux(
        "simulate --energy 5 --trajectories 8 --time 4 --arm both "
        "--criteria upright --no-chaos --write-initial-states " +
        init.string());
    ASSERT_EQ(s.status, 0) << s.err;
    const auto rows = csv_rows(init);  // header, then trajectory,energy,theta1,theta2,l1,l2
    ASSERT_EQ(rows.size(), 9u);
    std::string good =
        "# pendulum: m1=1 m2=1 L1=1 L2=1 g=1\n"
        "trajectory,energy,theta1,theta2,l1,l2,time,arm,criterion,flips\n";
    std::string bad = good;
    int wrong = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& r = rows[i];
        const auto t =
            run_flipflux("trajectory --state " + r[2] + "," + r[3] + "," + r[4] + "," + r[5] +
                         " --time 4 --criteria upright --precision quad "
                         "--route taylor");
        ASSERT_EQ(t.status, 0) << t.err;
        int flips[2] = {0, 0};
        std::stringstream ev(t.out);
        for (std::string line; std::getline(ev, line);)
            if (line.find(",1,upright,") != std::string::npos)
                ++flips[0];
            else if (line.find(",2,upright,") != std::string::npos)
                ++flips[1];
        for (int a = 1; a <= 2; ++a) {
            const std::string head = r[0] + "," + r[1] + "," + r[2] + "," + r[3] + "," + r[4] +
                                     "," + r[5] + ",4," + std::to_string(a) + ",Upright,";
            good += head + std::to_string(flips[a - 1]) + ".0\n";  // NumPy's 2.0 is a count
            const int off = a == 2 && wrong < 6 ? 1 : 0;           // six arm-2 counts one too many
            wrong += off;
            bad += head + std::to_string(flips[a - 1] + off) + "\n";
        }
    }
    std::ofstream(dir / "good.csv") << good;
    std::ofstream(dir / "bad.csv") << bad;
    const auto ok =
        run_flipflux("validate --ensemble " + (dir / "good.csv").string() + " --paired");
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
    EXPECT_NE(ok.out.find("first difference: none"), std::string::npos) << ok.out;
    const auto fail =
        run_flipflux("validate --ensemble " + (dir / "bad.csv").string() + " --paired");
    EXPECT_EQ(fail.status, 1) << fail.out << fail.err;
    EXPECT_NE(fail.out.find("first difference: line 4 (trajectory 0): arm 2 upright"),
              std::string::npos)
        << fail.out;
    // a state of another energy is an input error naming its line
    std::string other = good;
    other.replace(other.find(",5,"), 3, ",5.5,");
    std::ofstream(dir / "other.csv") << other;
    const auto e =
        run_flipflux("validate --ensemble " + (dir / "other.csv").string() + " --paired");
    EXPECT_EQ(e.status, 2);
    EXPECT_NE(e.err.find("other.csv:3: the state's energy H = "), std::string::npos) << e.err;
    fs::remove_all(dir);
}

// simulate --arm both: each arm's study is the single-arm run's, bit for bit; --initial-states
// reruns the written states with the same counts; the options that the file replaces are refused.
TEST(PairedCheck, BothArmsAndGivenInitialStatesReproduceTheSingleRuns) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("both_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string common =
        " --trajectories 5 --time 6 --criteria upright --no-chaos "
        "--no-timing";
    const auto both = run_flipflux("simulate --energy 3,5 --arm both" + common +
                                   " --write-initial-states " + (dir / "init.csv").string());
    ASSERT_EQ(both.status, 0) << both.err;
    EXPECT_NE(both.err.find("arm 1 is not counted at E = 3"), std::string::npos) << both.err;
    const auto one = run_flipflux("simulate --energy 5 --arm 1" + common);
    const auto two = run_flipflux("simulate --energy 3,5 --arm 2" + common);
    ASSERT_EQ(one.status, 0);
    ASSERT_EQ(two.status, 0);
    const auto j = nlohmann::json::parse(both.out);
    ASSERT_EQ(j["studies"].size(), 2u);
    EXPECT_EQ(j["studies"][0]["energies"], nlohmann::json::parse(one.out)["energies"]);
    EXPECT_EQ(j["studies"][1]["energies"], nlohmann::json::parse(two.out)["energies"]);
    const auto given =
        run_flipflux("simulate --arm both --initial-states " + (dir / "init.csv").string() +
                     " --time 6 --criteria upright --no-chaos --no-timing");
    ASSERT_EQ(given.status, 0) << given.err;
    const auto g = nlohmann::json::parse(given.out);
    for (int s = 0; s < 2; ++s)
        for (std::size_t k = 0; k < j["studies"][s]["energies"].size(); ++k)
            EXPECT_EQ(g["studies"][s]["energies"][k]["criteria"]["upright"]["flips"],
                      j["studies"][s]["energies"][k]["criteria"]["upright"]["flips"]);
    const auto refused = run_flipflux("simulate --energy 5 --initial-states " +
                                      (dir / "init.csv").string() + " --time 6");
    EXPECT_EQ(refused.status, 2);
    EXPECT_NE(refused.err.find("--energy: not with --initial-states"), std::string::npos);
    fs::remove_all(dir);
}

// Issue 44's review: a checkpoint of other given states is not resumed (its completed energies
// were another run's); an energy neither arm counts is refused with --arm both; one differing pair
// without a spread warns (the pairs decide), it does not fail on an infinite z.
TEST(PairedCheck, ReviewFindingsStayFixed) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("review_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string a = (dir / "a.csv").string(), b = (dir / "b.csv").string();
    const std::string ckpt = (dir / "c.ckpt").string();
    const std::string common = " --time 2 --criteria upright --no-chaos --no-timing";
    ASSERT_EQ(run_flipflux("simulate --energy 5 --trajectories 3 --seed 0 --write-initial-states " +
                           a + common)
                  .status,
              0);
    ASSERT_EQ(run_flipflux("simulate --energy 5 --trajectories 3 --seed 7 --write-initial-states " +
                           b + common)
                  .status,
              0);
    ASSERT_EQ(
        run_flipflux("simulate --initial-states " + a + " --checkpoint " + ckpt + common).status,
        0);
    const auto other =
        run_flipflux("simulate --initial-states " + b + " --checkpoint " + ckpt + common);
    EXPECT_EQ(other.status, 2) << other.out;
    EXPECT_NE(other.err.find("checkpoint"), std::string::npos) << other.err;
    const auto below = run_flipflux("simulate --energy 1,5 --trajectories 2 --arm both" + common);
    EXPECT_EQ(below.status, 2);
    EXPECT_NE(below.err.find("--energy: '1' lies at or below both arms' thresholds"),
              std::string::npos)
        << below.err;
    // one trajectory, its count one off: the pairs warn; no mean test without a spread
    const auto rows = csv_rows(a);
    std::ofstream(dir / "one.csv") << "energy,theta1,theta2,l1,l2,time,arm,flips\n"
                                   << rows[1][1] << "," << rows[1][2] << "," << rows[1][3] << ","
                                   << rows[1][4] << "," << rows[1][5] << ",0.5,2,7\n";
    const auto one =
        run_flipflux("validate --ensemble " + (dir / "one.csv").string() + " --paired");
    EXPECT_EQ(one.status, 0) << one.out << one.err;
    EXPECT_NE(one.out.find("warn (pairs warn)"), std::string::npos) << one.out;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace flipflux::test
