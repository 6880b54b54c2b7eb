// validate: accepts a correct candidate; catches a value off in its 9th digit, a missing row, a
// duplicated row and a malformed line, each reported by line number.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "flipflux/validation/validate.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

class Validate : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("validate_" + std::to_string(getpid()));
        fs::create_directories(dir_ / "golden");
        std::ofstream(dir_ / "golden" / "values.csv")
            << "quantity,arm,energy,value,digits,method\n"
               "flux-upright,2,2.5,1.23456789012345678901234567890123456789,38,elliptic\n"
               "flux-upright,2,3,2.71828182845904523536028747135266249775,38,elliptic\n"
               "flux-upright,1,4.5,0.577215664901532860606512090082402431042,38,elliptic\n";
    }
    void TearDown() override { fs::remove_all(dir_); }

    validation_report check(const std::string& candidate, bool allow_missing = false) {
        std::ofstream(dir_ / "candidate.csv") << candidate;
        return validate_candidate(dir_ / "candidate.csv", dir_ / "golden", 1e-12, allow_missing);
    }
    fs::path dir_;
};

const std::string header = "quantity,arm,energy,value\n";
const std::string row1 = "flux-upright,2,2.5,1.2345678901234568\n";
const std::string row2 = "flux-upright,2,3.0,2.718281828459045\n";  // "3.0" matches "3"
const std::string row3 = "flux-upright,1,4.5,0.57721566490153286\n";

TEST_F(Validate, AcceptsACorrectCandidate) {
    const auto r = check(header + row1 + row2 + row3);
    EXPECT_TRUE(r.passed()) << format_report(r, 1e-12);
    ASSERT_EQ(r.entries.size(), 3u);
    EXPECT_GE(r.entries[0].matched_digits, 16);
}

// Issue 14: rows the golden set lacks are counted, not fatal, unless require_all; the report puts
// the summary first and lists ok and missing rows only when verbose.
TEST_F(Validate, UnmatchedRowsAreCountedAndFailOnlyWhenAllAreRequired) {
    const std::string extra = "flux-upright,2,2.75,1.5\n";  // no golden value at E = 2.75
    const auto r = check(header + row1 + extra + row2 + row3);
    EXPECT_EQ(r.count(validation_entry::status::unmatched), 1u);
    EXPECT_TRUE(r.passed()) << format_report(r, 1e-12);
    std::ofstream(dir_ / "candidate.csv") << header + row1 + extra + row2 + row3;
    const auto strict =
        validate_candidate(dir_ / "candidate.csv", dir_ / "golden", 1e-12, false, true);
    EXPECT_FALSE(strict.passed());
    const std::string brief = format_report(r, 1e-12);
    EXPECT_EQ(brief.rfind("summary: 4 rows: 3 ok", 0), 0u) << brief;
    EXPECT_NE(brief.find("unmatched  flux-upright"), std::string::npos) << brief;
    EXPECT_EQ(brief.find(" ok "), std::string::npos) << brief;  // ok rows only when verbose
    const std::string full = format_report(r, 1e-12, true);
    EXPECT_NE(full.find(" ok "), std::string::npos) << full;
    // a missing row: counted in the summary, listed only when verbose
    const auto m = check(header + row1 + row3);
    EXPECT_FALSE(m.passed());
    EXPECT_EQ(format_report(m, 1e-12).find("has no candidate row"), std::string::npos);
    EXPECT_NE(format_report(m, 1e-12, true).find("has no candidate row"), std::string::npos);
}

TEST_F(Validate, CatchesAValueOffInItsNinthDigit) {
    const auto r = check(header + row1 + "flux-upright,2,3,2.718281838459045\n" + row3);
    EXPECT_FALSE(r.passed());
    ASSERT_EQ(r.count(validation_entry::status::fail), 1u);
    EXPECT_EQ(r.entries[1].line, 3);
    EXPECT_NEAR(r.entries[1].matched_digits, 8.4, 0.2);
}

TEST_F(Validate, CatchesAMissingRow) {
    const auto r = check(header + row1 + row3);
    EXPECT_FALSE(r.passed());
    ASSERT_EQ(r.count(validation_entry::status::missing), 1u);
    EXPECT_EQ(r.entries.back().energy, "3");
    EXPECT_TRUE(check(header + row1 + row3, true).passed());
}

