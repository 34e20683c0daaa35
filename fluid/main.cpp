// undex-fluid: the fluid solver (base/solver_cli.hpp has the whole command line).
//   undex-fluid CASE [--set key=value]... [-o DIR] [--couple ENDPOINT]   runs the fluid of a case; a case
//       with a structure couples to a structure solver through ENDPOINT (undex run does this)
//   undex-fluid --check CASE [--set key=value]... [-o DIR]                checks the fluid of a case
//   undex-fluid --options                                                  the fluid's named choices
//   undex-fluid --sample DIR --time T --line "x0,y0 x1,y1" --points N [--fields rho,u,v,p]
#include "base/case_file.hpp"
#include "base/exit_status.hpp"
#include "base/run_plan.hpp"
#include "base/solver_cli.hpp"
#include "coupler/participant.hpp"
#include "fluid/run.hpp"
#include "fluid/sample.hpp"
#include "fluid/setup.hpp"
#include "fluid/solver.hpp"
#include "proto/case.pb.h"

#include <iostream>
#include <string>

namespace {

// "CASE: ok: GEOMETRY, CELLS cells, degree D, end time T s, N output time(s), output to DIR".
int check(const undex::CaseFile& c) {
    undex::fluid::validate(c);
    const auto p = undex::plan(c);
    const auto& m = c.get();
    std::cout << c.path() << ": ok: " << undex::config::Geometry_Name(m.geometry()) << ", "
              << m.domain().cells_x();
    if (m.domain().has_cells_y()) std::cout << " x " << m.domain().cells_y();
    std::cout << " cells, degree " << m.numerics().degree() << ", end time " << m.end_time() << " s, "
              << p.output_times.size() << " output time(s), output to " << p.directory << "\n";
    return 0;
}

int options() {
    const auto list = [](const char* field, const std::vector<undex::fluid::NamedOption>& names) {
        std::cout << field << ":\n";
        for (const auto& n : names)
            std::cout << "  " << n.name << "  " << n.doc << "\n";
    };
    list("numerics.indicator", undex::fluid::indicator_names());
    list("numerics.limiter", undex::fluid::limiter_names());
    list("interface.method", undex::fluid::ghost_method_names());
    list("interface.riemann", undex::fluid::interface_riemann_names());
    std::cout << "geometry: PLANAR_1D CYLINDRICAL_1D SPHERICAL_1D PLANAR_2D AXISYMMETRIC_2D\n"
              << "boundary type: TRANSMISSIVE WALL SYMMETRY PRESSURE PERIODIC STRUCTURE (x_max: the "
                 "structure's wet face) INCIDENT (an incident wave p(t), non-reflecting)\n"
              << "material models: stiffened_gas { gamma p_inf }, tait { gamma B A rho0 as_stiffened_gas }\n";
    return 0;
}

int run(const undex::CaseFile& c, const std::string& couple, const std::string& resume) {
    try {
        return undex::fluid::run(c, std::cout, couple, resume);
    } catch (const undex::fluid::SolverFailure& e) {
        std::cerr << "undex-fluid: error: initial data: " << e.what() << "\n";
        return undex::exit_method_failed;
    }
}

} // namespace

int main(int argc, char** argv) {
    undex::SolverCommands commands;
    commands.name = "undex-fluid";
    commands.description = "undex-fluid: the RKDG fluid solver of undex (two fluids, cavitation, coupling)";
    commands.run = run;
    commands.check = check;
    commands.options = options;
    commands.sample = [](const undex::SampleRequest& r) { return undex::fluid::sample(r); };
    commands.failures.push_back(
        undex::failure_kind<undex::coupling::CouplingError>(undex::exit_coupling_failed, "coupling: "));
    return undex::solver_main(argc, argv, commands);
}
