// Runs at scale (issue 6): checkpoint records that read back bit for bit, checkpoints that refuse
// another run's file, a run killed with SIGKILL (or stopped by SIGTERM) and resumed that equals
// an uninterrupted one, thread counts and MPI processes that do not change a bit of the report,
// and the short-trajectory estimator.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <thread>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/fast_trig.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/io/checksum.hpp"
#include "flipflux/study/checkpoint.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_files.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

trajectory_result odd_result() {
    trajectory_result r;
    r.index = 123456789012345ULL;
    r.initial_state = {-0.0, 3.141592653589793, 1e-310, -2.5e300};
    r.status = rk_status::step_size_underflow;
    r.end_time = 0.1 + 0.2;
    r.max_energy_drift = 5e-324;
    r.lyapunov = std::numeric_limits<double>::quiet_NaN();
    r.steps = 1234567;
    r.rejected_steps = 3;
    r.evaluations = 9999999999L;
    r.energy_check_rejections = 2;
    r.crossing_times = {{1.0 / 3, 2.0 / 3, 1e4 - 1e-12}, {}, {std::nextafter(7.0, 8.0)}};
    return r;
}

TEST(Checkpoint, TrajectoryRecordsReadBackBitForBit) {
    const trajectory_result r = odd_result();
    const std::string line = trajectory_record(7, r, true);
    ASSERT_EQ(line.back(), '\n');
    std::size_t k = 0;
    const trajectory_result b =
        parse_trajectory_record(std::string_view(line).substr(0, line.size() - 1), 3, k);
    EXPECT_EQ(k, 7u);
    EXPECT_EQ(b.index, r.index);
    EXPECT_EQ(b.status, r.status);
    for (int i = 0; i < 4; ++i)
        EXPECT_TRUE(same_bits(b.initial_state[i], r.initial_state[i])) << i;
    EXPECT_TRUE(same_bits(b.end_time, r.end_time));
    EXPECT_TRUE(same_bits(b.max_energy_drift, r.max_energy_drift));
    EXPECT_TRUE(std::isnan(b.lyapunov));
    // the classification is written (for older readers) but computed, not read back: the record
    // of a regular trajectory differs in that one field and parses to the same trajectory
    const std::string regular = trajectory_record(7, r, false);
    const std::size_t at = line.find(" nan 1 ");  // lyapunov, then the classification
    ASSERT_NE(at, std::string::npos);
    std::string flipped = line.substr(0, line.rfind(" #"));
    flipped[at + 5] = '0';
    EXPECT_EQ(regular.substr(0, regular.rfind(" #")), flipped);
    EXPECT_EQ(parse_trajectory_record(std::string_view(regular).substr(0, regular.size() - 1), 3, k)
                  .steps,
              r.steps);
    EXPECT_EQ(b.steps, r.steps);
    EXPECT_EQ(b.rejected_steps, r.rejected_steps);
    EXPECT_EQ(b.evaluations, r.evaluations);
    EXPECT_EQ(b.energy_check_rejections, r.energy_check_rejections);
    ASSERT_EQ(b.crossing_times.size(), 3u);
    for (std::size_t c = 0; c < 3; ++c) {
        ASSERT_EQ(b.crossing_times[c].size(), r.crossing_times[c].size());
        for (std::size_t i = 0; i < r.crossing_times[c].size(); ++i)
            EXPECT_TRUE(same_bits(b.crossing_times[c][i], r.crossing_times[c][i]));
    }
}

// A completed energy's record: every statistic (NaN, signed zero, subnormal, histograms) reads
// back with the same bits, so a resumed study reports exactly what an uninterrupted one does.
TEST(Checkpoint, EnergyRecordsReadBackBitForBit) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    energy_result e;
    e.seconds = 0.1 + 0.7;
    e.cpu_seconds = 1.0 / 3;
    e.threads = 2;
    e.processes = 3;
    e.steps_per_trajectory = 1234.0 / 7;
    e.failed_trajectories = 1;
    e.energy_check_rejections = 9000000000LL;
    e.max_energy_drift = 5e-324;
    for (int c = 0; c < 2; ++c) {
        criterion_statistics x;
        x.predicted_rate = c == 0 ? 1.0 / 3 : nan;
        x.flips = 77 + c;
        x.rates = {40, 0.1 + 0.2, 1e-300, -0.0, 0, std::nextafter(1.0, 2.0)};
        x.z_score = c == 0 ? -1.5 : nan;
        x.chaotic = 39;
        x.chaotic_fraction = 39.0 / 40;
        x.chaotic_rates = {39, 2.0 / 3, 0.25, 0.125, 0.5, 1};
        x.chaotic_z_score = std::nextafter(-2.0, 0.0);
        x.residence.summary = {0, nan, nan, nan, nan, nan};
        x.residence.q001 = 1e-17;
        x.residence.q01 = 2.5;
        x.residence.median = 7.0 / 9;
        x.residence.distribution = {0, 1.0 / 3, {1, 0, 5}, 2, 3};
        x.rate_distribution = {-1, 10, {}, 0, 0};
        e.criteria.push_back({std::nullopt, x});
    }
    e.paired = {{0, 1, {40, -1.0 / 3, 0.125, 0.125 / std::sqrt(40.0), -1, 0.5}}};
    const std::string line = energy_record(4, e);
    ASSERT_EQ(line.back(), '\n');
    std::size_t k = 0;
    const energy_result b =
        parse_energy_record(std::string_view(line).substr(0, line.size() - 1), 2, k);
    EXPECT_EQ(k, 4u);
    EXPECT_TRUE(same_bits(b.seconds, e.seconds));
    EXPECT_TRUE(same_bits(b.cpu_seconds, e.cpu_seconds));
    EXPECT_EQ(b.threads, 2);
    EXPECT_EQ(b.processes, 3);
    EXPECT_TRUE(same_bits(b.steps_per_trajectory, e.steps_per_trajectory));
    EXPECT_EQ(b.failed_trajectories, 1u);
    EXPECT_EQ(b.energy_check_rejections, 9000000000LL);
    EXPECT_TRUE(same_bits(b.max_energy_drift, e.max_energy_drift));
    ASSERT_EQ(b.criteria.size(), 2u);
    auto same_summary = [](const summary_statistics& p, const summary_statistics& q) {
        return p.count == q.count && same_bits(p.mean, q.mean) &&
               same_bits(p.standard_deviation, q.standard_deviation) &&
               same_bits(p.standard_error, q.standard_error) && same_bits(p.minimum, q.minimum) &&
               same_bits(p.maximum, q.maximum);
    };
    auto same_histogram = [](const histogram& p, const histogram& q) {
        return same_bits(p.lower, q.lower) && same_bits(p.upper, q.upper) && p.counts == q.counts &&
               p.underflow == q.underflow && p.overflow == q.overflow;
    };
    for (std::size_t c = 0; c < 2; ++c) {
        const criterion_statistics &x = e.criteria[c].statistics, &y = b.criteria[c].statistics;
        EXPECT_FALSE(b.criteria[c].prediction.has_value());  // this run's, not stored
        EXPECT_EQ(std::isnan(y.predicted_rate), std::isnan(x.predicted_rate));
        if (!std::isnan(x.predicted_rate)) {
            EXPECT_TRUE(same_bits(y.predicted_rate, x.predicted_rate));
        }
        EXPECT_EQ(y.flips, x.flips);
        EXPECT_TRUE(same_summary(y.rates, x.rates)) << c;
        EXPECT_EQ(std::isnan(y.z_score), std::isnan(x.z_score));
        EXPECT_EQ(y.chaotic, x.chaotic);
        EXPECT_TRUE(same_bits(y.chaotic_fraction, x.chaotic_fraction));
        EXPECT_TRUE(same_summary(y.chaotic_rates, x.chaotic_rates));
        EXPECT_TRUE(same_bits(y.chaotic_z_score, x.chaotic_z_score));
        EXPECT_EQ(y.residence.summary.count, 0u);
        EXPECT_TRUE(std::isnan(y.residence.summary.mean));
        EXPECT_TRUE(same_bits(y.residence.q001, x.residence.q001));
        EXPECT_TRUE(same_bits(y.residence.median, x.residence.median));
        EXPECT_TRUE(same_histogram(y.residence.distribution, x.residence.distribution));
        EXPECT_TRUE(same_histogram(y.rate_distribution, x.rate_distribution));
    }
    ASSERT_EQ(b.paired.size(), 1u);
    EXPECT_EQ(b.paired[0].first, 0u);
    EXPECT_EQ(b.paired[0].second, 1u);
    EXPECT_TRUE(same_summary(b.paired[0].difference, e.paired[0].difference));
    // a record written before cpu_seconds was recorded (the same without its last field, hashed
    // as it was then) is read with cpu_seconds NaN
    const std::string body = line.substr(0, line.size() - 1);
    const std::string content = body.substr(0, body.rfind(" #"));
    const std::string older = content.substr(0, content.rfind(' '));
    const energy_result old = parse_energy_record(older + " #" + checksum_hex(older), 2, k);
    EXPECT_TRUE(std::isnan(old.cpu_seconds));
    EXPECT_TRUE(same_bits(old.seconds, e.seconds));
    // another criterion count, a damaged hash, a truncated record
    EXPECT_THROW(parse_energy_record(body, 3, k), std::runtime_error);
    std::string flipped = body;
    flipped[8] = flipped[8] == '1' ? '2' : '1';
    EXPECT_THROW(parse_energy_record(flipped, 2, k), std::runtime_error);
    EXPECT_THROW(parse_energy_record(body.substr(0, 40), 2, k), std::runtime_error);
}

