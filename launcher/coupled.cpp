// A coupled run of undex (launcher/coupled.hpp).
#include "launcher/coupled.hpp"

#include "base/run_lock.hpp"
#include "base/signals.hpp"
#include "coupler/conform.hpp"
#include "launcher/children.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>

namespace undex::launcher {

namespace {

volatile std::sig_atomic_t interrupted = 0; // the SIGINT, SIGTERM or SIGHUP that arrived
volatile std::sig_atomic_t interrupts = 0;  // how many

// SIGINT, SIGTERM or SIGHUP to undex stops both sides (each runs in its own process group).
void catch_stop_signals() {
    struct sigaction sa {};
    sa.sa_handler = [](int sig) { interrupted = sig, ++interrupts; };
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
}

// A free tcp port on this host (bound and released; the fluid binds it right after).
int free_tcp_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;
    socklen_t len = sizeof addr;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
        throw std::runtime_error("cannot find a free tcp port");
    close(fd);
    return ntohs(addr.sin_port);
}

std::string endpoint_of(const CoupledRun& r) {
    if (!r.endpoint.empty()) return r.endpoint;
    if (r.tcp) return "tcp://127.0.0.1:" + std::to_string(free_tcp_port());
    return "ipc://" +
           (std::filesystem::temp_directory_path() / ("undex-" + std::to_string(getpid()) + ".ipc")).string();
}

// The command lines of the fluid [0] and the structure [1].
std::vector<std::vector<std::string>> command_lines(const CoupledRun& r, const std::string& endpoint) {
    std::vector<std::string> fluid = r.fluid_prefix, solid;
    fluid.insert(fluid.end(), {r.fluid, r.case_path});
    fluid.insert(fluid.end(), r.solver_args.begin(), r.solver_args.end());
    fluid.insert(fluid.end(), {"--couple", endpoint});
    if (!r.fluid_resume.empty()) fluid.insert(fluid.end(), {"--resume", r.fluid_resume});
    if (!r.command.empty())
        return {fluid,
                {"/bin/sh", "-c", "exec " + r.command + " --couple " + coupling::shell_quote(endpoint)}};
    solid = {r.structure, r.case_path};
    solid.insert(solid.end(), r.solver_args.begin(), r.solver_args.end());
    solid.insert(solid.end(), {"--couple", endpoint});
    if (!r.structure_resume.empty()) solid.insert(solid.end(), {"--resume", r.structure_resume});
    return {fluid, solid};
}

// Starts both sides (when the second cannot start, the first is killed) and opens their logs. Each learns
// undex's pid and the path of its log (base/signals.hpp).
void start(Child (&children)[2], const std::vector<std::vector<std::string>>& lines, const std::string& dir,
           bool resumed, const std::vector<std::string>& structure_env) {
    children[0].name = "fluid";
    children[1].name = "solid";
    try {
        for (int k = 0; k < 2; ++k) {
            const auto log =
                std::filesystem::absolute(std::filesystem::path(dir) / (children[k].name + ".log"));
            std::vector<std::string> env = {std::string(launcher_pid_env) + "=" + std::to_string(getpid()),
                                            std::string(launcher_log_env) + "=" + log.string()};
            if (k == 1) env.insert(env.end(), structure_env.begin(), structure_env.end());
            spawn(children[k], lines[k], env);
        }
    } catch (...) {
        if (children[0].pid > 0) kill(-children[0].pid, SIGKILL), reap(children[0], true);
        throw;
    }
    for (auto& ch : children) // opened after both started, so that neither inherits the other's log
        ch.log.open(std::filesystem::path(dir) / (ch.name + ".log"), resumed ? std::ios::app : std::ios::out);
}

// Interleaves the output of both sides until both ended; when one side fails, the other gets a grace period
// to notice (it writes its last output), then is stopped.
class Supervisor {
  public:
    explicit Supervisor(Child (&children)[2]) : ch_(children) {}
    void run() {
        while (!ch_[0].ended || !ch_[1].ended) {
            pass_output();
            for (auto& c : ch_)
                if (reap(c, false) && c.status != 0 && !any_failed_) failed(0);
            if (interrupted != 0 && !passed_on_) {
                const bool hangup = interrupted == SIGHUP;
                std::cout << "undex: " << (hangup ? "hangup (SIGHUP)" : "interrupted")
                          << ": stopping both sides" << std::endl;
                signal_all(hangup ? SIGHUP : SIGTERM);
                passed_on_ = true;
                if (!any_failed_) failed(1);
            }
            if (interrupts > 1 && stopped_ < 2) { // a second interrupt: no waiting for the checkpoints
                std::cout << "undex: interrupted again: killing both sides" << std::endl;
                signal_all(SIGKILL);
                stopped_ = 2;
            }
            stop_the_other();
        }
        drain();
    }

