// undex: the command-line front end. It knows no physics: the solver executables next to it check their part
// of a case, run it and sample their output; undex starts them (both sides of a coupled case) and reads
// gauge series from HDF5.
//   undex check CASE [--set key=value]... [-o DIR]   check a case without running it
//   undex run CASE [--set key=value]... [-o DIR] [--tcp | --endpoint E] [--force] [--resume DIR]
//                                                    run a case: the solver process a single-field case
//                                                    needs, or the fluid and structure processes of a coupled
//                                                    case; the output directory is locked for the run
//                                                    (base/run_lock.hpp: --force takes over a stale lock);
//                                                    --resume DIR continues the run in DIR from its
//                                                    checkpoints (base/checkpoint.hpp)
//   undex sample DIR --time T --line "x0,y0 x1,y1" --points N [--fields rho,u,v,p]   (undex-fluid --sample)
//   undex gauges DIR [--name NAME]
//   undex options                                    the named choices of a case file, from each solver
//   undex conform [--timeout S] -- COMMAND...        check a structure solver against the protocol
// Every command has --help; a command line undex cannot use exits with status 64, naming what is wrong.
#include "base/case_file.hpp"
#include "base/checkpoint.hpp"
#include "base/exit_status.hpp"
#include "base/run_lock.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "base/solver_cli.hpp"
#include "coupler/conform.hpp"
#include "launcher/children.hpp"
#include "launcher/coupled.hpp"
#include "launcher/gauges.hpp"
#include "launcher/mpirun.hpp"
#include "proto/case.pb.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