TEST_F(Validate, CatchesADuplicatedRow) {
    const auto r = check(header + row1 + row2 + row2 + row3);
    EXPECT_FALSE(r.passed());
    ASSERT_EQ(r.count(validation_entry::status::duplicate), 1u);
    EXPECT_EQ(r.entries[2].line, 4);
    EXPECT_NE(r.entries[2].note.find("line 3"), std::string::npos);
}

TEST_F(Validate, CatchesMalformedAndUnmatchedLines) {
    const auto r = check(header + row1 + "flux-upright,2,3\n" + "flux-upright,2,abc,1\n" +
                         "flux-upright,2,3,1.0e\n" + "omega-typo,2,3,1\n" + "flux-upright,2,9,1\n" +
                         row2 + row3);
    EXPECT_FALSE(r.passed());
    // an unknown quantity is malformed (a typo must not drop the row as "unmatched")
    EXPECT_EQ(r.count(validation_entry::status::malformed), 4u);
    EXPECT_EQ(r.count(validation_entry::status::unmatched), 1u);
    EXPECT_EQ(r.entries[1].line, 3);
    EXPECT_EQ(r.entries[2].line, 4);
    EXPECT_NE(r.entries[4].note.find("'omega-typo' is not a registered quantity"),
              std::string::npos)
        << r.entries[4].note;
    const std::string text = format_report(r, 1e-12);
    EXPECT_NE(text.find("FAILED"), std::string::npos);
}

// A per-arm quantity needs arm 1 or 2: arm 3, 2.0 or none was "unmatched" and the report passed.
// omega (one value for both arms) ignores the column.
TEST_F(Validate, APerArmQuantityWithoutAValidArmIsMalformed) {
    const auto r = check(header + row1 + "flux-upright,3,2.5,1\n" + "flux-upright,2.0,2.5,1\n" +
                         "flux-upright,,2.5,1\n" + row2 + row3);
    EXPECT_FALSE(r.passed()) << format_report(r, 1e-12);
    EXPECT_EQ(r.count(validation_entry::status::malformed), 3u) << format_report(r, 1e-12);
    EXPECT_NE(r.entries[1].note.find("arm '3' is not 1 or 2"), std::string::npos)
        << r.entries[1].note;
}

// Unusable files: a directory (was "empty file"), a header naming a column twice (the second
// was ignored).
TEST_F(Validate, ADirectoryOrAHeaderWithATwiceNamedColumnIsRefused) {
    fs::create_directories(dir_ / "adir.csv");
    try {
        (void)validate_candidate(dir_ / "adir.csv", dir_ / "golden", 1e-12, false);
        ADD_FAILURE() << "a directory was read";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("is not a regular file (a folder)"), std::string::npos)
            << e.what();
    }
    try {
        (void)check("quantity,arm,energy,value,value\nflux-upright,2,2.5,1,1.2345678901234568\n");
        ADD_FAILURE() << "a column named twice was accepted";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find(":1: the header names the column 'value' twice"),
                  std::string::npos)
            << e.what();
    }
}

