#include "base/signals.hpp"

#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace undex {

namespace {
volatile std::sig_atomic_t stop_signal = 0;
// Read once by install_stop_handler, for the handler.
long launcher = 0;            // UNDEX_LAUNCHER_PID, 0 when not started by undex
char launcher_log[4096] = {}; // UNDEX_LOG
volatile std::sig_atomic_t following = 0;

bool launcher_ended() {
    return launcher > 0 && getppid() != launcher;
}

// Once the launcher has gone, stdout and stderr (the pipe it read) are appended to its log of this process
// instead. Called in the signal handler: open, dup2 and close only (async-signal-safe), so that everything
// written from here on, the error line and the last good state's place included, lands in the log.
void follow_into_log() {
    if (following || !launcher_log[0]) return;
    following = 1;
    const int fd = open(launcher_log, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return;
    dup2(fd, 1), dup2(fd, 2);
    close(fd);
}

void on_stop(int sig) {
    stop_signal = sig;
    if (launcher_ended()) follow_into_log();
}

} // namespace

void install_stop_handler() {
    if (const char* pid = std::getenv(launcher_pid_env)) launcher = std::atol(pid);
    if (const char* log = std::getenv(launcher_log_env))
        std::snprintf(launcher_log, sizeof launcher_log, "%s", log);
    struct sigaction sa {};
    sa.sa_handler = on_stop;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
    if (launcher_ended()) raise(SIGHUP); // it died before the handler was in place
    signal(SIGXFSZ, SIG_IGN); // past RLIMIT_FSIZE a write fails (EFBIG, named) instead of killing the run
}

bool stop_requested() {
    return stop_signal != 0;
}

std::string stop_reason() {
    const int sig = stop_signal;
    std::string why = std::string("stopped by a signal (") +
                      (sig == SIGINT    ? "SIGINT"
                       : sig == SIGTERM ? "SIGTERM"
                       : sig == SIGHUP  ? "SIGHUP"
                                        : "?") +
                      ")";
    if (launcher_ended()) {
        why += ": undex (pid " + std::to_string(launcher) + "), which started this solver, ended";
        std::cout.clear(), std::cerr.clear(); // a write that failed before the handler ran is forgotten
    }
    return why;
}

void protect_standard_streams() {
    signal(SIGPIPE, SIG_IGN);
    for (int fd = 0; fd < 3; ++fd)
        if (fcntl(fd, F_GETFD) < 0 && open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY) != fd) break;
}

} // namespace undex
