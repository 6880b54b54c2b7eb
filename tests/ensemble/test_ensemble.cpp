// The ensemble runner (ensemble/ensemble.hpp): results independent of the thread count and of
// how the index range is split; the chaos indicator leaves the trajectories untouched; option
// validation; energy drift scales with the tolerance; the finite-time Lyapunov exponent against
// Benettin's two-trajectory estimate and on a regular and a chaotic trajectory.
#include <cmath>
#include <cstdlib>
#include <string>

#include "ensemble_support.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/ensemble.hpp"

namespace flipflux::test {
namespace {

std::vector<ensemble_criterion> arm2_criteria(const double_pendulum<double>& m) {
    const pendulum_flow flow(m);
    return {{"upright", make_flip_detector(upright_curve<double>{arm::two}, flow)},
            {"approx", make_flip_detector(approximate_saddle_curve(m, arm::two), flow)}};
}

ensemble_options small_run(int threads) {
    ensemble_options o;
    o.energy = 5;
    o.trajectories = 24;
    o.time = 30;
    o.seed = 2024;
    o.rtol = 1e-9;
    o.threads = threads;
    return o;
}

void expect_identical(const trajectory_result& a, const trajectory_result& b) {
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.initial_state, b.initial_state);
    EXPECT_EQ(a.crossing_times, b.crossing_times);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.max_energy_drift, b.max_energy_drift);
    EXPECT_TRUE(a.lyapunov == b.lyapunov || (std::isnan(a.lyapunov) && std::isnan(b.lyapunov)));
}

// Within a thread, trajectories advance in lockstep lanes whose right-hand sides are evaluated
// together in vectors: with each instruction set the processor has (ensemble.hpp, vector_isa:
// sixteen lanes per thread in two groups of AVX-512 vectors, then AVX2 and SSE2 ones as lanes
// finish; eight lanes in two groups of AVX2 vectors; four lanes in SSE2 vectors, two per vector),
// every trajectory must have the bits
// of the same trajectory integrated alone (one lane), with and without the tangent equations, for
// DOP853 and DOPRI5. (That each lane's arithmetic is the scalar integrator's: ExplicitRk.
// VectorLanesHaveTheBitsOfTheDoubleStagesAndErrorSums.)
TEST(Ensemble, LockstepLanesGiveTheBitsOfALoneTrajectory) {
    const double_pendulum<double> m;
    const auto criteria = arm2_criteria(m);
    struct restore {
        ~restore() { set_ensemble_vector_isa(vector_isa::automatic); }
    } restore_isa;
    for (const vector_isa isa : {vector_isa::sse2, vector_isa::avx2, vector_isa::avx512}) {
        if (!processor_supports(isa)) continue;
        set_ensemble_vector_isa(isa);
        ASSERT_EQ(ensemble_vector_isa(), isa);
        for (const integration_method method :
             {integration_method::dop853, integration_method::dopri5, integration_method::taylor})
            for (bool chaos : {false, true}) {
                ensemble_options o = small_run(1);
                // 16 (8, 4) lanes in two groups, refilled, then the last ones: every vector
                // width, one and two groups, padded groups
                o.trajectories = 19;
                o.chaos = chaos;
                o.method = method;
                const ensemble_result lanes = run_ensemble(m, o, criteria);
                const microcanonical_sampler sampler(m, o.energy);
                for (std::uint64_t i = 0; i < o.trajectories; ++i) {
                    std::vector<std::unique_ptr<flip_detector_base>> own;
                    std::vector<flip_detector_base*> raw;
                    for (const ensemble_criterion& c : criteria) {
                        own.push_back(c.detector->clone());
                        raw.push_back(own.back().get());
                    }
                    const trajectory_result alone = run_trajectory(m, sampler, o, i, raw);
                    SCOPED_TRACE(to_string(isa) + ", " + to_string(method) + ", chaos " +
                                 std::to_string(chaos) + ", trajectory " + std::to_string(i));
                    expect_identical(lanes.trajectories[i], alone);
                    EXPECT_GT(alone.flips(0), 0u);
                }
            }
    }
}

