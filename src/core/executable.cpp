// The running program's own file (core/executable.hpp).
#include "flipflux/core/executable.hpp"

#include <system_error>

namespace flipflux {

std::filesystem::path executable_path() {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::filesystem::path() : exe;
}

}  // namespace flipflux
