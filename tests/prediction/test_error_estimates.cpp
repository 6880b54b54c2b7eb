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

// The prediction pendulums, a light first link under a long second arm (|m| = 21) and a second
// arm 100 times heavier (|m| = 100: its marginal's kinks, split off since 2026-11-30, had been
// inside the integrals).
std::vector<test::model_spec> specs() {
    std::vector<test::model_spec> all = test::model_specs();
    all.push_back({"light-link-long-arm", "0.0625", "1", "1", "3", "1", "3", "0", "0", "1"});
    all.push_back({"heavy-second-arm", "1", "100", "1", "1", "1", "1", "0", "0", "1"});
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

// Two nearly singular pendulums of an independent cross-check, with its own derivation's Omega
// in mpmath (its Lagrangian, ellipe; bench/results/crosscheck_2026-11-30/cmp_D.jsonl and
// cmp_E2.jsonl, omega rows), not flipflux's routes: a lower link 2^20 times heavier (|m| = 2^21)
// and 2^20 times lighter, in the well, between the saddles and just below arm 2's.
struct singular_point {
    const char *energy, *omega;
};
const std::vector<std::pair<test::model_spec, std::vector<singular_point>>>& singular_cases() {
    static const std::vector<std::pair<test::model_spec, std::vector<singular_point>>> cases{
        {{"heavy-lower-link", "1", "1048576", "0.5", "2", "0.25", "2", "0.0625", "0",
          "0.0009765625"},
         {{"512.000244140625", "13465167.945065301487404054986292499680942245998088"},
          {"1025.02448876953121725819073617458343505859375",
           "36888807.834332557105060020991709000406647319758639"},
          {"2560.000244140625", "82792423.332620088338911120565841758558957267185987"},
          {"4095.9999995903999661095440387725830078125",
           "128747794.91559842335768219328840095364220509866216"}}},
        {{"light-lower-link", "1", "9.5367431640625e-07", "1", "0.5", "1", "0.25", "0",
          "5.960464477539063e-08", "4096"},
         {{"0.0009765625", "0.00000717939009764899752382448165857677797592473914"},
          {"0.001955078124999999784894288978875920292921364307403564453125",
           "0.0000169935009149413332800270090013325160901811435"},
          {"4.00000190734817806514911353588104248046875",
           "0.00120473678644314195717886951131908343484708292"},
          {"8192.007811680799932219088077545166015625",
           "0.085626610680771012351295533070819394594318112"}}}};
    return cases;
}

// The independent route, quadrature_2d, at double on the nearly singular pendulums (the heavy
// link: the inner integrand's near-zeros reach the inner interval's ends: 7.8e-6 off against an
// estimate of 4.2e-8 before the outer integral was split there; the light link: the inner
// interval's width rounded with th2: 1e-14 relative off, 10x its estimate, before the inner
// integral ran over th1; 30 eps off just below arm 2's saddle).
TEST(ErrorEstimates, TwoDimensionalOmegaCoversItsErrorOnNearlySingularPendulums) {
    using std::abs;
    for (const auto& [spec, points] : singular_cases()) {
        const double_pendulum<double> model = test::make_model<double>(spec);
        for (const singular_point& p : points) {
            SCOPED_TRACE(spec.name + ", E = " + p.energy);
            const prediction_result<double> r = phase_volume(
                model, parse_real<double>(p.energy, "E"), phase_volume_method::quadrature_2d);
            const double actual = abs(r.value - parse_real<double>(p.omega, "reference"));
            EXPECT_GE(r.error_estimate, actual);
            EXPECT_LE(r.error_estimate, 100 * std::max(actual, test::eps<double>() * r.value));
        }
    }
}

// The default route, elliptic, on the same pendulums at double and quad, and its cost at quad.
// The heavy link's marginal nearly kinks where th1 -+ t(th1) meets 0 or pi (branch points
// 1e-3 off the path): before the integral was split there, quad took ~5 s (1e5 evaluations) with
// an estimate of 1.3e-10 for a value good to 1e-26, and mp:40 was 5e-24 relative off
// (docs/theory.md).
TYPED_TEST(ErrorEstimates, EllipticOmegaCoversItsErrorOnNearlySingularPendulums) {
    using Real = TypeParam;
    using std::abs;
    for (const auto& [spec, points] : singular_cases()) {
        const double_pendulum<Real> model = test::make_model<Real>(spec);
        for (const singular_point& p : points) {
            SCOPED_TRACE(spec.name + ", E = " + p.energy);
            const prediction_result<Real> r = phase_volume(model, parse_real<Real>(p.energy, "E"));
            const Real actual = abs(r.value - parse_real<Real>(p.omega, "reference"));
            const Real floor = test::eps<Real>() * r.value;
            EXPECT_GE(r.error_estimate, actual);
            EXPECT_LE(r.error_estimate, 100 * (actual > floor ? actual : floor));
            // the heavy link at quad: measured 3420-6839 evaluations (graded tanh-sinh next to
            // the kinks); the unsplit integral took ~1e5
            if constexpr (std::is_same_v<Real, quad>) {
                if (spec.name == "heavy-lower-link") {
                    EXPECT_LE(r.evaluations, 10000u);
                }
            }
        }
    }
}

// The cost at quad of pendulums with a heavier second arm (|m| = m2/m1 for point masses): the
// kinks split off, every piece is one nested Clenshaw-Curtis run or a graded tanh-sinh next to a
// kink. Measured 190-382 evaluations up to m2/m1 = 10 and 382-2564 at 100 and 1e3 (before, at 0.3
// and 0.6 E_max: 255, 2530, 4549, 9099, 36397 at m2/m1 = 1, 4, 10, 100, 1e3);
// PhaseVolumeWithin100xOfTheActualError checks the values and estimates of such a pendulum
// (m2/m1 = 100).
TEST(ErrorEstimates, HeavierSecondArmsCostLittleMoreThanEqualOnesAtQuad) {
    for (const char* m2 : {"1", "4", "10", "100", "1000"}) {
        const test::model_spec spec{
            "heavier-second-arm", "1", m2, "1", "1", "1", "1", "0", "0", "1"};
        const double_pendulum<quad> model = test::make_model<quad>(spec);
        const quad e_max = model.maximum_energy();
        for (const double fraction : {0.3, 0.6, 0.9}) {
            SCOPED_TRACE(std::string("m2 = ") + m2 + ", E = " + std::to_string(fraction) +
                         " E_max");
            const prediction_result<quad> r = phase_volume(model, quad(fraction * e_max));
            EXPECT_LE(r.evaluations, std::string(m2).size() <= 2 ? 600u : 4000u);
        }
    }
}

}  // namespace
}  // namespace flipflux