  private:
    void failed(int stopped) {
        any_failed_ = true;
        failed_at_ = std::chrono::steady_clock::now();
        stopped_ = stopped;
    }
    void signal_all(int sig) {
        for (auto& c : ch_)
            if (!c.ended) kill(-c.pid, sig), kill(-c.pid, SIGCONT);
    }
    void pass_output() {
        pollfd fds[2];
        int n = 0, which[2];
        for (int k = 0; k < 2; ++k)
            if (open_[k]) fds[n] = {ch_[k].fd, POLLIN, 0}, which[n++] = k;
        if (n > 0)
            poll(fds, n, 200);
        else
            usleep(50000);
        for (int i = 0; i < n; ++i)
            if (fds[i].revents & (POLLIN | POLLHUP | POLLERR))
                if (!pump(ch_[which[i]])) open_[which[i]] = false, close(ch_[which[i]].fd);
    }
    // A side that is still running 5 s after the other failed is stopped (SIGTERM, and SIGKILL 3 s later for
    // one that does not react, e.g. a stopped process). After an interrupt both sides finish their step and
    // write a checkpoint: a side is killed 60 s after it.
    void stop_the_other() {
        const auto since = std::chrono::steady_clock::now() - failed_at_;
        const auto grace = std::chrono::seconds(stopped_ == 0 ? 5 : passed_on_ ? 60 : 8);
        if (!any_failed_ || stopped_ >= 2 || since <= grace) return;
        for (auto& c : ch_)
            if (!c.ended && stopped_ == 0)
                std::cout << "undex: stopping " << c.name << " (the other side failed)" << std::endl;
        signal_all(stopped_ == 0 ? SIGTERM : SIGKILL);
        ++stopped_;
    }
    // What is left in the pipes (a process the solver started may still hold one: not waited for).
    void drain() {
        for (int k = 0; k < 2; ++k) {
            if (!open_[k]) continue;
            pollfd f{ch_[k].fd, POLLIN, 0};
            while (poll(&f, 1, 100) > 0 && pump(ch_[k])) {
            }
            close(ch_[k].fd);
        }
    }

    Child (&ch_)[2];
    bool open_[2] = {true, true};
    bool any_failed_ = false;
    bool passed_on_ = false; // the signal undex got went to both sides
    std::chrono::steady_clock::time_point failed_at_{};
    int stopped_ = 0; // 1: SIGTERM sent, 2: SIGKILL sent
};

} // namespace

int run_coupled(const CoupledRun& r) {
    catch_stop_signals(); // first: from here on a stop signal lets undex remove its lock
    const RunLock lock(r.directory, r.lock_command, r.force);
    lock.share_with_children();
    if (!lock.taken_over().empty())
        std::cout << "undex: --force: took over the stale lock of " << lock.taken_over() << std::endl;
    const std::string endpoint = endpoint_of(r);
    Child children[2];
    std::cout << "undex: " << r.case_path << ": coupled run over " << endpoint << "; logs " << r.directory
              << "/fluid.log, " << r.directory << "/solid.log" << std::endl;
    start(children, command_lines(r, endpoint), r.directory, !r.fluid_resume.empty(), r.structure_env);
    Supervisor(children).run();
    int code = 0;
    for (const auto& ch : children)
        if (ch.status != 0) {
            std::cout << "undex: " << ch.name << " ended with exit code " << ch.status << std::endl;
            if (code == 0) code = ch.status;
        }
    if (code == 0) std::cout << "undex: done: output in " << r.directory << std::endl;
    return code;
}

} // namespace undex::launcher
