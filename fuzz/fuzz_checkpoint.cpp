// Fuzz target: the checkpoint reader (study/checkpoint.hpp). The header the run expects is the
// input's own first line when it is JSON (so that the records behind it are reached), else {}.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/study/checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    nlohmann::ordered_json header = nlohmann::ordered_json::object();
    try {
        header = nlohmann::ordered_json::parse(text.substr(0, text.find('\n')));
    } catch (const nlohmann::json::exception&) {
    }
    for (std::size_t criteria : {1, 3}) {
        try {
            (void)flipflux::parse_checkpoint(text, header, criteria, "fuzz.checkpoint");
        } catch (const flipflux::input_error&) {
        }
    }
    return 0;
}
