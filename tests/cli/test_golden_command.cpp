// flipflux golden's progress bar (src/cli/progress.cpp): with --progress into a pipe one line per
// 10 s and the final one (done/total rows, rate, ETA); without it, nothing on stderr in a pipe.
#include <unistd.h>

#include <filesystem>

#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

TEST(GoldenCommand, ProgressBarOnlyWhenAskedInAPipe) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("golden_" + std::to_string(getpid()));
    const std::string args =
        "golden --quantities omega --max-rows 1 --precision mp:30 --out " + dir.string();
    const auto quiet = run_flipflux(args);
    ASSERT_EQ(quiet.status, 0) << quiet.err;
    // (not required empty: a coverage build's runtime may report a profile rewritten after a
    // rebuild)
    EXPECT_EQ(quiet.err.find("ETA"), std::string::npos) << quiet.err;
    const auto shown = run_flipflux(args + " --progress");
    ASSERT_EQ(shown.status, 0) << shown.err;
    EXPECT_NE(shown.err.find("] 1/1 rows, omega arm - E "), std::string::npos) << shown.err;
    EXPECT_NE(shown.err.find(" digits, "), std::string::npos) << shown.err;
    EXPECT_NE(shown.err.find("/s, ETA 0s\n"), std::string::npos) << shown.err;
    EXPECT_TRUE(fs::is_regular_file(dir / "golden.csv"));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace flipflux::test
