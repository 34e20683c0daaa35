// Running a case's fluid from start to end with output, gauges and progress lines, alone or coupled to a
// structure solver.
#pragma once
#include <iosfwd>
#include <string>

namespace undex {
class CaseFile;
}

namespace undex::fluid {

// Returns an exit status of base/exit_status.hpp: 0 on success, 2 when the solver met a state it cannot hold
// or reached numerics.max_steps, 3 when the coupling failed, 4 when stopped by a signal (all after writing
// the last good state). Throws CaseError for a bad case (before anything is written). A case with a
// structure couples through the endpoint couple (the fluid binds it; docs/protocol.md).
// resume: a checkpoint of this case to continue from (base/checkpoint.hpp), "" for a new run.
int run(const CaseFile& c, std::ostream& log, const std::string& couple = "", const std::string& resume = "");

} // namespace undex::fluid
