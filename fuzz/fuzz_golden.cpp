// Fuzz target: golden data files, as `flipflux validate --golden DIR` reads them (validation/
// validate.hpp's read_golden) and as the golden writer's parser reads them back
// (output/golden_files.hpp's parse_golden_csv).
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/output/golden_files.hpp"
#include "flipflux/validation/validate.hpp"

namespace {
const std::filesystem::path dir =
    std::filesystem::temp_directory_path() / ("flipflux_fuzz_golden_" + std::to_string(getpid()));
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        (void)flipflux::parse_golden_csv(text);
    } catch (const flipflux::input_error&) {
    }
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "golden.csv", std::ios::binary) << text;
    try {
        (void)flipflux::read_golden(dir);
    } catch (const flipflux::input_error&) {
    }
    return 0;
}
