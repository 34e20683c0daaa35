// The fluid solver's interface. One implementation per (dimension, degree, equation of state), chosen
// once at set-up (setup.cpp); hot loops inside see concrete types only.
#pragma once
#include "base/checkpoint.hpp"
#include "fluid/mesh.hpp"

#include <array>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex::fluid {

class Ranks;

// A state the method cannot hold: NaN, ρ ≤ 0 or p + P∞ ≤ 0 in a cell average after limiting.
struct SolverFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class BoundaryType { Transmissive, Wall, Symmetry, Pressure, Periodic, Structure, Incident, Absorbing };

struct Boundary {
    BoundaryType type = BoundaryType::Transmissive;
    std::function<double(double)> pressure; // p(t) for BoundaryType::Pressure and the incident p_inc(t)
    double p_ambient = 0;                   // BoundaryType::Incident: the still water's pressure outside
    double p_I = 0, u_I = 0;                // the structure's interface pressure and normal velocity
    int layer_cells = 0;                    // BoundaryType::Absorbing: the layer's cells (part of the mesh)
    double strength = 0;                    // BoundaryType::Absorbing: σ_max · layer / a
};

// Primitive state at a point.
struct Primitive {
    double rho = 0, u = 0, v = 0, p = 0;
};

enum class Indicator { Tvb, All, None };
enum class Limiter { Weno, Minmod, None };

struct Settings {
    int degree = 2;
    double cfl = 0.2;
    Indicator indicator = Indicator::Tvb;
    double tvb_m = 10;
    Limiter limiter = Limiter::Minmod;
    double weno_neighbour_weight = 0.001;
    double weno_epsilon = 1e-6;
    bool positivity = true;
    double positivity_epsilon = 1e-10;
    // Still water (numerics.skip_rest): cells whose state and whose neighbours' states within one step's
    // reach are `rest` (to 1e-14 relative) are not updated (Scheme::wake).
    bool skip_rest = false;
    Primitive rest;
};

class FluidSolver {
  public:
    virtual ~FluidSolver() = default;
    virtual const Mesh& mesh() const = 0;
    virtual int degree() const = 0;
    virtual int variables() const = 0;       // NV = dim + 2
    virtual int basis_functions() const = 0; // NB
    virtual double time() const = 0;
    virtual long steps() const = 0;
    // Largest stable Δt_f from the current cell averages.
    virtual double stable_dt() const = 0;
    // One TVD-RK3 step. On a state the method cannot hold, throws SolverFailure naming the cell and
    // leaves the solution at the start of the step.
    virtual void step(double dt) = 0;
    // Sets the solution to the L2 projection of a pointwise conserved state q(x, y) (q: ρ, ρu, [ρv,] E),
    // then limits it as after a stage. Throws SolverFailure for inadmissible data.
    virtual void project(const std::function<void(double, double, double*)>& conserved_at) = 0;
    // Modal coefficients of the interior cells, layout [cell j·nx + i][variable][basis].
    virtual std::vector<double> coefficients() const = 0;
    virtual void set_coefficients(const std::vector<double>& c, double time) = 0;
    // Primitive state from the DG polynomial at (x, y) (y ignored in 1D).
    virtual Primitive evaluate(double x, double y) const = 0;
    // Primitive state of the cell average of interior cell (i, j).
    virtual Primitive cell_average(int i, int j) const = 0;
    // Void fraction of the cavitation model at pressure p (0 without cavitation).
    virtual double void_fraction(double p) const = 0;
    virtual bool has_cavitation() const = 0;
    // Void fraction of the cell average of interior cell (i, j) (0 in a cell of a fluid without cavitation).
    virtual double cell_void_fraction(int i, int j) const { return void_fraction(cell_average(i, j).p); }
    // ∫U dx (mass, momentum, total energy; planar measure) over each row j of [j0, j1) of the interior:
    // variables() numbers per row, row after row.
    virtual std::vector<double> row_totals(int j0, int j1) const = 0;
    // The same over the whole interior: the rows' sums added in row order (so that many ranks, each giving
    // its rows, get the same sums bit for bit; sum_rows).
    std::vector<double> totals() const { return sum_rows(row_totals(0, mesh().ny), variables()); }
    static std::vector<double> sum_rows(const std::vector<double>& rows, int nv) {
        std::vector<double> t(nv, 0.0);
        for (size_t k = 0; k < rows.size(); ++k)
            t[k % nv] += rows[k];
        return t;
    }
    // Number of cells the indicator marked in the last step (all stages).
    virtual long troubled_cells() const = 0;
    // Number of cells the Zhang–Shu positivity scaling changed in the last step (all stages).
    virtual long positivity_scaled_cells() const = 0;
    // Cell updates (cells solved × steps, summed over the fluids) since the start, and of those the ones
    // skipped as still water (Settings::skip_rest).
    virtual long cell_updates() const = 0;
    virtual long cell_updates_skipped() const = 0;
    // Primitive state and sound speed at (x, y) from the DG polynomial (the fluid side of an interface).
    virtual double sound_speed(double x, double y) const = 0;
    // The lowest pressure the fluid can hold: the cavitation pressure, or where ρ or p + P∞ reach 0.
    virtual double pressure_floor() const = 0;
    // The interface pressure and velocity of the structure on the STRUCTURE side(s), held over the next step.
    virtual void set_structure_state(double p_I, double u_I) = 0;
    // Level set φ at the interior cell centres (index j·nx + i) of a two-fluid run; empty for one fluid.
    virtual std::vector<double> level_set() const { return {}; }
    virtual void set_level_set(const std::vector<double>& /*phi*/) {}
    // Structure level set φ_s at the interior cell centres of a 2D run with a structure (index j·nx + i):
    // the signed distance to the nearest wet face, < 0 in the fluid; empty without a structure.
    virtual std::vector<double> structure_level_set() const { return {}; }
    // Writes or reads (State::loading) everything a step reads that earlier steps wrote: a solver restored
    // from a checkpoint continues bit for bit. Called on a solver made from the same case (and, in 2D with a
    // structure, attached to the same wet nodes).
    virtual void state(State& s) = 0;
    // Takes back the last step (another rank's failed).
    virtual void revert_step() {}

