// undex-rigid: a rigid plate per unit area (structure.rigid_plate) driven by the fluid through the coupling
// protocol, the alternative structure solver of the simplest kind (rigid.cpp has the equations and the
// output layout).
#pragma once
#include <string>

namespace undex {
class CaseFile;
}

namespace undex::solid {

// Runs the rigid plate of a case coupled to the fluid bound at couple; returns an exit status of
// base/exit_status.hpp (after a failure, with the history so far written).
// A rigid plate keeps no checkpoints: resume must be empty.
int run_rigid(const CaseFile& c, const std::string& couple, const std::string& resume);

} // namespace undex::solid