TEST(Checkpoint, DamagedRecordsAreRecognised) {
    const std::string line = trajectory_record(0, odd_result(), false);
    const std::string body = line.substr(0, line.size() - 1);
    std::size_t k = 0;
    EXPECT_THROW(parse_trajectory_record(body, 2, k), std::runtime_error);  // criteria count
    std::string flipped = body;
    flipped[10] = flipped[10] == '1' ? '2' : '1';
    EXPECT_THROW(parse_trajectory_record(flipped, 3, k), std::runtime_error);  // hash
    EXPECT_THROW(parse_trajectory_record(body.substr(0, 30), 3, k), std::runtime_error);
    EXPECT_THROW(parse_trajectory_record("", 3, k), std::runtime_error);
    EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
    EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);  // the published FNV-1a test vector
}

json header_for(int seed) {
    return json{{"format", 1}, {"seed", seed}, {"energies", json::array({"5", "5.5"})}};
}

TEST(Checkpoint, ParsingChecksTheHeaderAndDropsATornLastLine) {
    const fs::path file = fs::path(::testing::TempDir()) / "flipflux_parse_checkpoint.txt";
    fs::remove(file);
    trajectory_result r = odd_result();
    {
        checkpoint_content empty;
        checkpoint_writer w(file, header_for(1), empty, 0);
        w.add(trajectory_record(0, r, false));
        r.index = 5;
        w.add(trajectory_record(0, r, false));
        EXPECT_EQ(w.saved_trajectories(), 2u);
    }
    bool exists = false;
    std::string text = read_checkpoint_text(file, exists);
    ASSERT_TRUE(exists);
    const checkpoint_content c = parse_checkpoint(text, header_for(1), 3, file);
    EXPECT_FALSE(c.torn);
    ASSERT_EQ(c.trajectories.at(0).size(), 2u);
    EXPECT_TRUE(c.trajectories.at(0).count(5));
    // another seed: refused, naming the field
    try {
        parse_checkpoint(text, header_for(2), 3, file);
        ADD_FAILURE() << "accepted another run's checkpoint";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("its seed is 1, this run's is 2"), std::string::npos)
            << e.what();
    }
    json extra = header_for(1);
    extra.erase("energies");
    EXPECT_THROW(parse_checkpoint(text, extra, 3, file), input_error);  // a field too many
    // a torn last line (killed while writing) is dropped
    const std::string torn = text.substr(0, text.size() - 7);
    const checkpoint_content t = parse_checkpoint(torn, header_for(1), 3, file);
    EXPECT_TRUE(t.torn);
    EXPECT_EQ(t.trajectories.at(0).size(), 1u);
    // ... and so is a complete but damaged last line; a damaged line before it is refused
    std::string damaged = text;
    damaged[damaged.size() - 30] ^= 1;
    EXPECT_TRUE(parse_checkpoint(damaged, header_for(1), 3, file).torn);
    std::string middle = text;
    middle[text.find('\n') + 20] ^= 1;
    EXPECT_THROW(parse_checkpoint(middle, header_for(1), 3, file), input_error);
    EXPECT_THROW(parse_checkpoint("hello\n", header_for(1), 3, file), input_error);
    EXPECT_THROW(parse_checkpoint("", header_for(1), 3, file), input_error);
    // completing an energy compacts the file to the header and the E lines
    {
        checkpoint_writer w(file, header_for(1), c, 10);
        energy_result e;
        e.seconds = 1.25;
        e.criteria.resize(3);
        e.paired = {{0, 1, {}}, {0, 2, {}}, {1, 2, {}}};
        w.complete(0, e);
        EXPECT_EQ(w.saved_trajectories(), 0u);
    }
    text = read_checkpoint_text(file, exists);
    const checkpoint_content done = parse_checkpoint(text, header_for(1), 3, file);
    EXPECT_TRUE(done.trajectories.empty());
    ASSERT_EQ(done.completed.size(), 1u);
    EXPECT_EQ(done.completed.at(0).seconds, 1.25);
    EXPECT_EQ(done.completed.at(0).criteria.size(), 3u);
    // unreadable
    EXPECT_THROW(read_checkpoint_text(fs::path(::testing::TempDir()), exists), input_error);
    fs::remove(file);
}

// The inline sin/cos pair of the right-hand side against libm (correctly rounded to < 1 ulp in
// glibc): within 2 ulp of 1 in absolute terms, and within 2 ulp relative for sin of small
// arguments; special points, quadrant boundaries, and the libm fallback beyond 2^19.
TEST(FastTrig, AgreesWithLibmToTwoUlp) {
    random_reals rnd(5);
    const double ulp1 = std::numeric_limits<double>::epsilon();
    double worst = 0;
    auto check = [&](double x) {
        double s = 0, c = 0;
        fast_sincos(x, s, c);
        double s2 = 0, c2 = 0, s3 = 0, c3 = 0;  // the two-lane version, bit for bit
        fast_sincos2(x, -0.5 * x, s2, c2, s3, c3);
        EXPECT_TRUE(same_bits(s2, s) && same_bits(c2, c)) << x;
        double s4 = 0, c4 = 0;
        fast_sincos(-0.5 * x, s4, c4);
        EXPECT_TRUE(same_bits(s3, s4) && same_bits(c3, c4)) << x;
        const double es = std::abs(s - std::sin(x)), ec = std::abs(c - std::cos(x));
        worst = std::max({worst, es / ulp1, ec / ulp1});
        if (std::abs(x) < 0.5) {
            EXPECT_LE(es, 2 * ulp1 * std::abs(std::sin(x))) << x;
        }
    };
    for (int i = 0; i < 200000; ++i)
        check(rnd(-8, 8));
    for (int i = 0; i < 20000; ++i)
        check(rnd(-1e5, 1e5));
    for (int k = -8; k <= 8; ++k)
        for (double d : {-1e-9, -1e-300, 0.0, 1e-300, 1e-9, 0.785, -0.786})
            check(k * std::numbers::pi / 4 + d);
    check(1e-310);
    check(-0.0);
    EXPECT_LE(worst, 2.0);
    double s = 0, c = 0;
    fast_sincos(1e7, s, c);  // fallback
    EXPECT_EQ(s, std::sin(1e7));
    EXPECT_EQ(c, std::cos(1e7));
    fast_sincos(std::numeric_limits<double>::quiet_NaN(), s, c);
    EXPECT_TRUE(std::isnan(s) && std::isnan(c));
    double s1 = 0, c1 = 0;
    fast_sincos2(1e7, 0.5, s, c, s1, c1);  // fallback of the two-lane version
    EXPECT_EQ(s, std::sin(1e7));
    EXPECT_TRUE(same_bits(s1, [] {
        double a = 0, b = 0;
        fast_sincos(0.5, a, b);
        return a;
    }()));
}

