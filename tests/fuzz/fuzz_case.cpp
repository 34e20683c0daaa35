// Fuzz target: arbitrary bytes as a case file, through the loader and every check `undex check` has the
// solvers run (undex-fluid --check, undex-solid --check, undex-rigid --check), and the run plan. A bad case
// must end in CaseError (a message naming the field); any other exception escaping, a crash, a sanitizer
// report, a leak or an input taking over 10 s is a finding.
#include "base/case_file.hpp"
#include "base/run_plan.hpp"
#include "fluid/setup.hpp"
#include "proto/case.pb.h"
#include "solid/structure_setup.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto c = undex::CaseFile::from_text(text, "fuzz.case");
        if (undex::has_fluid(c)) undex::fluid::validate(c);
        if (undex::has_structure(c)) {
            const auto& st = c.get().structure();
            if (st.has_rigid_plate())
                undex::solid::make_rigid_plate(c);
            else if (st.has_command())
                undex::solid::check_structure(c);
            else
                undex::solid::make_structure(c);
        }
        undex::validate_plan(c);
        undex::plan(c);
        c.text();
    } catch (const undex::CaseError&) {
    }
    return 0;
}
