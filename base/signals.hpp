// Signals that end a run: SIGINT, SIGTERM and SIGHUP end a solver's run at the next step, with its last good
// state written (exit status 4). SIGPIPE is ignored: a closed stdout (`undex run CASE | head -1`, a launcher
// that died) costs no run; the writes fail and are dropped (std::cout only sets its badbit, and the run goes
// on).
//
// A solver started by `undex run` notices when the launcher dies (SIGKILL included): undex sets
// PR_SET_PDEATHSIG = SIGHUP in the child before exec (launcher/children.cpp) and names itself in
// UNDEX_LAUNCHER_PID; the solver's parent is then no longer that pid, and stop_reason() says so. A launcher
// that died before the handler was installed is caught by the same parent check in install_stop_handler. The
// launcher also names in UNDEX_LOG the log it keeps of the solver's output (DIR/fluid.log, DIR/solid.log):
// from the signal on, the solver appends its stdout and stderr there itself (the handler redirects them).
#pragma once
#include <string>

namespace undex {

inline constexpr const char* launcher_pid_env = "UNDEX_LAUNCHER_PID";
inline constexpr const char* launcher_log_env = "UNDEX_LOG";

// The solvers' main functions install this; their run loops ask stop_requested().
void install_stop_handler();
bool stop_requested();
// Why the run stops: "stopped by a signal (SIGTERM)", or for a solver whose launcher ended "stopped by a
// signal (SIGHUP): undex (pid N), which started this solver, ended".
std::string stop_reason();
// SIGPIPE ignored, and /dev/null opened on a standard descriptor that is closed (`undex run CASE >&-`), so
// that no file opened later (an output, the run lock) becomes stdout. The solvers and undex call it first
// thing.
void protect_standard_streams();

} // namespace undex
