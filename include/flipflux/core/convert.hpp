// Conversion between the supported precisions through a decimal string with every digit of the
// source (exact for widening, correctly rounded for narrowing), and the relative error of one
// value against another, compared through their decimal texts independently of the working
// precision: for comparing results computed in different precisions (tests, verification,
// benchmarks' digits-versus-time).
#pragma once

#include <cmath>
#include <type_traits>

#include "flipflux/core/decimal.hpp"

namespace flipflux {

/// x converted to To through all the digits of From (for To = mp: into the working precision).
template <class To, class From>
To convert(const From& x) {
    if constexpr (std::is_same_v<To, From> && !has_variable_precision_v<To>)
        return x;
    else if constexpr (has_variable_precision_v<From>)  // every digit of x's own precision
        return parse_real<To>(to_decimal(x, static_cast<int>(x.precision()) + 4), "convert");
    else
        return parse_real<To>(to_decimal(x, output_digits<From>() + 2), "convert");
}

/// |a - b| / |b| (or |a - b| when b == 0), from every digit of both (0 below double's range).
template <class A, class B>
double relative_error(const A& a, const B& b) {
    return decimal_relative_error(to_decimal(a), to_decimal(b));
}

/// Correct significant digits of `value` against `reference`: -log10 of their relative error
/// (+infinity when they are equal).
template <class A, class B>
double correct_digits(const A& value, const B& reference) {
    return decimal_agreement(to_decimal(value), to_decimal(reference));
}

}  // namespace flipflux
