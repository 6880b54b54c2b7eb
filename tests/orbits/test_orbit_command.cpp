// The orbit module through the command line: `flipflux orbit` (CSV, atomic --out, bad input with
// exit status 2) and `flipflux eval` for the orbit quantities.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "flipflux/model/double_pendulum.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

std::vector<std::vector<double>> parse_csv(const std::string& text, std::string* header) {
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    if (header) *header = line;
    std::vector<std::vector<double>> rows;
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::istringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ','))
            row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    return rows;
}

TEST(OrbitCommand, WritesTheOrbitAsCsv) {
    const auto r = run_flipflux("orbit --energy 3.5 --samples 41");
    ASSERT_EQ(r.status, 0) << r.err;
    std::string header;
    const auto rows = parse_csv(r.out, &header);
    EXPECT_EQ(header, "t,theta1,theta2,l1,l2");
    ASSERT_EQ(rows.size(), 41u);
    const double_pendulum<double> model;
    for (const auto& row : rows) {
        ASSERT_EQ(row.size(), 5u);
        EXPECT_NEAR(model.hamiltonian({row[1], row[2], row[3], row[4]}), 3.5, 1e-13);
    }
    EXPECT_EQ(rows.front()[0], 0);
    EXPECT_EQ(rows.front()[1], 0);
    EXPECT_NEAR(rows.front()[2], 3.141592653589793, 1e-16);
    for (int i = 1; i < 5; ++i)
        EXPECT_EQ(rows.back()[i], rows.front()[i]);  // closed: the last row is the start
    // every digit: 17 significant digits for double
    const std::string first_momentum = r.out.substr(r.out.find('\n') + 1);
    EXPECT_GE(first_momentum.find('\n'), 40u);
}

TEST(OrbitCommand, ArmOneQuadAndSymmetricMethod) {
    const auto r = run_flipflux(
        "orbit --energy 5 --arm 1 --precision quad --samples 3 "
        "--method symmetric");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto rows = parse_csv(r.out, nullptr);
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_NEAR(rows.front()[1], 3.141592653589793, 1e-15);  // the saddle (pi, 0)
    EXPECT_EQ(rows.front()[2], 0);
    // the middle row is half a period later: back at the saddle with reversed momenta
    EXPECT_NEAR(rows[1][3], -rows[0][3], 1e-15);
    // quad output carries 36 digits
    EXPECT_NE(r.out.find("3.1415926535897932384626433832795028,"), std::string::npos);
}

TEST(OrbitCommand, IntegratorOptionChoosesTheRoute) {
    // the same orbit (double, arm 2, E = 3.5) by Taylor series and by Gauss-Legendre (the
    // default at double): the rows agree to the orbit's error, and eval names the integrator
    const auto t = run_flipflux("orbit --energy 3.5 --samples 3 --integrator taylor");
    const auto g = run_flipflux("orbit --energy 3.5 --samples 3 --method symmetric");
    ASSERT_EQ(t.status, 0) << t.err;
    ASSERT_EQ(g.status, 0) << g.err;
    const auto rt = parse_csv(t.out, nullptr), rg = parse_csv(g.out, nullptr);
    ASSERT_EQ(rt.size(), rg.size());
    for (std::size_t i = 0; i < rt.size(); ++i)
        for (std::size_t j = 0; j < rt[i].size(); ++j)
            EXPECT_NEAR(rt[i][j], rg[i][j], 1e-12) << i << "," << j;
    const auto et = run_flipflux("eval period --energy 3.5 --method symmetric --integrator taylor");
    const auto eg = run_flipflux("eval period --energy 3.5 --method symmetric");
    ASSERT_EQ(et.status, 0) << et.err;
    ASSERT_EQ(eg.status, 0) << eg.err;
    const auto jt = nlohmann::json::parse(et.out), jg = nlohmann::json::parse(eg.out);
    EXPECT_NE(jt["method"].get<std::string>().find("Taylor"), std::string::npos) << et.out;
    EXPECT_NE(jg["method"].get<std::string>().find("Gauss-Legendre"), std::string::npos) << eg.out;
    const double Tt = std::stod(jt["value"].get<std::string>());
    const double Tg = std::stod(jg["value"].get<std::string>());
    const double err = std::stod(jt["error_estimate"].get<std::string>()) +
                       std::stod(jg["error_estimate"].get<std::string>());
    EXPECT_LE(std::abs(Tt - Tg), err);
}

