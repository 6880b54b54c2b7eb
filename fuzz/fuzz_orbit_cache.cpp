// Fuzz target: the saddle-orbit cache reader and its physical checks (orbits/orbit_store.hpp).
// The input is used both as it is and resealed (a valid checksum), so that the field parsing and
// cached_orbit_problem behind the checksum are reached.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/orbits/orbit_store.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::string sealed;
    try {
        sealed = flipflux::seal_orbit_record(text);
    } catch (const nlohmann::json::exception&) {
    }
    const flipflux::double_pendulum<double> model;
    for (const std::string* t : {&text, static_cast<const std::string*>(&sealed)}) {
        try {
            const auto o = flipflux::orbit_from_json<double>(*t, "fuzz.json");
            (void)flipflux::cached_orbit_problem(model, o.flip_arm, o.energy, o);
        } catch (const flipflux::input_error&) {
        }
    }
    return 0;
}
