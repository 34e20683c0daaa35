// The processes undex starts: the solver executables (found next to undex) for a check, a run alone, a
// coupled run side by side, or in place of undex.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex::launcher {

// The directory of the undex executable, which holds the solver executables too.
std::filesystem::path bin_dir();

// A child process that failed; what it printed on stderr is the message (its "NAME: error: " prefix
// removed), status its exit status.
struct ChildFailure : std::runtime_error {
    ChildFailure(const std::string& message, int status) : std::runtime_error(message), status(status) {}
    int status;
};

// Runs args to its end with stdout and stderr captured.
struct Captured {
    int status = -1; // exit code (128 + signal when killed)
    std::string out, err;
};
Captured run_captured(const std::vector<std::string>& args);
// Runs args captured; its stdout when it ends with status 0, else throws ChildFailure.
std::string output_of(const std::vector<std::string>& args);

// Replaces undex by args (its output and exit status become undex's); returns 1 only when it cannot start.
int exec(const std::vector<std::string>& args);

// A child process whose stdout and stderr arrive on one pipe.
struct Child {
    std::string name; // the prefix of its lines
    pid_t pid = -1;
    int fd = -1;         // read end of its output
    std::string pending; // an incomplete last line
    std::ofstream log;   // <output>/<name>.log
    int status = -1;     // exit code once ended (128 + signal when killed)
    bool ended = false;
};
// Starts args as c, in a process group of its own, with env (NAME=VALUE) added to its environment. The child
// gets SIGHUP when undex dies (PR_SET_PDEATHSIG; the solvers then stop with their last good state,
// base/signals.hpp) and SIGPIPE back at its default.
void spawn(Child& c, const std::vector<std::string>& args, const std::vector<std::string>& env = {});
// Passes complete lines of c's output to the terminal (prefixed) and to its log; false at end of output.
bool pump(Child& c);
// Whether c has ended (waiting for it when block).
bool reap(Child& c, bool block);

} // namespace undex::launcher