// The two-state right-hand side (the ensemble's lockstep lanes) is bit for bit the one-state one,
// including the libm fallback for huge angles.
TEST(FastTrig, TwoLaneRightHandSideEqualsTheSingleOne) {
    random_reals rnd(9);
    const pendulum_flow flow(double_pendulum<double>(
        physical_parameters<double>{0.7, 1.3, 0.8, 1.2, 0.5, 0.65, 0.04, 0.09, 1.5}));
    for (int k = 0; k < 2000; ++k) {
        std::array<double, 4> a{rnd(-7, 7), rnd(-7, 7), rnd(-3, 3), rnd(-3, 3)};
        std::array<double, 4> b{rnd(-7, 7), rnd(-7, 7), rnd(-3, 3), rnd(-3, 3)};
        if (k == 0) b[1] = 1e7;
        v2d x[4], f[4];
        for (int i = 0; i < 4; ++i)
            x[i] = v2d{a[i], b[i]};
        flow.lanes(x, f);
        const auto fa = flow(0.0, a), fb = flow(0.0, b);
        for (int i = 0; i < 4; ++i) {
            EXPECT_TRUE(same_bits(f[i][0], fa[i])) << k << " " << i;
            EXPECT_TRUE(same_bits(f[i][1], fb[i])) << k << " " << i;
        }
    }
}

// The energy check's H at the trial step's end, two and four states at a time (the ensemble's last
// stage): per lane the bits of hamiltonian_absolute, including the libm fallback for a huge angle.
TEST(FastTrig, VectorEnergyEqualsTheSingleOne) {
    random_reals rnd(11);
    const pendulum_flow flow(double_pendulum<double>(
        physical_parameters<double>{0.7, 1.3, 0.8, 1.2, 0.5, 0.65, 0.04, 0.09, 1.5}));
    for (int k = 0; k < 1000; ++k) {
        std::array<std::array<double, 4>, 4> y{};
        for (auto& one : y)
            one = {rnd(-7, 7), rnd(-7, 7), rnd(-3, 3), rnd(-3, 3)};
        if (k == 0) y[1][1] = 5e6;
        v4d x4[4], h4{};
        v2d x2[4], h2{};
        for (int i = 0; i < 4; ++i)
            for (int l = 0; l < 4; ++l) {
                x4[i][l] = y[l][i];
                if (l < 2) x2[i][l] = y[l][i];
            }
        flow.hamiltonian_lanes(x4, h4);
        flow.hamiltonian_lanes(x2, h2);
        for (int l = 0; l < 4; ++l) {
            const double h = flow.hamiltonian_absolute(y[l]);
            EXPECT_TRUE(same_bits(h4[l], h)) << k << " " << l;
            if (l < 2) {
                EXPECT_TRUE(same_bits(h2[l], h)) << k << " " << l;
            }
        }
    }
}

// Four states per vector, and the tangent equations two and four at a time: per lane the bits of
// one state at a time, including the libm fallback for a huge angle in one lane.
TEST(FastTrig, VectorTangentAndFourLaneRightHandSidesEqualTheSingleOnes) {
    random_reals rnd(10);
    const pendulum_flow flow(double_pendulum<double>(
        physical_parameters<double>{0.7, 1.3, 0.8, 1.2, 0.5, 0.65, 0.04, 0.09, 1.5}));
    for (int k = 0; k < 1000; ++k) {
        std::array<std::array<double, 8>, 4> y{};
        for (auto& one : y) {
            one = {rnd(-7, 7), rnd(-7, 7), rnd(-3, 3), rnd(-3, 3),
                   rnd(-1, 1), rnd(-1, 1), rnd(-1, 1), rnd(-1, 1)};
        }
        if (k == 0) y[2][0] = -3e6;
        v4d x4[4], f4[4], t4[8], g4[8];
        v2d t2[8], g2[8];
        for (int i = 0; i < 8; ++i)
            for (int l = 0; l < 4; ++l) {
                if (i < 4) x4[i][l] = y[l][i];
                t4[i][l] = y[l][i];
                if (l < 2) t2[i][l] = y[l][i];
            }
        flow.lanes(x4, f4);
        flow.tangent_lanes(t4, g4);
        flow.tangent_lanes(t2, g2);
        for (int l = 0; l < 4; ++l) {
            const auto f = flow(0.0, {y[l][0], y[l][1], y[l][2], y[l][3]});
            const auto g = flow.tangent(y[l]);
            for (int i = 0; i < 8; ++i) {
                if (i < 4) {
                    EXPECT_TRUE(same_bits(f4[i][l], f[i])) << k << " " << l << " " << i;
                }
                EXPECT_TRUE(same_bits(g4[i][l], g[i])) << k << " " << l << " " << i;
                if (l < 2) {
                    EXPECT_TRUE(same_bits(g2[i][l], g[i])) << k << " " << l << " " << i;
                }
            }
        }
    }
}

// The flow's vector forms compiled for the instruction sets the ensemble dispatches to (AVX2,
// AVX-512): the right-hand side, its tangent equations and H of eight states at once, per lane
// the bits of one state at a time. The tests above run the same templates in generic code; here
// the compiler emits the wide instructions (masked blends, 512-bit divisions) the ensemble runs.
// (lanes_and_energy: the right-hand side or its tangent form and H from one set of sines and
// cosines, the last stage's evaluation: the bits of the three apart.)
template <class V>
struct flow_lanes_out {
    V f[4], g[8], h, fe[4], he, ge[8], hg;
};
template <class V>
[[gnu::always_inline]] inline void flow_lanes_at(const pendulum_flow& flow, const V (&t)[8],
                                                 flow_lanes_out<V>& out) {
    flow.lanes(t, out.f);
    flow.tangent_lanes(t, out.g);
    flow.hamiltonian_lanes(t, out.h);
    flow.template lanes_and_energy<4>(t, out.fe, out.he);
    flow.template lanes_and_energy<8>(t, out.ge, out.hg);
}
__attribute__((target("avx512f"), flatten)) void flow_lanes_avx512(const pendulum_flow& flow,
                                                                   const v8d (&t)[8],
                                                                   flow_lanes_out<v8d>& out) {
    flow_lanes_at(flow, t, out);
}
__attribute__((target("avx2"), flatten)) void flow_lanes_avx2(const pendulum_flow& flow,
                                                              const v4d (&t)[8],
                                                              flow_lanes_out<v4d>& out) {
    flow_lanes_at(flow, t, out);
}

TEST(FastTrig, WideInstructionSetsGiveTheBitsOfOneStateAtATime) {
    __builtin_cpu_init();
    const bool avx512 = __builtin_cpu_supports("avx512f") != 0,
               avx2 = __builtin_cpu_supports("avx2") != 0;
    if (!avx2) GTEST_SKIP() << "the processor has neither AVX2 nor AVX-512";
    random_reals rnd(11);
    const pendulum_flow flow(double_pendulum<double>(
        physical_parameters<double>{0.7, 1.3, 0.8, 1.2, 0.5, 0.65, 0.04, 0.09, 1.5}));
    for (int k = 0; k < 1000; ++k) {
        std::array<std::array<double, 8>, 8> y{};
        for (auto& one : y)
            one = {rnd(-7, 7), rnd(-7, 7), rnd(-3, 3), rnd(-3, 3),
                   rnd(-1, 1), rnd(-1, 1), rnd(-1, 1), rnd(-1, 1)};
        if (k == 0) y[5][1] = 4e6;   // the libm fallback in one lane of the eight ...
        if (k == 1) y[2][0] = -4e6;  // ... and of the four
        v8d t8[8];
        v4d t4[8];
        for (int i = 0; i < 8; ++i)
            for (int l = 0; l < 8; ++l) {
                t8[i][l] = y[l][i];
                if (l < 4) t4[i][l] = y[l][i];
            }
        flow_lanes_out<v8d> o8{};
        flow_lanes_out<v4d> o4{};
        if (avx512) flow_lanes_avx512(flow, t8, o8);
        flow_lanes_avx2(flow, t4, o4);
        for (int l = 0; l < 8; ++l) {
            const auto f = flow(0.0, {y[l][0], y[l][1], y[l][2], y[l][3]});
            const auto g = flow.tangent(y[l]);
            const double h = flow.hamiltonian_absolute({y[l][0], y[l][1], y[l][2], y[l][3]});
            // every output of one width against one state at a time: the right-hand side, its
            // tangent form and H, apart and from lanes_and_energy
            auto expect_lane = [&](const auto& o) {
                EXPECT_TRUE(same_bits(o.h[l], h)) << k << " " << l;
                EXPECT_TRUE(same_bits(o.he[l], h)) << k << " " << l;
                EXPECT_TRUE(same_bits(o.hg[l], h)) << k << " " << l;
                for (int i = 0; i < 8; ++i) {
                    if (i < 4) {
                        EXPECT_TRUE(same_bits(o.f[i][l], f[i])) << k << " " << l << " " << i;
                        EXPECT_TRUE(same_bits(o.fe[i][l], f[i])) << k << " " << l << " " << i;
                    }
                    EXPECT_TRUE(same_bits(o.g[i][l], g[i])) << k << " " << l << " " << i;
                    EXPECT_TRUE(same_bits(o.ge[i][l], g[i])) << k << " " << l << " " << i;
                }
            };
            if (avx512) expect_lane(o8);
            if (l < 4) expect_lane(o4);
        }
    }
    if (!avx512) std::cout << "[ NOTE     ] AVX2 checked; the processor has no AVX-512\n";
}