namespace {

using namespace undex::launcher;

std::string exe(const std::string& name) {
    return (bin_dir() / name).string();
}

// A case and its overrides, as `undex check` and `undex run` take them.
struct CaseRequest {
    std::string path, output;
    std::vector<std::string> sets;
    std::vector<std::string> overrides() const {
        auto o = sets;
        if (!output.empty()) o.push_back(undex::output_override(output));
        return o;
    }
    // The same for a solver executable: --set KEY=VALUE... [-o DIR].
    std::vector<std::string> solver_args() const {
        std::vector<std::string> a;
        for (const auto& s : sets)
            a.insert(a.end(), {"--set", s});
        if (!output.empty()) a.insert(a.end(), {"-o", output});
        return a;
    }
};

// `SOLVER --check CASE ...`: its summary line, or ChildFailure with its message.
std::string solver_check(const std::string& solver, const CaseRequest& r) {
    std::vector<std::string> args = {exe(solver), "--check", r.path};
    const auto more = r.solver_args();
    args.insert(args.end(), more.begin(), more.end());
    return output_of(args);
}

// Checks each part of the case with the solver that runs it (the fluid first); returns their summary lines,
// the structure's first. A case with neither part is an error.
std::string check_parts(const CaseRequest& r, const undex::CaseFile& c) {
    const bool fluid = undex::has_fluid(c), structure = undex::has_structure(c);
    if (!fluid && !structure) c.fail("regions", "the case models nothing: give fluid regions or a structure");
    std::string fluid_line, structure_line;
    if (fluid) fluid_line = solver_check("undex-fluid", r);
    if (structure) {
        const auto& st = c.get().structure();
        structure_line = solver_check(st.has_rigid_plate() ? "undex-rigid" : "undex-solid", r);
    }
    return structure_line + fluid_line;
}

int check(const CaseRequest& r) {
    const auto c = undex::CaseFile::load(r.path, r.overrides());
    std::cout << check_parts(r, c);
    return 0;
}

int run(CaseRequest r, const std::string& endpoint, bool tcp, bool force, const std::string& command,
        const std::string& resume, int ranks, const std::string& hosts) {
    // --resume DIR is the run of CASE in DIR: its output directory.
    if (!resume.empty()) {
        if (!r.output.empty() && r.output != resume)
            throw undex::UsageError("--resume " + resume + " continues the run in " + resume + ": -o " +
                                    r.output + " names another directory");
        r.output = resume;
    }
    // The case is checked first, so that a bad case is reported before any process starts.
    const auto c = undex::CaseFile::load(r.path, r.overrides());
    check_parts(r, c);
    const bool fluid = undex::has_fluid(c), structure = undex::has_structure(c);
    if (ranks == 0) ranks = c.get().numerics().ranks();
    if (ranks > 1 && !fluid)
        throw undex::UsageError("--ranks: the case has no fluid (the structure runs on one)");
    if (fluid && structure) {
        const auto& st = c.get().structure();
        CoupledRun run{r.path,
                       r.solver_args(),
                       undex::plan(c).directory,
                       endpoint,
                       tcp,
                       exe("undex-fluid"),
                       exe(st.has_rigid_plate() ? "undex-rigid" : "undex-solid"),
                       st.command(),
                       command,
                       force};
        if (!st.has_command()) run.command.clear();
        if (ranks > 1) run.fluid_prefix = mpirun_prefix(ranks, c.get().numerics().threads(), hosts);
        // The fluid takes the cores; the structure's threads would only compete with it (proto/case.proto).
        if (st.threads() == 0 && !std::getenv("OMP_NUM_THREADS")) run.structure_env = {"OMP_NUM_THREADS=1"};
        if (!resume.empty()) {
            if (!run.command.empty())
                throw undex::UsageError(
                    "--resume: the case's structure.command is a solver undex cannot resume");
            if (st.has_rigid_plate())
                throw undex::UsageError("--resume: undex-rigid keeps no checkpoints (a rigid plate's run takes "
                                        "seconds): run the case again");
            std::tie(run.fluid_resume, run.structure_resume) = undex::resume_pair(resume);
            std::cout << "undex: resuming from " << run.fluid_resume << " and " << run.structure_resume
                      << std::endl;
        }
        return run_coupled(run);
    }
    // A single-field case needs only its own process, which takes undex's place and locks the directory.
    std::vector<std::string> args;
    if (ranks > 1) args = mpirun_prefix(ranks, c.get().numerics().threads(), hosts);
    args.insert(args.end(), {exe(fluid ? "undex-fluid" : "undex-solid"), r.path});
    const auto more = r.solver_args();
    args.insert(args.end(), more.begin(), more.end());
    if (force) args.push_back("--force");
    if (!resume.empty())
        args.insert(args.end(), {"--resume", undex::resume_single(resume, fluid ? "fluid" : "solid")});
    return exec(args);
}

int options() {
    std::cout << output_of({exe("undex-fluid"), "--options"}) << output_of({exe("undex-solid"), "--options"})
              << "the schema with every field and its default: proto/case.proto\n";
    return 0;
}

// The case options of check and run.
void add_case_options(CLI::App& app, CaseRequest& r) {
    undex::add_case_options(app, r.path, r.sets, r.output)->required();
}

// What the command line asked for.
struct Request {
    CaseRequest case_request;
    std::string endpoint;
    bool tcp = false, force = false;
    std::string resume;                         // run --resume DIR
    int ranks = 0;                              // run --ranks N (0: the case's numerics.ranks)
    std::string hosts;                          // run --hosts FILE
    std::string command_line;                   // undex's own, for the lock file
    std::string dir, time, line, fields, gauge; // sample, gauges
    int points = 0;
    double timeout = 10;              // conform
    std::vector<std::string> command; // conform
};

void add_sample(CLI::App& app, Request& r) {
    auto* s = app.add_subcommand("sample", "print fluid fields along a line as CSV (undex-fluid --sample)");
    s->add_option("DIR", r.dir, "an output directory or its fluid.h5")->required();
    s->add_option("--time", r.time, "the output time nearest to T is sampled")
        ->type_name("T")
        ->check(CLI::Number)
        ->required();
    s->add_option("--line", r.line, "the line from (x0,y0) to (x1,y1)")
        ->type_name("\"x0,y0 x1,y1\"")
        ->required();
    s->add_option("--points", r.points, "number of points on the line, its ends included")
        ->type_name("N")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()))
        ->required();
    s->add_option("--fields", r.fields, "the fields printed (default: rho,u,v,p)")->type_name("rho,u,v,p");
}

