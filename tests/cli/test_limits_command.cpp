// Issue 20 (hardening), through the executable: sizes that drive allocations, thread counts,
// tolerances and budgets that could not finish, values that overflow the working precision and
// mistyped subcommands are refused up front with one line naming the option and exit status 2
// (docs/limits.md). Each case exits before any computation: cheap at -O0.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include "support.hpp"

namespace flipflux::test {
namespace {

/// `args` exits 2 with one line on stderr that contains every one of `expected`, and no stdout.
void expect_refused(const std::string& args, std::initializer_list<std::string> expected) {
    const command_result r = run_flipflux(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    for (const std::string& e : expected)
        EXPECT_NE(r.err.find(e), std::string::npos)
            << args << "\ngot: " << r.err << "expected: " << e;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
}

const std::string simulate = "simulate --energy 3 --trajectories 2 --time 1 ";

TEST(LimitsCommand, SimulateBinsBeyondTheLimitAreRefused) {
    expect_refused(simulate + "--bins 1000000000", {"--bins: '1000000000'", "at most 1000000"});
}

TEST(LimitsCommand, SimulateTrajectoriesBeyondMemoryAreRefused) {
    expect_refused("simulate --energy 3 --trajectories 1000000000 --time 1",
                   {"--trajectories: '1000000000' would need about", "GB"});
    expect_refused("simulate --energy 3 --trajectories 4294967297 --time 1",
                   {"--trajectories: '4294967297' is too many (at most 1000000000 per energy)"});
    ::setenv("FLIPFLUX_MEMORY_LIMIT", "100000", 1);
    expect_refused("simulate --energy 3 --trajectories 10000 --time 1", {"--trajectories"});
    ::unsetenv("FLIPFLUX_MEMORY_LIMIT");
}

// A saddle orbit the continuation from the saddle does not reach, on a valid pendulum (a lower
// link 2^20 times heavier, whose arm-2 saddle has a centre frequency 2.2e3 times its growth
// rate; docs/limits.md): one line, an error with the ratio as context and exit status 1, no
// output, not "internal error" (as it was).
TEST(LimitsCommand, SaddleOrbitsTheContinuationDoesNotReachAreErrorsNotInternalErrors) {
    const command_result r = run_flipflux(
        "eval period --arm 2 --energy 4500 --m1 1 --m2 1048576 --L1 0.5 --a1 0.25 --I1 0.0625 "
        "--L2 2 --g 0.0009765625");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("flipflux: error: saddle orbit at E = 4500 (arm 2): no convergence"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("times its growth rate"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

// The same pendulum's arm 1: its saddle's growth rate is 2.2e3 times its centre frequency, so
// the multiplier near the saddle is about 1e5927, far beyond what a quarter-period shot in double
// resolves (1e62.6): refused at once naming the cause (exit 2), where the continuation used to
// run for minutes without a result.
TEST(LimitsCommand, SaddleOrbitsFarTooUnstableAreRefusedWithoutTrying) {
    const auto t0 = std::chrono::steady_clock::now();
    const command_result r = run_flipflux(
        "eval period --arm 1 --energy 1030 --m1 1 --m2 1048576 --L1 0.5 --a1 0.25 --I1 0.0625 "
        "--L2 2 --g 0.0009765625");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("flipflux: error: saddle orbit at E = 1030 (arm 1): the pendulum's saddle "
                         "orbits for this arm are too unstable to be found by shooting"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("not attempted"), std::string::npos) << r.err;
    EXPECT_LT(seconds, 60) << "the continuation was attempted";  // it ran for minutes before
    EXPECT_TRUE(r.out.empty()) << r.out;
}

// Within 1e-13 of E_max the saddle orbit's period diverges and double's continuation from the
// saddle stops short: a refusal naming the energy and E_max, not "internal error" (exit 1) as
// before. (A pendulum whose continuation gives up in ~1 s, ~65 s in CI's instrumented build; the
// paper's takes ~5 s. `orbit` and the other callers share throw_not_converged, unit-tested in
// SaddleOrbit.NoConvergenceJustBelowTheMaximumIsTheEnergysFault.)
TEST(LimitsCommand, SaddleOrbitsTooCloseToTheMaximumAreRefused) {
    const std::string pendulum = " --arm 2 --m1 2 --m2 0.5 --L1 0.7 --L2 1.5";  // E_max = 5
    expect_refused("eval period --energy 4.9999999999999" + pendulum,
                   {"--energy: '4.9999999999999'", "too close to E_max = 5", "arm-2 saddle orbit",
                    "E_max - E = 1e-13"});
}

// A positive energy that the precision cannot hold at all is named as the user wrote it and
// called an underflow (it said "'0' is outside the domain ... needs E > 0"); E <= 0 is named too.
TEST(LimitsCommand, AnEnergyThatUnderflowsIsNamedAsWritten) {
    expect_refused("eval omega --energy 1e-999999", {"--energy: '1e-999999' underflows double"});
    expect_refused("eval flux-upright --energy=-0.5", {"--energy: '-0.5' is outside the domain"});
}

// An energy that double rounds onto the threshold it misses is quoted as written, not as its
// double: the closed form of omega "needs E >= E_max = 6" refused '6' (an independent audit found
// such a quote); the saddle-orbit family's range likewise.
TEST(LimitsCommand, EnergiesBesideAThresholdAreQuotedAsWritten) {
    expect_refused("eval omega --method closed-form --energy 5.99999999999999999999",
                   {"--energy: '5.99999999999999999999' is below the threshold of method "
                    "closed-form of omega (needs E >= E_max = 6"});
    expect_refused("eval period --energy 1.99999999999999999999 --arm 2",
                   {"--energy: '1.99999999999999999999' is outside the arm-2 saddle-orbit "
                    "family's range (2, 6)"});
}

TEST(LimitsCommand, SimulateTinySampleIntervalIsRefused) {
    const std::string dir = ::testing::TempDir() + "flipflux_limits_" + std::to_string(getpid());
    expect_refused(simulate + "--sample-interval 1e-300 --csv-dir " + dir,
                   {"--sample-interval: '1e-300' would need about"});
    std::filesystem::remove_all(dir);
}

TEST(LimitsCommand, ThreadCountsBeyondTheLimitAreRefused) {
    expect_refused(simulate + "--threads 100000", {"--threads: '100000' is too many threads"});
    expect_refused("golden --jobs 100000 --quantities omega --out /nonexistent",
                   {"--jobs: '100000' is too many threads"});
    const std::string scene = FLIPFLUX_SOURCE_DIR "/data/scenes/default.toml";
    expect_refused("run --dry-run --threads 100000 " + scene, {"--threads: '100000'"});
}

TEST(LimitsCommand, RtolBelowTheWorkingPrecisionIsRefused) {
    for (const std::string rtol : {"1e-19", "1e-100", "1e-300"})
        expect_refused(simulate + "--rtol " + rtol,
                       {"--rtol: '", "is below what double precision can meet"});
    expect_refused(
        "trajectory --state 0,3,0,0 --time 1 --criteria upright --route ensemble --rtol 1e-19",
        {"--rtol"});
}

TEST(LimitsCommand, BudgetsThatCannotFinishAreRefused) {
    expect_refused(simulate + "--estimator short --short-time 1e300",
                   {"--short-time: '", "is longer than the budget"});
    expect_refused("accuracy --min-seconds inf --quantities omega --out /dev/null",
                   {"--min-seconds"});
    expect_refused(simulate + "--max-seconds -1",
                   {"--max-seconds: '-1' is invalid (CPU seconds: finite and >= 0"});
    expect_refused(simulate + "--max-seconds inf", {"--max-seconds: 'inf' is not a finite"});
    // a run of about 2 CPU seconds bounded at 0.05: one line naming the bound, status 2, no
    // report on stdout
    const command_result r = run_flipflux(
        "simulate --energy 5 --trajectories 4000 --time 100 --criteria upright --threads 1 "
        "--no-chaos --max-seconds 0.05");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err,
              "flipflux: error: --max-seconds: stopped at its bound of 0.05 CPU seconds (without "
              "a checkpoint: the finished trajectories are lost)\n");
    EXPECT_EQ(r.out, "");
}

TEST(LimitsCommand, OverflowingInputsAreRefusedNotPrintedAsInf) {
    expect_refused("eval omega --energy 3 --m2 1e300", {"--m2: '", "is outside the magnitudes"});
    expect_refused("eval rate-upright --energy 5e307",
                   {"--energy: '", "is outside the magnitudes"});
    expect_refused("eval flux-approx --energy 5e307", {"--energy: '", "is outside the magnitudes"});
    // mp:N has the exponent range for it: a finite value
    const command_result r = run_flipflux("eval omega --energy 1e100 --precision mp:20");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
}

// Up to the magnitude limit (3.4e38 in double) the answers are finite and correct: the double
// values agree with mp:30 (an independent precision) to a few ulp times the closed forms'
// condition (the rates divide two large numbers: 64 eps).
TEST(LimitsCommand, LargeEnergiesBelowTheLimitGiveCorrectFiniteValues) {
    auto value = [](const std::string& args) {
        const command_result r = run_flipflux(args);
        EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
        const std::size_t at = r.out.find("\"value\": \"");
        return at == std::string::npos ? std::string("nan")
                                       : r.out.substr(at + 10, r.out.find('"', at + 10) - at - 10);
    };
    for (const std::string q : {"omega", "rate-upright", "rate-approx"}) {
        const std::string e = " --energy 3.3e38";
        const double d = std::stod(value("eval " + q + e));
        const double m = std::stod(value("eval " + q + e + " --precision mp:30"));
        EXPECT_TRUE(std::isfinite(d)) << q;
        EXPECT_NEAR(d / m, 1, 64 * std::numeric_limits<double>::epsilon()) << q;
    }
}

// Issue 20: E = 1e300 or T = 1e300 integrated forever (an interrupted run after minutes).
TEST(LimitsCommand, TrajectoriesThatCouldNotFinishAreRefused) {
    expect_refused(
        "simulate --energy 1e300 --trajectories 2 --time 1 --criteria upright",
        {"--time: T = 1 at E = 1.0000000000000001e+300 allows up to", "turns of the arms"});
    expect_refused("simulate --energy 3 --trajectories 2 --time 1e300 --criteria upright",
                   {"--time: T = 1.0000000000000001e+300 at E = ", "turns of the arms"});
    expect_refused("trajectory --state 0,3,0,0 --time 1e300 --criteria upright --route ensemble",
                   {"--time: T = 1.0000000000000001e+300 at E = ", "turns of the arms"});
    // the reference route (quad, mp:N) too: it ran forever (review of issue 20's merge)
    expect_refused("trajectory --state 0,3,0,0 --time 1e300 --criteria upright --route reference",
                   {"--time: T = 1.0000000000000001e+300 at E = ", "turns of the arms"});
    expect_refused("trajectory --state 0,3,0,0 --time 1e300 --criteria upright --precision quad",
                   {"--time: T = 1.0000000000000001e+300 at E = ", "turns of the arms"});
    // validate --ensemble's pilot ensemble runs at the candidate's time: a row with T = 1e300
    // ran forever; it is a no-prediction row now (exit 1), and an absurd --pilot is refused
    const std::string candidate =
        ::testing::TempDir() + "flipflux_limits_ensemble_" + std::to_string(getpid()) + ".csv";
    std::ofstream(candidate) << "criterion,arm,energy,trajectories,time,flips\n"
                                "upright,2,5,1000,1e300,5\n";
    const test::command_result r = test::run_flipflux("validate --ensemble " + candidate);
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("turns of the arms"), std::string::npos) << r.out;
    expect_refused("validate --ensemble " + candidate + " --pilot 100000000000000000",
                   {"--pilot", "memory"});
    std::remove(candidate.c_str());
}

// Issue 20: an output path that is a file's child, or a directory, ended in "internal error:
// filesystem error" after the computation; it is refused before measuring.
TEST(LimitsCommand, UnwritableOutputIsRefusedBeforeComputing) {
    const std::string file =
        ::testing::TempDir() + "flipflux_limits_file_" + std::to_string(getpid());
    std::ofstream(file) << "x";
    const std::string accuracy = "accuracy --quantities omega --precisions double --out ";
    expect_refused(accuracy + file + "/x.md", {"--out: '" + file + "/x.md' cannot be written"});
    expect_refused(accuracy + ::testing::TempDir(), {"is a folder, not a file"});
    std::remove(file.c_str());
}

TEST(LimitsCommand, MistypedSubcommandIsNamed) {
    expect_refused("evall omega --energy 3", {"'evall' is not a subcommand", "eval"});
}

// The closing probe campaign of issue 20 (tools/probes.py), each finding a test:
// golden --max-rows -1 was wrapped by CLI11 to 2^64 - 1 (every row: hours of computation).
TEST(LimitsCommand, ProbeGoldenMaxRowsMinusOneIsRefused) {
    expect_refused("golden --out /nonexistent/g --max-rows -1",
                   {"--max-rows: '-1' is invalid (expected a non-negative integer)"});
    expect_refused("golden --out /nonexistent/g --max-rows 1e3", {"--max-rows: '1e3'"});
    expect_refused("golden --out /nonexistent/g --max-seconds -1",
                   {"--max-seconds: '-1' must be finite and >= 0"});
    expect_refused("golden --out /nonexistent/g --max-seconds inf",
                   {"--max-seconds: 'inf' is not a finite decimal number"});
}

// trajectory --out/--events and orbit --out naming a directory or /proc were refused only after
// the computation (minutes at mp:N), after the notes the computation printed (several lines).
TEST(LimitsCommand, ProbeTrajectoryAndOrbitOutputsAreCheckedBeforeComputing) {
    const std::string dir = ::testing::TempDir();
    expect_refused("trajectory --state 1,2,0,0 --time 1 --out " + dir, {"--out: '" + dir + "'"});
    expect_refused("trajectory --state 1,2,0,0 --time 1 --events /proc/x", {"--events: '/proc/x'"});
    expect_refused("orbit --energy 4 --out " + dir, {"--out: '" + dir + "'"});
    expect_refused("orbit --energy 4 --precision mp:300 --out /proc/self/x", {"--out: '/proc"});
}

}  // namespace
}  // namespace flipflux::test
