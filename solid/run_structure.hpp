// Runs a structure-only case (a 1D layered column or a 2D layered plate) with output: undex-solid.
#pragma once
#include <ostream>
#include <string>

namespace undex {
class CaseFile;
}

namespace undex::solid {

// Output <dir>/solid.h5 (and, for plates, <dir>/solid.xmf for ParaView):
//   datasets    case (text after overrides), status ("running", "complete", "failed: ..."): scalar
//               fixed-length strings, null-padded (base/h5.hpp)
//   attributes  dimension (1 or 2), nodes, elements, layers (material names, comma-separated)
//   1D: x (node positions), element_x (element centres), in the reference configuration
//       /fields/NNNNNN  attributes time, step, last_good; node fields u, v, a; element fields stress_xx,
//                       strain_xx, plastic_strain_xx, peeq, peeq_rate
//   2D: nodes (n × 2 reference x, y), quads (elements × 4 node numbers, counter-clockwise), layer (per
//       element)
//       /fields/NNNNNN  attributes time, step, last_good; node fields position (n × 2, current), u_x, u_y,
//                       v_x, v_y, a_x, a_y, displacement and velocity (n × 3: x, y and 0, vectors in
//                       solid.xmf for ParaView's Warp By Vector); element fields stress_xx, stress_yy, stress_zz (hoop in
//                       axisymmetry), stress_xy, von_mises, peeq, peeq_rate, hourglass_energy
//   /energies       t, kinetic, elastic, plastic, viscous (the bulk viscosity's work), hourglass,
//                   external, coupling (the part of the fluid's
//                   work the integrator does not deliver, solid/material.hpp), balance_error (per unit area in 1D,
//                   per unit depth in plane strain, per radian in axisymmetry; every output.gauge_every
//                   steps and at every output)
//   /energies_by_layer  2D: t, then kinetic_L, elastic_L, plastic_L, viscous_L, hourglass_L of each layer L = 0, 1, …
//                   (the elements of each material law, in the order of `layers`), summing to /energies
//   /gauges/NAME    1D: t, u, v, a (nearest node), stress_xx, peeq (element containing the point);
//                   2D: t, u_x, u_y, v_x, v_y, a_x, a_y, stress_xx, stress_yy, stress_zz, stress_xy, peeq;
//                   the attribute columns of /gauges lists them
//   /coupling       t, dt, p_I, u_I, dt_s (the step offered) of every step and wet node of a run coupled to a
//                   fluid (a FLUID face) through the endpoint couple (the fluid binds it; docs/protocol.md)
// Returns an exit status of base/exit_status.hpp (after a failure, with the last good state written).
// resume: a checkpoint of this case to continue from (base/checkpoint.hpp), "" for a new run.
int run_structure(const CaseFile& c, std::ostream& log, const std::string& couple = "",
                  const std::string& resume = "");

} // namespace undex::solid