void describe(CLI::App& app, Request& r) {
    app.require_subcommand(1);
    auto* check =
        app.add_subcommand("check", "check a case without running it (each solver checks its part)");
    add_case_options(*check, r.case_request);
    auto* run = app.add_subcommand("run", "run a case: one solver, or the fluid and the structure coupled");
    add_case_options(*run, r.case_request);
    auto* tcp = run->add_flag("--tcp", r.tcp, "couple over a free tcp port of this host instead of ipc://");
    run->add_option("--endpoint", r.endpoint, "couple over ENDPOINT (ipc://PATH or tcp://HOST:PORT)")
        ->type_name("ENDPOINT")
        ->excludes(tcp);
    run->add_option("--ranks", r.ranks,
                    "run the fluid as N MPI ranks (mpirun; overrides numerics.ranks; docs/scale_out.md)")
        ->type_name("N")
        ->check(CLI::Range(1, 65536));
    run->add_option("--hosts", r.hosts, "mpirun's --hostfile: the hosts the fluid's ranks run on")
        ->type_name("FILE");
    run->add_flag("--force", r.force,
                  "take over a stale lock of the output directory (left by a run that was killed)");
    run->add_option("--resume", r.resume,
                    "continue the run of CASE in DIR (its output directory) from the checkpoints there, "
                    "with the same --set overrides")
        ->type_name("DIR")
        ->check(CLI::ExistingDirectory);
    add_sample(app, r);
    auto* gauges = app.add_subcommand("gauges", "print the gauge series of an output as CSV, time first");
    gauges->add_option("DIR", r.dir, "an output directory or its fluid.h5 / solid.h5")->required();
    gauges->add_option("--name", r.gauge, "only the gauge NAME")->type_name("NAME");
    app.add_subcommand("options", "list the named choices of a case file (from undex-fluid and undex-solid)");
    auto* conform = app.add_subcommand("conform", "check a structure solver against the coupling protocol");
    conform->add_option("--timeout", r.timeout, "seconds to wait for the solver")->type_name("S");
    conform
        ->add_option("COMMAND", r.command,
                     "the solver's command line (after --); --couple ENDPOINT is appended")
        ->required();
}

int dispatch(const CLI::App& app, const Request& r) {
    const std::string cmd = app.get_subcommands().front()->get_name();
    if (cmd == "check") return check(r.case_request);
    if (cmd == "run")
        return run(r.case_request, r.endpoint, r.tcp, r.force, r.command_line, r.resume, r.ranks, r.hosts);
    if (cmd == "sample") {
        std::vector<std::string> args = {
            exe("undex-fluid"),      "--sample", r.dir, "--time", r.time, "--line", r.line, "--points",
            std::to_string(r.points)};
        if (!r.fields.empty()) args.insert(args.end(), {"--fields", r.fields});
        return exec(args);
    }
    if (cmd == "gauges") return gauges(r.dir, r.gauge);
    if (cmd == "options") return options();
    return std::min(undex::coupling::conform(r.command, r.timeout), 100); // conform
}

} // namespace

int main(int argc, char** argv) {
    undex::protect_standard_streams(); // a closed stdout costs no run: the logs and the children go on
    CLI::App app("undex: underwater explosions: a fluid and a structure solver, coupled", "undex");
    Request r;
    r.command_line = undex::command_line(argc, argv);
    describe(app, r);
    const std::string hint = "run 'undex --help' or 'undex COMMAND --help' for the command line";
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        const auto named = [&](CLI::App* s) { return s->check_name(argv[1]); };
        if (argc > 1 && argv[1][0] != '-' && app.get_subcommands(named).empty())
            std::cerr << "undex: error: unknown command '" << argv[1] << "'\n" << hint << "\n";
        else
            std::cerr << "undex: error: " << e.what() << "\n" << hint << "\n";
        return undex::exit_usage;
    }
    try {
        return dispatch(app, r);
    } catch (const ChildFailure& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return e.status;
    } catch (const undex::CaseError& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return undex::exit_bad_case;
    } catch (const std::invalid_argument& e) {
        std::cerr << "undex: error: " << e.what() << "\n" << hint << "\n";
        return undex::exit_usage;
    } catch (const std::exception& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return undex::exit_bad_case;
    }
}
