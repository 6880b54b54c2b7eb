// The CLI through its executable: digits of the printed values and refusal of bad input.
#include <nlohmann/json.hpp>

#include "support.hpp"

namespace flipflux::test {
namespace {

using nlohmann::json;

/// Significant digits to which the decimal string `s` agrees with `ref`.
double matched_digits(const std::string& s, const reference_real& ref) {
    return correct_digits(s, ref);
}

TEST(ModelCommand, QuadPrintsOmegaSquaredToThirtyThreeDigits) {
    const auto r = run_flipflux("model --precision quad");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    EXPECT_EQ(j["precision"], "quad");
    const reference_real r2 = sqrt(reference_real(2));
    for (int s : {1, 2}) {
        const auto& mode = j["critical_points"][s]["normal_modes"][0];
        EXPECT_EQ(mode["kind"], "oscillatory");
        EXPECT_GE(matched_digits(mode["omega_squared"].get<std::string>(), r2), 33);
    }
    EXPECT_GE(matched_digits(j["critical_points"][1]["normal_modes"][0]["direction"][1],
                             reference_real(2 - r2)),
              33);
}

TEST(ModelCommand, Mp60PrintsOmegaSquaredToFiftyEightDigits) {
    const auto r = run_flipflux("model --precision mp:60");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    const reference_real r2 = sqrt(reference_real(2));
    for (int s : {1, 2}) {
        EXPECT_GE(matched_digits(j["critical_points"][s]["normal_modes"][0]["omega_squared"], r2),
                  58);
    }
}

TEST(ModelCommand, ParsesParametersInTheWorkingPrecision) {
    // beta = m2 g a2 = 0.3 * 1 * 1 must be 0.3 to 34 digits, not the double nearest 0.3
    const auto r = run_flipflux("model --m2 0.3 --precision quad");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    EXPECT_GE(
        matched_digits(j["model"]["coefficients"]["beta"], reference_real(reference_real(3) / 10)),
        33);
}

TEST(ModelCommand, RigidLinkDefaults) {
    const auto r = run_flipflux("model --L1 2 --L2 3");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    EXPECT_EQ(j["model"]["a1"], "2");
    EXPECT_EQ(j["model"]["a2"], "3");
}

TEST(ModelCommand, RefusesBadInputWithOneLineAndStatusTwo) {
    const std::pair<const char*, const char*> cases[] = {
        {"--m1 abc", "--m1"},
        {"--m2 nan", "--m2"},
        {"--L1 inf", "--L1"},
        {"--L2 0", "--L2"},
        {"--m1 -1", "--m1"},
        {"--g 0", "--g"},
        {"--I1 -0.5", "--I1"},
        {"--a2 -1", "--a2"},
        {"--precision float", "--precision"},
        {"--precision mp:0", "mp:0"},
        {"--precision mp:1000001", "mp:1000001"},
        {"--precision mp:abc", "mp:abc"},
        {"--precision mp:-3", "mp:-3"},
        {"--m1 1e999999", "--m1"},
        {"--bogus 1", "--bogus"},
    };
    for (const auto& [args, needle] : cases) {
        const auto r = run_flipflux(std::string("model ") + args);
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_TRUE(r.out.empty()) << args << ": " << r.out;
        EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    }
}

TEST(Cli, VersionNamesTheCommitAndHelpWorks) {
    const auto v = run_flipflux("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_NE(v.out.find("git"), std::string::npos);
    const auto h = run_flipflux("model --help");
    EXPECT_EQ(h.status, 0);
    EXPECT_NE(h.out.find("--precision"), std::string::npos);
}

}  // namespace
}  // namespace flipflux::test
