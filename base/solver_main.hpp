// The command line shared by the solver executables (undex-fluid, undex-solid, undex-rigid):
//   NAME CASE [--set key=value]... [--couple ENDPOINT]
// SIGINT and SIGTERM end the run at the next step (install_stop_handler); errors become one line on stderr
// and the exit status: 1 bad case (or another error), 3 coupling failure, 64 usage; run returns the rest.
#pragma once
#include "base/case_file.hpp"
#include "base/signals.hpp"
#include "coupler/participant.hpp"

#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace undex {

template <class Run> int solver_main(int argc, char** argv, const char* name, Run run) {
    const std::string usage =
        std::string("usage: ") + name + " CASE [--set key=value]... [--couple ENDPOINT]\n";
    std::string path, couple;
    std::vector<std::string> overrides;
    for (int k = 1; k < argc; ++k) {
        if (std::strcmp(argv[k], "--set") == 0 && k + 1 < argc)
            overrides.push_back(argv[++k]);
        else if (std::strncmp(argv[k], "--set=", 6) == 0)
            overrides.push_back(argv[k] + 6);
        else if (std::strcmp(argv[k], "--couple") == 0 && k + 1 < argc)
            couple = argv[++k];
        else if (argv[k][0] == '-' || !path.empty()) {
            std::cerr << usage;
            return 64;
        } else
            path = argv[k];
    }
    if (path.empty()) {
        std::cerr << usage;
        return 64;
    }
    install_stop_handler();
    try {
        return run(CaseFile::load(path, overrides), couple);
    } catch (const CaseError& e) {
        std::cerr << name << ": error: " << e.what() << "\n";
        return 1;
    } catch (const coupling::CouplingError& e) {
        std::cerr << name << ": error: coupling: " << e.what() << "\n";
        return 3;
    } catch (const std::exception& e) {
        std::cerr << name << ": error: " << e.what() << "\n";
        return 1;
    }
}

} // namespace undex
