// One run per output directory: DIR/undex.lock names the run that writes DIR (pid, host, start time in UTC,
// command line) and is held with flock(2) while it runs. It is taken before anything in DIR is created or
// replaced, by whoever starts the run: `undex run` for a coupled run (its solvers share it, below), a solver
// executable started on its own (undex-fluid, undex-solid, undex-rigid with a case; a single-field `undex
// run` becomes that solver by exec). A second run into DIR is refused before it touches any file, with a
// message naming the first (exit status 1, as for any error before the run starts). The lock is removed when
// the run ends in any way that lets code run (done, failure, SIGINT, SIGTERM, SIGHUP).
//
// Liveness is the flock, not the pid: a lock file nobody holds (its run was killed with SIGKILL, crashed, or
// its machine stopped) is stale. A stale lock is refused too, saying so (the files of that run may be
// incomplete); --force takes it over. A live lock is never taken over. Liveness across hosts is as good as
// the file system's flock (local file systems, NFS with lock support); the host in the file says where.
// A later --resume of the same directory will take a stale lock as its own the way --force does (the run it
// continues is the one that left it), and refuse a live one like any run.
//
// Sharing: `undex run` passes its lock to the solvers it starts as an inherited file descriptor named in the
// environment (UNDEX_RUN_LOCK_FD). A solver whose inherited descriptor is the lock file of its output
// directory and holds its flock runs under it and leaves it to its holder; the flock then lives as long as
// any of them runs (the solvers writing their last good state after the launcher died keep it live).
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex {

// The output directory is locked by another run, or holds a stale lock (and no --force).
struct RunLockError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The environment variable naming the lock descriptor a launcher passes on.
inline constexpr const char* run_lock_fd_env = "UNDEX_RUN_LOCK_FD";

class RunLock {
  public:
    // Takes the lock of directory (made when missing) for the run `command`, or throws RunLockError naming
    // the holder. force: take over a stale lock.
    RunLock(const std::string& directory, const std::string& command, bool force);
    // Removes the lock file if this process took the lock, then the directories it made if they are empty
    // (a run refused before writing anything leaves nothing behind).
    ~RunLock();
    RunLock(const RunLock&) = delete;
    RunLock& operator=(const RunLock&) = delete;
    // The processes started from here on (fork and exec) share the lock (UNDEX_RUN_LOCK_FD).
    void share_with_children() const;
    const std::string& path() const { return path_; }
    // The run whose stale lock --force took over ("pid N on host H since T (COMMAND)"), or "".
    const std::string& taken_over() const { return taken_over_; }

  private:
    void take(const std::filesystem::path& dir, std::string command, bool force);
    void remove_created() const;
    std::string path_;
    int fd_ = -1;
    bool own_ = false;                 // taken here (false: shared from the launcher that started us)
    std::vector<std::string> created_; // directories made for the lock, the deepest first
    std::string taken_over_;
};

// argv as one line for the lock file and messages (arguments with blanks or quotes in single quotes).
std::string command_line(int argc, char** argv);

} // namespace undex
