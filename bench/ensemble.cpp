// Ensemble throughput: integrated time units per CPU-second at rtol = 1e-10 with every arm-2
// criterion detected (one thread; the figure issue 6's targets refer to), with and without the
// chaos indicator (variational equations), for DOP853 and DOPRI5; and the costs of the pieces:
// one right-hand side (fast flow vs the templated model), one microcanonical sample.
#include <benchmark/benchmark.h>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/study/criteria.hpp"

namespace {

using namespace flipflux;

std::vector<ensemble_criterion> arm2_criteria(const double_pendulum<double>& m, double E) {
    std::vector<ensemble_criterion> out;
    for (const std::string& name : criterion_names()) {
        try {
            out.push_back(make_criterion(m, arm::two, name, E));
        } catch (const input_error&) {  // a criterion this build lacks
        }
    }
    return out;
}

void ensemble_throughput(benchmark::State& state) {
    const double_pendulum<double> m;
    ensemble_options o;
    o.energy = 5;
    o.trajectories = 8;
    o.time = 100;
    o.seed = 1;
    o.rtol = 1e-10;
    o.threads = 1;
    o.method = state.range(0) == 0 ? integration_method::dop853 : integration_method::dopri5;
    o.chaos = state.range(1) != 0;
    const auto criteria = arm2_criteria(m, o.energy);
    long steps = 0, flips = 0;
    for (auto _ : state) {
        const ensemble_result r = run_ensemble(m, o, criteria);
        for (const auto& t : r.trajectories) {
            steps += t.steps;
            for (std::size_t c = 0; c < criteria.size(); ++c)
                flips += static_cast<long>(t.flips(c));
        }
        o.seed += 1;  // fresh trajectories each iteration
    }
    const double units = static_cast<double>(state.iterations()) * o.trajectories * o.time;
    state.counters["time_units_per_s"] = benchmark::Counter(units, benchmark::Counter::kIsRate);
    state.counters["steps_per_time_unit"] = static_cast<double>(steps) / units;
    state.counters["criteria"] = static_cast<double>(criteria.size());
    state.counters["flips_per_time_unit"] = static_cast<double>(flips) / units;
    state.SetLabel(std::string(to_string(o.method)) + (o.chaos ? "+lyapunov" : ""));
}
BENCHMARK(ensemble_throughput)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

void fast_rhs(benchmark::State& state) {
    const pendulum_flow flow{double_pendulum<double>()};
    std::array<double, 4> x{0.3, 2.9, 0.4, -0.2};
    for (auto _ : state) {
        const auto f = flow(0, x);
        x[0] += 1e-9 * f[0];
        benchmark::DoNotOptimize(x);
    }
}
BENCHMARK(fast_rhs);

void model_rhs(benchmark::State& state) {
    const double_pendulum<double> m;
    phase_point<double> x{0.3, 2.9, 0.4, -0.2};
    for (auto _ : state) {
        const auto f = m.rhs(x);
        x[0] += 1e-9 * f[0];
        benchmark::DoNotOptimize(x);
    }
}
BENCHMARK(model_rhs);

void tangent_rhs(benchmark::State& state) {
    const pendulum_flow flow{double_pendulum<double>()};
    std::array<double, 8> y{0.3, 2.9, 0.4, -0.2, 1, 0, 0, 0};
    for (auto _ : state) {
        const auto f = flow.tangent(y);
        y[0] += 1e-9 * f[0];
        benchmark::DoNotOptimize(y);
    }
}
BENCHMARK(tangent_rhs);

void microcanonical_sample(benchmark::State& state) {
    const microcanonical_sampler s(double_pendulum<double>(), 5.0);
    std::uint64_t i = 0;
    for (auto _ : state)
        benchmark::DoNotOptimize(s.sample(1, i++));
}
BENCHMARK(microcanonical_sample);

}  // namespace

BENCHMARK_MAIN();
