// undex-fluid --sample: fields of a fluid output evaluated from its DG polynomials along a line, as CSV.
#pragma once
#include "base/solver_cli.hpp"

#include <cstdio>

namespace undex::fluid {

// Prints "# time = T s", the header "x,y,FIELDS" and one row per point to out. Throws UsageError for a bad
// request, std::runtime_error for output that cannot be sampled (a structure's, an empty one).
int sample(const SampleRequest& r, std::FILE* out = stdout);

} // namespace undex::fluid
