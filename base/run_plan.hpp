// What every solver executable needs of a case besides its own physics: which parts the case holds, the run
// plan (end time, output times, directory, gauges), the coupling timeouts, prescribed pressure histories.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace undex {
class CaseFile;
namespace config {
class PressureHistory;
}

struct GaugePoint {
    std::string name;
    double x = 0, y = 0;
};

struct RunPlan {
    double end_time = 0;
    std::vector<double> output_times; // sorted, ending with end_time
    std::string directory;
    double progress_seconds = 2;
    double checkpoint_seconds = 600; // wall seconds between checkpoints, 0: none (base/checkpoint.hpp)
    int gauge_every = 1;
    int threads = 0;
    long max_steps = 0;
    std::vector<GaugePoint> gauges;
    int coupling_timeout_ms = 0;  // coupling.timeout: the longest wait for the partner during the run
    int handshake_timeout_ms = 0; // coupling.handshake_timeout
};

// Whether the case holds a fluid (regions, domain, boundaries or fluid materials) and whether it holds a
// structure.
bool has_fluid(const CaseFile& c);
bool has_structure(const CaseFile& c);
// The run plan (output times, directory, gauges) of a validated case.
RunPlan plan(const CaseFile& c);
// Whether an output directory can be created or written (tested for real, leaving nothing behind).
bool writable_directory(const std::string& directory);
// The most output times a case may ask for (output.times, every output.interval, end_time): each is a
// snapshot of the whole state, so a million is beyond any use, and the list stays small (8 MB) and quick to
// make in `check`.
constexpr double max_output_times = 1e6;
// Checks what every solver's run reads of the case (throws CaseError naming the field): first every number
// against its range (CaseFile::check_ranges), then output times within end_time and at most
// max_output_times of them (counted before any list is made), the output directory (not empty, writable).
void validate_plan(const CaseFile& c);
// The memory a run may take: the machine's physical memory (sysconf), or the address-space limit when it is
// lower (ulimit -v); what says which.
struct MemoryLimit {
    double bytes;
    std::string what;
};
MemoryLimit memory_limit();
// Refuses (CaseError at field) count items of bytes_each bytes that would not fit in memory_limit(): called
// with sizes computed in double, before anything of that size is made; the message says both numbers.
void check_memory(const CaseFile& c, const std::string& field, const std::string& what, double count,
                  double bytes_each);
// A prescribed pressure history p(t) (exponential or table) of a case, checked and as a function; shared by
// fluid boundaries and structure faces.
void validate_pressure_history(const CaseFile& c, const config::PressureHistory& h, const std::string& path);
std::function<double(double)> pressure_history(const config::PressureHistory& h);

} // namespace undex
