// Fuzz target: arbitrary bytes as a case file with --set overrides, through the loader and every check `undex
// check` has the solvers run (undex-fluid --check; undex-solid or undex-rigid --check: check_structure), and
// the run plan. A bad case must end in CaseError (a message naming the field); any other exception escaping,
// a crash, a sanitizer report, a leak or an input taking over 10 s is a finding.
#include "base/case_file.hpp"
#include "base/run_plan.hpp"
#include "fluid/setup.hpp"
#include "proto/case.pb.h"
#include "solid/structure_setup.hpp"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

// validate_plan probes whether the output directory can be written (making and removing a directory in it):
// relative output directories land in a directory of the fuzzer's own.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    char dir[] = "/tmp/undex-fuzz-case-XXXXXX";
    if (!mkdtemp(dir) || chdir(dir) != 0) std::abort();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // Leading lines "--set KEY=VALUE" are overrides; the rest is the case file.
    std::string text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> overrides;
    while (text.rfind("--set ", 0) == 0) {
        const auto end = text.find('\n');
        overrides.push_back(text.substr(6, end == std::string::npos ? std::string::npos : end - 6));
        text.erase(0, end == std::string::npos ? text.size() : end + 1);
    }
    {
        std::ofstream out("fuzz.case", std::ios::binary | std::ios::trunc);
        out << text;
    }
    try {
        const auto c = undex::CaseFile::load("fuzz.case", overrides);
        if (undex::has_fluid(c)) undex::fluid::validate(c);
        if (undex::has_structure(c)) undex::solid::check_structure(c);
        undex::validate_plan(c);
        undex::plan(c);
        c.text();
    } catch (const undex::CaseError&) {
    }
    return 0;
}
