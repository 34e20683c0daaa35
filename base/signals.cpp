#include "base/signals.hpp"

#include <signal.h>

#include <csignal>

namespace undex {

namespace {
volatile std::sig_atomic_t stop_signal = 0;
}

void install_stop_handler() {
    struct sigaction sa {};
    sa.sa_handler = [](int sig) { stop_signal = sig; };
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    signal(SIGXFSZ, SIG_IGN); // past RLIMIT_FSIZE a write fails (EFBIG, named) instead of killing the run
}

bool stop_requested() {
    return stop_signal != 0;
}

} // namespace undex
