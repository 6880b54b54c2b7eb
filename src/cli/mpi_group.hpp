// MPI for the commands that spread work over processes (simulate, run): when launched by mpirun
// (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK in the environment) MPI is initialised and
// MPI_COMM_WORLD serves as the study's process_group (study/simulation.hpp); otherwise MPI is
// not touched at all. Open MPI lives in a plugin, libflipflux_mpi.so (mpi.plugin.cpp,
// core/plugin.hpp), loaded only then: a process outside mpirun never maps its libraries.
#pragma once

#include <memory>

#include "flipflux/study/simulation.hpp"

namespace flipflux::cli {

/// Whether the process was started by mpirun (its environment variables).
bool launched_by_mpirun();

/// MPI_COMM_WORLD as a process_group; MPI is initialised when it is made and finalised when it
/// is destroyed.
class mpi_group : public process_group {
  public:
    /// Ends every rank with `status` (MPI_Abort).
    [[noreturn]] virtual void abort(int status) = 0;
};

/// MPI initialised, from the plugin (plugin_error when it cannot be loaded).
std::unique_ptr<mpi_group> open_mpi_group();

}  // namespace flipflux::cli
