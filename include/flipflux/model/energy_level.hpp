// An energy as the user wrote it: its value in Real and the part of the decimal input Real could
// not hold, so that the distance to a critical level (a saddle energy, E_max) is exact.
//
// Just above a saddle the quantities scale with E - E_s (the upright and curve fluxes, the orbit's
// action, the rates), so "2.0000000000000000001" must give E - E_s = 1e-19 in double, not the 0
// of parse_real<double>(text) - 2. An energy_level carries E = value + residual, with value the
// correctly rounded Real and residual = text - value rounded once (core/decimal.hpp
// parse_difference). Then
//     E - level = (value - level) + residual,
// where value - level is exact when value is within a factor 2 of the level (Sterbenz), so the
// distance has the working precision's relative accuracy however close E is to the level. A Real
// converts implicitly (residual 0): energies computed in Real carry nothing more.
#pragma once

#include <string_view>
#include <type_traits>

#include "flipflux/core/decimal.hpp"

namespace flipflux {

template <class Real>
struct energy_level {
    Real value{0};     ///< E rounded to Real
    Real residual{0};  ///< (the exact E) - value, rounded to Real

    energy_level() = default;
    energy_level(const Real& e) : value(e), residual(0) {}  // NOLINT: implicit by design
    energy_level(const Real& v, const Real& r) : value(v), residual(r) {}

    /// E - level, to the working precision's relative accuracy near the level.
    Real above(const Real& level) const { return (value - level) + residual; }
    /// level - E.
    Real below(const Real& level) const { return (level - value) - residual; }
    /// E > 0 (the exact E, so a positive input that underflows Real still counts).
    bool positive() const { return value > 0 || (value == 0 && residual > 0); }
};

/// Parses a decimal energy: its correctly rounded value and the residual of the exact decimal.
/// Throws input_error about `what` for a text that is not a finite decimal number (or overflows).
template <class Real>
energy_level<Real> parse_energy_level(std::string_view text, std::string_view what) {
    const Real value = parse_real<Real>(text, what);
    return {value, parse_difference<Real>(text, value, what)};
}

/// For a parameter `const level_arg<Real>& energy` of a function template whose Real is deduced
/// from another argument (the model): a Real argument then converts implicitly.
template <class Real>
using level_arg = std::type_identity_t<energy_level<Real>>;

}  // namespace flipflux