// The instruction set from the environment: a name, checked; an unknown one is refused naming the
// variable and the value.
TEST(Ensemble, VectorInstructionSetFromTheEnvironment) {
    set_ensemble_vector_isa(vector_isa::automatic);
    struct restore {
        const char* old = std::getenv("FLIPFLUX_VECTOR_ISA");
        std::string value = old != nullptr ? old : "";
        ~restore() {
            if (old != nullptr)
                setenv("FLIPFLUX_VECTOR_ISA", value.c_str(), 1);
            else
                unsetenv("FLIPFLUX_VECTOR_ISA");
        }
    } restore_env;
    ASSERT_EQ(setenv("FLIPFLUX_VECTOR_ISA", "sse2", 1), 0);
    EXPECT_EQ(ensemble_vector_isa(), vector_isa::sse2);
    ASSERT_EQ(setenv("FLIPFLUX_VECTOR_ISA", "auto", 1), 0);
    EXPECT_NE(ensemble_vector_isa(), vector_isa::automatic);
    ASSERT_EQ(setenv("FLIPFLUX_VECTOR_ISA", "avx9", 1), 0);
    try {
        (void)ensemble_vector_isa();
        ADD_FAILURE() << "no error for avx9";
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "environment variable FLIPFLUX_VECTOR_ISA: 'avx9' is not a vector instruction "
                  "set (auto, sse2, avx2, avx512)");
    }
    // a choice made in the program takes precedence over the environment
    set_ensemble_vector_isa(vector_isa::sse2);
    EXPECT_EQ(ensemble_vector_isa(), vector_isa::sse2);
    set_ensemble_vector_isa(vector_isa::automatic);
}

TEST(Ensemble, ResultsDoNotDependOnThreadCountOrIndexSplit) {
    const double_pendulum<double> m;
    const auto criteria = arm2_criteria(m);
    for (const integration_method method :
         {integration_method::dop853, integration_method::taylor}) {
        SCOPED_TRACE(to_string(method));
        auto small_run = [method](int threads) {
            ensemble_options o = flipflux::test::small_run(threads);
            o.method = method;
            return o;
        };
        const ensemble_result one = run_ensemble(m, small_run(1), criteria);
        EXPECT_EQ(one.threads, 1);
        for (int threads : {2, 3}) {
            const ensemble_result many = run_ensemble(m, small_run(threads), criteria);
            EXPECT_EQ(many.threads, threads);
            ASSERT_EQ(many.trajectories.size(), one.trajectories.size());
            for (std::size_t i = 0; i < one.trajectories.size(); ++i)
                expect_identical(one.trajectories[i], many.trajectories[i]);
        }
        // [0, 24) = [0, 10) + [10, 24)
        ensemble_options a = small_run(2), b = small_run(2);
        a.trajectories = 10;
        b.first_index = 10;
        b.trajectories = 14;
        const ensemble_result ra = run_ensemble(m, a, criteria), rb = run_ensemble(m, b, criteria);
        for (std::size_t i = 0; i < 10; ++i)
            expect_identical(one.trajectories[i], ra.trajectories[i]);
        for (std::size_t i = 0; i < 14; ++i)
            expect_identical(one.trajectories[10 + i], rb.trajectories[i]);
        std::uint64_t flips = 0;
        for (const auto& t : one.trajectories)
            flips += t.flips(0);
        EXPECT_GT(flips, 50u);
    }
}

TEST(Ensemble, ChaosIndicatorAndCrossingRecordsLeaveTrajectoriesUntouched) {
    const double_pendulum<double> m(lopsided_parameters());
    const auto criteria = arm2_criteria(m);
    ensemble_options o = small_run(2);
    o.energy = 0.8 * m.maximum_energy();
    o.trajectories = 8;
    const ensemble_result with = run_ensemble(m, o, criteria);
    o.chaos = false;
    o.keep_crossings = true;
    o.method = integration_method::dop853;
    const ensemble_result without = run_ensemble(m, o, criteria);
    for (std::size_t i = 0; i < with.trajectories.size(); ++i) {
        const auto& a = with.trajectories[i];
        const auto& b = without.trajectories[i];
        EXPECT_EQ(a.crossing_times, b.crossing_times);
        EXPECT_EQ(a.steps, b.steps);
        EXPECT_FALSE(std::isnan(a.lyapunov));
        EXPECT_TRUE(std::isnan(b.lyapunov));
        EXPECT_FALSE(without.chaotic(b));
        EXPECT_TRUE(a.crossings.empty());
        ASSERT_EQ(b.crossings.size(), 2u);
        for (std::size_t c = 0; c < 2; ++c) {
            ASSERT_EQ(b.crossings[c].size(), b.crossing_times[c].size());
            for (std::size_t k = 0; k < b.crossings[c].size(); ++k)
                EXPECT_EQ(b.crossings[c][k].time, b.crossing_times[c][k]);
        }
    }
}