// Issue 20: golden files given to validate are outside data too. `digits = -5` made a 6834 %
// error pass, duplicate golden rows were accepted; malformed numbers now name file:line.
TEST_F(Validate, BadGoldenFilesAreRefusedNamingFileAndLine) {
    const fs::path golden = dir_ / "golden" / "values.csv";
    const std::string head = "quantity,arm,energy,value,digits,method\n";
    const std::string good = "flux-upright,2,2.5,1.23456789012345678901234567890123456789,38,e\n";
    auto refusal = [&](const std::string& bad_row) {
        std::ofstream(golden) << head + good + bad_row;
        try {
            (void)check(header + row1);
        } catch (const input_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string at = golden.string() + ":3: ";
    for (const std::string d : {"-5", "0", "x", "3.5", "", "1000001", "99999999999"})
        EXPECT_NE(refusal("flux-upright,2,3,2.7," + d + ",e\n").find(at + "digits '" + d + "'"),
                  std::string::npos)
            << d;
    EXPECT_NE(refusal("flux-upright,2,3,2.7e,30,e\n").find(at + "value '2.7e'"), std::string::npos);
    EXPECT_NE(refusal("flux-upright,2,x,2.7,30,e\n").find(at + "energy 'x'"), std::string::npos);
    EXPECT_NE(refusal("flux-upright,3,3,2.7,30,e\n").find(at + "arm '3'"), std::string::npos);
    EXPECT_NE(refusal(",2,3,2.7,30,e\n").find(at + "empty quantity"), std::string::npos);
    EXPECT_NE(refusal("flux-upright,2,2.50,1.2,30,e\n")
                  .find(at + "flux-upright arm 2 at E = 2.50 is given twice (first at " +
                        golden.string() + ":2)"),
              std::string::npos);
    EXPECT_EQ(refusal("flux-upright,2,3,2.7,30,e\n"), "");
}

// Issue 20: a candidate CSV with a UTF-8 byte-order mark (spreadsheet export) was refused while
// scenes accept one.
TEST_F(Validate, CandidateWithAByteOrderMarkIsRead) {
    const auto r = check("\xEF\xBB\xBF" + header + row1 + row2 + row3);
    EXPECT_TRUE(r.passed()) << format_report(r, 1e-12);
}

// Issue 20's probe campaign: a candidate of 200,000 rows took minutes (every row compared with
// every golden row in MPFR). The rows are now found by (quantity, arm) and energy: each matches
// its own golden row, "3.0" matches "3", an energy 1e-11 off (relative) matches none, and the
// repeated rows are duplicates of the first.
TEST_F(Validate, ProbeLargeCandidateIsMatchedRowByRow) {
    std::string text = header + row3 + row2 + row1 + "flux-upright,2,3.00000000003,2.7\n";
    for (int i = 0; i < 20000; ++i)
        text += row2;
    const auto r = check(text);
    ASSERT_EQ(r.entries.size(), 20004u);
    EXPECT_EQ(r.count(validation_entry::status::ok), 3u) << format_report(r, 1e-12);
    EXPECT_EQ(r.count(validation_entry::status::unmatched), 1u);
    EXPECT_EQ(r.count(validation_entry::status::duplicate), 20000u);
    EXPECT_EQ(r.entries[1].golden, "2.71828182845904523536028747135266249775");
    EXPECT_EQ(r.entries[4].note, "duplicates line 3");
}

TEST_F(Validate, CliExitStatus) {
    std::ofstream(dir_ / "good.csv") << header + row1 + row2 + row3;
    std::ofstream(dir_ / "bad.csv") << header + row1 + row2 + row2 + row3;
    const std::string g = " --golden " + (dir_ / "golden").string();
    const auto ok = run_flipflux("validate " + (dir_ / "good.csv").string() + g);
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
    EXPECT_NE(ok.out.find("PASSED"), std::string::npos);
    const auto bad = run_flipflux("validate " + (dir_ / "bad.csv").string() + g);
    EXPECT_EQ(bad.status, 1);
    const auto missing = run_flipflux("validate " + (dir_ / "nope.csv").string() + g);
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.err.find("nope.csv"), std::string::npos);
    const auto rtol = run_flipflux("validate " + (dir_ / "good.csv").string() + g + " --rtol 2");
    EXPECT_EQ(rtol.status, 2);
}

// Without --golden the command uses the golden data of its installation, found beside the
// executable (build tree: share/flipflux/golden, a link to the source data/golden; installed:
// ../share/flipflux/golden), whatever the working directory; an executable without one says so.
TEST_F(Validate, CliFindsTheGoldenDataBesideTheExecutable) {
    std::ifstream golden(fs::path(FLIPFLUX_SOURCE_DIR) / "data/golden/golden.csv");
    std::string line, row;
    while (std::getline(golden, line))
        if (line.rfind("omega,,3,", 0) == 0) row = line.substr(0, line.find(',', 9) - 25);
    ASSERT_FALSE(row.empty());
    std::ofstream(dir_ / "omega.csv") << header << row << "\n";
    const auto ok = run_flipflux("validate " + (dir_ / "omega.csv").string() + " --allow-missing");
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
    EXPECT_NE(ok.out.find("1 ok"), std::string::npos) << ok.out;

    fs::create_directories(dir_ / "bin");  // a copy of the executable with no share/ near it
    fs::copy_file(FLIPFLUX_EXE, dir_ / "bin" / "flipflux");
    const std::string cmd = (dir_ / "bin" / "flipflux").string() + " validate " +
                            (dir_ / "omega.csv").string() + " 2>" + (dir_ / "err.txt").string();
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 2);
    std::ifstream err(dir_ / "err.txt");
    std::getline(err, line);
    EXPECT_EQ(line.rfind("flipflux: error: --golden: no golden data beside the executable", 0), 0u)
        << line;
}

}  // namespace
}  // namespace flipflux::test
