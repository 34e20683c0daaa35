// The command line that starts the fluid as many MPI ranks (OpenMPI's mpirun; docs/scale_out.md).
#pragma once
#include <string>
#include <vector>

namespace undex::launcher {

// "mpirun -n RANKS ..." to put before the fluid's command line. threads: numerics.threads (0: the cores of
// this host shared among the ranks, OMP_NUM_THREADS set so). More ranks × threads than this host's cores:
// --oversubscribe, and waiting ranks and threads yield the core (mpi_yield_when_idle, OMP_WAIT_POLICY
// passive) instead of spinning on it. More than one thread per rank: the ranks are not bound to one core
// each. hostfile: mpirun's --hostfile (the hosts the ranks run on), "" for this host.
std::vector<std::string> mpirun_prefix(int ranks, int threads, const std::string& hostfile);

} // namespace undex::launcher
