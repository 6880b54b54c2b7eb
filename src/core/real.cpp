#include "flipflux/core/real.hpp"

#include <charconv>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"

namespace flipflux {

std::string precision_name(precision p) {
    switch (p) {
        case precision::double_:
            return "double";
        case precision::quad:
            return "quad";
        case precision::mp50:
            return "mp:50";
        case precision::mp100:
            break;
    }
    return "mp:100";
}

precision parse_precision(std::string_view text, std::string_view option) {
    if (text == "double") return precision::double_;
    if (text == "quad") return precision::quad;
    const std::string bad = std::string(option) + ": '" + std::string(text) + "' ";
    if (text.substr(0, 3) == "mp:") {
        const std::string_view digits = text.substr(3);
        int n = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
        if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size()) {
            throw input_error(bad + "is not a precision (mp:DIGITS needs an integer DIGITS)");
        }
        if (n < 1 || n > max_mp_digits) {
            throw input_error(bad + "is out of range (mp:DIGITS takes 1 <= DIGITS <= " +
                              std::to_string(max_mp_digits) + ")");
        }
        return n <= 50 ? precision::mp50 : precision::mp100;
    }
    throw input_error(bad + "is not a precision (expected double, quad or mp:DIGITS)");
}

int decimal_digits(precision p) {
    return dispatch(p, []<class Real>() { return std::numeric_limits<Real>::digits10; });
}

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

}  // namespace flipflux
