// Saddle-orbit quantities: the error estimates that `flipflux eval` publishes are honest up to
// E_max - 1e-6. For every orbit quantity (period, action, flux-saddle, rate-saddle, multiplier,
// stability-index), both arms and both methods, |value - reference| <= estimate, the reference
// computed in a higher precision by the symmetric formulation: double against quad on a grid up
// to E_max - 1e-6, quad against mp:40 on a coarser grid (mp orbits near E_max take minutes).
// The multiplier grows to ~1e26 there, and its estimate must follow (issue 20: it was too small
// by up to 1e5 in double).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

const char* const orbit_quantities[] = {"period",      "action",     "flux-saddle",
                                        "rate-saddle", "multiplier", "stability-index"};

struct value_text {
    bool ok = false;
    std::string value;
    double estimate = 0;
};

template <class Real>
value_text evaluate(const quantity& q, arm a, const std::string& energy, const std::string& m) {
    const double_pendulum<Real> model;
    try {
        const auto v = q.evaluate(model, a, parse_real<Real>(energy, "energy"), m);
        return {true, to_decimal(v.value, full_digits(v.value)),
                static_cast<double>(v.error_estimate)};
    } catch (const std::exception& e) {  // elliptic orbits have no real multiplier
        return {false, e.what(), 0};
    }
}

value_text evaluate_in(const precision& p, const quantity& q, arm a, const std::string& energy,
                       const std::string& m) {
    if (p.kind == real_kind::mp) {
        const precision_scope scope(p);
        return evaluate<mp>(q, a, energy, m);
    }
    return dispatch(p, [&]<class Real>() { return evaluate<Real>(q, a, energy, m); });
}

/// Checks every orbit quantity at `energy` in `lo` (both methods) against the symmetric orbit in
/// `hi`; prints the worst ratio error / estimate.
void check(const precision& lo, const precision& hi, arm a, const std::string& energy) {
    for (const char* name : orbit_quantities) {
        const quantity& q = find_quantity(name);
        const value_text ref = evaluate_in(hi, q, a, energy, "symmetric");
        for (const char* method : {"periodic", "symmetric"}) {
            const value_text v = evaluate_in(lo, q, a, energy, method);
            EXPECT_EQ(v.ok, ref.ok) << name << " " << method << " arm " << to_string(a)
                                    << " E = " << energy << ": " << v.value << " / " << ref.value;
            if (!v.ok || !ref.ok) continue;
            const double scale = std::abs(std::stod(ref.value));
            const double error = decimal_relative_error(v.value, ref.value) * scale;
            // the reference's own error counts too (it is far smaller, but not zero)
            const double bound = v.estimate + ref.estimate;
            std::printf(
                "  %-4s arm %s E = %-9s %-15s %-9s |error| %.2e  estimate %.2e  ratio %.2f\n",
                precision_name(lo).c_str(), to_string(a).c_str(), energy.c_str(), name, method,
                error, v.estimate, bound > 0 ? error / bound : 0.0);
            EXPECT_LE(error, bound)
                << name << " " << method << " in " << precision_name(lo) << " arm " << to_string(a)
                << " E = " << energy << ": " << v.value << " against " << ref.value;
        }
    }
}

// NOTE: the energies are dyadic (exact in double): a decimal such as 2.01 is rounded to double
// before E - E_s is formed, which moves the orbit by |dF/dE| ulp(E) (relative 2e-14 at
// E_s + 0.01): a property of the input, not of the solver, whose estimates are checked here.
TEST(OrbitsEstimates, DoubleAgainstQuadUpToTheMaximum) {
    // 6 - 2^-k: 6 - 0.0078, 6 - 0.00098, 6 - 6.1e-5, 6 - 7.6e-6, 6 - 9.5e-7
    const std::vector<std::string> tail{"5.5",
                                        "5.90625",
                                        "5.9921875",
                                        "5.9990234375",
                                        "5.99993896484375",
                                        "5.99999237060546875",
                                        "5.99999904632568359375"};
    for (arm a : {arm::two, arm::one}) {
        std::vector<std::string> energies{a == arm::two ? "2.0078125" : "4.0078125",
                                          a == arm::two ? "3.5" : "4.8125"};
        energies.insert(energies.end(), tail.begin(), tail.end());
        for (const std::string& e : energies)
            check(precision{real_kind::double_}, precision{real_kind::quad}, a, e);
    }
}

TEST(OrbitsEstimates, QuadAgainstMp40) {
    for (arm a : {arm::two, arm::one})
        for (const char* e : {a == arm::two ? "2.5" : "4.5", "5.5", "5.95"})
            check(precision{real_kind::quad}, mp_precision(40), a, e);
}

}  // namespace
}  // namespace flipflux
