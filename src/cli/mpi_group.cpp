// MPI for simulate and run (mpi_group.hpp).
#include "mpi_group.hpp"

#include <cstdlib>

#include "flipflux/core/plugin.hpp"

namespace flipflux::cli {

bool launched_by_mpirun() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}

std::unique_ptr<mpi_group> open_mpi_group() {
    using open_fn = mpi_group* (*)();
    // global: Open MPI's components (loaded by MPI_Init) need its libraries' symbols
    const auto open =
        reinterpret_cast<open_fn>(plugin_symbol("mpi", "flipflux_mpi_group_open", true));
    return std::unique_ptr<mpi_group>(open());
}

}  // namespace flipflux::cli
