// Proven enclosures of flux-approx and rate-approx (certified/curve_flux_enclosure.cpp): each
// must contain the value of the existing (non-rigorous) kinetic route computed 20 digits beyond
// the enclosure's precision (an independent route: tanh-sinh over pieces found by sampling and
// TOMS 748, no ball arithmetic), and reach the relative radius 10^(-N + 10) at mp:N; both arms,
// the paper's pendulum and a rigid-link pendulum with unequal masses, in every regime of the
// energy (below the saddle, between the saddles, between the upper saddle and E_max, above E_max,
// just above a saddle, exactly at the saddle and at E_max, at an inexact E_max).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/quantities/registry.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

/// alpha = 2, beta = 0.9: saddles 1.8 (arm 2) and 4 (arm 1), E_max = 5.8.
model_text rigid_pendulum() {
    model_text t;
    t.m1 = "1", t.m2 = "1.5", t.L1 = "1", t.L2 = "1.2", t.a1 = "0.5", t.a2 = "0.6";
    t.I1 = "0.0833", t.I2 = "0.18";
    return t;
}

std::string reference_value(const std::string& quantity, const model_text& t, arm a,
                            const std::string& energy, int digits) {
    return dispatch(mp_precision(digits), [&]<class Real>() {
        const double_pendulum<Real> model = make_model<Real>(t);
        return to_decimal(find_quantity(quantity)
                              .evaluate(model, a, parse_real<Real>(energy, "energy"), "")
                              .value);
    });
}

void expect_proven(const std::string& quantity, const model_text& t, arm a,
                   const std::string& energy, int digits) {
    SCOPED_TRACE(quantity + " arm " + to_string(a) + " at E = " + energy + ", " +
                 std::to_string(digits) + " digits");
    const certified_enclosure e = certified_value(quantity, t, a, energy, digits);
    const std::string ref = reference_value(quantity, t, a, energy, digits + 20);
    EXPECT_TRUE(enclosure_contains(e, ref))
        << "[" << e.mid << " +/- " << e.radius << "] does not contain " << ref;
    if (e.mid != "0") {
        EXPECT_GE(e.proven_digits, digits - 10) << e.radius;
    } else {
        EXPECT_EQ(e.radius, "0");  // an inaccessible curve: exactly 0
    }
}

struct approx_case {
    const char* name;
    bool rigid;
    const char* energy;
};

class ApproxFluxRegimes : public ::testing::TestWithParam<approx_case> {};

TEST_P(ApproxFluxRegimes, ContainTheKineticRouteAndReachTheRadius) {
    const approx_case c = GetParam();
    const model_text t = c.rigid ? rigid_pendulum() : model_text{};
    for (arm a : {arm::one, arm::two})
        expect_proven("flux-approx", t, a, c.energy, 30);
}

INSTANTIATE_TEST_SUITE_P(Paper, ApproxFluxRegimes,
                         ::testing::Values(approx_case{"BelowBothSaddles", false, "1.5"},
                                           approx_case{"BetweenTheSaddles", false, "3.2"},
                                           approx_case{"BelowTheMaximum", false, "5.5"},
                                           approx_case{"AboveTheMaximum", false, "7.25"},
                                           approx_case{"JustAboveTheLowerSaddle", false,
                                                       "2.00000000000000000001"},
                                           approx_case{"AtTheLowerSaddle", false, "2"},
                                           approx_case{"AtTheUpperSaddle", false, "4"},
                                           approx_case{"AtTheMaximum", false, "6"}),
                         [](const auto& info) { return std::string(info.param.name); });

INSTANTIATE_TEST_SUITE_P(RigidLinks, ApproxFluxRegimes,
                         ::testing::Values(approx_case{"BetweenTheSaddles", true, "2.9"},
                                           approx_case{"BelowTheMaximum", true, "5.1"},
                                           approx_case{"AboveTheMaximum", true, "9.3"},
                                           approx_case{"JustAboveTheUpperSaddle", true,
                                                       "4.00000000000000000001"},
                                           // E_max = 5.8 is not a dyadic: the energy ball
                                           // straddles it (the union of both sides)
                                           approx_case{"AtTheInexactMaximum", true, "5.8"}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(ApproxFluxEnclosure, RadiusFollowsTheRequestedDigits) {
    for (int digits : {30, 45, 60})
        expect_proven("flux-approx", rigid_pendulum(), arm::two, "3.7", digits);
}

TEST(ApproxFluxEnclosure, TheRateIsTheFluxOverThePhaseVolume) {
    expect_proven("rate-approx", rigid_pendulum(), arm::one, "5.1", 30);
    expect_proven("rate-approx", model_text{}, arm::one, "3.2", 30);  // below the saddle: 0
}

TEST(ApproxFluxEnclosure, AWrongValueLiesOutside) {
    // the test double: f2 off by 1e-25 relatively (a formula that agrees to 25 digits) fails
    const certified_enclosure e = certified_value("flux-approx", model_text{}, arm::two, "5.5", 30);
    const std::string ref = reference_value("flux-approx", model_text{}, arm::two, "5.5", 50);
    const std::string wrong = dispatch(mp_precision(50), [&]<class Real>() {
        const Real v = parse_real<Real>(ref, "v");
        return to_decimal(Real(v + v * parse_real<Real>("1e-25", "relative error")));
    });
    EXPECT_TRUE(enclosure_contains(e, ref));
    EXPECT_FALSE(enclosure_contains(e, wrong));
}

TEST(ApproxFluxEnclosure, EvalCertifyPrintsTheEnclosure) {
    const test::command_result r =
        test::run_flipflux("eval flux-approx --energy 5.5 --arm 1 --precision mp:30 --certify");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("enclosure")) << r.out;
    EXPECT_GE(j["enclosure"]["proven_digits"].get<int>(), 20);
    EXPECT_TRUE(has_certified_enclosure("rate-approx"));
}

}  // namespace
}  // namespace flipflux
