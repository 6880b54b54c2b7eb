// Conversion between the supported precisions through a decimal string with every digit of the
// source (exact for widening, correctly rounded for narrowing), and the relative error of one
// value against another, compared through their decimal texts independently of the working
// precision: for comparing results computed in different precisions (tests, verification,
// benchmarks' digits-versus-time).
#pragma once

#include <cmath>
#include <string>
#include <string_view>
#include <type_traits>

#include "flipflux/core/decimal.hpp"

namespace flipflux {

namespace detail {
inline std::string_view decimal_text(const std::string& text) {
    return text;
}
inline std::string_view decimal_text(const char* text) {
    return text;
}
template <class Real>
std::string decimal_text(const Real& x) {
    if constexpr (is_supported_real_v<Real>)
        return to_decimal(x, full_digits(x));
    else  // another type (a test's fixed-precision reference): every digit it has
        return to_decimal(x);
}
}  // namespace detail

/// x converted to To through all the digits of From (for To = mp: into the working precision).
template <class To, class From>
To convert(const From& x) {
    if constexpr (std::is_same_v<To, From> && !has_variable_precision_v<To>)
        return x;
    else
        return parse_real<To>(detail::decimal_text(x), "convert");
}

/// |a - b| / |b| (or |a - b| when b == 0) of two reals or decimal texts, from every digit of
/// both (0 below double's range).
template <class A, class B>
double relative_error(const A& a, const B& b) {
    return decimal_relative_error(detail::decimal_text(a), detail::decimal_text(b));
}

/// Correct significant digits of `value` against `reference` (reals or decimal texts): -log10
/// of their relative error (+infinity when they are equal).
template <class A, class B>
double correct_digits(const A& value, const B& reference) {
    return decimal_agreement(detail::decimal_text(value), detail::decimal_text(reference));
}

}  // namespace flipflux
