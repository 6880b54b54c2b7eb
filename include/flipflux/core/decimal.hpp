// Decimal input and output in the working precision.
//
// Inputs are parsed from their decimal text directly in Real (never through a double), so that
// `--energy 5.3 --precision quad` means 5.3 to all 34 digits. Outputs carry every digit of the
// precision: double 17 significant digits, quad 36, mp:N N + 2.
#pragma once

#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "flipflux/core/real.hpp"

namespace flipflux {

/// Significant digits written for Real: max_digits10 of the fixed types (double 17, quad 36),
/// N + 2 at mp:N.
template <class Real>
int output_digits() {
    if constexpr (has_variable_precision_v<Real>) {
        const int n = active_mp_digits();
        return (n > 0 ? n : static_cast<int>(Real::default_precision())) + 2;
    } else {
        return std::numeric_limits<Real>::max_digits10;
    }
}

/// Every digit x holds: max_digits10 of the fixed types, its own working digits + 2 for mp (to
/// compare values through their text without losing the guard digits; outputs use to_decimal).
template <class Real>
int full_digits(const Real& x) {
    if constexpr (has_variable_precision_v<Real>)
        return static_cast<int>(x.precision()) + 2;
    else
        return std::numeric_limits<Real>::max_digits10;
}

/// True when `text` is a plain finite decimal number: [+-]digits[.digits][(e|E)[+-]digits].
bool is_decimal_number(std::string_view text);

/// The sign (-1, 0 or +1) of a text accepted by is_decimal_number, exactly (whatever its size:
/// "1e-999999" is positive where every binary precision rounds it to 0).
int decimal_sign(std::string_view text);

/// Parses a finite decimal number into Real with correct rounding. Throws input_error
/// "<what>: '<text>' is not a finite decimal number" for anything else (NaN, inf, hex, junk).
template <class Real>
Real parse_real(std::string_view text, std::string_view what);

/// The decimal number `text` minus the Real `subtrahend`, computed from every digit of both and
/// rounded once to Real (MPFR with room for the cancellation; a tie may round either way). For
/// carrying a decimal input's distance to a critical level that Real itself cannot hold: with
/// text = "2.0000000000000000001" and subtrahend 2, double gives 1e-19 where
/// parse_real<double>(text) - 2 gives 0. Throws input_error about `what` like parse_real.
template <class Real>
Real parse_difference(std::string_view text, const Real& subtrahend, std::string_view what);

/// Exact decimal arithmetic on decimal texts (GMP integers: a decimal is m 10^e, and sums,
/// differences and products of decimals are decimals): the result as a decimal text
/// "[-]D.DDDeEXP" with no digit lost. For the distance of a decimal energy to a critical level
/// that is itself a product of decimal parameters (E - 2 g m2 a2), which no binary precision holds.
/// Throws input_error about `what` for a text that is not a finite decimal number, and when the
/// result's exponent has more than six digits (is_decimal_number's limit).
std::string decimal_sum(std::string_view a, std::string_view b, std::string_view what = "value");
std::string decimal_difference(std::string_view a, std::string_view b,
                               std::string_view what = "value");
std::string decimal_product(std::string_view a, std::string_view b,
                            std::string_view what = "value");

/// Formats x with output_digits<Real>() significant digits (shortest form of that precision).
template <class Real>
std::string to_decimal(const Real& x);

/// Formats with an explicit number of significant digits.
template <class Real>
std::string to_decimal(const Real& x, int significant_digits);

/// Another floating type (a test's fixed-precision reference, say): every digit it has.
template <class Real>
requires(!is_supported_real_v<Real>) std::string to_decimal(const Real& x) {
    std::ostringstream out;
    out << std::setprecision(std::numeric_limits<Real>::max_digits10) << x;
    return out.str();
}

namespace detail {
/// A %g text in scientific notation with an exponent in [-4, 17] written in fixed notation with
/// the same digits ("1.5e+03" -> "1500", "2.5e-04" -> "0.00025"); any other text as it is.
inline std::string fixed_if_moderate(const std::string& text) {
    const std::size_t e = text.find('e');
    if (e == std::string::npos) return text;
    const int exponent = std::stoi(text.substr(e + 1));
    if (exponent < -4 || exponent > 17) return text;
    const bool negative = text[0] == '-';
    std::string digits;
    for (std::size_t i = negative ? 1 : 0; i < e; ++i)
        if (text[i] != '.') digits += text[i];
    std::string out = negative ? "-" : "";
    if (exponent < 0) {
        out += "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
    } else if (static_cast<std::size_t>(exponent) + 1 >= digits.size()) {
        out += digits + std::string(static_cast<std::size_t>(exponent) + 1 - digits.size(), '0');
    } else {
        const std::size_t point = static_cast<std::size_t>(exponent) + 1;
        out += digits.substr(0, point) + "." + digits.substr(point);
    }
    return out;
}
}  // namespace detail

/// The fewest significant digits that parse_real reads back as x: a value echoed in a message
/// about the caller's input shows as it was typed ("'-0.1' is invalid", not
/// "'-0.10000000000000001'"), and still names the exact value; in fixed notation from 1e-4 to
/// 1e18 ("'1500'", not "'1.5e+03'"). Non-finite values, and values that parse_real does not read
/// (subnormals), as to_decimal.
template <class Real>
requires is_supported_real_v<Real> std::string to_shortest_decimal(const Real& x) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    if (!isfinite(x)) return to_decimal(x);
    const int most = full_digits(x);
    try {
        for (int n = 1; n < most; ++n) {
            std::string text = to_decimal(x, n);
            if (parse_real<Real>(text, "value") == x) return detail::fixed_if_moderate(text);
        }
    } catch (const std::exception&) {  // parse_real refuses it (a subnormal): every digit
    }
    return to_decimal(x);
}

