// Model parameters as decimal text (command-line options, scene files), parsed in the working
// precision (never through a double).
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "flipflux/core/decimal.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

/// Physical parameters as text; empty a1/a2 mean "the link's length" (point masses). Defaults:
/// parameter_fields' default texts.
struct model_text {
    std::string m1, m2, L1, L2, a1, a2, I1, I2, g;
    model_text();
    bool is_default() const;
};

/// The members of model_text in parameter_fields' order: t.*text_members[i].
inline constexpr std::array<std::string model_text::*, parameter_count> text_members{
    &model_text::m1, &model_text::m2, &model_text::L1, &model_text::L2, &model_text::a1,
    &model_text::a2, &model_text::I1, &model_text::I2, &model_text::g};

inline model_text::model_text() {
    for (std::size_t i = 0; i < parameter_count; ++i)
        this->*text_members[i] = std::string(parameter_fields[i].default_text);
}

inline bool model_text::is_default() const {
    for (std::size_t i = 0; i < parameter_count; ++i)
        if (this->*text_members[i] != parameter_fields[i].default_text) return false;
    return true;
}

/// The text of parameter i with the default rule applied (an empty a1 is L1's text): the value
/// the parameter has.
inline const std::string& resolved_text(const model_text& t, std::size_t i) {
    const std::string& own = t.*text_members[i];
    const int d = parameter_fields[i].defaults_to;
    return own.empty() && d >= 0 ? t.*text_members[static_cast<std::size_t>(d)] : own;
}

/// Parses every parameter in Real; errors name the field "<prefix><parameter>" (e.g. "m1").
template <class Real>
physical_parameters<Real> parse_parameters(const model_text& t, std::string_view prefix = "") {
    physical_parameters<Real> out;
    for (std::size_t i = 0; i < parameter_count; ++i) {
        const std::string& own = t.*text_members[i];
        const int d = parameter_fields[i].defaults_to;
        out.*parameter_members<Real>[i] =
            own.empty() && d >= 0
                ? out.*parameter_members<Real>[static_cast<std::size_t>(d)]
                : parse_real<Real>(own,
                                   std::string(prefix) + std::string(parameter_fields[i].name));
    }
    return out;
}

/// The critical energies of the decimal parameters, exactly: 2 alpha = 2 g (m1 a1 + m2 L1),
/// 2 beta = 2 g m2 a2 and their sum (core/decimal.hpp's exact decimal arithmetic). Empty texts
/// (the levels then carry no decimal) when a result lies beyond the decimal exponent range.
inline critical_decimals critical_decimals_of(const model_text& t) {
    try {
        const std::string& a1 = resolved_text(t, static_cast<std::size_t>(parameter_index("a1")));
        const std::string& a2 = resolved_text(t, static_cast<std::size_t>(parameter_index("a2")));
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
