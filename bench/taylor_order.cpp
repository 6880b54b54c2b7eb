// The Taylor ensemble's cost per time unit against its order: the calibration of
// ensemble_taylor_order's step-overhead constants (ensemble/taylor_ensemble.hpp).
//
// The workload is the heyoka side-by-side bench's (../shared/peers/heyoka/bench.sh: E = 4.3,
// 64 trajectories, arm-2 upright flips, one thread), shortened to T = 500, at the rtols of the
// four accuracy levels (docs/scale.md: 3e-11, 2e-13, 3e-14, epsilon), without and with the
// tangent vector (chaos indicator), at the automatic order and at orders 2, 4 and 6 below and 2
// above it (at most ensemble_taylor_max_order). Arguments: level, order offset, tangent.
// Counters: the order, the automatic order, integrated time units per CPU-second, steps per time
// unit and flips (the same trajectories at every order: their count moves only by the chaotic
// parting of trajectories integrated with different errors).
//
//     build/release/bench/bench_taylor_order --benchmark_repetitions=3
//         --benchmark_report_aggregates_only=true      (one line)
//
// Reading it: for each (level, tangent) the automatic order's throughput against the best of
// the scan (docs/scale.md quotes the ratios).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <limits>

#include "flipflux/core/budget.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/pendulum_taylor.hpp"
#include "flipflux/ensemble/taylor_ensemble.hpp"
#include "flipflux/study/criteria.hpp"

namespace {

using namespace flipflux;

constexpr double level_rtol[4] = {3e-11, 2e-13, 3e-14, std::numeric_limits<double>::epsilon()};

void taylor_order_scan(benchmark::State& state) {
    const double_pendulum<double> m;
    ensemble_options o;
    o.energy = 4.3;
    o.trajectories = 64;
    o.time = 500;
    o.seed = 1;
    o.threads = 1;
    o.rtol = level_rtol[state.range(0)];
    o.method = integration_method::taylor;
    o.chaos = state.range(2) != 0;
    const int automatic = ensemble_taylor_order(o.rtol, o.chaos);
    o.taylor_order = std::clamp(automatic + static_cast<int>(state.range(1)), min_taylor_order,
                                ensemble_taylor_max_order);
    const std::vector<ensemble_criterion> criteria{
        make_criterion(m, arm::two, "upright", o.energy)};
    long steps = 0, flips = 0;
    double cpu = 0;
    for (auto _ : state) {
        const double c0 = thread_cpu_seconds();
        const ensemble_result r = run_ensemble(m, o, criteria);
        cpu += thread_cpu_seconds() - c0;
        for (const auto& t : r.trajectories) {
            steps += t.steps;
            flips += static_cast<long>(t.flips(0));
        }
    }
    const double units = static_cast<double>(state.iterations()) * o.trajectories * o.time;
    state.counters["units_per_cpu_s"] = units / cpu;
    state.counters["steps_per_unit"] = static_cast<double>(steps) / units;
    state.counters["flips"] = static_cast<double>(flips) / static_cast<double>(state.iterations());
    state.counters["order"] = o.taylor_order;
    state.counters["automatic_order"] = automatic;
}
BENCHMARK(taylor_order_scan)
    ->ArgsProduct({{0, 1, 2, 3}, {-6, -4, -2, 0, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
