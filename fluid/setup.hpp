// From a case file to a ready fluid solver: the whole case is checked before anything runs.
#pragma once
#include "solver.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace undex {
class CaseFile;
namespace config {
class PressureHistory;
}
} // namespace undex

namespace undex::fluid {

struct GaugePoint {
    std::string name;
    double x = 0, y = 0;
};

struct RunPlan {
    double end_time = 0;
    std::vector<double> output_times; // sorted, ending with end_time
    std::string directory;
    double progress_seconds = 2;
    int gauge_every = 1;
    int threads = 0;
    long max_steps = 0;
    std::vector<GaugePoint> gauges;
};

// Checks every fluid part of the case; throws CaseError naming the field and line.
void validate(const CaseFile& c);
// Checks the case's coupling timeouts (used by both solvers).
void validate_coupling(const CaseFile& c);
// A prescribed pressure history p(t) (exponential or table) of a case, checked and as a function; shared by
// fluid boundaries and structure faces.
void validate_pressure_history(const CaseFile& c, const config::PressureHistory& h, const std::string& path);
std::function<double(double)> pressure_history(const config::PressureHistory& h);
// Whether an output directory can be created or written (tested for real, leaving nothing behind).
bool writable_directory(const std::string& directory);
// The run plan (output times, directory, gauges) of a validated case.
RunPlan plan(const CaseFile& c);
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
