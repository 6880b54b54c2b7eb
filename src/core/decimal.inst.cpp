// Decimal text <-> Real in the working precision (core/decimal.hpp): parse_real rounds the
// decimal correctly (strtod, strtoflt128, mpfr_set_str), to_decimal prints the digits of the
// type's output precision.
#include "flipflux/core/decimal.hpp"

#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/core/instantiate.hpp"

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
    return value;
}

template <class Real>
std::string to_decimal(const Real& x, int significant_digits) {
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
template std::string to_decimal<inst_real>(const inst_real&);
template std::string to_decimal<inst_real>(const inst_real&, int);

}  // namespace flipflux
