// Fuzz target: the candidate CSV that `flipflux validate` reads (io/csv.hpp, validation/
// validate.hpp), against a small golden table written once.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/validation/validate.hpp"

namespace {
const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                  ("flipflux_fuzz_candidate_" + std::to_string(getpid()));
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool ready = [] {
        std::filesystem::create_directories(dir / "golden");
        std::ofstream(dir / "golden" / "golden.csv")
            << "quantity,arm,energy,value,digits,method\n"
               "flux-upright,2,3,2.71828182845904523536028747135266249775,38,elliptic\n"
               "omega,,3,1.5,20,elliptic\n";
        return true;
    }();
    (void)ready;
    std::ofstream(dir / "candidate.csv", std::ios::binary)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    for (bool allow_missing : {false, true}) {
        try {
            const auto r = flipflux::validate_candidate(dir / "candidate.csv", dir / "golden",
                                                        1e-12, allow_missing);
            (void)flipflux::format_report(r, 1e-12);
        } catch (const flipflux::input_error&) {
        }
    }
    return 0;
}
