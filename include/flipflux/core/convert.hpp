// Conversion between the supported precisions through a decimal string with every digit of the
// source (exact for widening, correctly rounded for narrowing), and the relative error of one
// value against another evaluated in mp100: for comparing results computed in different
// precisions (tests, verification, benchmarks' digits-versus-time).
#pragma once

#include <cmath>
#include <type_traits>

#include "flipflux/core/decimal.hpp"

namespace flipflux {

/// x converted to To through all the digits of From.
template <class To, class From>
To convert(const From& x) {
    if constexpr (std::is_same_v<To, From>)
        return x;
    else
        return parse_real<To>(to_decimal(x, output_digits<From>() + 2), "convert");
}

/// |a - b| / |b| (or |a - b| when b == 0), evaluated in mp100.
template <class A, class B>
double relative_error(const A& a, const B& b) {
    const mp100 x = convert<mp100>(a), y = convert<mp100>(b);
    using std::abs;
    const mp100 d = abs(x - y);
    return static_cast<double>(y == 0 ? d : d / abs(y));
}

/// Correct significant digits of `value` against `reference`: -log10 of the relative error (100
/// when they are equal in mp100).
template <class A, class B>
double correct_digits(const A& value, const B& reference) {
    const double r = relative_error(value, reference);
    return r == 0 ? 100.0 : -std::log10(r);
}

}  // namespace flipflux
