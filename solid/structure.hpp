// What the run loop, the output and the coupling need of a structure model (a 1D column, a 2D plate, or any
// model added later): one step, the stable step, the energies, the wet nodes that a fluid loads, and the
// fields and gauges of the output. The run loop (solid/run_structure.cpp) holds a Structure and never asks
// which model it is. Adding a model: implement this interface in one file and build it in
// solid/structure_setup.cpp (docs/architecture.md).
#pragma once
#include "base/checkpoint.hpp"
#include "solid/interface_node.hpp"
#include "solid/material.hpp"

#include <span>
#include <string>
#include <vector>

namespace undex::solid {

// A node of a face wetted by a fluid: its current position, the unit normal from the fluid into the
// structure, its wetted area (per unit area in 1D, per unit depth in plane strain, per radian in
// axisymmetry), its velocity along the normal at the last half step, and the wet face it lies on (0, 1, ...:
// the nodes of a face consecutive and in order along it, docs/protocol.md).
struct WetNode {
    double x = 0, y = 0, normal_x = 0, normal_y = 0, area = 0, velocity = 0;
    int face = 0;
};

// A named output array: values of every node or element (rows × columns), or of the mesh.
struct Field {
    enum class Centre { Node, Element, Mesh };
    std::string name;
    Centre centre = Centre::Node;
    size_t columns = 1;
    std::vector<double> values;
    std::vector<int> integers; // instead of values for integer data (element connectivity, layer numbers)
};

// Where a gauge reads: the node nearest to its point and the element containing it.
struct GaugeSite {
    size_t node = 0, element = 0;
};

class Structure {
  public:
    virtual ~Structure() = default;
    // One line for the log, e.g. "1D column, 40 elements".
    virtual std::string description() const = 0;
    virtual int dimension() const = 0;
    virtual size_t nodes() const = 0;
    virtual size_t element_count() const = 0;
    virtual double time() const = 0;
    virtual long steps() const = 0;
    virtual const Energies& energies() const = 0;
    // Largest stable step, without safety factor.
    virtual double stable_dt() const = 0;

    // The nodes of every wet face (front first, then back; each in order along it), in a fixed order.
    virtual std::vector<WetNode> wet_nodes() const = 0;
    // One central-difference step of dt. fluid[k] is the fluid's characteristic state at wet node k (empty
    // for a dry structure); the interface pressure and velocity of each wet node are returned (physics.md
    // §5). Throws StructureFailure and then leaves the last good state in place.
    virtual std::vector<InterfaceSolution> step(double dt, std::span<const FluidCharacteristic> fluid) = 0;

    // Output: the reference mesh (written once), the fields of the current state, gauges. A 2D model's
    // fields are drawn in ParaView through solid.xmf, which reads quadrilaterals from the mesh fields
    // `quads` (elements × 4 node numbers, counter-clockwise) and `layer`, and the current node positions
    // from the state field `position` (nodes × 2); its other single-column node and element fields become
    // attributes. Another element shape needs its topology in that writer (solid/run_structure.cpp).
    virtual std::vector<Field> mesh_fields() const = 0;
    virtual std::vector<Field> state_fields() const = 0;
    // The energies of each material law's elements (each layer of a layered plate), summing to energies()
    // but for the external work, which stays with the whole; empty where a structure does not split them.
    virtual std::vector<Energies> law_energies() const { return {}; }
    virtual std::vector<std::string> gauge_columns() const = 0; // after t
    virtual GaugeSite locate(double x, double y) const = 0;     // in the reference configuration
    virtual void gauge_values(const GaugeSite& g, std::vector<double>& row) const = 0; // appended to row
    // Writes or reads (State::loading) everything a step reads that earlier steps wrote (the nodes' motion,
    // the half-step velocities, the points' stresses and internal variables, the energies, the clock): a
    // model restored from a checkpoint on one made from the same case continues bit for bit.
    virtual void state(State& s) = 0;
};

} // namespace undex::solid
