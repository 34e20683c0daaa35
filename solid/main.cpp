// undex-solid CASE [--set key=value]... [--couple ENDPOINT]: runs the structure solver on a case; a structure
// wetted by the case's fluid couples to the fluid solver bound at ENDPOINT (undex run does this).
#include "solid/run_structure.hpp"
#include "base/solver_main.hpp"

#include <iostream>
#include <string>

int main(int argc, char** argv) {
    return undex::solver_main(argc, argv, "undex-solid",
                              [](const undex::CaseFile& c, const std::string& couple) {
                                  return undex::solid::run_structure(c, std::cout, couple);
                              });
}
