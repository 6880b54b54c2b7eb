// The exact check of the whole chain -- sampler, integrator, crossing detection, flux and volume
// (issue 5): the microcanonical ensemble is invariant under the flow, so the expected number of
// crossings of any surface in a time T is exactly T f / Omega, for every T, ergodic or not.
// Many short trajectories with fixed seeds must therefore reproduce the predicted rate within 4
// standard errors, for every criterion, both arms, several energies, the egalitarian and a
// lopsided (rigid-link, unequal) pendulum.
//
// Predictions: the library's (quantity registry: prediction/ and orbits/), required for every
// criterion; for the upright and approximate curves they must also agree with the independent
// quadrature of ensemble_reference.hpp.
// Tolerance: rtol = 1e-7. A crossing is miscounted only if the integration error (~1e-7 per
// unit time; energy drift < 1e-5 over T = 10) moves it across the ends of [0, T] or through a
// grazing pair: a relative bias ~1e-6, far below the ~2 % statistical error of these ensembles.
// Sizes fit the -O0 coverage build (~1 minute); FLIPFLUX_EXACT_SCALE=k multiplies the number of
// trajectories (k = 10 reproduces the 20,000-trajectory scale for the report).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ensemble_reference.hpp"
#include "flipflux/ensemble/statistics.hpp"
#include "flipflux/study/criteria.hpp"
#include "pendulums.hpp"

namespace flipflux::verification {
namespace {

std::uint64_t scale() {
    const char* s = std::getenv("FLIPFLUX_EXACT_SCALE");
    const long k = s ? std::atol(s) : 1;
    return k > 0 ? static_cast<std::uint64_t>(k) : 1;
}

struct named_criterion {
    arm a;
    std::string name;
};

// The reference rate f / Omega by the independent quadrature (nullopt: no closed curve here).
std::optional<double> reference_rate(const double_pendulum<double>& m, arm a,
                                     const std::string& name, double E) {
    if (name == "upright") return curve_flux(m, upright_curve<double>{a}, E) / phase_volume(m, E);
    if (name == "approx")
        return curve_flux(m, approximate_saddle_curve(m, a), E) / phase_volume(m, E);
    return std::nullopt;
}

// Runs one ensemble with all criteria and checks each against its prediction.
void exact_check(const char* label, const double_pendulum<double>& m, double E,
                 const std::vector<named_criterion>& wanted, std::uint64_t trajectories, double T,
                 std::uint64_t seed) {
    std::vector<ensemble_criterion> criteria;
    std::vector<double> predicted;
    for (const named_criterion& c : wanted) {
        ensemble_criterion fc = make_criterion(m, c.a, c.name, E);
        const auto lib = criterion_prediction(m, c.a, c.name, E);
        const auto ref = reference_rate(m, c.a, c.name, E);
        ASSERT_TRUE(lib) << "the library has no prediction for " << c.name;
        if (lib && ref) {
            EXPECT_NEAR(lib->value, *ref, 1e-7 * *ref) << "library vs reference " << c.name;
        }
        fc.name += "-" + to_string(c.a);
        criteria.push_back(fc);
        predicted.push_back(lib->value);
    }
    ensemble_options o;
    o.energy = E;
    o.trajectories = trajectories * scale();
    o.time = T;
    o.seed = seed;
    o.rtol = 1e-7;
    o.chaos = false;
    const ensemble_result r = run_ensemble(m, o, criteria);
    double drift = 0;
    for (const trajectory_result& t : r.trajectories)
        drift = std::max(drift, t.max_energy_drift);
    EXPECT_LT(drift, 1e-4 * E);
    for (std::size_t c = 0; c < criteria.size(); ++c) {
        const criterion_statistics s = analyze(r, c, predicted[c]);
        std::printf(
            "%-10s E = %-7.4g %-9s N = %-6llu T = %-4g predicted %.6f  simulated %.6f "
            "+- %.6f  z = %+.2f  (%llu flips, %.1f s)\n",
            label, E, criteria[c].name.c_str(), static_cast<unsigned long long>(o.trajectories), T,
            predicted[c], s.rates.mean, s.rates.standard_error, s.z_score,
            static_cast<unsigned long long>(s.flips), r.seconds);
        EXPECT_LT(std::abs(s.z_score), 4) << label << " E = " << E << " " << criteria[c].name;
        EXPECT_GT(s.flips, 300u);  // enough events for the normal approximation
    }
}

const std::vector<named_criterion> arm2{
    {arm::two, "upright"}, {arm::two, "approx"}, {arm::two, "saddle"}};
const std::vector<named_criterion> both{{arm::two, "upright"}, {arm::two, "approx"},
                                        {arm::two, "saddle"},  {arm::one, "upright"},
                                        {arm::one, "approx"},  {arm::one, "saddle"}};

TEST(ExactCheck, EgalitarianLowEnergyArm2) {
    exact_check("egalitarian", double_pendulum<double>(), 2.5, arm2, 5000, 10, 101);
}

TEST(ExactCheck, EgalitarianBothArms) {
    const double_pendulum<double> m;
    exact_check("egalitarian", m, 4.6, both, 2400, 10, 102);
    exact_check("egalitarian", m, 5.6, both, 2400, 10, 103);
}

TEST(ExactCheck, LopsidedBothArms) {
    const double_pendulum<double> m(test::lopsided_parameters());
    exact_check("lopsided", m, 3.5, arm2, 2400, 10, 104);
    exact_check("lopsided", m, 5.8, both, 2400, 10, 105);
}

// Any T: the same energy with trajectories ten times shorter.
TEST(ExactCheck, HoldsForShortTimes) {
    exact_check("egalitarian", double_pendulum<double>(), 5.0, both, 15000, 1, 106);
}

}  // namespace
}  // namespace flipflux::verification
