// An energy as the user wrote it: its value in Real and the part of the decimal input Real could
// not hold, so that the distance to a critical level (a saddle energy, E_max) is exact.
//
// Just above a saddle the quantities scale with E - E_s (the upright and curve fluxes, the orbit's
// action, the rates), so "2.0000000000000000001" must give E - E_s = 1e-19 in double, not the 0
// of parse_real<double>(text) - 2. An energy_level carries E = value + residual, with value the
// correctly rounded Real and residual = text - value rounded once (core/decimal.hpp
// parse_difference), and the decimal text itself. The critical levels are energy_levels too
// (double_pendulum::saddle_level, maximum_level): for a model parsed from decimal parameters,
// 2 g m2 a2 and the others are exact decimals (model/model_text.hpp). Then
//     E - level = the exact decimal difference, rounded once          (both decimals known)
//               = (value - level.value) + (residual - level.residual)  (otherwise),
// where value - level.value is exact when value is within a factor 2 of the level (Sterbenz), so
// the distance has the working precision's relative accuracy however close E is to the level. A
// Real converts implicitly (residual 0, no decimal): energies computed in Real carry nothing more.
#pragma once

#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "flipflux/core/decimal.hpp"

namespace flipflux {

template <class Real>
struct energy_level {
    Real value{0};        ///< E rounded to Real
    Real residual{0};     ///< (the exact E) - value, rounded to Real
    std::string decimal;  ///< the exact E as a decimal text, when known (else empty)

    energy_level() = default;
    energy_level(const Real& e) : value(e), residual(0) {}  // NOLINT: implicit by design
    energy_level(const Real& v, const Real& r, std::string d = {})
        : value(v), residual(r), decimal(std::move(d)) {}

    /// E - level, to the working precision's relative accuracy near the level (exact, rounded
    /// once, when both decimals are known).
    Real above(const energy_level& level) const {
        if (!decimal.empty() && !level.decimal.empty())
            return parse_real<Real>(decimal_difference(decimal, level.decimal, "energy"), "energy");
        return (value - level.value) + (residual - level.residual);
    }
    /// level - E.
    Real below(const energy_level& level) const { return level.above(*this); }
    /// E > 0, for the exact E: from the decimal when known (so a positive input that underflows
    /// Real, 1e-999999 in double, counts; a computation needs value > 0 as well).
    bool positive() const { return decimal.empty() ? value > 0 : decimal_sign(decimal) > 0; }
    /// E as a message quotes it: as the caller gave it (the exact decimal, when known), else the
    /// shortest decimal of its value.
    std::string text() const { return decimal.empty() ? to_shortest_decimal(value) : decimal; }
};

/// Parses a decimal energy: its correctly rounded value and the residual of the exact decimal.
/// Throws input_error about `what` for a text that is not a finite decimal number (or overflows).
template <class Real>
energy_level<Real> parse_energy_level(std::string_view text, std::string_view what) {
    const Real value = parse_real<Real>(text, what);
    return {value, parse_difference<Real>(text, value, what), std::string(text)};
}

/// For a parameter `const level_arg<Real>& energy` of a function template whose Real is deduced
/// from another argument (the model): a Real argument then converts implicitly.
template <class Real>
using level_arg = std::type_identity_t<energy_level<Real>>;

}  // namespace flipflux
