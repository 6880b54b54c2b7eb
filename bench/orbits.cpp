// Saddle-orbit benchmarks: the whole arm-2 family on a 100-point grid at double, one orbit at
// quad, mp:50, mp:100 and mp:150, the saddle curve's construction and evaluation. Each orbit
// benchmark also reports the digits it reached (counters digits_T, digits_F: -log10 of the relative
// error against a solve at higher precision), so the figures are digits versus time.
#include <benchmark/benchmark.h>

#include <cmath>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {
namespace {

std::vector<double> arm2_grid() {
    std::vector<double> e;
    for (int k = 0; k < 100; ++k)
        e.push_back(2 + 4 * (k + 0.5) / 100);  // 2.02 .. 5.98
    return e;
}

void BM_Arm2FamilyDouble(benchmark::State& state) {
    const double_pendulum<double> model;
    const auto energies = arm2_grid();
    orbit_options<double> options;
    options.method = state.range(0) == 0 ? orbit_method::symmetric : orbit_method::periodic;
    std::size_t n = 0;
    for (auto _ : state) {
        const auto fam = continue_saddle_family(model, arm::two, energies, options);
        n = fam.orbits.size();
        benchmark::DoNotOptimize(fam.orbits.back().action);
    }
    state.counters["orbits"] = static_cast<double>(n);
    state.SetLabel(state.range(0) == 0 ? "symmetric" : "periodic (Ceres)");
}
BENCHMARK(BM_Arm2FamilyDouble)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

/// One orbit in precision p (E = 3, arm 2), timed; its T and F as decimal text.
struct timed_orbit {
    std::string period, action;
    double steps = 0, stages = 0;
};

template <class Real>
timed_orbit solve_timed(benchmark::State* state, orbit_method method, const std::string& tolerance,
                        int stages) {
    const double_pendulum<Real> model;
    const Real E = parse_real<Real>("3", "E");
    orbit_options<Real> options;
    options.method = method;
    if (!tolerance.empty()) options.tolerance = parse_real<Real>(tolerance, "tolerance");
    options.stages = stages;
    saddle_orbit<Real> o;
    if (state != nullptr) {
        for (auto _ : *state) {
            o = solve_saddle_orbit(model, arm::two, E, options);
            benchmark::DoNotOptimize(o.action);
        }
    } else {
        o = solve_saddle_orbit(model, arm::two, E, options);
    }
    return {to_decimal(o.period, full_digits(o.period)),
            to_decimal(o.action, full_digits(o.action)), static_cast<double>(o.steps),
            static_cast<double>(o.stages)};
}

/// One orbit in p, digits against a symmetric-shooting reference in `reference` (with its
/// tolerance and stages).
void orbit_benchmark(benchmark::State& state, const precision& p, orbit_method method,
                     const precision& reference, const std::string& ref_tolerance, int ref_stages) {
    const timed_orbit o =
        dispatch(p, [&]<class Real>() { return solve_timed<Real>(&state, method, "", 0); });
    const timed_orbit ref = dispatch(reference, [&]<class Real>() {
        return solve_timed<Real>(nullptr, orbit_method::symmetric, ref_tolerance, ref_stages);
    });
    state.counters["digits_T"] = correct_digits(o.period, ref.period);
    state.counters["digits_F"] = correct_digits(o.action, ref.action);
    state.counters["steps"] = o.steps;
    state.counters["stages"] = o.stages;
    state.SetLabel(to_string(method) + " " + precision_name(p) + " vs " +
                   precision_name(reference));
}

void BM_OrbitDouble(benchmark::State& state) {
    orbit_benchmark(state, precision{real_kind::double_}, static_cast<orbit_method>(state.range(0)),
                    precision{real_kind::quad}, "", 0);
}
BENCHMARK(BM_OrbitDouble)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_OrbitQuad(benchmark::State& state) {
    orbit_benchmark(state, precision{real_kind::quad}, static_cast<orbit_method>(state.range(0)),
                    mp_precision(50), "1e-40", 12);
}
BENCHMARK(BM_OrbitQuad)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_OrbitMp50(benchmark::State& state) {
    orbit_benchmark(state, mp_precision(50), static_cast<orbit_method>(state.range(0)),
                    mp_precision(100), "1e-72", 14);
}
BENCHMARK(BM_OrbitMp50)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_OrbitMp100(benchmark::State& state) {
    orbit_benchmark(state, mp_precision(100), orbit_method::symmetric, mp_precision(150), "1e-125",
                    0);
}
BENCHMARK(BM_OrbitMp100)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_OrbitMp150(benchmark::State& state) {
    orbit_benchmark(state, mp_precision(150), orbit_method::symmetric, mp_precision(200), "1e-175",
                    0);
}
BENCHMARK(BM_OrbitMp150)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_CurveBuildDouble(benchmark::State& state) {
    const double_pendulum<double> model;
    const double E = state.range(0) == 0 ? 4.0 : 5.999999;
    const auto o = solve_saddle_orbit(model, arm::two, E, {orbit_method::symmetric});
    int panels = 0;
    for (auto _ : state) {
        const auto c = make_saddle_curve(model, o);
        panels = c.panels();
        benchmark::DoNotOptimize(c);
    }
    state.counters["panels"] = panels;
    state.SetLabel(state.range(0) == 0 ? "E = 4" : "E = 6 - 1e-6");
}
BENCHMARK(BM_CurveBuildDouble)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_CurveOffsetDouble(benchmark::State& state) {
    const double_pendulum<double> model;
    const auto o = solve_saddle_orbit(model, arm::two, 4.0, {orbit_method::symmetric});
    const auto c = make_saddle_curve(model, o);
    const double sb = c.domain()[1];
    double s = -sb, acc = 0;
    const double ds = 2 * sb / 1000.0;
    for (auto _ : state) {
        acc += c.offset(s);
        s += ds;
        if (s > sb) s = -sb;
    }
    benchmark::DoNotOptimize(acc);
}
BENCHMARK(BM_CurveOffsetDouble);

}  // namespace
}  // namespace flipflux

BENCHMARK_MAIN();
