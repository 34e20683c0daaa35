// undex gauges DIR [--name NAME]: the gauge time series of a fluid or structure output as CSV, time first.
#pragma once
#include <string>

namespace undex::launcher {

// dir: an output directory (its fluid.h5, or solid.h5 of a structure run alone) or an .h5 file; name: one
// gauge ("": all). Throws std::runtime_error for an unknown gauge or an output without gauges.
int gauges(const std::string& dir, const std::string& name);

} // namespace undex::launcher