    // Many ranks (fluid/ranks.hpp, docs/scale_out.md): whether this solver can run on many; the division it
    // solves from now on (the state must be current in every row, as after the initial data or share());
    // the rows it reads beyond its block; the whole state current on every rank; per row of its block the
    // cells it updates (others 0).
    virtual bool divisible() const { return false; }
    virtual void divide(const Ranks* /*ranks*/) {}
    virtual int halo() const { return 1; }
    virtual void share() {}
    virtual std::vector<double> row_cost() const { return {}; }
};

// The fluid next to a wet node (physics.md §5.1): pressure, velocity along the node's normal, density and
// sound speed (Z_L = ρ a), radial (x) velocity for the geometric term.
struct WetSample {
    double p = 0, u_n = 0, rho = 0, a = 0, u_x = 0;
};

// A 2D fluid around a structure (physics.md §5.1, fluid/wet_fluid.hpp): the structure's wet faces move
// through the mesh; each face has its own fluid solution, real on its side and set in a ghost band behind
// it from the structure's interface pressure and velocity.
class WetFaces;
class WetSolver : public FluidSolver {
  public:
    // The structure's wet nodes (the Hello): face of each node, reference positions and normals. Throws
    // std::invalid_argument for faces the fluid cannot hold (a face of one node, nodes that coincide).
    virtual void attach(const std::vector<int>& face, const std::vector<double>& x,
                        const std::vector<double>& y, const std::vector<double>& normal_x,
                        const std::vector<double>& normal_y) = 0;
    // The node positions at the start of a step (the Offer): faces, structure level set, real cells and
    // ghost bands. Throws SolverFailure for a geometry the method cannot hold.
    virtual void move(const std::vector<double>& x, const std::vector<double>& y) = 0;
    virtual const WetFaces& faces() const = 0;
    // The fluid next to every wet node. Throws SolverFailure naming a node with no fluid next to it.
    virtual std::vector<WetSample> sample() const = 0;
    // The structure's interface pressure and normal velocity per node over the next step (the Answer).
    virtual void set_interface(const std::vector<double>& p_I, const std::vector<double>& u_I) = 0;
};

} // namespace undex::fluid
