// The pilot runs of steps_for_tolerance on two quarter orbits where the Gauss-Legendre stages
// converge to another solution of their implicit equations at coarse steps (2026-11-30, fifteenth
// session; docs/limits.md, theory.md "Step counts"). For n = 4 ... 4096 equal steps: whether the
// run split a step, and its endpoint's weighted distance from the 4096-step run; then the step
// count steps_for_tolerance chooses (tolerance 1e-12). Build against a release tree:
//   g++ -O2 -std=gnu++20 -DBOOST_ALL_NO_LIB -DBOOST_MATH_PROMOTE_DOUBLE_POLICY=false -I include \
//     -isystem /usr/include/eigen3 bench/results/pilot_runs_spurious.cpp
//     build/release/libflipflux.a \ -lquadmath -lgomp -ltomlplusplus -lmpfr -lgmp -lflint-arb
//     -lflint -ldl -fopenmp -o /tmp/pilot
//   /tmp/pilot > bench/results/pilot_runs_spurious.txt
#include <cmath>
#include <cstdio>

#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/orbits/shooting.hpp"

using namespace flipflux;

int main() {
    struct shot_case {
        const char* name;
        physical_parameters<double> p;
        double excess, beta, period;
    };
    physical_parameters<double> heavy;
    heavy.m1 = 0.1793, heavy.m2 = 31.6, heavy.L1 = heavy.a1 = 0.44, heavy.L2 = heavy.a2 = 0.868;
    heavy.g = 9.81;
    physical_parameters<double> e1024;
    e1024.m1 = 1, e1024.m2 = 1024, e1024.L1 = 0.5, e1024.a1 = 0.25, e1024.I1 = 0.0625;
    e1024.L2 = e1024.a2 = 2, e1024.g = 1;
    const shot_case cases[] = {{"heavy second arm m2 = 31.6, arm 2", heavy, 190.4940213680882,
                                0.38618825969963883, 1.4203250802756493},
                               {"pendulum E's geometry m2 = 1024, arm 2", e1024, 55.758568954737598,
                                0.23640741766989562, 1.3286492257761193}};
    for (const shot_case& c : cases) {
        const double_pendulum<double> model(c.p);
        const detail::shooting_setup<double> setup(model, arm::two, c.excess, 6);
        const double quarter = c.period / 4;
        const auto x0 = setup.start(c.beta);
        const std::array<double, 5> y0{x0[0], x0[1], x0[2], x0[3], 0.0};
        const double lscale = std::max(std::abs(x0[2]), std::abs(x0[3]));
        const std::array<double, 5> scale{lscale, lscale, lscale, lscale, c.excess};
        gauss_legendre<double, 5> gl(6);
        auto run = [&](long n, long& splits) {
            std::array<double, 5> y = y0;
            const auto r = gl.integrate(orbit_flow<double>{&setup.frame}, y, quarter / n, n);
            splits = r.statistics.split_steps;
            return y;
        };
        long s = 0;
        const auto ref = run(4096, s);
        std::printf("%s, E - E_s = %.17g\n", c.name, c.excess);
        std::array<double, 5> prev{};
        for (long n = 4; n <= 2048; n *= 2) {
            const auto x = run(n, s);
            double d = 0, dprev = 0;
            for (std::size_t k = 0; k < 5; ++k) {
                d = std::max(d, std::abs(x[k] - ref[k]) / scale[k]);
                dprev = std::max(dprev, std::abs(x[k] - prev[k]) / scale[k]);
            }
            char from_half[32] = "-";
            if (n > 4) std::snprintf(from_half, sizeof from_half, "%.3e", dprev);
            std::printf(
                "  n %ld | split steps %ld | distance from 4096 steps %.3e | from n/2 steps %s\n",
                n, s, d, from_half);
            prev = x;
        }
        const auto est = steps_for_tolerance<double, 5>(orbit_flow<double>{&setup.frame}, y0,
                                                        quarter, 1e-12, 6, scale, 4);
        std::printf("  steps_for_tolerance: %ld steps (observed order %.3g)\n", est.steps,
                    est.observed_order);
    }
}
