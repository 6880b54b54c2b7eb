// One saddle orbit (T, F and the multiplier) by each integrator, Taylor and Gauss-Legendre, in the
// same run (issue 14's targets: mp:100 < 5 s at E = 4 and < 60 s at E = 5.95, mp:300 < 60 s at
// E = 4, both arms). Each benchmark reports its seconds and the digits of T and F against a
// Taylor solve at 20 more digits (counters digits_T, digits_F); the ratio GL / Taylor is read
// from two rows of one run. The rows marked "uniform" solve with every Taylor coefficient at the
// working precision (graded precision off, integrators/taylor.hpp): the baseline of the graded
// default, measured in the same run.
//
//   bench_orbit_integrators [--benchmark_filter=BM_Orbit/N]   (one core: the solver is serial;
//   N indexes `cases` below)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <ctime>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/integrators/taylor.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {
namespace {

/// CPU seconds of this process (the solver is serial; on a shared machine wall time is not the
/// measure).
double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct timed {
    std::string period, action;
    double seconds = 0, cpu = 0, steps = 0, order = 0;
    std::string status;
};

template <class Real>
timed solve(const std::string& energy, arm a, orbit_integrator integrator, orbit_method method) {
    const double_pendulum<Real> model;
    orbit_options<Real> options;
    options.method = method;
    options.integrator = integrator;
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    const auto o = solve_saddle_orbit(model, a, parse_real<Real>(energy, "E"), options);
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = cpu_seconds();
    return {to_decimal(o.period, full_digits(o.period)),
            to_decimal(o.action, full_digits(o.action)),
            std::chrono::duration<double>(t1 - t0).count(),
            c1 - c0,
            static_cast<double>(o.steps),
            static_cast<double>(o.order),
            to_string(o.status)};
}

struct orbit_case {
    int digits;  ///< 0: quad, else mp:digits
    const char* energy;
    arm flip_arm;
    orbit_integrator integrator;
    orbit_method method;
    bool uniform = false;  ///< every Taylor coefficient at the working precision
};

constexpr auto T = orbit_integrator::taylor;
constexpr auto G = orbit_integrator::gauss_legendre;
constexpr auto P = orbit_method::periodic;
constexpr auto S = orbit_method::symmetric;
// arm 1's family starts at E = 4 (its saddle): its counterpart of arm 2's E = 4 is E = 5
// NOTE: Gauss-Legendre at mp:100 near E_max (periodic: > 45 min) and at mp:300 is left out
const orbit_case cases[] = {
    {0, "4", arm::two, T, P},         {0, "4", arm::two, G, P},
    {0, "4", arm::two, T, S},         {0, "4", arm::two, G, S},
    {0, "5.95", arm::two, T, P},      {0, "5.95", arm::two, G, P},
    {0, "5.95", arm::one, T, P},      {0, "5.95", arm::one, G, P},
    {100, "4", arm::two, T, P},       {100, "4", arm::two, G, P},
    {100, "4", arm::two, T, S},       {100, "4", arm::two, G, S},
    {100, "5", arm::one, T, P},       {100, "5", arm::one, T, S},
    {100, "5.95", arm::two, T, P},    {100, "5.95", arm::two, T, S},
    {100, "5.95", arm::two, G, S},    {100, "5.95", arm::one, T, P},
    {100, "5.95", arm::one, T, S},    {300, "4", arm::two, T, S},
    {300, "4", arm::two, T, P},       {100, "4", arm::two, T, P, true},
    {300, "4", arm::two, T, S, true}, {300, "4", arm::two, T, P, true},
};

void BM_Orbit(benchmark::State& state) {
    const orbit_case& c = cases[state.range(0)];
    const precision p = c.digits == 0 ? precision{real_kind::quad} : mp_precision(c.digits);
    timed o;
    {
        const taylor::graded_precision_scope graded(!c.uniform);
        for (auto _ : state)
            o = dispatch(p, [&]<class Real>() {
                return solve<Real>(c.energy, c.flip_arm, c.integrator, c.method);
            });
    }
    // the reference: Taylor, symmetric, 20 more digits
    const int ref_digits = (c.digits == 0 ? 34 : c.digits) + 20;
    const timed ref = dispatch(mp_precision(ref_digits), [&]<class Real>() {
        return solve<Real>(c.energy, c.flip_arm, orbit_integrator::taylor, orbit_method::symmetric);
    });
    state.counters["seconds"] = o.seconds;
    state.counters["cpu_seconds"] = o.cpu;
    state.counters["digits_T"] = correct_digits(o.period, ref.period);
    state.counters["digits_F"] = correct_digits(o.action, ref.action);
    state.counters["steps"] = o.steps;
    state.counters["order"] = o.order;
    const std::string label = precision_name(p) + " E=" + c.energy + " arm " +
                              to_string(c.flip_arm) + " " + to_string(c.integrator) + " " +
                              to_string(c.method) + (c.uniform ? " uniform" : "") + " " + o.status;
    state.SetLabel(label);
    std::printf("# %s: %.3f s (CPU %.3f s), digits T %.1f F %.1f, %g steps, order %g\n",
                label.c_str(), o.seconds, o.cpu, correct_digits(o.period, ref.period),
                correct_digits(o.action, ref.action), o.steps, o.order);
    std::fflush(stdout);
}
BENCHMARK(BM_Orbit)
    ->DenseRange(0, static_cast<int>(std::size(cases)) - 1)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace flipflux

BENCHMARK_MAIN();
