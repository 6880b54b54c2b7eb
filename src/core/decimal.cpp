// Decimal text independently of the working precision (core/decimal.hpp): recognising a decimal
// number, rounding it, and comparing two of them.
#include <gmp.h>
#include <mpfr.h>

#include <boost/multiprecision/mpfr.hpp>
#include <iomanip>
#include <ios>
#include <sstream>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/mpfr_number.hpp"

namespace flipflux {
namespace {

void set_decimal(mpfr_number& x, std::string_view text, std::string_view what) {
    if (!is_decimal_number(text))
        throw input_error::about(std::string(what),
                                 "'" + std::string(text) + "' is not a finite decimal number");
    const std::string s(text);
    mpfr_set_str(x.get(), s.c_str(), 10, MPFR_RNDN);
}

/// log10 |a - b| / |b| (log10 |a - b| when b == 0) in MPFR, as a double (-inf when equal).
/// Significant digits of a decimal text's mantissa (leading zeros not counted).
std::size_t significant_digits_of(std::string_view text) {
    std::size_t n = 0;
    bool started = false;
    for (const char c : text.substr(0, text.find_first_of("eE"))) {
        if (c < '0' || c > '9') continue;
        started = started || c != '0';
        n += started ? 1 : 0;
    }
    return n;
}

/// The text with its mantissa cut to `keep` significant digits (digits before the point become
/// zeros, after it are dropped): lexical, linear in the text's length.
std::string truncated_digits(std::string_view text, std::size_t keep) {
    const std::size_t e = std::min(text.find_first_of("eE"), text.size());
    std::string out;
    std::size_t n = 0;
    bool started = false, after_point = false;
    for (const char c : text.substr(0, e)) {
        if (c == '.') after_point = true;
        if (c < '0' || c > '9') {
            out += c;
            continue;
        }
        started = started || c != '0';
        n += started ? 1 : 0;
        if (n <= keep)
            out += c;
        else if (!after_point)
            out += '0';
    }
    if (!out.empty() && out.back() == '.') out.pop_back();
    return out + std::string(text.substr(e));
}

double log10_relative_difference(std::string_view a_text, std::string_view b_text,
                                 std::string_view what) {
    // NOTE: both texts are cut lexically to k = max(m + 40, 100000) significant digits, m the
    // shorter's: the cut moves the relative difference r by less than 10^(1 - k), so r keeps
    // double accuracy wherever r > 10^(20 - k), and below that the texts agree to more than
    // k - 20 >= m + 20 digits, more than the shorter has. A candidate value of millions of
    // digits against a golden one of 50 then costs milliseconds, not a minute.
    for (const std::string_view t : {a_text, b_text})
        if (!is_decimal_number(t))
            throw input_error::about(std::string(what),
                                     "'" + std::string(t) + "' is not a finite decimal number");
    const std::size_t keep = std::max<std::size_t>(
        std::min(significant_digits_of(a_text), significant_digits_of(b_text)) + 40, 100000);
    const std::string a = truncated_digits(a_text, keep), b = truncated_digits(b_text, keep);
    // every significant digit of both texts, and room for the difference
    const mpfr_prec_t bits = static_cast<mpfr_prec_t>(4 * (a.size() + b.size()) + 64);
    mpfr_number x(bits), y(bits);
    set_decimal(x, a, what);
    set_decimal(y, b, what);
    mpfr_sub(x.get(), x.get(), y.get(), MPFR_RNDN);
    mpfr_abs(x.get(), x.get(), MPFR_RNDN);
    if (mpfr_zero_p(x.get())) return -std::numeric_limits<double>::infinity();
    if (!mpfr_zero_p(y.get())) {
        mpfr_abs(y.get(), y.get(), MPFR_RNDN);
        mpfr_div(x.get(), x.get(), y.get(), MPFR_RNDN);
    }
    mpfr_log10(x.get(), x.get(), MPFR_RNDN);
    return mpfr_get_d(x.get(), MPFR_RNDN);
}

}  // namespace

bool is_decimal_number(std::string_view t) {
    std::size_t i = 0;
    const std::size_t n = t.size();
    if (i < n && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t mantissa_digits = 0;
    while (i < n && t[i] >= '0' && t[i] <= '9')
        ++i, ++mantissa_digits;
    if (i < n && t[i] == '.') {
        ++i;
        while (i < n && t[i] >= '0' && t[i] <= '9')
            ++i, ++mantissa_digits;
    }
    if (mantissa_digits == 0) return false;
    if (i < n && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        if (i < n && (t[i] == '+' || t[i] == '-')) ++i;
        std::size_t exponent_digits = 0;
        while (i < n && t[i] >= '0' && t[i] <= '9')
            ++i, ++exponent_digits;
        if (exponent_digits == 0 || exponent_digits > 6) return false;
    }
    return i == n;
}

int decimal_sign(std::string_view t) {
    const bool negative = !t.empty() && t.front() == '-';
    for (const char c : t) {
        if (c == 'e' || c == 'E') break;
        if (c >= '1' && c <= '9') return negative ? -1 : 1;
    }
    return 0;
}

std::string reduced_angle(std::string_view text, int significant_digits, std::string_view what) {
    mpfr_number probe(64);
    set_decimal(probe, text, what);
    if (mpfr_zero_p(probe.get())) return std::string(text);
    // bits for the integer part of x / 2 pi, the digits asked for, and 64 guard bits: the
    // remainder then keeps them all (|x| < 1e1000000, is_decimal_number's exponent limit)
    const long exponent = std::max(0L, static_cast<long>(mpfr_get_exp(probe.get())));
    const auto bits =
        static_cast<mpfr_prec_t>(exponent + 3.33 * significant_digits + 4 * text.size() + 64);
    mpfr_number x(bits), turn(bits), k(bits);
    set_decimal(x, text, what);
    mpfr_const_pi(turn.get(), MPFR_RNDN);
    mpfr_mul_2ui(turn.get(), turn.get(), 1, MPFR_RNDN);
    mpfr_div(k.get(), x.get(), turn.get(), MPFR_RNDN);
    mpfr_rint(k.get(), k.get(), MPFR_RNDN);
    mpfr_mul(k.get(), k.get(), turn.get(), MPFR_RNDN);
    mpfr_sub(x.get(), x.get(), k.get(), MPFR_RNDN);
    const int digits = significant_digits + 5;
    std::vector<char> buffer(static_cast<std::size_t>(digits) + 16);
    mpfr_exp_t e10 = 0;
    mpfr_get_str(buffer.data(), &e10, 10, static_cast<std::size_t>(digits), x.get(), MPFR_RNDN);
    std::string mantissa(buffer.data());
    const bool negative = !mantissa.empty() && mantissa[0] == '-';
    if (negative) mantissa.erase(0, 1);
    return std::string(negative ? "-" : "") + "0." + mantissa + "e" + std::to_string(e10);
}

std::string round_decimal(std::string_view text, int significant_digits, std::string_view what) {
    mpfr_number x(static_cast<mpfr_prec_t>(4 * text.size() + 64));
    set_decimal(x, text, what);
    // NOTE: never more digits than the text has: x holds the text to ~text.size() digits, and
    // its binary expansion printed beyond them is noise ("35.2" to 50 digits gave
    // 35.2000000000000000000000105879..., a golden value 1e-23 off)
    std::size_t digits = 0;
    bool leading = true;
    for (const char c : text.substr(0, text.find_first_of("eE"))) {
        if (c < '0' || c > '9') continue;
        if (leading && c == '0') continue;
        leading = false;
        ++digits;
    }
    const int shown = static_cast<int>(
        std::min<std::size_t>(std::max(significant_digits, 1), std::max<std::size_t>(digits, 1)));
    // formatted by Boost's MPFR backend, as to_decimal's iostream output is (its precision is
    // taken from x, not from the process-wide default)
    boost::multiprecision::mpfr_float_backend<0> b;
    b = static_cast<mpfr_srcptr>(x.get());
    return b.str(shown, std::ios_base::fmtflags(0));
}

double decimal_agreement(std::string_view a, std::string_view b, std::string_view what) {
    return -log10_relative_difference(a, b, what);
}

double decimal_relative_error(std::string_view a, std::string_view b, std::string_view what) {
    return std::pow(10.0, log10_relative_difference(a, b, what));
}

namespace {

/// m 10^e with m a GMP integer: a decimal number held exactly.
class exact_decimal {
  public:
    exact_decimal() { mpz_init(m_); }
    exact_decimal(std::string_view text, std::string_view what) : exact_decimal() {
        if (!is_decimal_number(text))
            throw input_error::about(std::string(what),
                                     "'" + std::string(text) + "' is not a finite decimal number");
        const std::size_t e = text.find_first_of("eE");
        std::string digits;
        long exponent = e == std::string_view::npos
                            ? 0
                            : std::strtol(std::string(text.substr(e + 1)).c_str(), nullptr, 10);
        bool fraction = false;
        for (const char c : text.substr(0, e)) {
            if (c == '-') digits += c;
            if (c == '.') fraction = true;
            if (c >= '0' && c <= '9') {
                digits += c;
                if (fraction) --exponent;
            }
        }
        mpz_set_str(m_, digits.c_str(), 10);
        e_ = exponent;
    }
    exact_decimal(const exact_decimal&) = delete;
    exact_decimal& operator=(const exact_decimal&) = delete;
    ~exact_decimal() { mpz_clear(m_); }

    /// out = a + sign b (sign = +1 or -1), exactly.
    static void sum(exact_decimal& out, const exact_decimal& a, const exact_decimal& b, int sign) {
        // align to the smaller exponent: the other mantissa times 10^(difference)
        const exact_decimal& low = a.e_ <= b.e_ ? a : b;
        const exact_decimal& high = a.e_ <= b.e_ ? b : a;
        mpz_t scaled;
        mpz_init(scaled);
        mpz_ui_pow_ui(scaled, 10, static_cast<unsigned long>(high.e_ - low.e_));
        mpz_mul(scaled, scaled, high.m_);
        if (&high == &a)
            sign > 0 ? mpz_add(out.m_, scaled, low.m_) : mpz_sub(out.m_, scaled, low.m_);
        else
            sign > 0 ? mpz_add(out.m_, low.m_, scaled) : mpz_sub(out.m_, low.m_, scaled);
        out.e_ = low.e_;
        mpz_clear(scaled);
    }
    static void product(exact_decimal& out, const exact_decimal& a, const exact_decimal& b) {
        mpz_mul(out.m_, a.m_, b.m_);
        out.e_ = a.e_ + b.e_;
    }

    /// "[-]D.DDDeEXP" with every digit (trailing zeros dropped); input_error about `what` when
    /// the exponent has more than six digits.
    std::string text(std::string_view what) {
        if (mpz_sgn(m_) == 0) return "0";
        while (mpz_divisible_ui_p(m_, 10)) {
            mpz_divexact_ui(m_, m_, 10);
            ++e_;
        }
        char* digits = mpz_get_str(nullptr, 10, m_);
        std::string out(digits);
        void (*release)(void*, std::size_t) = nullptr;
        mp_get_memory_functions(nullptr, nullptr, &release);
        release(digits, std::strlen(digits) + 1);
        // the exponent of the leading digit is what the reader's limit applies to
        const long leading = e_ + static_cast<long>(out.size()) - (out[0] == '-' ? 2 : 1);
        if (std::labs(leading) > 999999)
            throw input_error::about(std::string(what), "an exact decimal result of magnitude 1e" +
                                                            std::to_string(leading) +
                                                            " is outside the decimal range");
        // d.ddd...eLEADING: the exponent is that of the leading digit
        const std::size_t first = out[0] == '-' ? 1 : 0;
        if (out.size() > first + 1) out.insert(first + 1, ".");
        return out + "e" + std::to_string(leading);
    }

  private:
    mpz_t m_;
    long e_ = 0;
};

}  // namespace

std::string decimal_sum(std::string_view a, std::string_view b, std::string_view what) {
    exact_decimal x(a, what), y(b, what), out;
    exact_decimal::sum(out, x, y, +1);
    return out.text(what);
}

std::string decimal_difference(std::string_view a, std::string_view b, std::string_view what) {
    exact_decimal x(a, what), y(b, what), out;
    exact_decimal::sum(out, x, y, -1);
    return out.text(what);
}

std::string decimal_product(std::string_view a, std::string_view b, std::string_view what) {
    exact_decimal x(a, what), y(b, what), out;
    exact_decimal::product(out, x, y);
    return out.text(what);
}

namespace {

// NOTE: grid arithmetic in a fixed 100-digit MPFR type, independent of the working precision (and
// of mp's process-wide default precision)
using grid_decimal = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<100>,
                                                   boost::multiprecision::et_off>;

std::string grid_text(const grid_decimal& x, int digits) {
    std::ostringstream out;
    out << std::setprecision(digits) << x;
    return out.str();
}

}  // namespace

std::vector<std::string> decimal_grid(std::string_view from_text, std::string_view to_text,
                                      std::string_view step_text, const std::string& field,
                                      long max_points) {
    const auto number = [&](std::string_view text, const char* name) {
        if (!is_decimal_number(text))
            throw input_error::about(field, std::string(name) + " '" + std::string(text) +
                                                "' is not a finite decimal number");
        return grid_decimal(std::string(text));
    };
    const grid_decimal from = number(from_text, "from");
    const grid_decimal to = number(to_text, "to");
    const grid_decimal step = number(step_text, "step");
    using std::abs;
    using std::round;
    if (!(step > 0))
        throw input_error::about(field, "step '" + std::string(step_text) + "' must be > 0");
    if (to < from)
        throw input_error::about(field, "to '" + std::string(to_text) + "' is below from '" +
                                            std::string(from_text) + "'");
    const grid_decimal count = round((to - from) / step);
    if (count + 1 > max_points)
        throw input_error::about(field, "more than " + std::to_string(max_points) + " values");
    if (abs(from + count * step - to) > step / 1000000000)
        throw input_error::about(field,
                                 "to - from = " + grid_text(to - from, 10) +
                                     " is not a multiple of step = " + std::string(step_text));
    // from + i step in 100 digits, written with 40: the decimal the user meant
    const long n = static_cast<long>(count);
    std::vector<std::string> out;
    for (long i = 0; i <= n; ++i)
        out.push_back(i == n ? std::string(to_text) : grid_text(from + i * step, 40));
    return out;
}

}  // namespace flipflux
