// Running a fluid-only case from start to end with output, gauges and progress lines.
#pragma once
#include <iosfwd>

namespace undex {
class CaseFile;
}

namespace undex::fluid {

// Returns 0 on success, 2 when the solver met a state it cannot hold (after writing the last good state).
// Throws CaseError for a bad case (before anything is written).
int run(const CaseFile& c, std::ostream& log);

} // namespace undex::fluid
