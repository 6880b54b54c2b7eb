// The real types flipflux computes in, their names, and run-time dispatch among them.
//
// Supported types (every numerical routine is a template on `Real` and explicitly instantiated
// for exactly these, see src/*.inst.cpp):
//   double                                   53-bit binary, "double"
//   quad  = boost::multiprecision::float128  113-bit binary, "quad"
//   mp50  = MPFR with 50 decimal digits       "mp:DIGITS" for 1 <= DIGITS <= 50
//   mp100 = MPFR with 100 decimal digits      "mp:DIGITS" for 51 <= DIGITS <= 100
//
// NOTE: the MPFR types have a fixed precision and expression templates off (et_off). Fixed
// precision makes every static cache (Boost constants, quadrature nodes, Gauss-Legendre tableaux)
// correct by construction; et_off makes `auto x = a * b;` a value, not an unevaluated expression.
#pragma once

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

namespace flipflux {

using quad = boost::multiprecision::float128;
using mp50 = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<50>,
                                           boost::multiprecision::et_off>;
using mp100 = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<100>,
                                            boost::multiprecision::et_off>;

namespace detail {

/// Fills std::numeric_limits<Real>'s value caches (epsilon, round_error, min, max, infinity,
/// quiet_NaN).
/// NOTE: Boost 1.74 fills those of MPFR numbers on first call, unguarded:
/// `if (!value.first) { value.first = true; value.second = ...; }`, so a second thread arriving
/// in between reads max() == 0 (seen as a spurious "ellint_rf: numeric overflow" under
/// `flipflux golden --jobs 2`). Boost's own start-up initializer warms the expression-template
/// type only, not the et_off types flipflux uses; flipflux warms them during static
/// initialisation below, before any thread exists.
template <class Real>
bool warm_numeric_limits() {
    using limits = std::numeric_limits<Real>;
    const bool ready = limits::epsilon() > 0 && limits::round_error() > 0 && (limits::min)() > 0 &&
                       (limits::max)() > 0 && limits::infinity() > 0;
    (void)limits::quiet_NaN();
    return ready;
}

inline const bool mpfr_limits_warm = warm_numeric_limits<mp50>() && warm_numeric_limits<mp100>();

}  // namespace detail

/// The run-time name of a supported real type.
enum class precision { double_, quad, mp50, mp100 };

/// Largest MPFR precision (decimal digits) accepted by "mp:DIGITS".
inline constexpr int max_mp_digits = 100;

template <class Real>
inline constexpr bool is_supported_real_v =
    std::is_same_v<Real, double> || std::is_same_v<Real, quad> || std::is_same_v<Real, mp50> ||
    std::is_same_v<Real, mp100>;

template <class Real>
constexpr precision precision_of() {
    static_assert(is_supported_real_v<Real>, "unsupported real type");
    if constexpr (std::is_same_v<Real, double>)
        return precision::double_;
    else if constexpr (std::is_same_v<Real, quad>)
        return precision::quad;
    else if constexpr (std::is_same_v<Real, mp50>)
        return precision::mp50;
    else
        return precision::mp100;
}

/// "double", "quad", "mp:50", "mp:100".
std::string precision_name(precision p);
template <class Real>
std::string precision_name() {
    return precision_name(precision_of<Real>());
}

/// Parses "double", "quad" or "mp:DIGITS" (1 <= DIGITS <= 100, rounded up to 50 or 100).
/// Throws input_error naming `option` and the offending text.
precision parse_precision(std::string_view text, std::string_view option = "--precision");

/// Significant decimal digits the type resolves (std::numeric_limits<Real>::digits10).
int decimal_digits(precision p);

/// Calls f.template operator()<Real>() for the real type named by p, returning its result.
template <class F>
decltype(auto) dispatch(precision p, F&& f) {
    switch (p) {
        case precision::double_:
            return f.template operator()<double>();
        case precision::quad:
            return f.template operator()<quad>();
        case precision::mp50:
            return f.template operator()<mp50>();
        case precision::mp100:
            break;
    }
    return f.template operator()<mp100>();
}

/// Machine epsilon of Real, the root of every tolerance in flipflux.
template <class Real>
inline Real epsilon() {
    return std::numeric_limits<Real>::epsilon();
}

}  // namespace flipflux

/// Declares the explicit instantiations of a class template for every supported real type.
#define FLIPFLUX_EXTERN_CLASS(tmpl)               \
    extern template class tmpl<double>;           \
    extern template class tmpl<::flipflux::quad>; \
    extern template class tmpl<::flipflux::mp50>; \
    extern template class tmpl<::flipflux::mp100>
