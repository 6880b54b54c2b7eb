// The prediction quantities at mp:300 and mp:1000, and the saddle orbit at mp:150: the targets of
// arbitrary precision (relative error <= 10^-(N-10) at mp:N for every prediction quantity on its
// domain; the saddle period at mp:150 to >= 140 digits). Each value is checked against the same
// quantity in a higher precision (mp:(N + 30)) and, where one is fast enough at these precisions,
// against an independent method in the same precision (f1 by its 1-D integral route, Omega above
// E_max by its closed form). Too slow for CI (about 15 minutes in the release build): label
// "verify", run by `bash setup.sh verify` (docs/verification.md).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

struct probe {
    const char* quantity;
    arm a;
    const char* energy;
    const char* independent;  ///< another method of the quantity, or ""
};

// Omega below and above E_max; each flux and rate for arm 2 (E = 3) and arm 1 (E = 5).
const probe probes[] = {
    {"omega", arm::two, "3", ""},
    {"omega", arm::two, "20", "closed-form"},
    {"flux-upright", arm::two, "3", "integral"},
    {"flux-upright", arm::one, "5", "integral"},
    {"flux-approx", arm::two, "3", ""},
    {"flux-approx", arm::one, "5", ""},
    {"rate-upright", arm::two, "3", ""},
    {"rate-upright", arm::one, "5", ""},
    {"rate-approx", arm::two, "3", ""},
    {"rate-approx", arm::one, "5", ""},
};

struct timed_text {
    std::string value;
    double seconds = 0;
};

timed_text evaluate(const probe& p, const std::string& method, int digits) {
    const quantity& q = find_quantity(p.quantity);
    return dispatch(mp_precision(digits), [&]<class Real>() {
        const auto start = std::chrono::steady_clock::now();
        const quantity_value<Real> v =
            q.evaluate(double_pendulum<Real>(), p.a, parse_real<Real>(p.energy, "E"), method);
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return timed_text{to_decimal(v.value, full_digits(v.value)), s};
    });
}

void check_prediction_quantities(int digits) {
    const double target = digits - 10;
    for (const probe& p : probes) {
        const timed_text v = evaluate(p, "", digits);
        const timed_text ref = evaluate(p, "", digits + 30);
        const double d = correct_digits(v.value, ref.value);
        std::printf("%s arm %s E = %s: mp:%d %.1f digits against mp:%d (%.3g s)", p.quantity,
                    to_string(p.a).c_str(), p.energy, digits, d, digits + 30, v.seconds);
        EXPECT_GE(d, target) << p.quantity << " arm " << to_string(p.a) << " E " << p.energy;
        if (*p.independent != 0) {
            const timed_text other = evaluate(p, p.independent, digits);
            const double di = correct_digits(other.value, ref.value);
            std::printf(", %s %.1f digits (%.3g s)", p.independent, di, other.seconds);
            EXPECT_GE(di, target) << p.quantity << " " << p.independent;
        }
        std::printf("\n");
    }
}

TEST(HighPrecision, PredictionQuantitiesAtMp300) {
    check_prediction_quantities(300);
}

TEST(HighPrecision, PredictionQuantitiesAtMp1000) {
    check_prediction_quantities(1000);
}

/// T and F of the arm-2 saddle orbit at E = 4 in mp:digits by `method` (the default integrator,
/// Taylor series), as text.
std::pair<timed_text, std::string> saddle_orbit_at(int digits, orbit_method method) {
    return dispatch(mp_precision(digits), [&]<class Real>() {
        const auto start = std::chrono::steady_clock::now();
        orbit_options<Real> o;
        o.method = method;
        const saddle_orbit<Real> s =
            solve_saddle_orbit(double_pendulum<Real>(), arm::two, Real(4), o);
        EXPECT_EQ(s.status, orbit_status::converged);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return std::pair{timed_text{to_decimal(s.period, full_digits(s.period)), seconds},
                         to_decimal(s.action, full_digits(s.action))};
    });
}

TEST(HighPrecision, SaddlePeriodAtMp150) {
    // two precisions and two formulations (other unknowns, conditions and Newton iteration)
    const auto [t150, f150] = saddle_orbit_at(150, orbit_method::symmetric);
    const auto [t200, f200] = saddle_orbit_at(200, orbit_method::periodic);
    const double dT = correct_digits(t150.value, t200.value), dF = correct_digits(f150, f200);
    std::printf(
        "saddle orbit arm 2 E = 4, symmetric shooting in mp:150: T %.1f digits, F %.1f digits "
        "against periodic shooting in mp:200 (%.3g s at mp:150, %.3g s at mp:200)\n",
        dT, dF, t150.seconds, t200.seconds);
    EXPECT_GE(dT, 140);
    EXPECT_GE(dF, 140);
}

}  // namespace
}  // namespace flipflux
