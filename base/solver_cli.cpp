// The solvers' command line (base/solver_cli.hpp), parsed with CLI11.
#include "base/solver_cli.hpp"

#include "base/case_file.hpp"
#include "base/checkpoint.hpp"
#include "base/exit_status.hpp"
#include "base/h5.hpp"
#include "base/run_lock.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "proto/case.pb.h"

#include <google/protobuf/text_format.h>

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

namespace undex {

std::string output_override(const std::string& directory) {
    return "output.directory=" + directory;
}

CLI::Option* add_case_options(CLI::App& app, std::string& path, std::vector<std::string>& sets,
                              std::string& output) {
    auto* case_opt = app.add_option("CASE", path, "the case file (text format or JSON of proto/case.proto)");
    app.add_option("--set", sets, "override a scalar of the case, e.g. numerics.cfl=0.4 (repeatable)")
        ->type_name("KEY=VALUE")
        ->allow_extra_args(false);
    app.add_option("-o,--output", output, "the output directory (the override output.directory=DIR)")
        ->type_name("DIR")
        ->check([](const std::string& dir) {
            return dir.empty() ? std::string("the output directory is empty") : "";
        });
    return case_opt;
}

namespace {

// What the command line asked for.
struct Request {
    std::string case_path, couple, output, resume;
    std::vector<std::string> sets;
    bool check = false, options = false, force = false;
    std::string command; // the whole command line, for the lock file
    SampleRequest sample;
    bool sampling = false;
    std::vector<std::string> overrides() const {
        auto o = sets;
        if (!output.empty()) o.push_back(output_override(output));
        return o;
    }
};

// The options of the --sample mode (undex-fluid).
void add_sample_options(CLI::App& app, Request& r) {
    auto* s = app.add_option("--sample", r.sample.directory,
                             "print fields of the output in DIR (or an .h5 file) along a line as CSV")
                  ->type_name("DIR");
    app.add_option("--time", r.sample.time, "the output time nearest to T is sampled")
        ->type_name("T")
        ->needs(s);
    app.add_option("--line", r.sample.line, "the line from (x0,y0) to (x1,y1)")
        ->type_name("\"x0,y0 x1,y1\"")
        ->needs(s);
    app.add_option("--points", r.sample.points, "number of points on the line, its ends included")
        ->type_name("N")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()))
        ->needs(s);
    app.add_option("--fields", r.sample.fields, "the fields printed (default: rho,u,v,p)")
        ->type_name("rho,u,v,p")
        ->delimiter(',')
        ->needs(s);
}

// The command line of c; request is filled by CLI11's parse.
void describe(CLI::App& app, const SolverCommands& c, Request& r) {
    auto* case_opt = add_case_options(app, r.case_path, r.sets, r.output);
    auto* couple = app.add_option("--couple", r.couple, "couple to the other solver through ENDPOINT")
                       ->type_name("ENDPOINT");
    auto* force = app.add_flag(
        "--force", r.force, "take over a stale lock of the output directory (left by a run that was killed)");
    auto* resume = app.add_option("--resume", r.resume,
                                  "continue the run of CASE from a checkpoint of it (undex run --resume)")
                       ->type_name("CHECKPOINT")
                       ->check(CLI::ExistingFile);
    if (c.check)
        app.add_flag("--check", r.check, "check this solver's part of CASE, print a summary, write nothing")
            ->excludes(couple)
            ->excludes(force)
            ->excludes(resume);
    if (c.options)
        app.add_flag("--options", r.options, "list the named choices of a case file")->excludes(case_opt);
    if (c.sample) {
        add_sample_options(app, r);
        app.get_option("--sample")->excludes(case_opt)->excludes(couple);
    }
}

// A checkpoint continues the run it was written by: the same case and overrides but for where the outputs
// go and how often progress lines and checkpoints come (--resume DIR is the output directory).
std::string resumable_text(const std::string& text, const std::string& path) {
    config::Case c;
    if (!google::protobuf::TextFormat::ParseFromString(text, &c))
        throw UsageError(path + ": the checkpoint's case does not read as a case of this version");
    c.mutable_output()->clear_directory();
    c.mutable_output()->clear_checkpoint_seconds();
    c.mutable_output()->clear_progress_seconds();
    std::string out;
    google::protobuf::TextFormat::PrintToString(c, &out);
    return out;
}

