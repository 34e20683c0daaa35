#include "launcher/mpirun.hpp"

#include <unistd.h>

#include <algorithm>
#include <thread>

namespace undex::launcher {

std::vector<std::string> mpirun_prefix(int ranks, int threads, const std::string& hostfile) {
    const int cores = std::max(1u, std::thread::hardware_concurrency());
    const int per_rank = threads > 0 ? threads : std::max(1, cores / ranks);
    std::vector<std::string> a = {"mpirun", "-n", std::to_string(ranks)};
    if (geteuid() == 0) a.push_back("--allow-run-as-root"); // OpenMPI refuses root without it
    if (!hostfile.empty()) a.insert(a.end(), {"--hostfile", hostfile});
    if (hostfile.empty() && ranks * per_rank > cores)
        a.insert(a.end(),
                 {"--oversubscribe", "--mca", "mpi_yield_when_idle", "1", "-x", "OMP_WAIT_POLICY=passive"});
    if (per_rank > 1) a.insert(a.end(), {"--bind-to", "none"});
    if (threads == 0) a.insert(a.end(), {"-x", "OMP_NUM_THREADS=" + std::to_string(per_rank)});
    return a;
}

} // namespace undex::launcher
