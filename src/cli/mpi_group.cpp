// MPI for simulate and run (mpi_group.hpp).
#include "mpi_group.hpp"

#include <cstdlib>

namespace flipflux::cli {

bool launched_by_mpirun() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}

}  // namespace flipflux::cli