TEST(Ensemble, ValidatesOptions) {
    const double_pendulum<double> m;
    const auto criteria = arm2_criteria(m);
    auto expect_error = [&](ensemble_options o, const std::string& option) {
        try {
            run_ensemble(m, o, criteria);
            ADD_FAILURE() << "no error for " << option;
        } catch (const input_error& e) {
            EXPECT_EQ(e.field(), option) << e.what();
        }
    };
    ensemble_options o = small_run(1);
    o.trajectories = 0;
    expect_error(o, "trajectories");
    o = small_run(1);
    o.time = 0;
    expect_error(o, "time");
    o.time = std::nan("");
    expect_error(o, "time");
    o = small_run(1);
    o.rtol = 0;
    expect_error(o, "rtol");
    o.rtol = 0.5;
    expect_error(o, "rtol");
    o = small_run(1);
    o.atol = -1;
    expect_error(o, "atol");
    o = small_run(1);
    o.energy = -2;
    expect_error(o, "energy");
    o = small_run(1);
    o.threads = -1;
    expect_error(o, "threads");
    o = small_run(1);
    o.chaos_threshold = 0;
    expect_error(o, "chaos_threshold");
    o = small_run(1);
    o.first_index = ~std::uint64_t{0};
    expect_error(o, "first_index");
    EXPECT_EQ(parse_name<integration_method>("dopri5", "method"), integration_method::dopri5);
    EXPECT_EQ(parse_name<integration_method>("dop853", "method"), integration_method::dop853);
    EXPECT_EQ(to_string(integration_method::dopri5), "dopri5");
    EXPECT_THROW(parse_name<integration_method>("rk4", "method"), input_error);
    EXPECT_THROW(run_ensemble(m, small_run(1), {{"none", nullptr}}), std::invalid_argument);
}

TEST(Ensemble, EnergyDriftFollowsTheTolerance) {
    const double_pendulum<double> m;
    ensemble_options o = small_run(2);
    o.chaos = false;
    o.trajectories = 6;
    double previous = 0;
    for (double rtol : {1e-7, 1e-9, 1e-11}) {
        o.rtol = rtol;
        for (integration_method method : {integration_method::dop853, integration_method::dopri5}) {
            o.method = method;
            const ensemble_result r = run_ensemble(m, o, {});
            double drift = 0;
            for (const auto& t : r.trajectories) {
                drift = std::max(drift, t.max_energy_drift);
                EXPECT_EQ(t.status, rk_status::ok);
                EXPECT_EQ(t.end_time, o.time);
            }
            // local error ~ rtol per step, ~ 10 steps per time unit, T = 30
            EXPECT_LT(drift, 300 * o.time * rtol * o.energy) << to_string(method) << " " << rtol;
            if (method == integration_method::dop853) {
                if (previous > 0) {
                    EXPECT_LT(drift, previous);
                }
                previous = drift;
            }
        }
    }
}

// Benettin's method: two trajectories 1e-8 apart, renormalised every unit of time.
double two_trajectory_lyapunov(const double_pendulum<double>& m, const phase_point<double>& x0,
                               const std::array<double, 4>& v0, double T) {
    const pendulum_flow flow(m);
    rk_options ro;
    ro.rtol = ro.atol = 1e-12;
    const double d0 = 1e-8;
    phase_point<double> a = x0, b = x0;
    for (int i = 0; i < 4; ++i)
        b[i] += d0 * v0[i];
    double sum = 0;
    for (double t = 0; t < T; t += 1) {
        explicit_rk<dormand_prince_853, 4, pendulum_flow> ra(flow, ro), rb(flow, ro);
        ra.initialize(0, a);
        rb.initialize(0, b);
        ra.integrate(1, [](auto&) {});
        rb.integrate(1, [](auto&) {});
        a = ra.x();
        double d = 0;
        for (int i = 0; i < 4; ++i)
            d += (rb.x()[i] - a[i]) * (rb.x()[i] - a[i]);
        d = std::sqrt(d);
        sum += std::log(d / d0);
        for (int i = 0; i < 4; ++i)
            b[i] = a[i] + (rb.x()[i] - a[i]) * d0 / d;
    }
    return sum / T;
}

