// The error estimates of Omega(E) and of the fluxes built on tanh-sinh quadrature
// (quadrature/tanh_sinh.inst.cpp's converged_error): against the actual errors, measured with
// 40-digit references of the same routes (in_mp), at double and quad, for the four prediction
// pendulums (the light first link's nearly singular mass matrix among them) at energies in the
// well, between and just above the saddles, near and above the maximum. Every estimate bounds the
// actual error and is within 100x of it, or of the rounding level eps |value| where the actual
// error happens to lie below that (an estimate cannot see luck).
#include <map>
#include <string>
#include <vector>

#include "flipflux/core/decimal.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/prediction/upright_flux.hpp"
#include "pendulums.hpp"

namespace flipflux {
namespace {

template <class Real>
class ErrorEstimates : public test::real_test<Real> {};
using fixed_types = ::testing::Types<double, quad>;
TYPED_TEST_SUITE(ErrorEstimates, fixed_types, test::real_name);

// The energies of a pendulum: fractions of E_max deep in the well, between and above the saddles
// and above the maximum, and 1e-4 (relative) on either side of each saddle level and below E_max,
// where the rounding of E - V is amplified (a review found an underestimate at E_max - 1e-4 of
// the last pendulum below).
std::vector<double> energies_of(const double_pendulum<double>& m) {
    std::vector<double> e;
    // (1e-12 and 1e-7: the tiny allowed regions, where Boost 1.74's unscaled level difference
    // made Omega's estimate 1e5 to 1e11 times its error)
    for (const double x : {1e-12, 1e-7, 0.0003, 0.52, 0.8, 1.3})
        e.push_back(x * m.maximum_energy());
    for (const arm a : {arm::one, arm::two})
        for (const double s : {1 - 1e-4, 1 + 1e-4})
            e.push_back(m.saddle_energy(a) * s);
    e.push_back(m.maximum_energy() * (1 - 1e-4));
    return e;
}

// The prediction pendulums and a light first link under a long second arm (|m| = 21).
std::vector<test::model_spec> specs() {
    std::vector<test::model_spec> all = test::model_specs();
    all.push_back({"light-link-long-arm", "0.0625", "1", "1", "3", "1", "3", "0", "0", "1"});
    return all;
}

// The 40-digit references, once for double and quad (keyed by quantity, pendulum and energy).
std::map<std::string, std::string>& reference_cache() {
    static std::map<std::string, std::string> cache;
    return cache;
}

template <class Real, class F, class G>
void check_estimates(const char* what, F evaluate, G reference) {
    using std::abs;
    int checked = 0;
    for (const test::model_spec& spec : specs()) {
        const double_pendulum<Real> model = test::make_model<Real>(spec);
        for (const double e : energies_of(test::make_model<double>(spec))) {
            // a double energy, so that double and quad share the references
            const Real E = Real(e);
            const std::string e_text = to_decimal(E, 60);
            const prediction_result<Real> r = evaluate(model, E);
            if (r.value == 0) continue;  // below the level where it starts
            std::map<std::string, std::string>& cache = reference_cache();
            const std::string key = std::string(what) + "/" + spec.name + "/" + e_text;
            if (!cache.count(key))
                cache[key] = test::in_mp(40, [&] {
                    const double_pendulum<mp> m = test::make_model<mp>(spec);
                    return to_decimal(reference(m, parse_real<mp>(e_text, "E")), 40);
                });
            const std::string& exact = cache[key];
            const Real actual = abs(r.value - parse_real<Real>(exact, "reference"));
            const Real floor = test::eps<Real>() * abs(r.value);
            SCOPED_TRACE(std::string(what) + ", " + spec.name + ", E = " + e_text);
            EXPECT_GE(r.error_estimate, actual);
            EXPECT_LE(r.error_estimate, 100 * (actual > floor ? actual : floor));
            ++checked;
        }
    }
    EXPECT_GT(checked, 20);
}

TYPED_TEST(ErrorEstimates, PhaseVolumeWithin100xOfTheActualError) {
    using Real = TypeParam;
    check_estimates<Real>(
        "omega", [](const double_pendulum<Real>& m, const Real& E) { return phase_volume(m, E); },
        [](const double_pendulum<mp>& m, const mp& E) { return phase_volume(m, E).value; });
}

TYPED_TEST(ErrorEstimates, UprightFluxWithin100xOfTheActualError) {
    using Real = TypeParam;
    check_estimates<Real>(
        "flux-upright",
        [](const double_pendulum<Real>& m, const Real& E) { return upright_flux(m, arm::two, E); },
        [](const double_pendulum<mp>& m, const mp& E) {
            return upright_flux(m, arm::two, E).value;
        });
}

}  // namespace
}  // namespace flipflux
