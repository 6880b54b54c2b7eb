// Google Benchmark: every registered quantity (prediction and, once registered, orbits) with each
// of its methods at double, quad, mp:50 and mp:100, for the egalitarian pendulum at a
// representative energy (omega: E = 3.5 and 7; arm 2: E = 3.5; arm 1: E = 5). Registered from the
// quantity registry at start-up, so new quantities are benchmarked without an edit here.
// Filter with --benchmark_filter, e.g. 'omega/elliptic' or '/mp:50'.
#include <benchmark/benchmark.h>

#include <optional>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/orbit_store.hpp"
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

}  // namespace

int main(int argc, char** argv) {
    for (const char* p : {"double", "quad", "mp:50", "mp:100"})
        register_all(parse_precision(p));
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
