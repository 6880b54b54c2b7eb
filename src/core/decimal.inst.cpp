// Decimal text <-> Real in the working precision (core/decimal.hpp): parse_real rounds the
// decimal correctly (strtod, strtoflt128, mpfr_set_str), to_decimal prints the digits of the
// type's output precision.
#include "flipflux/core/decimal.hpp"

#include <mpfr.h>

#include <charconv>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "flipflux/core/error.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/core/mpfr_number.hpp"

namespace flipflux {

template <class Real>
Real parse_real(std::string_view text, std::string_view what) {
    if (!is_decimal_number(text)) {
        throw input_error::about(std::string(what),
                                 "'" + std::string(text) + "' is not a finite decimal number");
    }
    const std::string s(text);
    Real value;
    if constexpr (std::is_same_v<Real, double>) {
        value = std::strtod(s.c_str(), nullptr);  // correctly rounded (glibc)
    } else if constexpr (std::is_floating_point_v<Real>) {
        value = static_cast<Real>(std::strtold(s.c_str(), nullptr));
    } else {
        value = Real(s.c_str());  // strtoflt128 / mpfr_set_str: correctly rounded
    }
    using boost::multiprecision::isfinite;
    using std::isfinite;
    if (!isfinite(value)) {
        throw input_error::about(std::string(what),
                                 "'" + s + "' overflows " + precision_name<Real>());
    }
    // a nonzero text that rounds to 0 (or, in a fixed type, below its normal range, where
    // digits are lost) is refused rather than run as a meaningless limit: 1e-400 is not 0
    // NOTE: numeric_limits<mp>::min() is not asked (Boost computes it at, and may disturb, the
    // default precision); MPFR's exponent range leaves only an exact 0 to refuse there
    using std::abs;
    bool below = value == 0;
    if constexpr (!has_variable_precision_v<Real>)
        below = below || abs(value) < std::numeric_limits<Real>::min();
    if (decimal_sign(text) != 0 && below)
        throw input_error::about(std::string(what), "'" + s + "' underflows " +
                                                        precision_name<Real>() +
                                                        " (below its smallest normal number)");
    return value;
}

namespace {

/// Binary digits of Real's significand (of the working precision for mp).
template <class Real>
long significand_bits(const Real& x) {
    if constexpr (has_variable_precision_v<Real>)
        return static_cast<long>(mpfr_get_prec(x.backend().data()));
    else
        return std::numeric_limits<Real>::digits;
}

/// out = x exactly (out has at least x's significand bits).
template <class Real>
void set_exactly(mpfr_ptr out, const Real& x) {
    if constexpr (std::is_same_v<Real, double>) {
        mpfr_set_d(out, x, MPFR_RNDN);
    } else if constexpr (has_variable_precision_v<Real>) {
        mpfr_set(out, x.backend().data(), MPFR_RNDN);
    } else {
        // quad: three doubles hold its 113 bits exactly (each remainder is exact in quad), taken
        // from the significand in [1/2, 1) so that quad's exponent range (1e+-4932), far beyond
        // double's, is carried by the power of two
        using std::frexp;
        int e = 0;
        const Real m = frexp(x, &e);
        const double hi = static_cast<double>(m);
        const Real r1 = m - Real(hi);
        const double mid = static_cast<double>(r1);
        const double lo = static_cast<double>(r1 - Real(mid));
        mpfr_set_d(out, hi, MPFR_RNDN);
        mpfr_add_d(out, out, mid, MPFR_RNDN);
        mpfr_add_d(out, out, lo, MPFR_RNDN);
        mpfr_mul_2si(out, out, e, MPFR_RNDN);
    }
}

/// x rounded to Real.
template <class Real>
Real rounded(mpfr_srcptr x) {
    if constexpr (std::is_same_v<Real, double>) {
        return mpfr_get_d(x, MPFR_RNDN);
    } else if constexpr (has_variable_precision_v<Real>) {
        Real r;
        mpfr_set(r.backend().data(), x, MPFR_RNDN);
        return r;
    } else {
        // quad: through 45 significant digits (the rounding from 150 to 113 bits is then the only
        // one that matters)
        if (mpfr_zero_p(x)) return Real(0);
        std::vector<char> buffer(64);
        mpfr_exp_t e = 0;
        mpfr_get_str(buffer.data(), &e, 10, 45, x, MPFR_RNDN);
        std::string digits(buffer.data());
        const bool negative = !digits.empty() && digits[0] == '-';
        if (negative) digits.erase(0, 1);
        const std::string text = std::string(negative ? "-" : "") + "0." + digits + "e" +
                                 std::to_string(static_cast<long>(e));
        return Real(text.c_str());
    }
}

/// The decimal exponent of a decimal text (0 without one).
long decimal_exponent(std::string_view text) {
    const std::size_t e = text.find_first_of("eE");
    return e == std::string_view::npos
               ? 0
               : std::strtol(std::string(text.substr(e + 1)).c_str(), nullptr, 10);
}

}  // namespace

template <class Real>
Real parse_difference(std::string_view text, const Real& subtrahend, std::string_view what) {
    const Real value = parse_real<Real>(text, what);  // validates the text, and its range
    using boost::multiprecision::isfinite;
    using std::frexp;
    using std::isfinite;
    const auto exponent = [](const Real& x) {
        int e = 0;
        if (x != 0) frexp(x, &e);
        return std::labs(static_cast<long>(e));
    };
    if (!isfinite(subtrahend)) throw std::domain_error("parse_difference: subtrahend not finite");
    // |text - b| >= 1 / (10^m 2^n) unless 0 (text = k 10^-m, b = j 2^-n): enough bits for the
    // cancellation down to that, plus Real's own and guard bits
    const long bits = significand_bits(subtrahend);
    const long m = static_cast<long>(text.size()) + std::labs(decimal_exponent(text));
    const long n = bits + exponent(subtrahend);
    const long scale = exponent(value);
    mpfr_number a(static_cast<mpfr_prec_t>(2 * bits + 4 * m + n + scale + 128));
    mpfr_number b(static_cast<mpfr_prec_t>(bits + 64));
    const std::string s(text);
    mpfr_set_str(a.get(), s.c_str(), 10, MPFR_RNDN);
    set_exactly(b.get(), subtrahend);
    mpfr_sub(a.get(), a.get(), b.get(), MPFR_RNDN);
    return rounded<Real>(a.get());
}

template <class Real>
std::string to_decimal(const Real& x, int significant_digits) {
    if constexpr (std::is_same_v<Real, double>) {
        // std::to_chars in general format with a precision is printf's %.*g in the C locale,
        // which is what the stream below prints in the classic locale (flipflux never sets
        // another), at a tenth of the cost (an ensemble's CSVs print millions of crossing times)
        if (significant_digits > 0 && significant_digits <= 40) {
            char buf[64];
            const std::to_chars_result r = std::to_chars(
                buf, buf + sizeof buf, x, std::chars_format::general, significant_digits);
            if (r.ec == std::errc()) return std::string(buf, r.ptr);
        }
    }
    std::ostringstream out;
    out << std::setprecision(significant_digits) << x;
    return out.str();
}

template <class Real>
std::string to_decimal(const Real& x) {
    if constexpr (has_variable_precision_v<Real>) {
        // a value of another precision than the active one (e.g. an outer scope's) keeps its own
        const int active = active_mp_digits();
        if (active == 0 || static_cast<int>(x.precision()) != mp_working_digits(active))
            return to_decimal(x, static_cast<int>(x.precision()) + 2);
    }
    return to_decimal(x, output_digits<Real>());
}

template inst_real parse_real<inst_real>(std::string_view, std::string_view);
template inst_real parse_difference<inst_real>(std::string_view, const inst_real&,
                                               std::string_view);
template std::string to_decimal<inst_real>(const inst_real&);
template std::string to_decimal<inst_real>(const inst_real&, int);

}  // namespace flipflux
