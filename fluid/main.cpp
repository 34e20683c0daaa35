// undex-fluid CASE [--set key=value]... [--couple ENDPOINT]: runs the fluid solver on a case; a case with a
// structure couples to a structure solver through ENDPOINT (undex run does this).
#include "case_file.hpp"
#include "participant.hpp"
#include "run.hpp"
#include "solver.hpp"

#include <cstring>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    const char* usage = "usage: undex-fluid CASE [--set key=value]... [--couple ENDPOINT]\n";
    std::string path, couple;
    std::vector<std::string> overrides;
    for (int k = 1; k < argc; ++k) {
        if (std::strcmp(argv[k], "--set") == 0 && k + 1 < argc)
            overrides.push_back(argv[++k]);
        else if (std::strncmp(argv[k], "--set=", 6) == 0)
            overrides.push_back(argv[k] + 6);
        else if (std::strcmp(argv[k], "--couple") == 0 && k + 1 < argc)
            couple = argv[++k];
        else if (argv[k][0] == '-') {
            std::cerr << usage;
            return 64;
        } else
            path = argv[k];
    }
    if (path.empty()) {
        std::cerr << usage;
        return 64;
    }
    undex::install_stop_handler();
    try {
        const auto c = undex::CaseFile::load(path, overrides);
        return undex::fluid::run(c, std::cout, couple);
    } catch (const undex::CaseError& e) {
        std::cerr << "undex-fluid: error: " << e.what() << "\n";
        return 1;
    } catch (const undex::fluid::SolverFailure& e) {
        std::cerr << "undex-fluid: error: initial data: " << e.what() << "\n";
        return 2;
    } catch (const undex::coupling::CouplingError& e) {
        std::cerr << "undex-fluid: error: coupling: " << e.what() << "\n";
        return 3;
    } catch (const std::exception& e) {
        std::cerr << "undex-fluid: error: " << e.what() << "\n";
        return 1;
    }
}
