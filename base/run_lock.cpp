#include "base/run_lock.hpp"

#include "base/signals.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>

namespace undex {

namespace fs = std::filesystem;

namespace {

std::string error_text(const std::string& what, int err) {
    return what + ": " + std::strerror(err);
}

std::string read_text(int fd) {
    std::string s;
    char buf[4096];
    for (off_t at = 0;;) {
        const ssize_t n = pread(fd, buf, sizeof buf, at);
        if (n <= 0 || s.size() > 65536) break;
        s.append(buf, static_cast<size_t>(n));
        at += n;
    }
    return s;
}

// The lines key=value of a lock file.
std::map<std::string, std::string> fields_of(const std::string& text) {
    std::map<std::string, std::string> f;
    size_t from = 0;
    while (from < text.size()) {
        size_t nl = text.find('\n', from);
        if (nl == std::string::npos) nl = text.size();
        const std::string line = text.substr(from, nl - from);
        const size_t eq = line.find('=');
        if (eq != std::string::npos) f[line.substr(0, eq)] = line.substr(eq + 1);
        from = nl + 1;
    }
    return f;
}

std::string host_name() {
    char h[256] = {};
    gethostname(h, sizeof h - 1);
    return h;
}

// "pid 123 on host H since 2026-11-30T22:13:40Z (undex run case.case)".
std::string holder_of(const std::string& text) {
    auto f = fields_of(text);
    if (f["pid"].empty()) return "a run that has not written its name yet";
    std::string s =
        "pid " + f["pid"] + " on host " + f["host"] + " since " + f["start"] + " (" + f["command"] + ")";
    return s;
}

// The pid of a lock's holder when it ran on this host and is gone (its solvers may still run), else 0.
long gone_holder(const std::string& text) {
    auto f = fields_of(text);
    const long pid = std::atol(f["pid"].c_str());
    if (pid <= 0 || f["host"] != host_name()) return 0;
    return kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH ? pid : 0;
}

// Whether a held lock is that of the launcher that started this solver through mpirun, which does not
// pass the descriptor on (inherited): the lock names the launcher's pid (launcher_pid_env) on this host.
bool held_by_launcher(const std::string& text) {
    const char* launcher = std::getenv(launcher_pid_env);
    auto f = fields_of(text);
    return launcher && *launcher && f["pid"] == launcher && f["host"] == host_name();
}

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

bool same_file(int fd, const std::string& path) {
    struct stat a {
    }, b{};
    return fstat(fd, &a) == 0 && stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

// The descriptor a launcher passed on, if it is this lock file and holds its flock (flock on a descriptor
// that already holds the lock succeeds); else -1.
int inherited(const std::string& path) {
    const char* env = std::getenv(run_lock_fd_env);
    if (!env || !*env) return -1;
    char* end = nullptr;
    const long fd = std::strtol(env, &end, 10);
    if (*end != '\0' || fd < 0 || fd > 1 << 20 || fcntl(static_cast<int>(fd), F_GETFD) < 0) return -1;
    if (!same_file(static_cast<int>(fd), path) || flock(static_cast<int>(fd), LOCK_EX | LOCK_NB) != 0)
        return -1;
    fcntl(static_cast<int>(fd), F_SETFD, FD_CLOEXEC);
    return static_cast<int>(fd);
}

} // namespace

RunLock::RunLock(const std::string& directory, const std::string& command, bool force) {
    std::error_code ec;
    const fs::path dir = fs::absolute(directory, ec);
    if (ec) throw RunLockError("output directory " + directory + ": " + ec.message());
    for (fs::path p = dir; !p.empty() && !fs::exists(p, ec) && p != p.parent_path(); p = p.parent_path())
        created_.push_back(p.string());
    try {
        fs::create_directories(dir);
        take(dir, command, force);
    } catch (...) {
        remove_created();
        throw;
    }
}

void RunLock::remove_created() const {
    for (const auto& d : created_)
        rmdir(d.c_str()); // fails, leaving it, unless empty
}

void RunLock::take(const std::filesystem::path& dir, std::string command, bool force) {
    path_ = (dir / "undex.lock").string();
    if ((fd_ = inherited(path_)) >= 0) return; // the run of the launcher that started this solver
    // A lock file removed by its holder between our open and flock is not the lock any more: open again.
    for (;;) {
        fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0) throw RunLockError(error_text("cannot create the lock file " + path_, errno));
        if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            const int err = errno;
            const std::string text = read_text(fd_);
            close(fd_), fd_ = -1;
            if (err != EWOULDBLOCK) throw RunLockError(error_text("cannot lock " + path_, err));
            if (held_by_launcher(text)) return; // the launcher holds it for this run
            std::string msg =
                "output directory " + dir.string() + " is in use by another run: " + holder_of(text);
            if (const long pid = gone_holder(text))
                msg +=
                    "; pid " + std::to_string(pid) + " has ended, but processes it started still write there";
            throw RunLockError(msg + " (lock " + path_ +
                               "); wait for it to end or choose another directory (-o DIR)");
        }
        if (same_file(fd_, path_)) break;
        close(fd_);
    }
    const std::string text = read_text(fd_);
    if (!text.empty() && !force) {
        close(fd_), fd_ = -1; // the stale file stays as it was
        throw RunLockError("output directory " + dir.string() +
                           " holds the stale lock of a run that ended without "
                           "removing it (killed, crashed, or its machine stopped): " +
                           holder_of(text) +
                           "; its files there may be incomplete. --force takes the lock over (" + path_ +
                           ")");
    }
    own_ = true;
    if (!text.empty()) taken_over_ = holder_of(text);
    for (char& ch : command)
        if (ch == '\n') ch = ' ';
    const std::string mine = "pid=" + std::to_string(getpid()) + "\nhost=" + host_name() +
                             "\nstart=" + utc_now() + "\ncommand=" + command + "\n";
    if (ftruncate(fd_, 0) != 0 ||
        pwrite(fd_, mine.data(), mine.size(), 0) != static_cast<ssize_t>(mine.size())) {
        const int err = errno;
        unlink(path_.c_str());
        close(fd_), fd_ = -1;
        throw RunLockError(error_text("cannot write the lock file " + path_, err));
    }
}

RunLock::~RunLock() {
    if (fd_ < 0) return;
    if (own_) unlink(path_.c_str()); // while holding the flock: a run that opened this file opens a new one
    close(fd_);
    remove_created();
}

void RunLock::share_with_children() const {
    fcntl(fd_, F_SETFD, 0);
    setenv(run_lock_fd_env, std::to_string(fd_).c_str(), 1);
}

std::string command_line(int argc, char** argv) {
    std::string s;
    for (int k = 0; k < argc; ++k) {
        std::string a = argv[k];
        if (a.empty() || a.find_first_of(" \t\n'\"\\$") != std::string::npos) {
            std::string q = "'";
            for (char ch : a)
                q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
            a = q + "'";
        }
        if (k) s += ' ';
        s += a;
    }
    return s;
}

} // namespace undex