/// (Another floating type: every digit it has.)
template <class Real>
requires(!is_supported_real_v<Real>) std::string to_shortest_decimal(const Real& x) {
    return to_decimal(x);
}

/// Agreement of two decimal numbers in significant digits: -log10(|a - b| / |b|) (-log10 |a - b|
/// when b == 0), +infinity when they are equal. Computed in MPFR with every digit of both texts
/// (plus 64 bits), independently of the working precision; thread-safe. Throws input_error
/// naming `what` for a text that is not a finite decimal number.
double decimal_agreement(std::string_view a, std::string_view b, std::string_view what = "value");

/// |a - b| / |b| (|a - b| when b == 0) of two decimal numbers, as decimal_agreement computes it,
/// rounded to double (0 below double's range).
double decimal_relative_error(std::string_view a, std::string_view b,
                              std::string_view what = "value");

/// The angle `text` (a decimal number of radians, of any magnitude) reduced exactly modulo 2 pi
/// into [-pi, pi], as a decimal text with significant_digits + 5 digits: computed in MPFR with
/// as many bits as the integer part of text / 2 pi has, plus the digits asked for (the decimal
/// text is exact; 1e17 rad is not the double nearest it). Throws input_error about `what` for a
/// text that is not a finite decimal number.
std::string reduced_angle(std::string_view text, int significant_digits,
                          std::string_view what = "angle");

/// An angle in radians parsed into Real: as parse_real, except that beyond 1e6 rad it is first
/// reduced exactly modulo 2 pi from its decimal text (reduced_angle): the dynamics is 2 pi-periodic
/// in each angle, and a double at 1e6 rad keeps only ~1e-10 rad of its fraction of a turn (at 1e17
/// none). Angles up to 1e6 are kept as given (outputs then unwrap from them).
template <class Real>
Real parse_angle(std::string_view text, std::string_view what) {
    if (is_decimal_number(text) && decimal_agreement(text, "0") < -6)  // |text - 0| > 1e6
        return parse_real<Real>(reduced_angle(text, output_digits<Real>(), what), what);
    return parse_real<Real>(text, what);
}

/// A decimal number rounded to `significant_digits` (>= 1) digits, correctly rounded from every
/// digit of the text, in the form to_decimal writes.
std::string round_decimal(std::string_view text, int significant_digits,
                          std::string_view what = "value");

/// The grid FROM, FROM + STEP, ..., TO of decimal numbers, as decimal texts: the decimals the user
/// meant ("2.1", not 2.1000000000000000888), computed in a fixed 100-digit arithmetic whatever the
/// working precision, each to be parsed later in the working precision; TO is returned as given.
/// The one grid rule of flipflux (CLI `--energy FROM:TO:STEP` and scene `{from, to, step}`):
/// STEP > 0, TO >= FROM, TO - FROM a whole multiple of STEP (to 1e-9 STEP), at most max_points
/// values. Throws input_error about `field` otherwise.
std::vector<std::string> decimal_grid(std::string_view from, std::string_view to,
                                      std::string_view step, const std::string& field,
                                      long max_points = 100000);

#define FLIPFLUX_DECIMAL_EXTERN(R)                                                       \
    extern template R parse_real<R>(std::string_view, std::string_view);                 \
    extern template R parse_difference<R>(std::string_view, const R&, std::string_view); \
    extern template std::string to_decimal<R>(const R&);                                 \
    extern template std::string to_decimal<R>(const R&, int);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_DECIMAL_EXTERN)
#undef FLIPFLUX_DECIMAL_EXTERN

}  // namespace flipflux