void check_resume(const std::string& path, const CaseFile& cf) {
    const std::string saved = resumable_text(State::open(path).case_text(), path),
                      now = resumable_text(cf.text(), path);
    if (saved == now) return;
    auto lines = [](const std::string& text) {
        std::vector<std::string> out;
        std::istringstream in(text);
        for (std::string l; std::getline(in, l);)
            out.push_back(l);
        return out;
    };
    const auto a = lines(now), b = lines(saved);
    size_t k = 0;
    while (k < a.size() && k < b.size() && a[k] == b[k])
        ++k;
    throw UsageError(path + ": the checkpoint is of another case (or other --set overrides): line " +
                     std::to_string(k + 1) + " of the case is '" + (k < a.size() ? a[k] : "") +
                     "', the checkpoint's '" + (k < b.size() ? b[k] : "") +
                     "' (only output.directory, checkpoint_seconds and progress_seconds may differ)");
}

int dispatch(const SolverCommands& c, Request& r) {
    if (r.options) return c.options();
    if (!r.sample.directory.empty()) {
        if (r.sample.line.empty() || r.sample.points == 0 || r.sample.time != r.sample.time)
            throw UsageError("--sample needs --time, --line and --points");
        return c.sample(r.sample);
    }
    if (r.case_path.empty()) throw UsageError("CASE is required");
    if (r.check) return c.check(CaseFile::load(r.case_path, r.overrides()));
    install_stop_handler();
    const auto cf = CaseFile::load(r.case_path, r.overrides());
    validate_plan(cf); // the output directory is usable before it is locked (base/run_lock.hpp)
    // Of a solver started as many MPI ranks (mpirun sets OMPI_COMM_WORLD_RANK), the first one locks the
    // directory and writes the output for all.
    const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
    std::optional<RunLock> lock;
    if (!rank || std::string(rank) == "0") lock.emplace(plan(cf).directory, r.command, r.force);
    if (lock && !lock->taken_over().empty())
        std::cerr << c.name << ": --force: took over the stale lock of " << lock->taken_over() << "\n";
    if (!r.resume.empty()) check_resume(r.resume, cf);
    try {
        return c.run(cf, r.couple, r.resume);
    } catch (const h5::Error& e) { // an output that cannot be created: the run fails (exit status 2)
        std::cerr << c.name << ": error: " << e.what() << "\n";
        return exit_method_failed;
    }
}

} // namespace

// Where an error every rank meets alike (the command line, the case) is told: stderr of the first MPI rank
// (mpirun sets OMPI_COMM_WORLD_RANK) or of the one process, not once per rank.
static std::ostream& once() {
    static std::ostream quiet(nullptr);
    const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
    return !rank || std::string(rank) == "0" ? std::cerr : quiet;
}

int solver_main(int argc, char** argv, const SolverCommands& c) {
    protect_standard_streams();
    CLI::App app(c.description, c.name);
    Request r;
    r.command = command_line(argc, argv);
    r.sample.time = std::numeric_limits<double>::quiet_NaN(); // --time not given
    describe(app, c, r);
    const std::string hint = "run '" + c.name + " --help' for the command line";
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        once() << c.name << ": error: " << e.what() << "\n" << hint << "\n";
        return exit_usage;
    }
    try {
        return dispatch(c, r);
    } catch (const UsageError& e) {
        once() << c.name << ": error: " << e.what() << "\n" << hint << "\n";
        return exit_usage;
    } catch (const CaseError& e) {
        once() << c.name << ": error: " << e.what() << "\n";
        return exit_bad_case;
    } catch (const std::exception& e) {
        for (const auto& f : c.failures)
            if (f.matches(e)) {
                // Many ranks: a coupling's failure is the root's, relayed to every rank (fluid/run.cpp).
                once() << c.name << ": error: " << f.prefix << e.what() << "\n";
                // A wait of the handshake ended by SIGINT, SIGTERM or SIGHUP: stopped, as in the run
                // (drive()).
                return stop_requested() ? exit_stopped : f.status;
            }
        std::cerr << c.name << ": error: " << e.what() << "\n";
        return exit_bad_case;
    }
}

} // namespace undex
