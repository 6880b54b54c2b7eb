// The paired flip-count check of tests/ensemble/test_taylor_ensemble.cpp
// (TaylorEnsemble.FlipCountsAgreeWithDop853OnTheSameStates) over many seeds: E = 4.3, T = 300, the
// same PAIRS initial states integrated by DOP853 at rtol 1e-10 and by the Taylor lanes at 1e-12;
// per seed and criterion (arm-2 upright and approximate-curve flips) the mean paired difference
// (Taylor - DOP853), its standard error from the pairs and their ratio z (2026-12-03, thirtieth
// session: bench/results/taylor_jet_loads_zen5_2026-12-03.txt). Build against a release tree:
//   g++ -std=gnu++20 -O2 -DPAIRS=64 -I include -isystem /usr/include/eigen3 -fopenmp \
//     bench/results/taylor_dop853_paired_seeds.cpp -Lbuild/release \
//     -Wl,-rpath,$PWD/build/release -lflipflux -lmpfr -lgmp -lquadmath -o /tmp/paired
//   /tmp/paired FIRST_SEED END_SEED
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/flip_detector.hpp"

#ifndef PAIRS
#define PAIRS 64
#endif

using namespace flipflux;

int main(int argc, char** argv) {
    if (argc < 3) return 2;
    const int first = std::atoi(argv[1]), end = std::atoi(argv[2]);
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    const std::vector<ensemble_criterion> criteria{
        {"upright", make_flip_detector(upright_curve<double>{arm::two}, flow)},
        {"approx", make_flip_detector(approximate_saddle_curve(m, arm::two), flow)}};
    for (int seed = first; seed < end; ++seed) {
        ensemble_options o;
        o.energy = 4.3;
        o.trajectories = PAIRS;
        o.time = 300;
        o.seed = static_cast<std::uint64_t>(seed);
        o.chaos = false;
        o.rtol = 1e-10;
        const ensemble_result dop = run_ensemble(m, o, criteria);
        o.method = integration_method::taylor;
        o.rtol = 1e-12;
        const ensemble_result tay = run_ensemble(m, o, criteria);
        for (std::size_t c = 0; c < criteria.size(); ++c) {
            double sum = 0, sum2 = 0, total = 0;
            for (std::size_t i = 0; i < PAIRS; ++i) {
                const double d = static_cast<double>(tay.trajectories[i].flips(c)) -
                                 static_cast<double>(dop.trajectories[i].flips(c));
                sum += d;
                sum2 += d * d;
                total += static_cast<double>(dop.trajectories[i].flips(c));
            }
            const double mean = sum / PAIRS, var = (sum2 - PAIRS * mean * mean) / (PAIRS - 1);
            const double se = std::sqrt(var / PAIRS);
            std::printf("seed %d %s total %.0f mean %.3f se %.3f z %.2f\n", seed,
                        criteria[c].name.c_str(), total, mean, se, mean / se);
        }
    }
}