// ---- the command line ------------------------------------------------------------------------

const std::string study =
    "simulate --energy 4.6,5.2 --criteria upright,approx,saddle --trajectories 24 --time 200 "
    "--seed 11 --rtol 1e-9 --no-timing";

json report(const std::string& text) {
    json j = json::parse(text);
    j.erase("model");
    return j;
}

std::size_t trajectory_lines(const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    std::size_t n = 0;
    while (std::getline(in, line))
        n += !line.empty() && (line[0] == 'T' || line[0] == 'E');
    return n;
}

// Starts the CLI in the background (stdout, stderr to /dev/null); returns its pid.
pid_t spawn(const std::string& args) {
    const pid_t pid = fork();
    if (pid == 0) {
        const int null = open("/dev/null", O_WRONLY);
        dup2(null, 1);
        dup2(null, 2);
        execl("/bin/sh", "sh", "-c", ("exec " + std::string(FLIPFLUX_EXE) + " " + args).c_str(),
              static_cast<char*>(nullptr));
        _exit(127);
    }
    return pid;
}

// Waits until the checkpoint holds at least `n` records, or the process ends.
bool wait_for_records(pid_t pid, const fs::path& file, std::size_t n) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
        if (fs::exists(file) && trajectory_lines(file) >= n) return true;
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
}

class CliScale : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        const command_result r = run_flipflux(study + " --threads 2");
        ASSERT_EQ(r.status, 0) << r.err;
        reference_ = new json(report(r.out));
    }
    static void TearDownTestSuite() {
        delete reference_;
        reference_ = nullptr;
    }
    static json* reference_;
};
json* CliScale::reference_ = nullptr;

TEST_F(CliScale, ThreadCountDoesNotChangeABit) {
    const command_result one = run_flipflux(study + " --threads 1");
    ASSERT_EQ(one.status, 0) << one.err;
    EXPECT_EQ(report(one.out), *reference_);
    EXPECT_FALSE(reference_->at("energies").at(0).contains("seconds"));
}

TEST_F(CliScale, KilledAndResumedRunEqualsAnUninterruptedOne) {
    const fs::path file = fs::path(::testing::TempDir()) / "flipflux_killed.ckpt";
    fs::remove(file);
    // one thread, a record after every trajectory: kill it once 4 records are in the file
    const pid_t pid =
        spawn(study + " --threads 1 --checkpoint-interval 0 --checkpoint " + file.string());
    ASSERT_TRUE(wait_for_records(pid, file, 4)) << "the run ended before the checkpoint filled";
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    const std::size_t saved = trajectory_lines(file);
    EXPECT_GE(saved, 4u);
    const command_result resumed =
        run_flipflux(study + " --threads 2 --checkpoint " + file.string());
    ASSERT_EQ(resumed.status, 0) << resumed.err;
    EXPECT_EQ(report(resumed.out), *reference_);
    // a finished run's checkpoint holds only the completed energies; running again reads them
    EXPECT_EQ(trajectory_lines(file), 2u);
    const command_result again = run_flipflux(study + " --checkpoint " + file.string());
    ASSERT_EQ(again.status, 0) << again.err;
    EXPECT_EQ(report(again.out), *reference_);
    fs::remove(file);
}

TEST_F(CliScale, SigtermStopsCleanlyAndTheRunResumes) {
    const fs::path file = fs::path(::testing::TempDir()) / "flipflux_sigterm.ckpt";
    fs::remove(file);
    const pid_t pid =
        spawn(study + " --threads 1 --checkpoint-interval 0 --checkpoint " + file.string());
    ASSERT_TRUE(wait_for_records(pid, file, 2));
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
    const command_result resumed = run_flipflux(study + " --checkpoint " + file.string());
    ASSERT_EQ(resumed.status, 0) << resumed.err;
    EXPECT_EQ(report(resumed.out), *reference_);
    fs::remove(file);
}

