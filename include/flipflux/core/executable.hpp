// The running program's own file: where the command-line tool finds what it ships beside it (its
// share/ folder, its plugins), wherever the installation was moved.
#pragma once

#include <filesystem>

namespace flipflux {

/// The path of the running executable (Linux: /proc/self/exe, symbolic links resolved), or an
/// empty path when it cannot be read.
std::filesystem::path executable_path();

}  // namespace flipflux
