// Fuzz target: the checkpoint reader (study/checkpoint.hpp). Every line of a checkpoint carries a
// hash, so the input is read both as it is and resealed (each line's hash recomputed), so that
// the header comparison and the record parsers behind the hashes are reached. The header the run
// expects is the input's own header when it is a JSON object with an "energies" array (the run's
// header always has one), else a fixed one of two energies.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "flipflux/core/error.hpp"
#include "flipflux/study/checkpoint.hpp"

namespace {

std::string hex16(std::uint64_t v) {
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, v >>= 4)
        s[static_cast<std::size_t>(i)] = "0123456789abcdef"[v & 15];
    return s;
}

// Every complete line with its " #hash" tail (if any) replaced by the right one.
std::string reseal(const std::string& text) {
    std::string out;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) {
            out.append(text, pos, std::string::npos);
            break;
        }
        std::string_view line(text.data() + pos, nl - pos);
        if (line.size() >= 18 && line.substr(line.size() - 18, 2) == " #") line.remove_suffix(18);
        out.append(line);
        out += " #" + hex16(flipflux::fnv1a64(line)) + "\n";
        pos = nl + 1;
    }
    return out;
}

nlohmann::ordered_json expected_header(const std::string& text) {
    constexpr std::string_view tag = "flipflux-checkpoint ";
    std::string first = text.substr(0, text.find('\n'));
    if (first.size() >= 18 && first.compare(first.size() - 18, 2, " #") == 0)
        first.resize(first.size() - 18);
    if (first.starts_with(tag)) first.erase(0, tag.size());
    try {
        auto h = nlohmann::ordered_json::parse(first);
        if (h.is_object() && h.contains("energies") && h["energies"].is_array()) return h;
    } catch (const nlohmann::json::exception&) {
    }
    return nlohmann::ordered_json{{"format", 2}, {"energies", {"3", "3.5"}}};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const nlohmann::ordered_json header = expected_header(text);
    const std::string sealed = reseal(text);
    for (const std::string* t : {&text, &sealed})
        for (std::size_t criteria : {1, 3}) {
            try {
                (void)flipflux::parse_checkpoint(*t, header, criteria, "fuzz.checkpoint");
            } catch (const flipflux::input_error&) {
            }
        }
    return 0;
}
