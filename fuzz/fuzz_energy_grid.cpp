// Fuzz target: energy lists and grids as the command line and scenes give them
// (study/settings.hpp's parse_energy_list, the grid rule of core/decimal.hpp).
#include <cstdint>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/study/settings.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        (void)flipflux::parse_energy_list(text, "energy");
    } catch (const flipflux::input_error&) {
    }
    try {
        (void)flipflux::parse_criterion_list(text, "criteria");
    } catch (const flipflux::input_error&) {
    }
    return 0;
}