TEST(OrbitCommand, OutWritesTheFileAtomically) {
    const std::string path = ::testing::TempDir() + "flipflux_orbit_test.csv";
    std::remove(path.c_str());
    const auto r = run_flipflux("orbit --energy 2.5 --samples 5 --out " + path);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.out.empty());
    const std::string written = read_text(path);
    const auto stdout_run = run_flipflux("orbit --energy 2.5 --samples 5");
    EXPECT_EQ(written, stdout_run.out);
    std::remove(path.c_str());
    // a folder that cannot be created, even by root (check_output_file creates missing folders)
    const auto bad = run_flipflux("orbit --energy 2.5 --out /proc/flipflux-none/x.csv");
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("--out"), std::string::npos);
}

TEST(OrbitCommand, BadInputExitsWithStatusTwo) {
    struct bad_case {
        std::string args, option;
    };
    for (const auto& c :
         std::vector<bad_case>{{"orbit --energy 2", "--energy"},
                               {"orbit --energy 1.9", "--energy"},
                               {"orbit --energy 6", "--energy"},
                               {"orbit --energy 6.5", "--energy"},
                               {"orbit --energy 3.9 --arm 1", "--energy"},
                               {"orbit --energy nan", "--energy"},
                               {"orbit --energy 3 --arm 3", "--arm"},
                               {"orbit --energy 3 --samples 1", "--samples"},
                               {"orbit --energy 3 --samples x", "--samples"},
                               {"orbit --energy 3 --method ceres", "--method"},
                               {"eval period --energy 2", "--energy"},
                               {"eval action --energy 6 --arm 1", "--energy"},
                               {"eval period --energy 3 --method x", "--method"},
                               {"orbit --energy 3 --m1 -1", "--m1"},
                               {"orbit --energy 3 --integrator rk4", "--integrator"},
                               {"eval period --energy 3 --integrator rk4", "--integrator"},
                               {"eval omega --energy 3 --integrator taylor", "--integrator"}}) {
        const auto r = run_flipflux(c.args);
        EXPECT_EQ(r.status, 2) << c.args;
        EXPECT_NE(r.err.find(c.option), std::string::npos) << c.args << ": " << r.err;
        EXPECT_TRUE(r.out.empty()) << c.args;
    }
}

double json_value(const std::string& text) {
    return std::stod(nlohmann::json::parse(text)["value"].get<std::string>());
}

TEST(OrbitCommand, EvalServesTheOrbitQuantities) {
    const auto T = run_flipflux("eval period --energy 4");
    const auto F = run_flipflux("eval action --energy 4");
    const auto f3 = run_flipflux("eval flux-saddle --energy 4 --method symmetric");
    const auto mu = run_flipflux("eval multiplier --energy 4");
    const auto k = run_flipflux("eval stability-index --energy 4");
    for (const auto* r : {&T, &F, &f3, &mu, &k})
        ASSERT_EQ(r->status, 0) << r->err;
    EXPECT_NEAR(json_value(f3.out), 2 * json_value(F.out), 1e-12);
    const double m = json_value(mu.out);
    EXPECT_NEAR(json_value(k.out), m + 1 / m, 1e-9 * m);
    EXPECT_GT(json_value(T.out), 5.0);
    const auto j = nlohmann::json::parse(T.out);
    EXPECT_EQ(j["quantity"], "period");
    EXPECT_EQ(j["arm"], "2");
    EXPECT_NE(j["method"].get<std::string>().find("periodic"), std::string::npos);
    // a non-egalitarian pendulum echoes its model
    const auto r = run_flipflux("eval period --energy 7 --m1 2 --L2 0.6 --arm 1");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::parse(r.out).contains("model"));
}

}  // namespace
}  // namespace flipflux::test