// NOTE: over T = 30 both routes follow the same chaotic trajectory (divergence e^(0.5 T) ~ 1e6
// times 1e-12 stays small); over much longer times they would sample different trajectories,
// whose finite-time exponents differ by their fluctuations (~15 % at T = 150).
TEST(Ensemble, LyapunovExponentAgreesWithTwoTrajectoryEstimate) {
    const double_pendulum<double> m;
    ensemble_options o = small_run(1);
    o.time = 30;
    o.rtol = 1e-12;
    const microcanonical_sampler sampler(m, 5.0);
    const phase_point<double> x0 = sampler.sample(o.seed, 3);
    const trajectory_result r = simulate_trajectory(m, x0, o, 3, {});
    // the same initial tangent vector as the runner (its own random stream)
    philox_stream rng(o.seed, o.energy, 3, random_purpose::tangent_vector);
    std::array<double, 4> v{};
    double n2 = 0;
    for (double& c : v) {
        c = 2 * rng.uniform() - 1;
        n2 += c * c;
    }
    for (double& c : v)
        c /= std::sqrt(n2);
    const double benettin = two_trajectory_lyapunov(m, x0, v, o.time);
    EXPECT_GT(r.lyapunov, 0.1);
    EXPECT_NEAR(r.lyapunov, benettin, 0.03 * benettin);
    EXPECT_TRUE(is_chaotic(m, o.chaos, o.chaos_threshold, r.lyapunov));
    // a small-energy (regular) trajectory: lambda_T ~ ln(T) / T, far below the threshold
    const microcanonical_sampler low(m, 0.05);
    o.time = 150;
    o.rtol = 1e-9;
    const trajectory_result q = simulate_trajectory(m, low.sample(1, 0), o, 0, {});
    EXPECT_LT(q.lyapunov, 2 * std::log(o.time) / o.time);
    EXPECT_FALSE(is_chaotic(m, o.chaos, o.chaos_threshold, q.lyapunov));
    EXPECT_NEAR(chaos_threshold_rate(m, 0.05), 0.05, 1e-15);  // egalitarian: sqrt(alpha/A) = 1
}

TEST(Ensemble, TrajectoriesAreStoredOnlyWhenAsked) {
    const double_pendulum<double> m;
    ensemble_options o = small_run(1);
    o.trajectories = 2;
    o.time = 10;
    const ensemble_result none = run_ensemble(m, o, {});
    EXPECT_TRUE(none.trajectories[0].samples.empty());
    o.sample_interval = 0.25;
    const ensemble_result r = run_ensemble(m, o, {});
    const pendulum_flow flow(m);
    for (const trajectory_result& t : r.trajectories) {
        ASSERT_EQ(t.samples.size(), 41u);
        EXPECT_EQ(t.samples[0][1], t.initial_state[0]);
        for (std::size_t k = 0; k < t.samples.size(); ++k) {
            EXPECT_DOUBLE_EQ(t.samples[k][0], 0.25 * static_cast<double>(k));
            const std::array<double, 4> x{t.samples[k][1], t.samples[k][2], t.samples[k][3],
                                          t.samples[k][4]};
            EXPECT_NEAR(flow.hamiltonian(x), o.energy, 1e-6);
            EXPECT_LE(std::abs(x[0]), 4.0);
        }
    }
    o.sample_interval = -1;
    EXPECT_THROW(run_ensemble(m, o, {}), input_error);
}

// Regression: DOP853's error estimate passed a step of size 0.25 with |dH| = 1.6e-3 at
// rtol = 1e-7 (lopsided pendulum, E = 5.8, seed 105, trajectory 179655, t = 9.56): found as an
// outlier of the energy drift in 240,000 trajectories. The energy check refuses such steps.
TEST(Ensemble, Dop853EstimatorFailureIsCaughtByTheEnergyCheck) {
    const double_pendulum<double> m(lopsided_parameters());
    ensemble_options o;
    o.energy = 5.8;
    o.time = 10;
    o.seed = 105;
    o.rtol = 1e-7;
    o.chaos = false;
    const microcanonical_sampler sampler(m, o.energy);
    const trajectory_result r = run_trajectory(m, sampler, o, 179655, {});
    EXPECT_GE(r.energy_check_rejections, 1);
    EXPECT_LT(r.max_energy_drift, 2e-5);
    // ordinary trajectories are not touched by the check, however far their energy drifts over
    // a long time (the check is per step, not on the accumulated drift)
    o.time = 1000;
    double drift = 0;
    for (std::uint64_t i = 0; i < 3; ++i) {
        const trajectory_result q = run_trajectory(m, sampler, o, i, {});
        EXPECT_EQ(q.energy_check_rejections, 0);
        drift = std::max(drift, q.max_energy_drift);
    }
    EXPECT_GT(drift, energy_jump_factor * o.rtol * (1 + o.energy));
}

TEST(Ensemble, ProgressIsReportedForEveryTrajectory) {
    const double_pendulum<double> m;
    ensemble_options o = small_run(2);
    o.trajectories = 5;
    o.time = 1;
    std::vector<std::uint64_t> seen;
    o.progress = [&](std::uint64_t done, std::uint64_t total) {
        EXPECT_EQ(total, 5u);
        seen.push_back(done);
    };
    run_ensemble(m, o, arm2_criteria(m));
    EXPECT_EQ(seen, (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
}

}  // namespace
}  // namespace flipflux::test
