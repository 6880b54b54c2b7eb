// Decimal input and output in the working precision.
//
// Inputs are parsed from their decimal text directly in Real (never through a double), so that
// `--energy 5.3 --precision quad` means 5.3 to all 34 digits. Outputs carry every digit of the
// precision: double 17 significant digits, quad 36, MPFR its digits + 2.
#pragma once

#include <string>
#include <string_view>

#include "flipflux/core/real.hpp"

namespace flipflux {

/// Significant digits written for Real: 17 (double), 36 (quad), digits10 + 2 (MPFR).
template <class Real>
int output_digits() {
    if constexpr (std::is_same_v<Real, double>)
        return 17;
    else if constexpr (std::is_same_v<Real, quad>)
        return 36;
    else
        return std::numeric_limits<Real>::digits10 + 2;
}

/// True when `text` is a plain finite decimal number: [+-]digits[.digits][(e|E)[+-]digits].
bool is_decimal_number(std::string_view text);

/// Parses a finite decimal number into Real with correct rounding. Throws input_error
/// "<what>: '<text>' is not a finite decimal number" for anything else (NaN, inf, hex, junk).
template <class Real>
Real parse_real(std::string_view text, std::string_view what);

/// Formats x with output_digits<Real>() significant digits (shortest form of that precision).
template <class Real>
std::string to_decimal(const Real& x);

/// Formats with an explicit number of significant digits.
template <class Real>
std::string to_decimal(const Real& x, int significant_digits);

#define FLIPFLUX_DECIMAL_EXTERN(R)                                       \
    extern template R parse_real<R>(std::string_view, std::string_view); \
    extern template std::string to_decimal<R>(const R&);                 \
    extern template std::string to_decimal<R>(const R&, int)
FLIPFLUX_DECIMAL_EXTERN(double);
FLIPFLUX_DECIMAL_EXTERN(quad);
FLIPFLUX_DECIMAL_EXTERN(mp50);
FLIPFLUX_DECIMAL_EXTERN(mp100);
#undef FLIPFLUX_DECIMAL_EXTERN

}  // namespace flipflux
