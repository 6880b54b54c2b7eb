// Plugins: the parts of flipflux that need a heavy dependency few commands use are shared modules
// loaded on first use, so that a process that does not need them never maps their libraries
// (each costs start-up time: the dynamic loader's relocations and the kernel's page mappings).
//   libflipflux_ceres.so  Ceres' Levenberg-Marquardt (and its sparse stack and BLAS) for the
//                         saddle orbits' periodic shooting (orbits/least_squares.hpp)
//   libflipflux_mpi.so    Open MPI, for simulate and run under mpirun (src/cli/mpi_group.hpp)
// A plugin's interface is plain data and function pointers (extern "C"): it calls nothing of the
// library, and the library nothing of it but the symbols it exports.
//
// Where a plugin is looked for, by the object that holds this code (the executable, or
// libflipflux.so for the Python module and other programs linked to it):
//   - $FLIPFLUX_PLUGIN_DIR when it is set (and nowhere else);
//   - an object in the build tree: the build tree's plugins/ folder;
//   - an installed object: LIBDIR/flipflux/ (cmake --install puts them there), found from BINDIR
//     or LIBDIR, wherever the prefix was moved.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace flipflux {

/// A plugin that cannot be loaded, or lacks a symbol: the message names the file and every folder
/// looked in, or the dynamic loader's reason.
class plugin_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// The folders plugin `name` is looked for in, in order.
std::vector<std::string> plugin_directories();

/// The file name of plugin `name`: libflipflux_<name>.so.
std::string plugin_file_name(const std::string& name);

/// The address of `symbol` in plugin `name`, loaded (once per process, thread-safe) on first use
/// and kept loaded. `global`: its symbols are made available to libraries loaded after it (Open
/// MPI's components need its libraries' symbols). Throws plugin_error.
void* plugin_symbol(const std::string& name, const char* symbol, bool global = false);

}  // namespace flipflux
