// One saddle orbit (T, F and the multiplier) by each integrator, Taylor and Gauss-Legendre, in the
// same run (issue 14's targets: mp:100 < 5 s at E = 4 and < 60 s at E = 5.95, mp:300 < 60 s at
// E = 4, both arms). Each benchmark reports its seconds and the digits of T and F against a
// Taylor solve at 20 more digits (counters digits_T, digits_F); the ratio GL / Taylor is read
// from two rows of one run.
//
//   bench_orbit_integrators --benchmark_filter='Mp100/.*'   (one core: the solver is serial)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {
namespace {

struct timed {
    std::string period, action;
    double seconds = 0, steps = 0, order = 0;
    std::string status;
};

template <class Real>
timed solve(const std::string& energy, arm a, orbit_integrator integrator, orbit_method method) {
    const double_pendulum<Real> model;
    orbit_options<Real> options;
    options.method = method;
    options.integrator = integrator;
    const auto t0 = std::chrono::steady_clock::now();
    const auto o = solve_saddle_orbit(model, a, parse_real<Real>(energy, "E"), options);
    const auto t1 = std::chrono::steady_clock::now();
    return {to_decimal(o.period, full_digits(o.period)),
            to_decimal(o.action, full_digits(o.action)),
            std::chrono::duration<double>(t1 - t0).count(),
            static_cast<double>(o.steps),
            static_cast<double>(o.order),
            to_string(o.status)};
}

const char* const energies[] = {"4", "5.95", "5.99"};

/// range(0): energy index, range(1): arm (1, 2), range(2): 0 Taylor, 1 Gauss-Legendre,
/// range(3): 0 periodic, 1 symmetric.
void orbit_at(benchmark::State& state, int digits) {
    const std::string E = energies[state.range(0)];
    const arm a = state.range(1) == 1 ? arm::one : arm::two;
    const orbit_integrator integ =
        state.range(2) == 0 ? orbit_integrator::taylor : orbit_integrator::gauss_legendre;
    const orbit_method method =
        state.range(3) == 0 ? orbit_method::periodic : orbit_method::symmetric;
    const precision p = digits == 0 ? precision{real_kind::quad} : mp_precision(digits);
    timed o;
    for (auto _ : state)
        o = dispatch(p, [&]<class Real>() { return solve<Real>(E, a, integ, method); });
    const int ref_digits = (digits == 0 ? 34 : digits) + 20;
    const timed ref = dispatch(mp_precision(ref_digits), [&]<class Real>() {
        return solve<Real>(E, a, orbit_integrator::taylor, orbit_method::symmetric);
    });
    state.counters["seconds"] = o.seconds;
    state.counters["digits_T"] = correct_digits(o.period, ref.period);
    state.counters["digits_F"] = correct_digits(o.action, ref.action);
    state.counters["steps"] = o.steps;
    state.counters["order"] = o.order;
    state.SetLabel(precision_name(p) + " E=" + E + " arm " + to_string(a) + " " + to_string(integ) +
                   " " + to_string(method) + " " + o.status);
    std::printf("# %s E=%s arm %s %s %s: %.3f s, %g steps, order %g\n", precision_name(p).c_str(),
                E.c_str(), to_string(a).c_str(), to_string(integ).c_str(),
                to_string(method).c_str(), o.seconds, o.steps, o.order);
    std::fflush(stdout);
}

void BM_Quad(benchmark::State& s) {
    orbit_at(s, 0);
}
void BM_Mp50(benchmark::State& s) {
    orbit_at(s, 50);
}
void BM_Mp100(benchmark::State& s) {
    orbit_at(s, 100);
}
void BM_Mp300(benchmark::State& s) {
    orbit_at(s, 300);
}

// {energy, arm, integrator, method}
#define FLIPFLUX_ORBIT_ARGS(B, E)                    \
    BENCHMARK(B)                                     \
        ->ArgsProduct({{E}, {1, 2}, {0, 1}, {0, 1}}) \
        ->Unit(benchmark::kSecond)                   \
        ->Iterations(1)
FLIPFLUX_ORBIT_ARGS(BM_Quad, 0);
FLIPFLUX_ORBIT_ARGS(BM_Mp50, 0);
FLIPFLUX_ORBIT_ARGS(BM_Mp100, 0);
BENCHMARK(BM_Mp100)
    ->ArgsProduct({{1, 2}, {1, 2}, {0}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK(BM_Mp300)
    ->ArgsProduct({{0}, {1, 2}, {0}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace flipflux

BENCHMARK_MAIN();
