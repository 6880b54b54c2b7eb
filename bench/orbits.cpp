// Saddle-orbit benchmarks: the whole arm-2 family on a 100-point grid at double, one orbit at
// quad, mp50 and mp100, the saddle curve's construction and evaluation. Each orbit benchmark also
// reports the digits it reached (counters digits_T, digits_F: -log10 of the relative error against
// a solve at higher precision), so the figures are digits versus time.
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

/// One orbit at Real (E = 3, arm 2), digits against a reference at Ref.
template <class Real, class Ref>
void orbit_benchmark(benchmark::State& state, orbit_method method, const Ref& ref_tolerance,
                     int ref_stages) {
    const double_pendulum<Real> model;
    const Real E = parse_real<Real>("3", "E");
    orbit_options<Real> options;
    options.method = method;
    saddle_orbit<Real> o;
    for (auto _ : state) {
        o = solve_saddle_orbit(model, arm::two, E, options);
        benchmark::DoNotOptimize(o.action);
    }
    orbit_options<Ref> ro;
    ro.method = orbit_method::symmetric;
    ro.tolerance = ref_tolerance;
    ro.stages = ref_stages;
    const auto ref =
        solve_saddle_orbit(double_pendulum<Ref>(), arm::two, parse_real<Ref>("3", "E"), ro);
    state.counters["digits_T"] = correct_digits(o.period, ref.period);
    state.counters["digits_F"] = correct_digits(o.action, ref.action);
    state.counters["steps"] = static_cast<double>(o.steps);
    state.counters["stages"] = o.stages;
    state.SetLabel(to_string(method));
}

void BM_OrbitDouble(benchmark::State& state) {
    orbit_benchmark<double, quad>(state, static_cast<orbit_method>(state.range(0)), quad(0), 0);
}
BENCHMARK(BM_OrbitDouble)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_OrbitQuad(benchmark::State& state) {
    orbit_benchmark<quad, mp50>(state, static_cast<orbit_method>(state.range(0)), mp50("1e-40"),
                                12);
}
BENCHMARK(BM_OrbitQuad)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_OrbitMp50(benchmark::State& state) {
    orbit_benchmark<mp50, mp100>(state, static_cast<orbit_method>(state.range(0)), mp100("1e-56"),
                                 14);
}
BENCHMARK(BM_OrbitMp50)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_OrbitMp100(benchmark::State& state) {
    // no higher precision to compare with: time only (its accuracy is that of the tolerance,
    // 64 eps, as verified for the other types)
    const double_pendulum<mp100> model;
    orbit_options<mp100> options;
    options.method = orbit_method::symmetric;
    saddle_orbit<mp100> o;
    for (auto _ : state) {
        o = solve_saddle_orbit(model, arm::two, mp100(3), options);
        benchmark::DoNotOptimize(o.action);
    }
    state.counters["steps"] = static_cast<double>(o.steps);
    state.counters["stages"] = o.stages;
}
BENCHMARK(BM_OrbitMp100)->Unit(benchmark::kMillisecond)->Iterations(1);

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
