// Google Benchmark: every registered quantity (prediction and, once registered, orbits) with each
// of its methods at double, quad, mp:50 and mp:100, for the egalitarian pendulum at a
// representative energy (omega: E = 3.5 and 7; arm 2: E = 3.5; arm 1: E = 5). Registered from the
// quantity registry at start-up, so new quantities are benchmarked without an edit here.
// Filter with --benchmark_filter, e.g. 'omega/elliptic' or '/mp:50'.
// omega_just_above_the_saddles/<precision>: Omega at E = 2 beta + 1e-D and 2 alpha + 1e-D (decimal
// energies, the distances exact; D = the working digits + 15), each side timed in the same run,
// counter arm1_over_arm2 their ratio: the graded quadrature's hard case on either end of its
// interval (theta1 = 0 for arm 2's saddle, theta1 = pi for arm 1's).
#include <benchmark/benchmark.h>

#include <optional>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/quantities/registry.hpp"

namespace {

using namespace flipflux;

template <class Real>
void run_in(benchmark::State& state, const quantity* q, const std::string& method, arm a,
            const std::string& e) {
    const double_pendulum<Real> model;
    const Real energy = parse_real<Real>(e, "--energy");
    for (auto _ : state) {
        // every saddle orbit solved from scratch (the memo would make repeats free)
        std::optional<saddle_orbit_memo_bypass> bypass;
        if (q->needs_saddle_orbit) bypass.emplace();
        try {
            benchmark::DoNotOptimize(q->evaluate(model, a, energy, method));
        } catch (const input_error& err) {
            state.SkipWithError(err.what());
            break;
        }
    }
}

void run(benchmark::State& state, const quantity* q, std::string method, arm a, std::string e,
         precision p) {
    dispatch(p, [&]<class Real>() { run_in<Real>(state, q, method, a, e); });
}

void register_all(const precision& p) {
    for (const quantity& q : quantities()) {
        std::vector<std::pair<arm, std::string>> cases;
        if (q.per_arm)
            cases = {{arm::two, "3.5"}, {arm::one, "5"}};
        else
            cases = {{arm::two, "3.5"}, {arm::two, "7"}};
        for (const std::string& m : q.methods) {
            for (const auto& [a, e] : cases) {
                const std::string name = q.name + "/" + m +
                                         (q.per_arm ? "/arm" + to_string(a) : "") + "/E=" + e +
                                         "/" + precision_name(p);
                benchmark::RegisterBenchmark(name.c_str(), run, &q, m, a, e, p)
                    ->Unit(benchmark::kMicrosecond);
            }
        }
    }
}

template <class Real>
void omega_near_saddles_in(benchmark::State& state) {
    const double_pendulum<Real> model;
    const std::string tail =
        std::string(static_cast<std::size_t>(binary_digits<Real>() * 3 / 10 + 14), '0') + "1";
    const energy_level<Real> above2 = parse_energy_level<Real>("2." + tail, "energy"),
                             above1 = parse_energy_level<Real>("4." + tail, "energy");
    double arm2 = 0, arm1 = 0;
    for (auto _ : state) {
        const double c0 = thread_cpu_seconds();
        benchmark::DoNotOptimize(phase_volume(model, above2));
        const double c1 = thread_cpu_seconds();
        benchmark::DoNotOptimize(phase_volume(model, above1));
        arm2 += c1 - c0;
        arm1 += thread_cpu_seconds() - c1;
    }
    state.counters["arm2_side_s"] = arm2 / static_cast<double>(state.iterations());
    state.counters["arm1_side_s"] = arm1 / static_cast<double>(state.iterations());
    state.counters["arm1_over_arm2"] = arm1 / arm2;
}

void omega_near_saddles(benchmark::State& state, precision p) {
    dispatch(p, [&]<class Real>() { omega_near_saddles_in<Real>(state); });
}

}  // namespace

int main(int argc, char** argv) {
    for (const char* p : {"double", "quad", "mp:50", "mp:100"})
        register_all(parse_precision(p));
    for (const char* p : {"double", "quad", "mp:30", "mp:50"}) {
        const std::string name = std::string("omega_just_above_the_saddles/") + p;
        benchmark::RegisterBenchmark(name.c_str(), omega_near_saddles, parse_precision(p))
            ->Unit(benchmark::kMillisecond);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
