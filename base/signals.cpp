#include "base/signals.hpp"

#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace undex {

namespace {
volatile std::sig_atomic_t stop_signal = 0;
// Read once by install_stop_handler, for the handler.
long launcher = 0; // UNDEX_LAUNCHER_PID when undex is this process's parent (not a wrapper's), else 0
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
    const int saved = errno; // the code the signal interrupted may read errno next
    stop_signal = sig;
    if (launcher_ended()) follow_into_log();
    errno = saved;
}

} // namespace

void install_stop_handler() {
    // undex sets PR_SET_PDEATHSIG (SIGHUP) on the processes it starts: its death before the handler is in
    // place ends this process by the signal's default action, so a parent other than undex here is a program
    // in between (a structure.command wrapper), whose own parent undex is: this process does not follow
    // undex.
    if (const char* pid = std::getenv(launcher_pid_env))
        if (std::atol(pid) == static_cast<long>(getppid())) launcher = std::atol(pid);
    if (const char* log = std::getenv(launcher_log_env))
        std::snprintf(launcher_log, sizeof launcher_log, "%s", log);
    struct sigaction sa {};
    sa.sa_handler = on_stop;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
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
    if (launcher_ended())
        why += ": undex (pid " + std::to_string(launcher) + "), which started this solver, ended";
    // A write that the signal interrupted (or that failed before the handler ran) is forgotten, so that the
    // lines saying how the run ended are written.
    std::cout.clear(), std::cerr.clear();
    return why;
}

void protect_standard_streams() {
    signal(SIGPIPE, SIG_IGN);
    for (int fd = 0; fd < 3; ++fd)
        if (fcntl(fd, F_GETFD) < 0 && open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY) != fd) break;
}

} // namespace undex
