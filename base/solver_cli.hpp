// The command line shared by the solver executables (undex-fluid, undex-solid, undex-rigid):
//   NAME CASE [--set key=value]... [-o DIR] [--couple ENDPOINT] [--force] [--resume CHECKPOINT]   run the
//                                                                  case (from a checkpoint of it)
//   NAME --check CASE [--set key=value]... [-o DIR]                check the solver's part of the case
//   NAME --options                                                  list the named choices it accepts
//   NAME --sample DIR --time T --line "x0,y0 x1,y1" --points N [--fields rho,u,v,p]   (undex-fluid only)
// -o DIR is the override output.directory=DIR, applied after the --set ones. Every mode has --help. A run
// locks its output directory (base/run_lock.hpp; a directory in use, or with a stale lock and no --force, is
// refused with exit status 1). SIGINT, SIGTERM and SIGHUP end a run at the next step (install_stop_handler);
// SIGPIPE and SIGXFSZ are ignored. Errors become one line on stderr and the exit status: 1 bad case (or
// another error), 2 an output that cannot be created or written (h5::Error), 3 coupling failure, 64 usage (an
// unknown option names it); the callbacks return the rest.
#pragma once
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
class Option;
} // namespace CLI

namespace undex {
class CaseFile;

// A command line that asks for the impossible (exit status 64), thrown by callbacks as well.
struct UsageError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// undex-fluid --sample: the fields of an output at the output time nearest to time, at points evenly spaced
// on the line from one point to another.
struct SampleRequest {
    std::string directory; // an output directory or an .h5 file
    double time = 0;
    std::string line;                // "x0,y0 x1,y1" (y may be left out in 1D)
    int points = 0;                  // number of points, the ends included
    std::vector<std::string> fields; // empty: all
};

// What a solver executable does; the callbacks left empty are modes it does not offer.
struct SolverCommands {
    std::string name;        // the executable's name, prefix of its error lines
    std::string description; // one line for --help
    // Runs the case; couple: the endpoint of the coupling ("" for a run alone); resume: the checkpoint to
    // continue from ("" for a new run), written for this case (checked before).
    std::function<int(const CaseFile&, const std::string& couple, const std::string& resume)> run;
    // Checks the solver's part of a case, prints one line "CASE: ok: ..." and returns 0 (throws CaseError).
    std::function<int(const CaseFile&)> check;
    // Prints the named choices of a case file the solver accepts.
    std::function<int()> options;
    std::function<int(const SampleRequest&)> sample;
    // Errors with an exit status of their own (e.g. 3 and "coupling: " for a coupling failure: base knows no
    // coupling, the solver's main names the type with failure_kind); any other error is status 1.
    struct FailureKind {
        std::function<bool(const std::exception&)> matches;
        int status;
        std::string prefix; // before the message on the error line
    };
    std::vector<FailureKind> failures;
};

template <class Error> SolverCommands::FailureKind failure_kind(int status, std::string prefix) {
    return {[](const std::exception& e) { return dynamic_cast<const Error*>(&e) != nullptr; }, status,
            std::move(prefix)};
}

// The main function of a solver executable.
int solver_main(int argc, char** argv, const SolverCommands& commands);

// The override -o DIR stands for.
std::string output_override(const std::string& directory);

// The case options of every command that reads a case (the solvers, `undex check`, `undex run`): CASE,
// --set KEY=VALUE (repeatable), -o/--output DIR (not empty). Returns the CASE option.
CLI::Option* add_case_options(CLI::App& app, std::string& path, std::vector<std::string>& sets,
                              std::string& output);

} // namespace undex
