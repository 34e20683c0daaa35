// From a case file to a structure model: the whole structure part of the case is checked first.
#pragma once
#include "solid/structure.hpp"

#include <memory>
#include <utility>
#include <vector>

namespace undex {
class CaseFile;
}

namespace undex::solid {

// The structure of a case: a 1D column (PLANAR_1D) or a 2D layered plate (PLANAR_2D, AXISYMMETRIC_2D).
struct StructureModel {
    std::unique_ptr<Structure> structure; // null when a check left a large structure unbuilt (Build::IfSmall)
    double elements = 0;                  // the element count (of the case, built or not)
    std::vector<std::string> layers;      // material name of each layer
    double dt = 0;                        // the time step: the forced one, or safety × the stable one
    int threads = 0;                      // structure.threads
    bool wet = false;                     // a face is coupled to a fluid
};

// A rigid plate per unit area (undex-rigid): m du/dt = p_I − back_pressure − k u − c du/dt. In 1D one wet
// node of area 1; in 2D the nodes of its front face (x along the span, y = y_front, normal +y), the whole
// face moving as one body.
struct RigidPlateModel {
    double mass_per_area = 0, stiffness = 0, damping = 0, back_pressure = 0;
    double dt = 0;         // the step it offers
    int dimension = 1;     // 1 or 2
    int alpha = 0;         // 0 planar (per unit depth in 2D), 1 axisymmetric (x = r, per radian)
    std::vector<double> x; // 2D: the front face's nodes, increasing
    double y_front = 0;    // 2D: the front face's y in the fluid's frame
};
RigidPlateModel make_rigid_plate(const CaseFile& c);

// Checks the structure part of a case, whichever solver it is for (undex-solid, undex-rigid or a command),
// as `--check` does (make_structure with Build::IfSmall).
void check_structure(const CaseFile& c);

// Whether make_structure builds the structure: always (a run), or for a check only when it takes at most
// check_build_bytes (a check stays small and quick on any input; a larger structure is built, and its forced
// time step checked against the stable one, when it runs).
enum class Build { Always, IfSmall };
constexpr double check_build_bytes = 256.0 * (1 << 20);

// Checks every structure part of the case and builds the column or plate; throws CaseError naming the field
// and line (a material without a required constant, an element of zero or negative size, a layer thinner than
// one element, a forced time step above the stable one, more elements than memory holds, ...). Every number
// was checked against its range in proto/case.proto first (validate_plan).
StructureModel make_structure(const CaseFile& c, Build build = Build::Always);

// Names accepted by structure.kinematics.
const std::vector<std::pair<const char*, const char*>>& kinematics_names();

} // namespace undex::solid
