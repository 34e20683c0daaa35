// undex run on a coupled case: the fluid and the structure process side by side (docs/protocol.md).
#pragma once
#include <string>
#include <vector>

namespace undex::launcher {

struct CoupledRun {
    std::string case_path;
    std::vector<std::string>
        solver_args;          // --set KEY=VALUE... [-o DIR], passed to undex-fluid and undex-solid
    std::string directory;    // the output directory (the logs go there)
    std::string endpoint;     // "": an ipc:// endpoint of its own
    bool tcp = false;         // a free tcp port on this host instead of ipc://
    std::string fluid;        // the fluid solver's executable
    std::string structure;    // the structure solver's executable, or
    std::string command;      // structure.command of the case (then no --set and -o are passed)
    std::string lock_command; // undex's command line, for the lock of the directory (base/run_lock.hpp)
    bool force = false;       // take over a stale lock
    // undex run --resume: the checkpoints each side continues from (base/checkpoint.hpp); "" for a new run.
    std::string fluid_resume, structure_resume;
    std::vector<std::string> fluid_prefix; // what starts the fluid: mpirun and its options on many ranks
    std::vector<std::string> structure_env; // NAME=VALUE set for the structure's process
};

// Locks DIR for the run (both sides share the lock), runs both sides, their output interleaved on stdout
// (a closed stdout costs nothing) and kept in DIR/fluid.log and DIR/solid.log; when one side fails the other
// is stopped after a grace period, as both are on SIGINT or SIGTERM (passed on as SIGTERM) or SIGHUP (passed
// on as SIGHUP): each then finishes its step and writes a checkpoint; a side still running 60 s later, or
// at a second interrupt, is killed. Should undex die instead, both sides get SIGHUP (children.hpp). Returns the fluid's exit
// status when it is not 0, else the structure's (128 + signal for a killed side).
int run_coupled(const CoupledRun& r);

} // namespace undex::launcher
