// Model parameters as decimal text (command-line options, scene files), parsed in the working
// precision (never through a double).
#pragma once

#include <string>
#include <string_view>

#include "flipflux/core/decimal.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

/// Physical parameters as text; empty a1/a2 mean "the link's length" (point masses).
struct model_text {
    std::string m1 = "1", m2 = "1", L1 = "1", L2 = "1", a1, a2, I1 = "0", I2 = "0", g = "1";
    bool is_default() const {
        return m1 == "1" && m2 == "1" && L1 == "1" && L2 == "1" && a1.empty() && a2.empty() &&
               I1 == "0" && I2 == "0" && g == "1";
    }
};

/// Parses every parameter in Real; errors name the field "<prefix><parameter>" (e.g. "m1").
template <class Real>
physical_parameters<Real> parse_parameters(const model_text& t, std::string_view prefix = "") {
    const std::string p(prefix);
    physical_parameters<Real> out;
    out.m1 = parse_real<Real>(t.m1, p + "m1");
    out.m2 = parse_real<Real>(t.m2, p + "m2");
    out.L1 = parse_real<Real>(t.L1, p + "L1");
    out.L2 = parse_real<Real>(t.L2, p + "L2");
    out.a1 = t.a1.empty() ? out.L1 : parse_real<Real>(t.a1, p + "a1");
    out.a2 = t.a2.empty() ? out.L2 : parse_real<Real>(t.a2, p + "a2");
    out.I1 = parse_real<Real>(t.I1, p + "I1");
    out.I2 = parse_real<Real>(t.I2, p + "I2");
    out.g = parse_real<Real>(t.g, p + "g");
    return out;
}

/// The critical energies of the decimal parameters, exactly: 2 alpha = 2 g (m1 a1 + m2 L1),
/// 2 beta = 2 g m2 a2 and their sum (core/decimal.hpp's exact decimal arithmetic). Empty texts
/// (the levels then carry no decimal) when a result lies beyond the decimal exponent range.
inline critical_decimals critical_decimals_of(const model_text& t) {
    try {
        const std::string& a1 = t.a1.empty() ? t.L1 : t.a1;
        const std::string& a2 = t.a2.empty() ? t.L2 : t.a2;
        const std::string alpha = decimal_product(
            t.g, decimal_sum(decimal_product(t.m1, a1), decimal_product(t.m2, t.L1)));
        const std::string beta = decimal_product(t.g, decimal_product(t.m2, a2));
        const std::string two_alpha = decimal_sum(alpha, alpha);
        const std::string two_beta = decimal_sum(beta, beta);
        return {two_alpha, two_beta, decimal_sum(two_alpha, two_beta)};
    } catch (const input_error&) {
        return {};
    }
}

/// The pendulum of decimal parameters: parameters rounded to Real, critical levels exact.
template <class Real>
double_pendulum<Real> make_model(const model_text& t) {
    const physical_parameters<Real> p = parse_parameters<Real>(t);  // validates the texts
    const critical_decimals exact = critical_decimals_of(t);
    if (exact.maximum.empty()) return double_pendulum<Real>(p);
    return double_pendulum<Real>(p, exact);
}

}  // namespace flipflux
