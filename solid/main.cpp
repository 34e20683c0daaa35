// undex-solid: the structure solver (base/solver_cli.hpp has the whole command line).
//   undex-solid CASE [--set key=value]... [-o DIR] [--couple ENDPOINT]   runs the structure of a case; a
//       structure wetted by the case's fluid couples to the fluid solver bound at ENDPOINT (undex run does
//       this)
//   undex-solid --check CASE [--set key=value]... [-o DIR]                checks the structure of a case
//   undex-solid --options                                                  the structure's named choices
#include "base/case_file.hpp"
#include "base/exit_status.hpp"
#include "base/run_plan.hpp"
#include "base/solver_cli.hpp"
#include "coupler/participant.hpp"
#include "proto/case.pb.h"
#include "solid/run_structure.hpp"
#include "solid/structure_setup.hpp"

#include <iostream>
#include <sstream>
#include <string>

namespace {

// "structure of L layer(s), N elements[ (axisymmetric|plane strain)], time step DT s" (or, for a structure
// too large to build in a check, that the time step is computed when it runs).
std::string describe(const undex::CaseFile& c, const undex::solid::StructureModel& s) {
    std::ostringstream o;
    o << "structure of " << s.layers.size() << " layer(s), " << static_cast<long long>(s.elements)
      << " elements";
    const auto g = c.get().geometry();
    if (g != undex::config::PLANAR_1D)
        o << (g == undex::config::AXISYMMETRIC_2D ? " (axisymmetric)" : " (plane strain)");
    if (s.structure)
        o << ", time step " << s.dt << " s";
    else
        o << ", time step computed when it runs (too large to build in a check)";
    return o.str();
}

// "CASE: ok: structure of ...", with the end time when the structure runs alone. A structure solved by
// another program (structure.command) is checked for what the case says of it.
int check(const undex::CaseFile& c) {
    if (c.get().structure().has_command()) {
        undex::solid::check_structure(c);
        std::cout << c.path() << ": ok: structure solver '" << c.get().structure().command() << "'\n";
        return 0;
    }
    const std::string summary = describe(
        c, undex::solid::make_structure(c, undex::solid::Build::IfSmall)); // before any output: it may throw
    std::cout << c.path() << ": ok: " << summary;
    if (!undex::has_fluid(c)) std::cout << ", end time " << c.get().end_time() << " s";
    std::cout << "\n";
    return 0;
}

int options() {
    std::cout << "structure.kinematics:\n";
    for (const auto& n : undex::solid::kinematics_names())
        std::cout << "  " << n.first << "  " << n.second << "\n";
    std::cout << "structure face type: FREE FIXED PRESSURE FLUID (front: wetted by the fluid)\n";
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    undex::SolverCommands commands;
    commands.name = "undex-solid";
    commands.description = "undex-solid: the explicit finite-element structure solver of undex";
    commands.run = [](const undex::CaseFile& c, const std::string& couple, const std::string& resume) {
        return undex::solid::run_structure(c, std::cout, couple, resume);
    };
    commands.check = check;
    commands.options = options;
    commands.failures.push_back(
        undex::failure_kind<undex::coupling::CouplingError>(undex::exit_coupling_failed, "coupling: "));
    return undex::solver_main(argc, argv, commands);
}
