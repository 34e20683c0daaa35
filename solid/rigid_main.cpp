// undex-rigid: the rigid-plate structure solver (solid/rigid.hpp; base/solver_cli.hpp has the command line).
//   undex-rigid CASE [--set key=value]... [-o DIR] --couple ENDPOINT   runs the rigid plate of a case
//   undex-rigid --check CASE [--set key=value]... [-o DIR]             checks it
#include "base/case_file.hpp"
#include "base/exit_status.hpp"
#include "base/solver_cli.hpp"
#include "coupler/participant.hpp"
#include "solid/rigid.hpp"
#include "solid/structure_setup.hpp"

#include <iostream>

int main(int argc, char** argv) {
    undex::SolverCommands commands;
    commands.name = "undex-rigid";
    commands.description = "undex-rigid: a rigid plate per unit area behind the coupling protocol";
    commands.run = undex::solid::run_rigid;
    commands.check = [](const undex::CaseFile& c) {
        const auto plate = undex::solid::make_rigid_plate(c);
        std::cout << c.path() << ": ok: structure rigid plate of " << plate.mass_per_area
                  << " kg/m² (undex-rigid)\n";
        return 0;
    };
    commands.failures.push_back(
        undex::failure_kind<undex::coupling::CouplingError>(undex::exit_coupling_failed, "coupling: "));
    return undex::solver_main(argc, argv, commands);
}
