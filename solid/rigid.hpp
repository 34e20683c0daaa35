// undex-rigid: a rigid plate per unit area
// (structure.rigid_plate) driven by the fluid through the coupling protocol: the alternative structure solver
// of the simplest kind.
//     m du/dt = p_I − p_back − k x − c du/dt,   x the displacement along the normal into the plate,
// central differences with the interface condition of physics.md §5 solved together with the plate's
// equation of motion (interface_node.hpp); the dashpot uses the velocity of the last half step.
// Output <dir>/solid.h5: attributes case, status; /gauges/plate with t, u, v, p_I (columns attribute of
// /gauges), so `undex gauges DIR/solid.h5` prints it; /coupling with t, dt, p_I, u_I of every step.
#pragma once
#include <string>

namespace undex {
class CaseFile;
}

namespace undex::solid {

// Runs the rigid plate of a case coupled to the fluid bound at couple; returns 0 when complete, 3 when the
// coupling failed, 4 when stopped by a signal (after writing the history so far).
int run_rigid(const CaseFile& c, const std::string& couple);

} // namespace undex::solid
