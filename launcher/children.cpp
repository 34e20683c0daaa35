// Child processes of undex (launcher/children.hpp).
#include "launcher/children.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

namespace undex::launcher {

namespace {

std::vector<char*> c_args(std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (auto& s : args)
        argv.push_back(s.data());
    argv.push_back(nullptr);
    return argv;
}

std::string read_all(std::FILE* f) {
    std::string s;
    std::rewind(f);
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;)
        s.append(buf, n);
    std::fclose(f);
    return s;
}

int exit_code(int st) {
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

} // namespace

std::filesystem::path bin_dir() {
    return std::filesystem::read_symlink("/proc/self/exe").parent_path();
}

Captured run_captured(const std::vector<std::string>& args) {
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    if (!out || !err) throw std::runtime_error(std::string("cannot create a file: ") + std::strerror(errno));
    std::vector<std::string> copy = args;
    auto argv = c_args(copy);
    std::cout.flush();
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error(std::string("cannot start a process: ") + std::strerror(errno));
    if (pid == 0) {
        dup2(fileno(out), 1);
        dup2(fileno(err), 2);
        execv(argv[0], argv.data());
        std::fprintf(stderr, "undex: cannot start %s: %s\n", argv[0], std::strerror(errno));
        _exit(127);
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
    return {exit_code(st), read_all(out), read_all(err)};
}

std::string output_of(const std::vector<std::string>& args) {
    auto r = run_captured(args);
    if (r.status == 0) return r.out;
    // "undex-fluid: error: MESSAGE" becomes MESSAGE (undex prints it as "undex: error: MESSAGE").
    const std::string prefix = std::filesystem::path(args[0]).filename().string() + ": error: ";
    if (r.err.rfind(prefix, 0) == 0) r.err.erase(0, prefix.size());
    while (!r.err.empty() && r.err.back() == '\n')
        r.err.pop_back();
    if (r.err.empty()) r.err = args[0] + " ended with exit status " + std::to_string(r.status);
    throw ChildFailure(r.err, r.status);
}

int exec(const std::vector<std::string>& args) {
    std::vector<std::string> copy = args;
    auto argv = c_args(copy);
    std::cout.flush();
    execvp(argv[0], argv.data()); // a path, or a program on PATH (mpirun)
    std::cerr << "undex: error: cannot start " << args[0] << ": " << std::strerror(errno) << "\n";
    return 1;
}

void spawn(Child& c, const std::vector<std::string>& args, const std::vector<std::string>& env) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) // not inherited by the other side's process
        throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
    std::vector<std::string> copy = args, vars = env;
    auto argv = c_args(copy);
    auto envs = c_args(vars);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        throw std::runtime_error(std::string("cannot start a process: ") + std::strerror(errno));
    }
    if (pid == 0) {
        setpgid(0, 0); // its own process group: stopping it reaches whatever it starts
        // SIGHUP when undex dies, even by SIGKILL (kept across exec); undex may have died before this line.
        prctl(PR_SET_PDEATHSIG, SIGHUP);
        if (getppid() != parent) _exit(128 + SIGHUP);
        signal(SIGPIPE, SIG_DFL); // undex ignores it; the solvers ignore it themselves
        for (size_t k = 0; k + 1 < envs.size(); ++k)
            putenv(envs[k]);
        dup2(fds[1], 1);
        dup2(fds[1], 2);
        close(fds[0]);
        close(fds[1]);
        execvp(argv[0], argv.data());
        std::fprintf(stderr, "undex: cannot start %s: %s\n", argv[0], std::strerror(errno));
        _exit(127);
    }
    close(fds[1]);
    c.pid = pid;
    c.fd = fds[0];
}

bool pump(Child& c) {
    char buf[65536];
    const ssize_t n = read(c.fd, buf, sizeof buf);
    if (n <= 0) {
        if (!c.pending.empty()) c.pending += "\n";
    } else {
        c.pending.append(buf, static_cast<size_t>(n));
    }
    size_t from = 0;
    for (size_t nl; (nl = c.pending.find('\n', from)) != std::string::npos; from = nl + 1) {
        const std::string line = c.pending.substr(from, nl - from);
        c.log << line << '\n';
        std::cout << c.name << " | " << line << '\n';
    }
    c.pending.erase(0, from);
    std::cout.flush();
    c.log.flush();
    return n > 0;
}

bool reap(Child& c, bool block) {
    if (c.ended) return true;
    int st = 0;
    const pid_t r = waitpid(c.pid, &st, block ? 0 : WNOHANG);
    if (r != c.pid) return false;
    c.ended = true;
    c.status = exit_code(st);
    return true;
}

} // namespace undex::launcher
