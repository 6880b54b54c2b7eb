// Fuzz target: decimal parsing in every precision (core/decimal.hpp) and the comparison of
// decimal texts validate uses.
#include <cstdint>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::size_t cut = text.find('\n');
    const std::string a = text.substr(0, cut),
                      b = cut == std::string::npos ? "1" : text.substr(cut + 1);
    (void)flipflux::is_decimal_number(a);
    for (const char* p : {"double", "quad", "mp:30"}) {
        try {
            flipflux::dispatch(flipflux::parse_precision(p, "precision"), [&]<class Real>() {
                const Real x = flipflux::parse_real<Real>(a, "x");
                (void)flipflux::to_decimal(x);
            });
        } catch (const flipflux::input_error&) {
        }
    }
    try {
        (void)flipflux::decimal_agreement(a, b);
    } catch (const flipflux::input_error&) {
    }
    return 0;
}
