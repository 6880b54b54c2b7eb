// flipflux simulate through its executable: the JSON's statistics agree with the CSVs written
// next to it, thread counts give identical numbers, energy lists and ranges, and every kind of
// bad input is refused with a one-line error naming the option and exit status 2.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include "support.hpp"

namespace flipflux::test {
namespace {

using nlohmann::json;

std::vector<std::string> read_lines(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::vector<std::string> lines;
    for (std::string line; std::getline(f, line);)
        lines.push_back(line);
    return lines;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string field; std::getline(ss, field, ',');)
        out.push_back(field);
    return out;
}

const std::string base =
    "simulate --energy 5 --criteria upright,approx --trajectories 12 "
    "--time 25 --seed 3 --rtol 1e-8";

TEST(SimulateCommand, JsonAgreesWithCsvAndThreadCounts) {
    const std::filesystem::path dir =
        std::filesystem::path(::testing::TempDir()) / ("flipflux_sim_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    const auto r1 =
        run_flipflux(base + " --threads 1 --sample-interval 5 --csv-dir " + dir.string());
    ASSERT_EQ(r1.status, 0) << r1.err;
    const auto r2 = run_flipflux(base + " --threads 2");
    ASSERT_EQ(r2.status, 0) << r2.err;
    json a = json::parse(r1.out), b = json::parse(r2.out);
    // identical up to the timing fields
    for (json* j : {&a, &b})
        for (auto& e : (*j)["energies"]) {
            e.erase("seconds");
            e.erase("cpu_seconds");
            e.erase("threads");
        }
    EXPECT_EQ(a, b);
    const json& e = a["energies"][0];
    EXPECT_EQ(e["energy"], "5");
    EXPECT_EQ(e["failed_trajectories"], 0);
    EXPECT_LT(std::stod(e["max_energy_drift"].get<std::string>()), 1e-5);
    for (const std::string c : {"upright", "approx"}) {
        const json& s = e["criteria"][c];
        // the per-trajectory rates in the CSV reproduce the JSON's mean and flip count
        const auto lines = read_lines(dir / "trajectories_E5.csv");
        ASSERT_EQ(lines.size(), 13u);
        const auto header = split(lines[0]);
        const auto col = std::find(header.begin(), header.end(), "flips_" + c) - header.begin();
        long flips = 0;
        for (std::size_t i = 1; i < lines.size(); ++i)
            flips += std::stol(split(lines[i])[static_cast<std::size_t>(col)]);
        EXPECT_EQ(s["flips"], flips);
        EXPECT_NEAR(std::stod(s["mean_rate"].get<std::string>()), flips / (12.0 * 25), 1e-15);
        // residence times: one row per successive pair of crossings
        const auto res = read_lines(dir / ("residence_E5_" + c + ".csv"));
        EXPECT_EQ(res.size() - 1, s["residence_times"]["count"].get<std::size_t>());
        long hist = 0;
        for (const auto& n : s["rate_histogram"]["counts"])
            hist += n.get<long>();
        EXPECT_EQ(hist, 12);
        EXPECT_TRUE(std::filesystem::exists(dir / ("rate_histogram_E5_" + c + ".csv")));
        EXPECT_TRUE(std::filesystem::exists(dir / ("residence_histogram_E5_" + c + ".csv")));
        EXPECT_FALSE(s["chaotic_fraction"].is_null());
    }
    EXPECT_EQ(a["chaos"]["classification_reliable"], false);            // T = 25 is too short
    EXPECT_EQ(read_lines(dir / "samples_E5.csv").size(), 1u + 12 * 6);  // t = 0, 5, ..., 25
    EXPECT_TRUE(a.contains("quality"));
    EXPECT_TRUE(a["regimes"].is_array());
    // no temporary files are left behind
    for (const auto& f : std::filesystem::directory_iterator(dir))
        EXPECT_NE(f.path().filename().string()[0], '.') << f.path();
    std::filesystem::remove_all(dir);
}

TEST(SimulateCommand, SaddleCriterionWithItsPrediction) {
    const auto r = run_flipflux(
        "simulate --energy 4.5 --arm 1 --criteria saddle,upright --trajectories 20 --time 10 "
        "--rtol 1e-7 --no-chaos");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    const json& s = j["energies"][0]["criteria"]["saddle"];
    const json& u = j["energies"][0]["criteria"]["upright"];
    // the saddle orbit's flux is the minimal one: below the upright criterion's
    EXPECT_LT(std::stod(s["predicted_rate"].get<std::string>()),
              std::stod(u["predicted_rate"].get<std::string>()));
    EXPECT_LE(s["flips"].get<long>(), u["flips"].get<long>());
    EXPECT_FALSE(s["prediction_method"].is_null());
}

TEST(SimulateCommand, EnergyListsRangesArmOneAndNoChaos) {
    const auto r = run_flipflux(
        "simulate --energy 4.5:5:0.25,5.5 --arm 1 --criteria approx,upright --trajectories 3 "
        "--time 5 --rtol 1e-7 --no-chaos --method dopri5 --bins 4 --m1 1.2 --L2 0.9");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    ASSERT_EQ(j["energies"].size(), 4u);
    EXPECT_EQ(j["energies"][0]["energy"], "4.5");
    EXPECT_EQ(j["energies"][1]["energy"], "4.75");
    EXPECT_EQ(j["energies"][2]["energy"], "5");
    EXPECT_EQ(j["energies"][3]["energy"], "5.5");
    EXPECT_EQ(j["arm"], "1");
    EXPECT_EQ(j["method"], "dopri5");
    EXPECT_EQ(j["model"]["m1"], "1.2");
    const json& s = j["energies"][0]["criteria"]["approx"];
    EXPECT_TRUE(s["chaotic_fraction"].is_null());
    // no classification: no chaotic subset (not a block of zero trajectories)
    EXPECT_TRUE(s["chaotic"].is_null());
    EXPECT_TRUE(j["quality"]["approx"]["chaotic_trajectories"].is_null());
    EXPECT_FALSE(j["quality"]["approx"]["all_trajectories"].is_null());
    EXPECT_EQ(s["rate_histogram"]["counts"].size(), 4u);
    EXPECT_EQ(j["chaos"]["indicator"], "none");
    // the binary that computed it, as --version names it
    const auto v = run_flipflux("--version");
    ASSERT_EQ(v.status, 0) << v.err;
    EXPECT_NE(v.out.find("flipflux " + j["flipflux"]["version"].get<std::string>() + " (git " +
                         j["flipflux"]["git_commit"].get<std::string>() + ")"),
              std::string::npos)
        << v.out;
}

// The Taylor order is named in the output (the run's JSON) when the integrator is taylor: the
// automatic order at the rtol, with or without the chaos indicator's tangent vector (16 and 20 at
// 3e-11: the minima of the cost model, worked out outside the code), and not for DOP853.
TEST(SimulateCommand, TaylorRunsNameTheirOrder) {
    const std::string base =
        "simulate --energy 4.3 --criteria upright --trajectories 2 --time 2 --rtol 3e-11 ";
    for (const auto& [flags, order] :
         std::vector<std::pair<std::string, int>>{{"--no-chaos", 20}, {"", 16}}) {
        const auto r = run_flipflux(base + flags);
        ASSERT_EQ(r.status, 0) << r.err;
        const json j = json::parse(r.out);
        EXPECT_EQ(j["method"], "taylor");
        EXPECT_EQ(j["taylor_order"], order) << flags;
    }
    const auto d = run_flipflux(
        "simulate --energy 4.3 --criteria upright --trajectories 2 --time 2 --rtol 1e-10");
    ASSERT_EQ(d.status, 0) << d.err;
    const json j = json::parse(d.out);
    EXPECT_EQ(j["method"], "dop853");
    EXPECT_FALSE(j.contains("taylor_order"));
}

void expect_refused(const std::string& args, const std::string& option) {
    const auto r = run_flipflux(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
}

TEST(SimulateCommand, RefusesBadInput) {
    const std::string ok = " --criteria upright --time 5";
    expect_refused("simulate --energy 5 --trajectories 0" + ok, "--trajectories");
    expect_refused("simulate --energy 5 --trajectories -4" + ok, "--trajectories");
    expect_refused("simulate --energy 5 --trajectories 1x" + ok, "--trajectories");
    expect_refused("simulate --energy 5 --trajectories 3 --criteria upright --time 0", "--time");
    expect_refused("simulate --energy 5 --trajectories 3 --criteria upright --time -2", "--time");
    expect_refused("simulate --energy 1.5 --trajectories 3" + ok, "--energy");
    expect_refused("simulate --energy 2 --trajectories 3" + ok, "--energy");
    expect_refused("simulate --energy 3.9 --arm 1 --trajectories 3" + ok, "--energy");
    expect_refused("simulate --energy 5 --trajectories 3 --time 5 --criteria upright,sideways",
                   "--criteria");
    expect_refused("simulate --energy 5 --trajectories 3 --time 5 --criteria upright,upright",
                   "--criteria");
    expect_refused("simulate --energy 5 --trajectories 3 --arm 3" + ok, "--arm");
    expect_refused("simulate --energy 5 --trajectories 3 --rtol 0" + ok, "--rtol");
    expect_refused("simulate --energy 5 --trajectories 3 --method rk4" + ok, "--method");
    expect_refused("simulate --energy 5 --trajectories 3 --seed -1" + ok, "--seed");
    expect_refused("simulate --energy 5 --trajectories 3 --chaos-threshold 0" + ok,
                   "--chaos-threshold");
    expect_refused("simulate --energy 5:4:0.1 --trajectories 3" + ok, "--energy");
    expect_refused("simulate --energy 5:6 --trajectories 3" + ok, "--energy");
    expect_refused("simulate --energy five --trajectories 3" + ok, "--energy");
    expect_refused("simulate --energy 5 --trajectories 3 --m2 -1" + ok, "--m2");
    expect_refused("simulate --energy 5 --trajectories 3 --csv-dir /proc/flipflux" + ok,
                   "--csv-dir");
    expect_refused("simulate --energy 5 --trajectories 3 --sample-interval 1" + ok,
                   "--sample-interval");
    expect_refused("simulate --energy 5 --trajectories 3 --bins x" + ok, "--bins");
    // the saddle orbits exist only below the maximum energy
    expect_refused("simulate --energy 6.5 --trajectories 3 --criteria saddle --time 5", "--energy");
}

}  // namespace
}  // namespace flipflux::test
