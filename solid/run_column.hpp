// Runs a structure-only case (the 1D layered column) with output: undex-solid.
#pragma once
#include <ostream>

namespace undex {
class CaseFile;
}

namespace undex::solid {

// Output <dir>/solid.h5:
//   attributes  case (text after overrides), nodes, elements, status ("running", "complete", "failed: ...")
//   x (node positions), element_x (element centres), in the reference configuration
//   /fields/NNNNNN  attributes time, step, last_good; node fields u, v, a; element fields stress_xx,
//                   strain_xx, plastic_strain_xx, peeq, peeq_rate
//   /energies       t, kinetic, elastic, plastic, external, balance_error (per unit area, every
//                   output.gauge_every steps and at every output)
//   /gauges/NAME    t, u, v, a (nearest node), stress_xx, peeq (element containing x), as often
// Returns 0 when complete, 2 when the run stopped on a state the method cannot hold (after writing the last
// good state).
int run_column(const CaseFile& c, std::ostream& log);

} // namespace undex::solid
