// The exit statuses of the solver executables and of undex (which passes a solver's on).
#pragma once

namespace undex {

// Exit statuses of the solver executables.
enum ExitStatus : int {
    exit_complete = 0,
    exit_bad_case = 1, // or another error before the run started (an output directory locked by another run)
    exit_method_failed = 2, // a state the method cannot hold, numerics.max_steps reached, or an output that
                            // cannot be written (h5::Error)
    exit_coupling_failed = 3,
    exit_stopped = 4, // SIGINT, SIGTERM or SIGHUP (also: the undex that started the solver died)
    exit_usage = 64,
};

} // namespace undex
