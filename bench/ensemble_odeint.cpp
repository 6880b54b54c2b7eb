// Ensemble throughput against the straightforward alternative (issue 6's speed target): in the
// same run and on the same trajectories (microcanonical initial conditions at E = 5, seed 1,
// egalitarian pendulum), integrated time units per CPU-second at rtol = atol = 1e-10 with every
// arm-2 criterion (upright, approx, saddle) detected, of
//   - ours: run_trajectories (DOP853, angles reduced per step, cheap Hermite step test before any
//     dense-output root finding, the energy check), one thread, no Lyapunov exponent;
//   - odeint: Boost.Odeint's runge_kutta_dopri5 wrapped by make_dense_output(1e-10, 1e-10, ...),
//     integrate step by step with do_step(); after every step, for each criterion, the crossing
//     function phi = th2 - pi - h(th1) is compared at the step's ends (the level 2 pi k it
//     passed) and each crossing located by TOMS 748 on calc_state to ~4 ulp in time; its
//     right-hand side is Hamilton's equations as written from the paper (libm sin/cos of
//     th1 - th2, sin th1, sin th2: plain_rhs). speedup = its CPU time / ours.
//   - odeint with our right-hand side (pendulum_flow, inline sin/cos): speedup_same_rhs
//     separates what the right-hand side gains from what integrator and detection gain;
//   - ours with the chaos indicator (the tangent equations, ensemble_options::chaos):
//     speedup_chaos = odeint's CPU time / this one's;
//   - the right-hand-side bound: the CPU time of one Hamilton right-hand side per lane in the
//     widest vectors of the instruction set in use (vector_isa: eight AVX-512 lanes, four AVX2
//     lanes; pendulum_flow::lanes on independent states) times our evaluations per
//     time unit gives the throughput if nothing but right-hand sides cost anything
//     (rhs_bound_units_per_cpu_s); ours / that is fraction_of_rhs_bound. The right-hand side's
//     time (rhs_ns_per_lane) is the median of timings interleaved with ours, one after each
//     timed ensemble call (since 2026-12-03): this VM's speed varies from run to run (3.9 to 4.8
//     ns per lane, bench/results/quiet_lanes_xeon_2026-12-03.txt), and a bound timed apart
//     from the ensemble moves the fraction with it. The earlier bound, the
//     median of five timings after the loop, is kept beside it (rhs_ns_per_lane_after,
//     fraction_of_rhs_bound_after).
// Counters: throughputs (time units per CPU-second), the ratios, flips of each criterion for
// ours and odeint, and z = (n_ours - n_odeint) / sqrt(n_ours + n_odeint) per criterion (|z| of
// a few at most: both integrate the same initial conditions).
// ensemble_rhs_fraction (below) measures the same fraction without Odeint, by batch size and with
// or without the detectors: where the fraction is lost.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <boost/math/tools/toms748_solve.hpp>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <numbers>

#include "flipflux/core/budget.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/ensemble/sampler.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/study/criteria.hpp"