// A scene's runs side by side: a fresh folder `tag`, scene files in it writing to dir/NAME.
struct scene_runs {
    fs::path dir;
    explicit scene_runs(const std::string& tag)
        : dir(fs::path(::testing::TempDir()) / (tag + std::to_string(getpid()))) {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~scene_runs() { fs::remove_all(dir); }
    scene_runs(const scene_runs&) = delete;
    scene_runs& operator=(const scene_runs&) = delete;
    /// dir/NAME.toml: the scene NAME with `body` (its tables), output dir/NAME.
    fs::path scene(const std::string& name, const std::string& body) const {
        const fs::path file = dir / (name + ".toml");
        std::ofstream(file) << "[scene]\nname = \"" << name << "\"\noutput = \""
                            << (dir / name).string() << "\"\n"
                            << body;
        return file;
    }
    /// Ensemble ENSEMBLE's result in run NAME less its timing fields.
    json result(const std::string& name, const std::string& ensemble) const {
        json j = json::parse(read_text(dir / name / ("ensemble-" + ensemble + ".json")));
        for (json& e : j.at("energies"))
            for (const char* wall : {"seconds", "cpu_seconds", "threads", "processes"})
                e.erase(wall);
        return j;
    }
    /// Expects ENSEMBLE's per-trajectory CSVs of run `other` to be those of run `whole`, byte for
    /// byte; returns how many there are.
    std::size_t expect_same_csvs(const std::string& whole, const std::string& other,
                                 const std::string& ensemble) const {
        std::size_t csvs = 0;
        const fs::path folder = "ensemble-" + ensemble;
        for (const fs::directory_entry& f : fs::directory_iterator(dir / whole / folder)) {
            EXPECT_EQ(read_text(dir / other / folder / f.path().filename()), read_text(f.path()))
                << f.path();
            ++csvs;
        }
        return csvs;
    }
};

// A scene's ensembles checkpoint too (<output>/ensemble-NAME.checkpoint): `flipflux run` killed
// in the middle of an ensemble and run again resumes it, and writes every bit an uninterrupted run
// writes (the result less its wall-clock fields, and every per-trajectory CSV).
TEST(CliScene, KilledRunResumesItsEnsembleFromTheCheckpoint) {
    const scene_runs runs("flipflux_scene_kill_");
    const fs::path& dir = runs.dir;
    const std::string body =
        "[[ensemble]]\nname = \"k\"\ncriteria = [\"upright\", \"approx\"]\n"
        "energies = [4.6, 5.2]\ntrajectories = 24\ntime = 1000\nseed = 7\nrtol = 1e-9\n";
    const fs::path whole = runs.scene("whole", body), killed = runs.scene("killed", body);
    const command_result reference = run_flipflux("run --no-cache --threads 2 " + whole.string());
    ASSERT_EQ(reference.status, 0) << reference.err;

    const fs::path checkpoint = dir / "killed" / "ensemble-k.checkpoint";
    const pid_t pid =
        spawn("run --no-cache --threads 1 --checkpoint-interval 0 " + killed.string());
    ASSERT_TRUE(wait_for_records(pid, checkpoint, 4))
        << "the run ended before the checkpoint filled";
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    const std::size_t saved = trajectory_lines(checkpoint);
    EXPECT_GE(saved, 4u);
    EXPECT_LT(saved, 48u);
    const command_result resumed = run_flipflux("run --no-cache --threads 2 " + killed.string());
    ASSERT_EQ(resumed.status, 0) << resumed.err;
    EXPECT_FALSE(fs::exists(checkpoint)) << "a complete ensemble's checkpoint is removed";

    EXPECT_EQ(runs.result("killed", "k"), runs.result("whole", "k"));
    EXPECT_GE(runs.expect_same_csvs("whole", "killed", "k"), 2u);
    EXPECT_EQ(run_flipflux("run --checkpoint-interval -1 " + whole.string()).status, 2);
}

// `flipflux run --max-seconds B`: a scene whose run takes about four times B (its run is 0.07 CPU
// seconds in a release build) stops at the bound (status 2, one line naming --max-seconds and
// saying how to resume), keeping its finished trajectories and finished ensemble steps; the same
// command, repeated, completes the run, and its files are an unbounded run's, bit for bit (the
// results less their timing fields, every per-trajectory CSV and the predictions). No checkpoint
// is left behind. A negative bound is refused. (And --progress shows each ensemble step's bar.)
TEST(CliScene, ARunStoppedAtItsCpuBoundResumesToTheSameFiles) {
    const scene_runs runs("flipflux_scene_bound_");
    const fs::path& dir = runs.dir;
    const std::string body =
        "[predictions]\nquantities = [\"rate-upright\"]\narms = [2]\nenergies = [4.6]\n"
        "[[ensemble]]\nname = \"a\"\ncriteria = [\"upright\", \"approx\"]\n"
        "energies = [4.6, 5.2]\ntrajectories = 50\ntime = 200\nseed = 7\nchaos = false\n"
        "[[ensemble]]\nname = \"b\"\narm = 1\ncriteria = [\"upright\"]\n"
        "energies = [5.6]\ntrajectories = 50\ntime = 200\nseed = 8\nchaos = false\n";
    const fs::path whole = runs.scene("whole", body), bounded = runs.scene("bounded", body);
    const command_result reference =
        run_flipflux("run --no-cache --threads 1 --progress " + whole.string());
    ASSERT_EQ(reference.status, 0) << reference.err;
    // --progress into a pipe: each ensemble step's bar, its last line complete
    for (const char* done : {"] 100/100 trajectories, ensemble a, energy 2/2, ",
                             "] 50/50 trajectories, ensemble b, energy 1/1, "})
        EXPECT_NE(reference.err.find(done), std::string::npos) << reference.err;
    const double cpu = json::parse(read_text(dir / "whole" / "run.json")).at("cpu_seconds");
    const double bound = std::max(0.02, cpu / 4);
    const std::string command =
        "run --no-cache --threads 1 --checkpoint-interval 0 --max-seconds " +
        std::to_string(bound) + " " + bounded.string();
    int stops = 0;
    for (;;) {
        const command_result r = run_flipflux(command);
        if (r.status == 0) break;
        ASSERT_EQ(r.status, 2) << r.err;
        EXPECT_EQ(r.err.find("flipflux: error: --max-seconds: stopped at its bound of "), 0u)
            << r.err;
        EXPECT_NE(r.err.find("; rerun the same command to resume\n"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        ASSERT_LT(++stops, 40) << "the run makes no progress at its bound";
    }
    EXPECT_GE(stops, 1) << "a run of " << cpu << " CPU seconds was not stopped at " << bound;
    for (const fs::directory_entry& f : fs::directory_iterator(dir / "bounded"))
        EXPECT_NE(f.path().extension(), ".checkpoint") << f.path();
    for (const char* ensemble : {"a", "b"})
        EXPECT_EQ(runs.result("bounded", ensemble), runs.result("whole", ensemble)) << ensemble;
    EXPECT_EQ(read_text(dir / "bounded" / "predictions.csv"),
              read_text(dir / "whole" / "predictions.csv"));
    EXPECT_GE(runs.expect_same_csvs("whole", "bounded", "a") +
                  runs.expect_same_csvs("whole", "bounded", "b"),
              3u);
    const command_result negative = run_flipflux("run --max-seconds -1 " + whole.string());
    EXPECT_EQ(negative.status, 2);
    EXPECT_NE(negative.err.find("--max-seconds: '-1' is invalid"), std::string::npos)
        << negative.err;
}

// The bound, and a signal, stop a step that runs on the calling thread where it is, not at its
// end: Ω at mp:600 takes about 12 CPU seconds per energy (this project's machine), and a run
// bounded at 1 stops inside its predictions step, saying so, with no predictions.csv (nothing
// half-written); so does a long trajectory, and SIGINT in the predictions.
TEST(CliScene, ARunsBoundStopsALongPredictionStepInsideIt) {
    const scene_runs runs("flipflux_scene_step_bound_");
    // scene NAME with BODY, run with a bound of 1 CPU second
    auto bounded = [&runs](const std::string& name, const std::string& body) {
        return run_flipflux("run --no-cache --max-seconds 1 " + runs.scene(name, body).string());
    };
    const fs::path file = runs.dir / "slow.toml";
    const command_result r = bounded("slow",
                                     "precision = \"mp:600\"\n[predictions]\nquantities = "
                                     "[\"omega\"]\nenergies = [4.6, 5.2]\n");
    ASSERT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err.find("flipflux: error: --max-seconds: stopped at its bound of 1 CPU seconds "
                         "in step 1 of "),
              0u)
        << r.err;
    EXPECT_NE(r.err.find("): its work so far is not kept; rerun with a larger --max-seconds to "
                         "finish it\n"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(runs.dir / "slow" / "predictions.csv"));
    EXPECT_FALSE(fs::exists(runs.dir / "slow" / "run.json"));
    // a trajectory at double (DOP853's lone lane) of 1e6 time units (about 11 million steps, tens
    // of CPU seconds): stopped inside its step too, no CSV
    const command_result t =
        bounded("long",
                "[[trajectory]]\nname = \"t\"\nstate = [1.4, 2.2, 0.2, 0.8]\ntime = 1e6\n"
                "sample_interval = 0\ncriteria = [\"upright\"]\narms = [2]\n");
    ASSERT_EQ(t.status, 2) << t.err;
    EXPECT_NE(t.err.find("in step 1 of 1 (trajectory 't'"), std::string::npos) << t.err;
    EXPECT_NE(t.err.find("): its work so far is not kept"), std::string::npos) << t.err;
    EXPECT_FALSE(fs::exists(runs.dir / "long" / "trajectory-t.csv"));
    // SIGINT in the predictions step (no bound): the run stops there too, status 128 + SIGINT,
    // rather than after the step (which, the scene's last, would end the run normally)
    const fs::path err = runs.dir / "sigint.err";
    const pid_t pid = spawn("run --no-cache " + file.string() + " 2> " + err.string());
    // inside the step: 1.5 CPU seconds used (start-up takes well under 1, the step about 24)
    auto cpu_of = [](pid_t p) {
        std::ifstream stat("/proc/" + std::to_string(p) + "/stat");
        const std::string text((std::istreambuf_iterator<char>(stat)),
                               std::istreambuf_iterator<char>());
        std::istringstream fields(text.substr(text.rfind(')') + 2));  // after "pid (comm) "
        std::string f;
        double ticks = 0;
        for (int i = 3; i <= 15 && fields >> f; ++i)
            if (i >= 14) ticks += std::stod(f);  // utime, stime
        return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int status = 0;
    bool ended = false;  // early, e.g. refused
    while (std::chrono::steady_clock::now() < deadline && cpu_of(pid) < 1.5)
        if ((ended = waitpid(pid, &status, WNOHANG) == pid))
            break;
        else
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_FALSE(ended) << read_text(err);
    kill(pid, SIGINT);
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
    const std::string said = read_text(err);
    EXPECT_EQ(said.find("flipflux: interrupted in step 1 of 1 (predictions omega"), 0u) << said;
    EXPECT_NE(said.find("): its work so far is not kept; rerun the same command to resume\n"),
              std::string::npos)
        << said;
    EXPECT_FALSE(fs::exists(runs.dir / "slow" / "predictions.csv"));
}

TEST_F(CliScale, MismatchedOrUnreadableCheckpointsAreRefused) {
    const fs::path file = fs::path(::testing::TempDir()) / "flipflux_mismatch.ckpt";
    fs::remove(file);
    const std::string small = "simulate --no-chaos --checkpoint " + file.string();
    const std::string same = " --criteria upright --trajectories 2 --time 5";
    ASSERT_EQ(run_flipflux(small + same + " --seed 1 --energy 5").status, 0);
    for (const auto& [args, field] : std::vector<std::pair<std::string, std::string>>{
             {" --seed 2 --energy 5", "seed"},
             {" --seed 1 --energy 5.1", "energies"},
             {" --seed 1 --energy 5 --rtol 1e-8", "rtol"},
             {" --seed 1 --energy 5 --arm 1", "arm"},
             {" --seed 1 --energy 5 --m2 2", "model"},
             {" --seed 1 --energy 5 --criteria approx --trajectories 2 --time 5", "criteria"},
             {" --seed 1 --energy 5 --criteria upright --trajectories 2 --time 6", "time"},
             {" --seed 1 --energy 5 --criteria upright --trajectories 3 --time 5", "trajectories"},
             {" --seed 1 --energy 5 --method dopri5", "method"}}) {
        const command_result r =
            run_flipflux(small + args + (args.find("--time") == std::string::npos ? same : ""));
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_NE(r.err.find("its " + field + " is"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    { std::ofstream(file) << "not a checkpoint\n"; }
    const command_result bad = run_flipflux(small + same + " --seed 1 --energy 5");
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("--checkpoint"), std::string::npos) << bad.err;
    fs::remove(file);
    const command_result dir = run_flipflux(small + same + " --seed 1 --energy 5 --checkpoint " +
                                            fs::path(::testing::TempDir()).string());
    EXPECT_EQ(dir.status, 2) << dir.err;
    EXPECT_EQ(run_flipflux(small + same + " --seed 1 --energy 5 --checkpoint-interval -1").status,
              2);
    EXPECT_EQ(run_flipflux(small + same + " --seed 1 --energy 5 --estimator medium").status, 2);
    EXPECT_EQ(run_flipflux(small + same + " --seed 1 --energy 5 --sample-interval 1 --csv-dir " +
                           fs::path(::testing::TempDir()).string())
                  .status,
              2);
    fs::remove(file);
}

TEST_F(CliScale, ProgressBarReportsDoneTotalRateAndEta) {
    const command_result r = run_flipflux(
        "simulate --energy 5 --criteria upright --trajectories 3 --time 5 --no-chaos --progress");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("3/3 trajectories"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("ETA"), std::string::npos) << r.err;
}

TEST_F(CliScale, MpirunGivesTheSameReport) {
    if (std::system("command -v mpirun >/dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
    // OpenMPI in a container as root: allow it, no ssh/rsh launcher, no CMA single copy; no
    // LeakSanitizer in the ASan build (OpenMPI itself leaks)
    const std::string env =
        "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "OMPI_MCA_plm=isolated "
        "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1 ";
    const std::string cmd = env + "mpirun --oversubscribe -np 2 " + std::string(FLIPFLUX_EXE) +
                            " " + study + " --threads 1 2>/dev/null";
    FILE* pipe = popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string out;
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0)
        out.append(buf, n);
    const int status = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
    EXPECT_EQ(report(out), *reference_);
}

// `mpirun -np 2 flipflux run SCENE` against one process with two threads: every file the scene
// writes is byte-identical except the timing fields (seconds, cpu_seconds, threads, processes
// and run.json's step clocks); the ensembles include the saddle criterion (its orbit curve built
// on both ranks) and a Taylor ensemble chosen by `auto`.
TEST(CliScaleRun, MpirunRunsASceneAsOneProcessDoes) {
    if (std::system("command -v mpirun >/dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
    const fs::path dir =
        fs::temp_directory_path() / ("flipflux-mpi-run-" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string body = R"(
precision = "double"
[predictions]
quantities = ["omega", "rate-upright", "rate-saddle"]
arms = [2]
energies = [3.5, 5.3]
[orbits]
arms = [2]
energies = { from = 2.1, to = 5.7, step = 0.4 }
curve_samples = 33
[[ensemble]]
name = "arm2"
arm = 2
criteria = ["upright", "approx", "saddle"]
energies = [3.5, 5.3]
trajectories = 12
replicates = 3
time = 100
seed = 1
chaos = true
[[ensemble]]
name = "tay"
arm = 1
criteria = ["upright"]
energies = [5.3]
trajectories = 9
time = 100
seed = 4
rtol = "1e-13"
integrator = "auto"
)";
    for (const char* name : {"one", "two"}) {
        std::ofstream(dir / (std::string(name) + ".toml"))
            << "[scene]\nname = \"mpi-run\"\noutput = \"" << (dir / name).string() << "\"\n"
            << body;
    }
    const std::string env =
        "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "OMPI_MCA_plm=isolated "
        "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1 ";
    const std::string exe = FLIPFLUX_EXE;
    ASSERT_EQ(std::system((exe + " run " + (dir / "one.toml").string() +
                           " --threads 2 --no-cache >/dev/null 2>&1")
                              .c_str()),
              0);
    ASSERT_EQ(std::system((env + "mpirun --oversubscribe -np 2 " + exe + " run " +
                           (dir / "two.toml").string() + " --threads 1 --no-cache >/dev/null 2>&1")
                              .c_str()),
              0);
    auto read_file = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    // timing fields and the two runs' own paths out; the rest compared as text
    auto strip = [](const fs::path& p) {
        std::ifstream in(p);
        std::string line, out;
        while (std::getline(in, line))
            if (line.find("seconds\"") == std::string::npos &&
                line.find("\"threads\"") == std::string::npos &&
                line.find("\"processes\"") == std::string::npos &&
                line.find("\"scene_file\"") == std::string::npos &&
                line.find("\"csv_dir\"") == std::string::npos &&
                line.find("/one") == std::string::npos)
                out += line + "\n";
        return out;
    };
    int files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir / "one")) {
        if (!e.is_regular_file()) continue;
        const fs::path rel = fs::relative(e.path(), dir / "one");
        SCOPED_TRACE(rel.string());
        ASSERT_TRUE(fs::exists(dir / "two" / rel));
        if (rel.extension() == ".json")
            EXPECT_EQ(strip(e.path()), strip(dir / "two" / rel));
        else
            EXPECT_EQ(read_file(e.path()), read_file(dir / "two" / rel));
        ++files;
    }
    EXPECT_GT(files, 15);
    const std::string tay = read_file(dir / "two" / "ensemble-tay.json");
    EXPECT_NE(tay.find("\"method\": \"taylor\""), std::string::npos);
    EXPECT_NE(tay.find("\"processes\": 2"), std::string::npos);
    fs::remove_all(dir);
}

// The short estimator spends the budget on trajectories of --short-time: count and an exact
// check of the mean rate against the prediction (the invariant ensemble's crossing count is exact
// for any T).
TEST(ShortEstimator, SpendsTheBudgetOnShortTrajectories) {
    const double_pendulum<double> m;
    simulation_request q;
    q.criteria = {"upright"};
    q.energies = {{"5", 5.0}};
    q.options.trajectories = 4;
    q.options.time = 1000;
    q.options.seed = 3;
    q.options.rtol = 1e-8;
    q.options.chaos = false;
    q.estimator = rate_estimator::short_trajectories;
    q.short_time = 3;  // 4000 / 3 -> 1334 trajectories
    const json j = study_json(*simulate(m, q));
    EXPECT_EQ(j.at("trajectories").get<std::uint64_t>(), 1334u);
    EXPECT_EQ(j.at("time").get<std::string>(), "3");
    EXPECT_EQ(j.at("estimator"), "short");
    const json& c = j.at("energies").at(0).at("criteria").at("upright");
    const double z = std::stod(c.at("z_score").get<std::string>());
    EXPECT_LT(std::abs(z), 4) << c.dump();
    q.short_time = 0;
    EXPECT_THROW(simulate(m, q), input_error);
    EXPECT_EQ(to_string(rate_estimator::long_trajectories), "long");
    EXPECT_EQ(parse_name<rate_estimator>("short", "estimator"), rate_estimator::short_trajectories);
    EXPECT_THROW(parse_name<rate_estimator>("x", "estimator"), input_error);
}

// Both arms' studies from one set of trajectories (study/simulation.hpp): at E = 5 (above both
// saddle energies) each trajectory is integrated once and counts the flips of both arms; each
// study's report is identical, bit for bit, to the one a separate run of it gives (the
// trajectories depend on (seed, E, index) only), and both pass the exact check of the mean rate
// against the prediction (the invariant ensemble's crossing count is exact for any T). An arm-1
// energy below arm 2's list is run for arm 1 alone. Then the shared run's checkpoint: stopped
// after 100 trajectories and resumed, the reports are the same again; a single study refuses it.
TEST(SharedStudies, BothArmsFromOneEnsembleEqualSeparateRuns) {
    const double_pendulum<double> m;
    simulation_request arm2;
    arm2.criteria = {"upright", "approx"};
    arm2.energies = {{"5", 5.0}};
    arm2.options.trajectories = 4;
    arm2.options.time = 150;
    arm2.options.seed = 3;
    arm2.options.rtol = 1e-8;
    arm2.options.chaos = false;
    arm2.options.threads = 2;
    arm2.estimator = rate_estimator::short_trajectories;
    arm2.short_time = 3;  // 200 trajectories of T = 3
    arm2.timing = false;
    simulation_request arm1 = arm2;
    arm1.flip_arm = arm::one;
    arm1.criteria = {"approx", "upright"};
    arm1.energies = {{"4.5", 4.5}, {"5.0", 5.0}};
    std::uint64_t integrated = 0;
    std::vector<simulation_request> both{arm2, arm1};
    both[0].progress = [&](const simulation_progress& p) {
        integrated = p.done;
        EXPECT_EQ(p.total, 2 * 200u);  // two energies in all, not three
    };
    const std::vector<study_result> shared = *simulate(m, both);
    EXPECT_EQ(integrated, 2 * 200u);
    ASSERT_EQ(shared.size(), 2u);
    const json j2 = study_json(shared[0]), j1 = study_json(shared[1]);
    EXPECT_EQ(j2, study_json(*simulate(m, arm2)));
    EXPECT_EQ(j1, study_json(*simulate(m, arm1)));
    EXPECT_EQ(j1.at("arm"), "1");
    EXPECT_EQ(j1.at("energies").at(1).at("energy"), "5.0");  // its own label
    for (const json* j : {&j2, &j1})
        for (const json& e : j->at("energies"))
            for (const auto& [name, c] : e.at("criteria").items()) {
                const double z = std::stod(c.at("z_score").get<std::string>());
                EXPECT_LT(std::abs(z), 4) << name << " " << c.dump();
                EXPECT_GT(c.at("flips").get<std::uint64_t>(), 5u) << name;
            }

    const fs::path file = fs::path(::testing::TempDir()) / "flipflux_shared.ckpt";
    fs::remove(file);
    std::atomic<int> stop{0};
    for (simulation_request& q : both) {
        q.checkpoint = file;
        q.checkpoint_interval = 0;
        q.options.stop = &stop;
    }
    both[0].progress = [&](const simulation_progress& p) {
        if (p.done >= 100) stop = SIGTERM;
    };
    EXPECT_THROW(simulate(m, both), simulation_interrupted);
    stop = 0;
    both[0].progress = nullptr;
    const std::vector<study_result> resumed = *simulate(m, both);
    EXPECT_EQ(study_json(resumed[0]), j2);
    EXPECT_EQ(study_json(resumed[1]), j1);
    const std::vector<study_result> again = *simulate(m, both);  // from the E records
    EXPECT_EQ(study_json(again[0]), j2);
    EXPECT_EQ(study_json(again[1]), j1);
    simulation_request alone = arm2;
    alone.checkpoint = file;
    try {
        simulate(m, alone);
        ADD_FAILURE() << "a single study read the shared studies' checkpoint";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("its arm is [\"2\",\"1\"]"), std::string::npos)
            << e.what();
    }
    fs::remove(file);
    both[1].options.seed = 4;  // other trajectories: not shareable
    EXPECT_THROW(simulate(m, both), std::invalid_argument);
}

// Studies that differ only in the chaos threshold (the paper scenes' threshold studies) share
// their trajectories: the threshold classifies them and changes none. Each study's report, its
// chaotic sub-ensemble included, equals a separate run's bit for bit; the thresholds are chosen
// so that the classifications differ. Stopped in an energy and resumed, the reports are the same
// again. The shared checkpoint records every study's threshold.
TEST(SharedStudies, ChaosThresholdsClassifyOneSetOfTrajectories) {
    const double_pendulum<double> m;
    simulation_request low;
    low.criteria = {"upright"};
    low.energies = {{"3", 3.0}, {"5", 5.0}};
    low.options.trajectories = 6;
    low.options.time = 120;
    low.options.seed = 5;
    low.options.rtol = 1e-8;
    low.options.chaos = true;
    low.options.chaos_threshold = 0.02;
    low.options.threads = 2;
    low.timing = false;
    simulation_request high = low;
    high.energies = {{"5", 5.0}};
    high.options.chaos_threshold = 0.5;  // lambda_T at E = 5, T = 120: 0.43 ... 0.54
    std::uint64_t integrated = 0;
    std::vector<simulation_request> both{low, high};
    both[0].progress = [&](const simulation_progress& p) { integrated = p.done; };
    const std::vector<study_result> shared = *simulate(m, both);
    EXPECT_EQ(integrated, 2 * 6u);  // E = 5 integrated once
    ASSERT_EQ(shared.size(), 2u);
    const json jl = study_json(shared[0]), jh = study_json(shared[1]);
    EXPECT_EQ(jl, study_json(*simulate(m, low)));
    EXPECT_EQ(jh, study_json(*simulate(m, high)));
    const auto chaotic_at_5 = [](const study_result& r) {
        return r.energies.back().criteria.front().statistics.chaotic;
    };
    EXPECT_GT(chaotic_at_5(shared[0]), chaotic_at_5(shared[1]))
        << "the thresholds classify E = 5's trajectories alike: the test shows nothing";

    const fs::path file = fs::path(::testing::TempDir()) / "flipflux_thresholds.ckpt";
    fs::remove(file);
    for (simulation_request& q : both) {
        q.checkpoint = file;
        q.checkpoint_interval = 0;
    }
    // stopped in E = 5, after 3 of its 6 trajectories: their records, classified with the run's
    // threshold, are classified again by each study when resumed
    std::atomic<int> stop{0};
    for (simulation_request& q : both)
        q.options.stop = &stop;
    both[0].progress = [&](const simulation_progress& p) {
        if (p.done >= 6 + 3) stop = SIGTERM;
    };
    try {
        simulate(m, both);
        ADD_FAILURE() << "not interrupted";
    } catch (const simulation_interrupted& e) {
        EXPECT_GE(e.saved(), 3u);  // of E = 5's trajectories: the energy is incomplete
        EXPECT_LT(e.saved(), 6u);
    }
    stop = 0;
    both[0].progress = nullptr;
    const std::vector<study_result> resumed = *simulate(m, both);
    EXPECT_EQ(study_json(resumed[0]), jl);
    EXPECT_EQ(study_json(resumed[1]), jh);
    EXPECT_EQ(study_json((*simulate(m, both))[1]), jh);  // from the checkpoint's E records
    both[1].options.chaos_threshold = 0.4;  // another classification: the checkpoint is refused
    try {
        simulate(m, both);
        ADD_FAILURE() << "a checkpoint of other thresholds was resumed";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("chaos_threshold"), std::string::npos) << e.what();
    }
    fs::remove(file);
}

// A small upright study on one thread, for the interruption tests: no chaos indicator, no timing.
simulation_request small_study(std::vector<std::pair<std::string, double>> energies,
                               std::uint64_t trajectories, double time, std::uint64_t seed) {
    simulation_request q;
    q.criteria = {"upright"};
    q.energies = std::move(energies);
    q.options.trajectories = trajectories;
    q.options.time = time;
    q.options.seed = seed;
    q.options.chaos = false;
    q.options.threads = 1;
    q.timing = false;
    return q;
}

// max_seconds bounds the integration's CPU time: a study of 0.5 CPU seconds or more given 0.1 stops
// near it (by the process's CPU clock, measured here independently), says so, and keeps its
// finished trajectories in the checkpoint; rerun without the bound it resumes and its report is
// the unbounded run's, bit for bit. Without a checkpoint (and without a stop flag of the
// caller's) it stops alike. A bound the run does not reach changes nothing.
// The study's size follows the build's speed: it starts at 20 trajectories per energy and, while
// it costs less than 0.3 CPU seconds (three times the bound), grows to an estimated 0.6 (1000 or
// so in the release build; CI's instrumented build stays at 20, about 0.7 s, where 1000 took 35 s).
TEST(Interruption, TheCpuBoundStopsTheStudyAndTheRerunResumes) {
    const double_pendulum<double> m;
    const fs::path file =
        fs::path(::testing::TempDir()) / ("flipflux_bound_" + std::to_string(getpid()) + ".ckpt");
    fs::remove(file);
    simulation_request q = small_study({{"4", 4.0}, {"5", 5.0}}, 20, 100, 3);
    json full;
    double cost = 0;
    for (int attempt = 0; attempt < 5; ++attempt) {
        const double c0 = process_cpu_seconds();
        full = study_json(*simulate(m, q));
        cost = process_cpu_seconds() - c0;
        if (cost >= 0.3) break;
        const std::uint64_t n = q.options.trajectories;
        const double scaled = std::ceil(static_cast<double>(n) * 0.6 / std::max(cost, 1e-3));
        q.options.trajectories = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(scaled),
                                                           2 * n, std::uint64_t{100000});
    }
    ASSERT_GE(cost, 0.3) << q.options.trajectories << " trajectories";
    q.checkpoint = file;
    q.checkpoint_interval = 0;
    q.max_seconds = 0.1;
    const double c0 = process_cpu_seconds();
    try {
        simulate(m, q);
        ADD_FAILURE() << "not stopped at the bound";
    } catch (const simulation_interrupted& e) {
        const double used = process_cpu_seconds() - c0;
        EXPECT_EQ(e.signal(), cpu_bound_stop);
        EXPECT_GE(used, 0.1);
        EXPECT_LT(used, 0.6);  // the bound, the watch's 10 ms and one step of each lane
        EXPECT_NE(std::string(e.what()).find("stopped at its bound of 0.1 CPU seconds: "),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("rerun the same command to resume"), std::string::npos)
            << e.what();
    }
    q.max_seconds = 0;
    EXPECT_EQ(study_json(*simulate(m, q)), full);
    fs::remove(file);
    // no checkpoint, no stop flag of the caller's: the study's own flag
    simulation_request bare = small_study({{"5", 5.0}}, 1000, 100, 3);
    bare.max_seconds = 0.05;
    try {
        simulate(m, bare);
        ADD_FAILURE() << "not stopped at the bound";
    } catch (const simulation_interrupted& e) {
        EXPECT_EQ(e.signal(), cpu_bound_stop);
        EXPECT_NE(std::string(e.what()).find("without a checkpoint"), std::string::npos)
            << e.what();
    }
    bare.max_seconds = 1e6;
    bare.energies = {{"4", 4.0}};
    bare.options.trajectories = 8;
    simulation_request plain = bare;
    plain.max_seconds = 0;
    EXPECT_EQ(study_json(*simulate(m, bare)), study_json(*simulate(m, plain)));
    bare.max_seconds = -1;
    try {
        simulate(m, bare);
        ADD_FAILURE() << "a negative bound was accepted";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("max_seconds: '-1' is invalid"), std::string::npos)
            << e.what();
    }
}

// A record's hash covers the record, not the run: trajectory records spliced in from a run with
// another seed passed before (an independent audit: the rerun exited 0 with changed statistics).
// Their initial states are not this run's samples, so the resumption is refused naming the file.
TEST(Interruption, CheckpointRecordsOfAnotherRunAreRefused) {
    const double_pendulum<double> m;
    const fs::path dir =
        fs::path(::testing::TempDir()) / ("flipflux_splice_" + std::to_string(getpid()));
    fs::create_directories(dir);
    auto interrupted = [&](std::uint64_t seed, const fs::path& file) {
        simulation_request q = small_study({{"5", 5.0}}, 40, 20, seed);
        q.checkpoint = file;
        q.checkpoint_interval = 0;
        std::atomic<int> stop{0};
        q.options.stop = &stop;
        q.progress = [&](const simulation_progress& p) {
            if (p.done >= 10) stop = SIGTERM;
        };
        EXPECT_THROW(simulate(m, q), simulation_interrupted);
        q.options.stop = nullptr;
        q.progress = nullptr;
        return q;
    };
    const simulation_request mine = interrupted(7, dir / "seed7.ckpt");
    (void)interrupted(8, dir / "seed8.ckpt");
    auto lines = [](const fs::path& f) {
        std::ifstream in(f);
        std::vector<std::string> out;
        for (std::string l; std::getline(in, l);)
            out.push_back(l);
        return out;
    };
    const std::vector<std::string> a = lines(dir / "seed7.ckpt"), b = lines(dir / "seed8.ckpt");
    ASSERT_GE(a.size(), 2u);
    ASSERT_GE(b.size(), 2u);
    // seed 7's header, seed 8's trajectory records
    std::ofstream(dir / "seed7.ckpt") << [&] {
        std::string text = a[0] + "\n";
        for (std::size_t i = 1; i < b.size(); ++i)
            if (b[i].rfind("T ", 0) == 0) text += b[i] + "\n";
        return text;
    }();
    try {
        simulate(m, mine);
        ADD_FAILURE() << "records of seed 8 were used in a run of seed 7";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("is not this run's"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("seed7.ckpt"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

// A complete energy's checkpoint record holds its statistics, not its per-trajectory CSVs: when
// they are gone before the rerun (a CSV folder deleted), the energy is integrated again. Before,
// the rerun exited 0 without them (an independent audit).
TEST(Interruption, ACompleteEnergyWhoseFilesAreGoneIsIntegratedAgain) {
    const double_pendulum<double> m;
    const fs::path dir =
        fs::path(::testing::TempDir()) / ("flipflux_gone_" + std::to_string(getpid()));
    fs::remove_all(dir);
    simulation_request q = small_study({{"4.5", 4.5}, {"5", 5.0}}, 12, 10, 5);
    q.csv_dir = dir / "whole";
    const json whole = study_json(*simulate(m, q));
    const std::string first = read_text(dir / "whole" / "trajectories_E4.5.csv");
    q.csv_dir = dir / "csv";
    q.checkpoint = dir / "run.ckpt";
    q.checkpoint_interval = 0;
    std::atomic<int> stop{0};
    q.options.stop = &stop;
    q.progress = [&](const simulation_progress& p) {
        if (p.done >= 12 + 2) stop = SIGTERM;  // E = 4.5 complete, E = 5 begun
    };
    EXPECT_THROW(simulate(m, q), simulation_interrupted);
    ASSERT_TRUE(fs::exists(dir / "csv" / "trajectories_E4.5.csv"));
    fs::remove_all(dir / "csv");
    q.options.stop = nullptr;
    std::uint64_t integrated = 0;
    q.progress = [&](const simulation_progress& p) { integrated = p.done - p.resumed; };
    EXPECT_EQ(study_json(*simulate(m, q)), whole);
    EXPECT_EQ(read_text(dir / "csv" / "trajectories_E4.5.csv"), first);
    EXPECT_GE(integrated, 12u + 1);  // E = 4.5 again, and what E = 5 still needed
    fs::remove_all(dir);
}

// A stop request before the run: nothing is integrated, simulate() reports the interruption.
TEST(Interruption, StopFlagEndsTheStudy) {
    const double_pendulum<double> m;
    simulation_request q;
    q.criteria = {"upright"};
    q.energies = {{"5", 5.0}};
    q.options.trajectories = 3;
    q.options.time = 5;
    q.options.chaos = false;
    std::atomic<int> stop{SIGINT};
    q.options.stop = &stop;
    try {
        simulate(m, q);
        ADD_FAILURE() << "not interrupted";
    } catch (const simulation_interrupted& e) {
        EXPECT_EQ(e.signal(), SIGINT);
        EXPECT_EQ(e.saved(), 0u);
    }
    ensemble_options o = q.options;
    o.energy = 5;
    EXPECT_THROW(run_ensemble(m, o, {}), std::runtime_error);
}

}  // namespace
}  // namespace flipflux::test
