// From a case file to a ready fluid solver: the whole case is checked before anything runs.
#pragma once
#include "fluid/solver.hpp"

#include <memory>
#include <string>
#include <vector>

namespace undex {
class CaseFile;
} // namespace undex

namespace undex::fluid {

// Checks every fluid part of the case; throws CaseError naming the field and line.
void validate(const CaseFile& c);
// Builds the solver and projects the initial data. Throws CaseError or SolverFailure.
std::unique_ptr<FluidSolver> make_solver(const CaseFile& c);

// Names accepted by the indicator and limiter fields, with one line of documentation each.
struct NamedOption {
    const char* name;
    const char* doc;
};
const std::vector<NamedOption>& indicator_names();
const std::vector<NamedOption>& limiter_names();
const std::vector<NamedOption>& ghost_method_names();
const std::vector<NamedOption>& interface_riemann_names();

} // namespace undex::fluid
