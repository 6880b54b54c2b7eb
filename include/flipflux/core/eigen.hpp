// Eigen support for the multiprecision real types (float128 and the MPFR et_off type).
//
// NOTE: Boost 1.74's boost/multiprecision/eigen.hpp is broken with Eigen 3.4 (no infinity() or
// quiet_NaN(), lowest() = +min), so it is not included; this specialisation replaces it. It is
// valid for et_off numbers only, which is all flipflux uses. Include this header, not
// <Eigen/...>, wherever a matrix has a multiprecision scalar. Eigen decompositions on these
// scalars are expensive to compile: keep each (solver, type) pair in its own translation unit.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "flipflux/core/real.hpp"

namespace Eigen {

template <class Backend>
struct NumTraits<boost::multiprecision::number<Backend, boost::multiprecision::et_off>>
    : GenericNumTraits<boost::multiprecision::number<Backend, boost::multiprecision::et_off>> {
    using Self = boost::multiprecision::number<Backend, boost::multiprecision::et_off>;
    using Real = Self;
    using NonInteger = Self;
    using Literal = Self;
    using Nested = Self;
    enum {
        IsComplex = 0,
        IsInteger = 0,
        IsSigned = 1,
        RequireInitialization = 1,
        ReadCost = 1,
        AddCost = 4,
        MulCost = 8
    };
    static Self epsilon() { return std::numeric_limits<Self>::epsilon(); }
    static Self dummy_precision() { return 1000 * epsilon(); }
    static Self highest() { return (std::numeric_limits<Self>::max)(); }
    static Self lowest() { return -(std::numeric_limits<Self>::max)(); }
    static Self infinity() { return std::numeric_limits<Self>::infinity(); }
    static Self quiet_NaN() { return std::numeric_limits<Self>::quiet_NaN(); }
    // NOTE: run-time values for mp (its numeric_limits say INT_MAX)
    static int digits() { return flipflux::binary_digits<Self>(); }
    static int digits10() { return (digits() - 1) * 301 / 1000; }
    static int min_exponent() { return std::numeric_limits<Self>::min_exponent; }
    static int max_exponent() { return std::numeric_limits<Self>::max_exponent; }
};

}  // namespace Eigen
