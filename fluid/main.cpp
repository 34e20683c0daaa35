// undex-fluid CASE [--set key=value]... [--couple ENDPOINT]: runs the fluid solver on a case; a case with a
// structure couples to a structure solver through ENDPOINT (undex run does this).
#include "fluid/run.hpp"
#include "fluid/solver.hpp"
#include "base/solver_main.hpp"

#include <iostream>
#include <string>

int main(int argc, char** argv) {
    return undex::solver_main(argc, argv, "undex-fluid",
                              [](const undex::CaseFile& c, const std::string& couple) {
                                  try {
                                      return undex::fluid::run(c, std::cout, couple);
                                  } catch (const undex::fluid::SolverFailure& e) {
                                      std::cerr << "undex-fluid: error: initial data: " << e.what() << "\n";
                                      return 2;
                                  }
                              });
}
