// Proven enclosures (certified/), the expensive checks (label "verify"): just above each saddle
// (E_s + 1e-20, where the energy ball's radius is amplified and the precision loop raises the
// precision), the radius at mp:30 ... mp:60 (both arms), and the cost of a proof at mp:50,
// mp:100 and mp:300 per quantity (omega, flux-upright, rate-upright, flux-approx, rate-approx),
// printed for docs/verification.md. Each enclosure must contain the value of the
// existing (non-rigorous) route at 20 more digits.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/quantities/registry.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

model_text rigid_pendulum() {  // alpha = 2, beta = 0.9: saddles 1.8 and 4, E_max = 5.8
    model_text t;
    t.m1 = "1", t.m2 = "1.5", t.L1 = "1", t.L2 = "1.2", t.a1 = "0.5", t.a2 = "0.6";
    t.I1 = "0.0833", t.I2 = "0.18";
    return t;
}

std::string reference_value(const std::string& quantity, const model_text& t, arm a,
                            const std::string& energy, int digits, const std::string& method = "") {
    return dispatch(mp_precision(digits), [&]<class Real>() {
        const double_pendulum<Real> model = make_model<Real>(t);
        return to_decimal(find_quantity(quantity)
                              .evaluate(model, a, parse_real<Real>(energy, "energy"), method)
                              .value);
    });
}

void check(const std::string& quantity, const model_text& t, arm a, const std::string& energy,
           int digits) {
    SCOPED_TRACE(quantity + " arm " + to_string(a) + " at E = " + energy + ", " +
                 std::to_string(digits) + " digits");
    const certified_enclosure e = certified_value(quantity, t, a, energy, digits);
    const std::string ref = reference_value(quantity, t, a, energy, digits + 20);
    EXPECT_TRUE(enclosure_contains(e, ref))
        << "[" << e.mid << " +/- " << e.radius << "] does not contain " << ref;
    if (e.mid != "0") {
        EXPECT_GE(e.proven_digits, digits - 10) << e.radius;
    }
}

TEST(CertifiedVerify, JustAboveEachSaddle) {
    for (const char* energy : {"2.00000000000000000001", "4.00000000000000000001"})
        for (const char* q :
             {"omega", "flux-upright", "rate-upright", "flux-approx", "rate-approx"})
            for (arm a : {arm::one, arm::two})
                check(q, model_text{}, a, energy, 30);
    for (const char* energy : {"1.80000000000000000001", "4.00000000000000000001"})
        for (const char* q :
             {"omega", "flux-upright", "rate-upright", "flux-approx", "rate-approx"})
            for (arm a : {arm::one, arm::two})
                check(q, rigid_pendulum(), a, energy, 30);
}

TEST(CertifiedVerify, RadiusFollowsThePrecision) {
    for (int digits : {30, 40, 50, 60})
        for (const char* energy : {"1.5", "3.2", "5.5", "7.25"})
            for (const char* q :
                 {"omega", "flux-upright", "rate-upright", "flux-approx", "rate-approx"})
                for (arm a : {arm::one, arm::two})
                    if (a == arm::two || std::string(q) != "omega")  // omega has no arm
                        check(q, rigid_pendulum(), a, energy, digits);
}

TEST(CertifiedVerify, ApproxFluxContainsTheMomentumRoute) {
    // the momentum route shares only K with the enclosure (its momentum integral is done by
    // Gauss-Kronrod in the velocity angle, not by the closed form sqrt(2K Q))
    for (const model_text& t : {model_text{}, rigid_pendulum()})
        for (arm a : {arm::one, arm::two})
            for (const char* energy : {"4.3", "5.5", "7.25"}) {
                SCOPED_TRACE(std::string("arm ") + to_string(a) + " at E = " + energy);
                const certified_enclosure e = certified_value("flux-approx", t, a, energy, 30);
                const std::string ref =
                    reference_value("flux-approx", t, a, energy, 50, "momentum");
                EXPECT_TRUE(enclosure_contains(e, ref))
                    << "[" << e.mid << " +/- " << e.radius << "] does not contain " << ref;
            }
}

TEST(CertifiedVerify, SecondsPerProof) {
    // the energies; each proof timed alone (one core), with its proven digits
    for (int digits : {50, 100, 300}) {
        for (const char* q :
             {"omega", "flux-upright", "rate-upright", "flux-approx", "rate-approx"}) {
            double worst = 0;
            int fewest = 1 << 30;
            for (const char* energy : {"0.5", "2.5", "3.2", "4.3", "5.5", "5.99", "6.01", "12"}) {
                const auto start = std::chrono::steady_clock::now();
                const certified_enclosure e =
                    certified_value(q, model_text{}, arm::two, energy, digits);
                const double s =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                worst = std::max(worst, s);
                if (e.mid != "0") fewest = std::min(fewest, e.proven_digits);
                EXPECT_GE(e.proven_digits, digits - 10) << q << " at " << energy;
            }
            std::printf(
                "certified %s at mp:%d: at most %.3g s per proof, at least %d proven digits "
                "(E = 0.5 ... 12)\n",
                q, digits, worst, fewest);
        }
    }
}

}  // namespace
}  // namespace flipflux
