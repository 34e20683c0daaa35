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

// The pid of the undex that started this solver, 0 when started otherwise.
long launcher_pid() {
    const char* env = std::getenv(launcher_pid_env);
    return env ? std::atol(env) : 0;
}

bool launcher_ended() {
    const long pid = launcher_pid();
    return pid > 0 && getppid() != pid;
}

// stdout and stderr appended to the launcher's log of this process (once).
void follow_into_log() {
    static bool done = false;
    const char* log = std::getenv(launcher_log_env);
    if (done || !log || !*log) return;
    done = true;
    const int fd = open(log, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return;
    std::cout.flush(), std::cerr.flush();
    std::fflush(stdout), std::fflush(stderr); // whatever is left fails on the closed pipe and is dropped
    dup2(fd, 1), dup2(fd, 2);
    close(fd);
    std::clearerr(stdout), std::clearerr(stderr);
    std::cout.clear(), std::cerr.clear();
}

} // namespace

void install_stop_handler() {
    struct sigaction sa {};
    sa.sa_handler = [](int sig) { stop_signal = sig; };
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
    if (launcher_ended()) raise(SIGHUP); // it died before the handler was in place
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
        why += ": undex (pid " + std::to_string(launcher_pid()) + "), which started this solver, ended";
        follow_into_log();
    }
    return why;
}

void ignore_broken_pipes() {
    signal(SIGPIPE, SIG_IGN);
}

} // namespace undex