namespace {

using namespace flipflux;
namespace odeint = boost::numeric::odeint;
using state4 = std::array<double, 4>;
constexpr double two_pi = 2 * std::numbers::pi;

// A criterion as the baseline sees it: h(s) on [lo, hi] (continued by its end values outside).
struct plain_curve {
    std::function<double(double)> offset;
    double lo, hi;
    double phi(const state4& x, double& s) const {
        const double centre = 0.5 * (lo + hi);
        s = x[0] - two_pi * std::round((x[0] - centre) / two_pi);
        return x[1] - std::numbers::pi - offset(std::clamp(s, lo, hi));
    }
};

template <class Curve>
plain_curve plain(Curve c) {
    const auto d = c.domain();
    return {[c](double s) { return static_cast<double>(c.offset(s)); }, d[0], d[1]};
}

struct odeint_result {
    std::array<long, 3> flips{};
    long steps = 0;
};

// Hamilton's equations as a user writes them from the paper: libm's sin and cos of th1 - th2,
// sin th1, sin th2.
struct plain_rhs {
    lagrangian_coefficients<double> k;
    void operator()(const state4& x, state4& dxdt, double) const {
        const double d = x[0] - x[1];
        const double sd = std::sin(d), cd = std::cos(d);
        const double det = k.D0 + k.C * k.C * sd * sd;
        const double w1 = (k.B * x[2] - k.C * cd * x[3]) / det;
        const double w2 = (k.A * x[3] - k.C * cd * x[2]) / det;
        const double P = k.C * sd * w1 * w2;
        dxdt = {w1, w2, -P - k.alpha * std::sin(x[0]), P - k.beta * std::sin(x[1])};
    }
};

// Our right-hand side (one inline sin/cos pair per angle), to separate the gains.
struct fast_rhs {
    pendulum_flow flow;
    void operator()(const state4& x, state4& dxdt, double) const { dxdt = flow(0.0, x); }
};

// The straightforward integration a user would write with Boost.Odeint.
template <class Rhs>
odeint_result odeint_trajectory(const Rhs& rhs, const state4& x0, double T,
                                const std::vector<plain_curve>& curves) {
    auto stepper = odeint::make_dense_output(1e-10, 1e-10, odeint::runge_kutta_dopri5<state4>());
    stepper.initialize(x0, 0.0, 0.01);
    odeint_result r;
    std::vector<double> phi0(curves.size());
    for (std::size_t c = 0; c < curves.size(); ++c) {
        double s = 0;
        phi0[c] = curves[c].phi(x0, s);
    }
    state4 xt;
    while (stepper.current_time() < T) {
        // do not step past T: shrink the proposed step
        if (stepper.current_time() + stepper.current_time_step() > T)
            stepper.initialize(stepper.current_state(), stepper.current_time(),
                               T - stepper.current_time());
        const auto [t0, t1] = stepper.do_step(rhs);
        ++r.steps;
        const state4& x1 = stepper.current_state();
        for (std::size_t c = 0; c < curves.size(); ++c) {
            double s = 0;
            const double p1 = curves[c].phi(x1, s);
            const double a = phi0[c], b = p1;
            const double k_lo = std::ceil(std::min(a, b) / two_pi);
            const double k_hi = std::floor(std::max(a, b) / two_pi);
            for (double k = k_lo; k <= k_hi; ++k) {
                const double level = k * two_pi;
                if ((a >= level) == (b >= level)) continue;
                auto g = [&](double t) {
                    stepper.calc_state(t, xt);
                    double ss = 0;
                    return curves[c].phi(xt, ss) - level;
                };
                std::uintmax_t it = 100;
                const auto root = boost::math::tools::toms748_solve(
                    g, t0, t1, a - level, b - level, boost::math::tools::eps_tolerance<double>(50),
                    it);
                stepper.calc_state(0.5 * (root.first + root.second), xt);
                double sx = 0;
                curves[c].phi(xt, sx);
                if (sx >= curves[c].lo && sx <= curves[c].hi) ++r.flips[c];
            }
            phi0[c] = p1;
        }
    }
    return r;
}

// CPU seconds per right-hand side and lane: pendulum_flow::lanes on W x 16 independent states in
// the widest vectors the ensemble's lanes use (ensemble_vector_isa: AVX-512, eight lanes per
// vector; AVX2, four; the four-lane code in SSE2 registers otherwise). FLIPFLUX_VECTOR_ISA selects
// another instruction set for the whole bench.
template <class V>
[[gnu::always_inline]] inline double rhs_seconds_lanes(const pendulum_flow& flow,
                                                       const std::vector<state4>& x, int rounds) {
    constexpr int groups = 16, W = lanes_of<V>;
    V in[groups][4], out[groups][4];
    for (int g = 0; g < groups; ++g)
        for (int c = 0; c < 4; ++c)
            for (int l = 0; l < W; ++l)
                in[g][c][l] = x[(W * g + l) % x.size()][c];
    const double c0 = thread_cpu_seconds();
    for (int r = 0; r < rounds; ++r) {
        for (int g = 0; g < groups; ++g) {
            flow.lanes(in[g], out[g]);
            benchmark::DoNotOptimize(out[g]);
        }
        benchmark::ClobberMemory();
    }
    return (thread_cpu_seconds() - c0) / (static_cast<double>(rounds) * groups * W);
}
__attribute__((target("avx512f"), flatten)) double rhs_seconds_avx512(const pendulum_flow& flow,
                                                                      const std::vector<state4>& x,
                                                                      int rounds) {
    return rhs_seconds_lanes<v8d>(flow, x, rounds);
}
__attribute__((target("avx2"), flatten)) double rhs_seconds_avx2(const pendulum_flow& flow,
                                                                 const std::vector<state4>& x,
                                                                 int rounds) {
    return rhs_seconds_lanes<v4d>(flow, x, rounds);
}
double rhs_seconds_once(const pendulum_flow& flow, const std::vector<state4>& x, int rounds) {
    switch (ensemble_vector_isa()) {
        case vector_isa::avx512:
            return rhs_seconds_avx512(flow, x, rounds / 2);
        case vector_isa::avx2:
            return rhs_seconds_avx2(flow, x, rounds);
        default:
            return rhs_seconds_lanes<v4d>(flow, x, rounds);
    }
}
// The median of `t` (sorted in place).
double median_of(std::vector<double>& t) {
    std::sort(t.begin(), t.end());
    const std::size_t n = t.size();
    return n == 0 ? 0.0 : n % 2 == 1 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

// One timing of the right-hand side in a bench's loop, after each timed ensemble call: rounds of
// about a millisecond (AVX-512: 4000 / 2 rounds of 16 x 8 lanes).
constexpr int interleaved_rhs_rounds = 4000;

// The median of five timings of rounds / 5 each: one timing of this VM's CPU time varied by
// up to 40 % between runs (6.4 to 9.0 ns per lane on a Zen 4), and the bound is proportional to
// it.
double flipflux_bench_rhs_seconds(const pendulum_flow& flow, const std::vector<state4>& x,
                                  int rounds) {
    std::array<double, 5> t{};
    for (double& ti : t)
        ti = rhs_seconds_once(flow, x, rounds / 5);
    std::sort(t.begin(), t.end());
    return t[2];
}

// The benches' ensemble: energy E, T time units per trajectory, seed 1, rtol = atol = 1e-10,
// one thread, no chaos indicator.
ensemble_options bench_options(double E, double T, integration_method method) {
    ensemble_options o;
    o.energy = E;
    o.time = T;
    o.seed = 1;
    o.rtol = 1e-10;
    o.threads = 1;
    o.chaos = false;
    o.method = method;
    return o;
}

void ensemble_vs_odeint(benchmark::State& state) {
    const double_pendulum<double> m;
    const double E = 5, T = 100;
    // the trajectories one thread advances in lockstep (16 with AVX-512, 8 with AVX2)
    const std::uint64_t batch = ensemble_lanes_per_thread();
    const pendulum_flow flow(m);
    const microcanonical_sampler sampler(m, E);
    std::vector<ensemble_criterion> criteria;
    for (const char* name : {"upright", "approx", "saddle"})
        criteria.push_back(make_criterion(m, arm::two, name, E));
    const saddle_orbit<double> orbit = solve_saddle_orbit<double>(m, arm::two, E);
    const std::vector<plain_curve> curves{plain(upright_curve<double>{arm::two}),
                                          plain(approximate_saddle_curve(m, arm::two)),
                                          plain(make_saddle_curve<double>(m, orbit))};
    const ensemble_options o = bench_options(
        E, T, state.range(0) == 0 ? integration_method::dop853 : integration_method::dopri5);
    ensemble_options chaos = o;
    chaos.chaos = true;
    std::array<long, 3> ours{}, theirs{};
    double cpu_ours = 0, cpu_theirs = 0, cpu_fast = 0, cpu_chaos = 0, units = 0;
    long evaluations_ours = 0;
    std::vector<state4> starts;
    const plain_rhs user_rhs{m.coefficients()};
    const fast_rhs our_rhs{flow};
    long steps_ours = 0, steps_theirs = 0;
    std::uint64_t next = 0;
    // the right-hand side's timings, one per iteration, on the initial states of the first 64
    // trajectories (those of the iterations so far)
    std::vector<double> rhs_slices;
    for (auto _ : state) {
        std::vector<std::uint64_t> indices;
        for (std::uint64_t i = 0; i < batch; ++i) {
            if (starts.size() < 64) starts.push_back(sampler.sample(o.seed, next));
            indices.push_back(next++);
        }
        double c0 = thread_cpu_seconds();
        run_trajectories(m, o, criteria, indices, [&](trajectory_result&& r) {
            for (std::size_t c = 0; c < 3; ++c)
                ours[c] += static_cast<long>(r.flips(c));
            steps_ours += r.steps;
            evaluations_ours += r.evaluations;
        });
        double c1 = thread_cpu_seconds();
        cpu_ours += c1 - c0;
        rhs_slices.push_back(rhs_seconds_once(flow, starts, interleaved_rhs_rounds));
        c1 = thread_cpu_seconds();
        run_trajectories(m, chaos, criteria, indices,
                         [&](trajectory_result&& r) { benchmark::DoNotOptimize(r.lyapunov); });
        const double c1c = thread_cpu_seconds();
        cpu_chaos += c1c - c1;
        c1 = c1c;
        for (const std::uint64_t i : indices) {
            const odeint_result r =
                odeint_trajectory(user_rhs, sampler.sample(o.seed, i), T, curves);
            for (std::size_t c = 0; c < 3; ++c)
                theirs[c] += r.flips[c];
            steps_theirs += r.steps;
        }
        const double c2 = thread_cpu_seconds();
        cpu_theirs += c2 - c1;
        for (const std::uint64_t i : indices)
            benchmark::DoNotOptimize(
                odeint_trajectory(our_rhs, sampler.sample(o.seed, i), T, curves));
        cpu_fast += thread_cpu_seconds() - c2;
        units += static_cast<double>(batch) * T;
    }
    const double evaluations_per_unit = static_cast<double>(evaluations_ours) / units;
    const double rhs_seconds = median_of(rhs_slices);
    const double bound = 1 / (evaluations_per_unit * rhs_seconds);
    const double rhs_after = flipflux_bench_rhs_seconds(flow, starts, 200000);
    state.counters["rhs_ns_per_lane_after"] = 1e9 * rhs_after;
    state.counters["fraction_of_rhs_bound_after"] =
        units / cpu_ours * evaluations_per_unit * rhs_after;
    state.counters["ours_units_per_cpu_s"] = units / cpu_ours;
    state.counters["ours_chaos_units_per_cpu_s"] = units / cpu_chaos;
    state.counters["speedup_chaos"] = cpu_theirs / cpu_chaos;
    state.counters["rhs_ns_per_lane"] = 1e9 * rhs_seconds;
    state.counters["ours_evaluations_per_unit"] = evaluations_per_unit;
    state.counters["rhs_bound_units_per_cpu_s"] = bound;
    state.counters["fraction_of_rhs_bound"] = units / cpu_ours / bound;
    state.counters["odeint_units_per_cpu_s"] = units / cpu_theirs;
    state.counters["odeint_fast_rhs_units_per_cpu_s"] = units / cpu_fast;
    state.counters["speedup"] = cpu_theirs / cpu_ours;
    state.counters["speedup_same_rhs"] = cpu_fast / cpu_ours;
    state.counters["ours_steps_per_unit"] = static_cast<double>(steps_ours) / units;
    state.counters["odeint_steps_per_unit"] = static_cast<double>(steps_theirs) / units;
    const char* names[3] = {"upright", "approx", "saddle"};
    for (std::size_t c = 0; c < 3; ++c) {
        const double a = static_cast<double>(ours[c]), b = static_cast<double>(theirs[c]);
        state.counters[std::string("flips_ours_") + names[c]] = a;
        state.counters[std::string("flips_odeint_") + names[c]] = b;
        state.counters[std::string("z_") + names[c]] = a + b > 0 ? (a - b) / std::sqrt(a + b) : 0;
    }
    state.SetLabel(
        std::string(o.method == integration_method::dop853 ? "ours=dop853" : "ours=dopri5") +
        " vector_isa=" + to_string(ensemble_vector_isa()));
}
BENCHMARK(ensemble_vs_odeint)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MinTime(3);

// Where the right-hand-side bound's fraction is lost (issue 42's target >= 0.3): the same workload
// and bound as ensemble_vs_odeint (DOP853, its energy, seed, rtol and criteria; no Odeint), with
// run_trajectories given `batch` trajectories per call (args: batch, criteria). batch 8 fills one
// group of AVX-512 lanes once (ensemble_vs_odeint's batch until 2026-12-02; it is now one thread's
// lanes, ensemble_lanes_per_thread(): 16, two groups, with AVX-512), so its last rounds run
// part-filled vectors; 16 is the issue bench's batch (its tail with one thread's lanes); 64
// refills the lanes from the same call, as a large ensemble does. criteria
// 0 runs the integrator alone (no detector: no step tests, examinations or dense output), 3 the
// bench's three arm-2 criteria. Counters: fraction_of_rhs_bound, ours_units_per_cpu_s,
// ours_evaluations_per_unit, rhs_ns_per_lane and the _after pair (as in ensemble_vs_odeint).
void ensemble_rhs_fraction(benchmark::State& state) {
    const double_pendulum<double> m;
    const double E = 5, T = 100;
    const auto batch = static_cast<std::uint64_t>(state.range(0));
    const pendulum_flow flow(m);
    const microcanonical_sampler sampler(m, E);
    std::vector<ensemble_criterion> criteria;
    const char* names[3] = {"upright", "approx", "saddle"};
    for (std::int64_t c = 0; c < state.range(1); ++c)
        criteria.push_back(make_criterion(m, arm::two, names[c], E));
    const ensemble_options o = bench_options(E, T, integration_method::dop853);
    double cpu = 0, units = 0;
    long evaluations = 0;
    std::vector<state4> starts;
    std::vector<double> rhs_slices;  // the right-hand side's timings, one per iteration
    std::uint64_t next = 0;
    for (auto _ : state) {
        std::vector<std::uint64_t> indices;
        for (std::uint64_t i = 0; i < batch; ++i) {
            if (starts.size() < 64) starts.push_back(sampler.sample(o.seed, next));
            indices.push_back(next++);
        }
        const double c0 = thread_cpu_seconds();
        run_trajectories(m, o, criteria, indices,
                         [&](trajectory_result&& r) { evaluations += r.evaluations; });
        cpu += thread_cpu_seconds() - c0;
        units += static_cast<double>(batch) * T;
        rhs_slices.push_back(rhs_seconds_once(flow, starts, interleaved_rhs_rounds));
    }
    const double evaluations_per_unit = static_cast<double>(evaluations) / units;
    const double rhs_seconds = median_of(rhs_slices);
    const double bound = 1 / (evaluations_per_unit * rhs_seconds);
    state.counters["fraction_of_rhs_bound"] = units / cpu / bound;
    const double rhs_after = flipflux_bench_rhs_seconds(flow, starts, 200000);
    state.counters["rhs_ns_per_lane_after"] = 1e9 * rhs_after;
    state.counters["fraction_of_rhs_bound_after"] = units / cpu * evaluations_per_unit * rhs_after;
    state.counters["ours_units_per_cpu_s"] = units / cpu;
    state.counters["ours_evaluations_per_unit"] = evaluations_per_unit;
    state.counters["rhs_ns_per_lane"] = 1e9 * rhs_seconds;
    state.SetLabel("ours=dop853 vector_isa=" + to_string(ensemble_vector_isa()));
}
BENCHMARK(ensemble_rhs_fraction)
    ->ArgNames({"batch", "criteria"})
    ->Args({8, 3})
    ->Args({16, 3})
    ->Args({64, 3})
    ->Args({8, 0})
    ->Args({64, 0})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3);

}  // namespace

BENCHMARK_MAIN();
