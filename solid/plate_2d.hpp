// Explicit 2D finite elements (physics.md §6): four-node quadrilaterals in plane strain (per unit depth) or
// axisymmetry (x = r, y = z, per radian), one-point integration with hourglass stiffness, lumped mass,
// central differences. Each element carries its own material law; layers are perfectly bonded because they
// share nodes.
//
// Element kinematics (updated Lagrangian, small strain increments): the uniform-gradient matrix b of
// Flanagan and Belytschko (1981) at the mid-step configuration gives the strain increment and the spin;
// the stress is rotated by the spin (a 2D Hughes–Winget update) before the law sees the increment. In
// axisymmetry the hoop increment is the centroid's Δu_r / r.
//
// Hourglass control (stiffness form, total displacement, reference geometry): the modes q = γ · u with
// γ_I = ¼ (h_I − (h·X) b_xI − (h·Y) b_yI), h = (1, −1, 1, −1), are orthogonal to every linear field, so the
// patch test is untouched. Their stiffness reproduces pure bending of a rectangle exactly
// (Belytschko & Bindeman 1993): for a rectangle 2a × 2b, K_x = (4/3) E' b / a and K_y = (4/3) E' a / b with
// the bending modulus E' = E / (1 − ν²) of the elastic constants, times r_c in axisymmetry, times a
// user factor (1 by default). The hourglass energy is ½ K q², part of the energy balance.
//
// Bulk viscosity (optional; BulkViscosity): in compression (ε̇_v < 0) each element's pressure gains
// q = ρ L (C_q² L ε̇_v² − C_l c ε̇_v), ρ the element's current density, L = √(area) of the mid-step
// configuration, c the law's elastic wave speed; q of a step acts on the forces of the next, its work
// ½ (q_old + q_new) (−Δε_v) V is the dissipated energy `viscous`. The stable step then uses the wave speed
// Q + √(Q² + c²) with Q = C_l c − C_q² L ε̇_v of the element's last step where it was compressed (as explicit
// codes do), c elsewhere.
#pragma once
#include "solid/material.hpp"
#include "solid/structure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <sstream>
#include <vector>

namespace undex::solid {

enum class Plane { Strain, Axisymmetric };

struct QuadMesh {
    std::vector<double> x, y;              // reference node coordinates (x = r in axisymmetry)
    std::vector<std::array<int, 4>> quads; // node numbers, counter-clockwise
    std::vector<int> law;                  // per element: index into the laws
    // A structured grid of grid_nx × grid_ny elements: node (i, j) is j (grid_nx + 1) + i, element (i, j) is
    // j grid_nx + i (0 for other meshes).
    int grid_nx = 0, grid_ny = 0;
};

// A layered plate on a structured mesh: x from x0 over the span (nx elements), y through the thickness from
// the front face y = y0, each layer with its own element count. Node (i, j) is j * (nx + 1) + i.
struct LayeredPlate {
    QuadMesh mesh;
    int nx = 0, ny = 0;
    std::vector<int> layer_of_row; // per element row j: its layer
    int node(int i, int j) const { return j * (nx + 1) + i; }
    int element(int i, int j) const { return j * nx + i; }
};

inline LayeredPlate layered_plate(double x0, double span, int nx, const std::vector<double>& thickness,
                                  const std::vector<int>& rows, double y0 = 0) {
    LayeredPlate p;
    p.nx = nx;
    std::vector<double> y = {0.0};
    double top = 0;
    for (size_t l = 0; l < thickness.size(); ++l) {
        const double bottom = top;
        top += thickness[l];
        for (int k = 1; k <= rows[l]; ++k) {
            y.push_back(k == rows[l] ? top : bottom + thickness[l] * k / rows[l]);
            p.layer_of_row.push_back(static_cast<int>(l));
        }
    }
    p.ny = static_cast<int>(y.size()) - 1;
    for (int j = 0; j <= p.ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            p.mesh.x.push_back(i == nx ? x0 + span : x0 + span * i / nx);
            p.mesh.y.push_back(y0 + y[j]);
        }
    for (int j = 0; j < p.ny; ++j)
        for (int i = 0; i < nx; ++i) {
            p.mesh.quads.push_back({p.node(i, j), p.node(i + 1, j), p.node(i + 1, j + 1), p.node(i, j + 1)});
            p.mesh.law.push_back(p.layer_of_row[j]);
        }
    p.mesh.grid_nx = p.nx, p.mesh.grid_ny = p.ny;
    return p;
}

// Coefficients of the bulk viscosity (quadratic C_q, linear C_l); 0 and 0: none.
struct BulkViscosity {
    double quadratic = 0, linear = 0;
    bool on() const { return quadratic > 0 || linear > 0; }
};

class Plate2D : public Structure {
  public:
    Plate2D(QuadMesh mesh, std::vector<std::shared_ptr<const MaterialLaw>> laws, Plane plane,
            double hourglass = 1.0, BulkViscosity bulk = {})
        : plane_(plane), bulk_(bulk), laws_(std::move(laws)), X_(std::move(mesh.x)), Y_(std::move(mesh.y)),
          quads_(std::move(mesh.quads)), law_of_(std::move(mesh.law)), grid_nx_(mesh.grid_nx),
          grid_ny_(mesh.grid_ny) {
        const size_t n = X_.size(), ne = quads_.size();
        parallel_ = ne >= 2048;
        require(Y_.size() == n && law_of_.size() == ne && ne > 0, "a 2D mesh needs nodes and elements");
        require(hourglass >= 0, "the hourglass factor must be >= 0");
        require(bulk.quadratic >= 0 && bulk.linear >= 0, "the bulk viscosity coefficients must be >= 0");
        for (auto* v : {&ux_, &uy_, &vx_, &vy_, &ax_, &ay_, &mass_, &wx_, &wy_, &dux_, &duy_})
            v->assign(n, 0.0);
        cx_.assign(n, 0);
        cy_.assign(n, 0);
        points_.assign(ne, PointState{});
        gamma_.resize(ne);
        kx_.resize(ne);
        ky_.resize(ne);
        efx_.assign(4 * ne, 0.0);
        efy_.assign(4 * ne, 0.0);
        ehg_.assign(ne, 0.0);
        e_internal_.assign(ne, 0.0);
        e_plastic_.assign(ne, 0.0);
        e_viscous_.assign(ne, 0.0);
        q_.assign(ne, 0.0);
        rate_v_.assign(ne, 0.0);
        mshare_.assign(ne, 0.0);
        std::vector<int> count(n + 1, 0);
        for (size_t e = 0; e < ne; ++e) {
            const auto& q = quads_[e];
            require(law_of_[e] >= 0 && law_of_[e] < static_cast<int>(laws_.size()),
                    "element " + std::to_string(e) + " has no material law");
            const MaterialLaw& law = *laws_[law_of_[e]];
            require(law.shear_modulus() > 0,
                    "material law '" + law.name() + "' is uniaxial and cannot be used in 2D elements");
            Geometry g = geometry(e, X_.data(), Y_.data(), nullptr, nullptr);
            if (!(g.area > 0) || !corners_positive(e, X_.data(), Y_.data(), nullptr, nullptr, 0))
                throw MaterialError("element " + std::to_string(e) +
                                    " has zero or negative area, or its nodes are not counter-clockwise");
            if (plane_ == Plane::Axisymmetric)
                for (int k = 0; k < 4; ++k)
                    require(X_[q[k]] >= 0, "axisymmetric nodes need r >= 0");
            const double r = plane_ == Plane::Axisymmetric ? g.rc : 1.0;
            const double m = law.density() * g.area * r / 4;
            mshare_[e] = m;
            // Hourglass vectors and stiffnesses from the reference geometry.
            const double hx = X_[q[0]] - X_[q[1]] + X_[q[2]] - X_[q[3]];
            const double hy = Y_[q[0]] - Y_[q[1]] + Y_[q[2]] - Y_[q[3]];
            static constexpr double h[4] = {1, -1, 1, -1};
            for (int k = 0; k < 4; ++k) {
                gamma_[e][k] = 0.25 * (h[k] - hx * g.bx[k] - hy * g.by[k]);
                mass_[q[k]] += m;
                ++count[q[k] + 1];
            }
            const double a = 0.25 * std::hypot(-X_[q[0]] + X_[q[1]] + X_[q[2]] - X_[q[3]],
                                               -Y_[q[0]] + Y_[q[1]] + Y_[q[2]] - Y_[q[3]]);
            const double b = 0.25 * std::hypot(-X_[q[0]] - X_[q[1]] + X_[q[2]] + X_[q[3]],
                                               -Y_[q[0]] - Y_[q[1]] + Y_[q[2]] + Y_[q[3]]);
            const double G = law.shear_modulus(), lambda = law.wave_modulus() - 2 * G;
            const double Eb = 4 * G * (lambda + G) / (lambda + 2 * G); // E / (1 − ν²)
            kx_[e] = hourglass * (4.0 / 3.0) * Eb * b / a * r;
            ky_[e] = hourglass * (4.0 / 3.0) * Eb * a / b * r;
        }
        // Node → (element, corner) incidence for the gather of element forces.
        for (size_t i = 0; i < n; ++i)
            count[i + 1] += count[i];
        incidence_start_ = count;
        incidence_.assign(4 * ne, 0);
        for (size_t e = 0; e < ne; ++e)
            for (int k = 0; k < 4; ++k)
                incidence_[count[quads_[e][k]]++] = static_cast<int>(4 * e + k);
        for (size_t i = 0; i < n; ++i)
            if (!(mass_[i] > 0)) throw MaterialError("node " + std::to_string(i) + " belongs to no element");
    }

    Plane plane() const { return plane_; }
    size_t nodes() const override { return X_.size(); }
    size_t element_count() const override { return quads_.size(); }
    double node_x(size_t i) const { return X_[i]; } // reference coordinates
    double node_y(size_t i) const { return Y_[i]; }
    const std::array<int, 4>& quad(size_t e) const { return quads_[e]; }
    int law_of(size_t e) const { return law_of_[e]; }
    double element_x(size_t e) const { return 0.25 * sum(e, X_.data()); }
    double element_y(size_t e) const { return 0.25 * sum(e, Y_.data()); }
    double ux(size_t i) const { return ux_[i]; }
    double uy(size_t i) const { return uy_[i]; }
    double vx(size_t i) const { return vx_[i]; } // at the last half step
    double vy(size_t i) const { return vy_[i]; }
    double ax(size_t i) const { return ax_[i]; }
    double ay(size_t i) const { return ay_[i]; }
    double mass(size_t i) const { return mass_[i]; }
    const PointState& point(size_t e) const { return points_[e]; }
    double hourglass_energy(size_t e) const { return ehg_[e]; }
    double time() const override { return time_; }
    long steps() const override { return steps_; }
    const Energies& energies() const override { return en_; }
    // Per law: internal and plastic energy and hourglass energy of its elements, kinetic energy of the mass
    // each element lumps to its nodes (at the velocities of kinetic()).
    std::vector<Energies> law_energies() const override {
        std::vector<Energies> out(laws_.size());
        for (size_t e = 0; e < quads_.size(); ++e) {
            Energies& l = out[law_of_[e]];
            l.internal += e_internal_[e];
            l.plastic += e_plastic_[e];
            l.viscous += e_viscous_[e];
            l.hourglass += ehg_[e];
            for (int k : quads_[e]) {
                const double vx = vx_[k] + 0.5 * last_dt_ * ax_[k], vy = vy_[k] + 0.5 * last_dt_ * ay_[k];
                l.kinetic += 0.5 * mshare_[e] * (vx * vx + vy * vy);
            }
        }
        return out;
    }
    void state(State& s) override {
        s.io("ux", ux_), s.io("uy", uy_), s.io("vx", vx_), s.io("vy", vy_), s.io("ax", ax_), s.io("ay", ay_);
        s.io("wx", wx_), s.io("wy", wy_), s.io("dux", dux_), s.io("duy", duy_), s.io("points", points_);
        s.io("efx", efx_), s.io("efy", efy_), s.io("ehg", ehg_);
        s.io("wet_fx", wet_fx_), s.io("wet_fy", wet_fy_);
        s.io("other_fx", other_fx_), s.io("other_fy", other_fy_);
        s.io("energies", en_), s.io("time", time_), s.io("last_dt", last_dt_), s.io("steps", steps_);
        s.io("e_internal", e_internal_), s.io("e_plastic", e_plastic_), s.io("e_viscous", e_viscous_);
        s.io("q", q_), s.io("rate_v", rate_v_);
    }
    std::string description() const override {
        std::string d = plane_ == Plane::Axisymmetric ? "axisymmetric plate, " : "plane-strain plate, ";
        if (grid_nx_ > 0)
            return d + std::to_string(grid_nx_) + " x " + std::to_string(grid_ny_) + " elements";
        return d + std::to_string(quads_.size()) + " elements";
    }
    int dimension() const override { return 2; }

    // Constrains the x and/or y velocity of a node to its present value (zero unless set_velocity changed
    // it): fixed nodes, symmetry planes and axes, clamped edges, and prescribed motion in tests.
    void constrain(size_t i, bool x, bool y) {
        cx_[i] |= x;
        cy_[i] |= y;
    }
    void set_velocity(size_t i, double vx, double vy) {
        vx_[i] = vx, vy_[i] = vy;
        en_.kinetic = kinetic(0);
    }
    // Pressure p(t) on boundary edges, each given as (node, next node) in its element's counter-clockwise
    // order, so that (Δy, −Δx) points out of the body; a positive p pushes into the body.
    void add_pressure(std::vector<std::array<int, 2>> edges, std::function<double(double)> p) {
        loads_.push_back({std::move(edges), std::move(p)});
    }
    // A face wetted by a fluid (docs/protocol.md): its nodes in order along it, with the structure on the
    // left of that direction (structure_left) or on its right. Faces are numbered 0, 1, ... in the order they
    // are added; the wet nodes are those of face 0 in order, then those of face 1, ...
    void add_wet_face(const std::vector<int>& nodes, bool structure_left) {
        require(nodes.size() >= 2, "a wet face needs at least two nodes");
        wet_index_.resize(X_.size(), -1);
        for (int i : nodes) {
            require(i >= 0 && static_cast<size_t>(i) < X_.size(),
                    "a wet face names a node that does not exist");
            require(wet_index_[i] < 0, "node " + std::to_string(i) + " lies on two wet faces");
            wet_index_[i] = static_cast<int>(wet_.size());
            wet_.push_back(i);
            wet_face_.push_back(static_cast<int>(face_left_.size()));
        }
        face_left_.push_back(structure_left);
        wet_fx_.assign(wet_.size(), 0.0), wet_fy_.assign(wet_.size(), 0.0);
        other_fx_.assign(wet_.size(), 0.0), other_fy_.assign(wet_.size(), 0.0);
    }
    size_t wet_count() const { return wet_.size(); }
    int wet_node(size_t k) const { return wet_[k]; } // the node number of wet node k

    // Wet nodes on the current configuration (docs/protocol.md): the area vector of node k is
    // a_k = Σ n_s ∫_s N_k r ds over the segments s of its face that touch it, n_s the segment's unit normal
    // into the structure, r = x in axisymmetry (per radian) and 1 in plane strain; for a segment a → b of
    // length L that is n_s L / 2 to each end in plane strain and n_s L (2 r_a + r_b) / 6, n_s L (r_a + 2 r_b)
    // / 6 in axisymmetry. The area is |a_k|, the normal a_k / |a_k|.
    std::vector<WetNode> wet_nodes() const override {
        std::vector<WetNode> w(wet_.size());
        const bool axi = plane_ == Plane::Axisymmetric;
        for (size_t k = 0; k + 1 < wet_.size(); ++k) {
            if (wet_face_[k] != wet_face_[k + 1]) continue; // the last node of a face
            const int a = wet_[k], b = wet_[k + 1];
            const double xa = X_[a] + ux_[a], xb = X_[b] + ux_[b];
            const double dx = xb - xa, dy = Y_[b] + uy_[b] - Y_[a] - uy_[a];
            // (−Δy, Δx) is the normal times L, on the left of a → b.
            const double s = face_left_[wet_face_[k]] ? 1.0 : -1.0;
            const double sa = axi ? (2 * xa + xb) / 6 : 0.5, sb = axi ? (xa + 2 * xb) / 6 : 0.5;
            w[k].normal_x += -s * dy * sa, w[k].normal_y += s * dx * sa;
            w[k + 1].normal_x += -s * dy * sb, w[k + 1].normal_y += s * dx * sb;
        }
        for (size_t k = 0; k < wet_.size(); ++k) {
            WetNode& n = w[k];
            const size_t i = wet_[k];
            n.area = std::hypot(n.normal_x, n.normal_y);
            if (!(n.area > 0)) // e.g. a face folded back onto itself
                throw StructureFailure("wet node " + std::to_string(i) + " (x = " + std::to_string(X_[i]) +
                                       ", y = " + std::to_string(Y_[i]) +
                                       " m) has no wetted area: its wet segments cancel");
            n.normal_x /= n.area, n.normal_y /= n.area;
            n.x = X_[i] + ux_[i], n.y = Y_[i] + uy_[i];
            n.velocity = vx_[i] * n.normal_x + vy_[i] * n.normal_y;
            n.face = wet_face_[k];
        }
        return w;
    }
    // A step with the fluid's characteristic state at every wet node (none: a dry step).
    std::vector<InterfaceSolution> step(double dt, std::span<const FluidCharacteristic> fluid) override {
        if (!fluid.empty() && fluid.size() != wet_.size())
            throw std::invalid_argument("Plate2D::step: " + std::to_string(fluid.size()) +
                                        " fluid states for " + std::to_string(wet_.size()) + " wet nodes");
        return advance(dt, fluid.empty() ? nullptr : fluid.data());
    }

    // Largest stable step, without safety factor: min over elements of L_e / c_e with L_e the area over the
    // longest diagonal, which bounds the one-point quadrilateral's dilatational mode for any Poisson ratio.
    double stable_dt() const override {
        double dt = 1e300;
        for (size_t e = 0; e < quads_.size(); ++e) {
            const auto& q = quads_[e];
            const MaterialLaw& law = *laws_[law_of_[e]];
            const Geometry g = geometry(e, X_.data(), Y_.data(), ux_.data(), uy_.data());
            auto d = [&](int i, int j) {
                return std::hypot(X_[q[i]] + ux_[q[i]] - X_[q[j]] - ux_[q[j]],
                                  Y_[q[i]] + uy_[q[i]] - Y_[q[j]] - uy_[q[j]]);
            };
            const double L = g.area / std::max(d(0, 2), d(1, 3));
            const double c = std::sqrt(law.wave_modulus() / law.density());
            double speed = c;
            if (bulk_.on() && rate_v_[e] < 0) {
                const double Q = bulk_.linear * c + bulk_.quadratic * bulk_.quadratic * L * -rate_v_[e];
                speed = Q + std::sqrt(Q * Q + c * c);
            }
            dt = std::min(dt, L / speed);
        }
        return dt;
    }

    // One central-difference step, as in the 1D column. The state changes only after every increment is
    // finite and every element keeps positive corner areas; otherwise StructureFailure leaves it as it was.
    void step(double dt) { advance(dt, nullptr); }

  private:
    // The step; with a fluid (fluid[k] at wet node k) each wet node is solved with the interface condition
    // along its normal n_k of the start of the step (physics.md §5, solid/interface_node.hpp), its load
    // A_k p_I n_k, and the interface pressures and velocities are returned.
    std::vector<InterfaceSolution> advance(double dt, const FluidCharacteristic* fluid) {
        const long n = static_cast<long>(X_.size()), ne = static_cast<long>(quads_.size());
        if (steps_ == 0) forces(time_);
        const double h = steps_ == 0 ? 0.5 * dt : 0.5 * (dt + last_dt_);
#pragma omp parallel for schedule(static) if (parallel_)
        for (long i = 0; i < n; ++i) {
            dux_[i] = dt * (cx_[i] ? vx_[i] : vx_[i] + h * ax_[i]);
            duy_[i] = dt * (cy_[i] ? vy_[i] : vy_[i] + h * ay_[i]);
        }
        std::vector<InterfaceSolution> out;
        std::vector<double> load_x, load_y; // A_k p_I n_k, kept once the step is good
        double fluid_work = 0, delivered = 0; // the load's work after the fluid and after the update
        if (fluid) {
            const auto w = wet_nodes(); // areas and normals of the start of the step
            out.resize(wet_.size());
            load_x.resize(wet_.size()), load_y.resize(wet_.size());
            for (size_t k = 0; k < wet_.size(); ++k) {
                const int i = wet_[k];
                const double nx = w[k].normal_x, ny = w[k].normal_y, A = w[k].area;
                const WetMotion m = solve_wet_node(k, nx, ny, A, h, fluid[k]);
                dux_[i] = dt * m.vx, duy_[i] = dt * m.vy;
                out[k] = m.s;
                out[k].u_I = nx * m.vx + ny * m.vy;
                load_x[k] = A * m.s.p_I * nx, load_y[k] = A * m.s.p_I * ny;
                fluid_work += load_x[k] * dux_[i] + load_y[k] * duy_[i];
                delivered += 0.5 * h * (load_x[k] * (vx_[i] + m.vx) + load_y[k] * (vy_[i] + m.vy));
            }
        }
        long nonfinite = -1;
#pragma omp parallel for schedule(static) reduction(max : nonfinite) if (parallel_)
        for (long i = 0; i < n; ++i)
            if (!std::isfinite(dux_[i]) || !std::isfinite(duy_[i])) nonfinite = std::max(nonfinite, i);
        if (nonfinite >= 0) {
            const long i = nonfinite;
            std::ostringstream s;
            s << "node " << i << " (x = " << X_[i] << ", y = " << Y_[i]
              << " m) has a non-finite velocity at t = " << time_ + dt << " s in step " << steps_ + 1;
            throw StructureFailure(s.str());
        }
        long bad = -1;
#pragma omp parallel for schedule(static) reduction(max : bad) if (parallel_)
        for (long e = 0; e < ne; ++e)
            if (!corners_positive(e, X_.data(), Y_.data(), ux_.data(), uy_.data(), 1.0))
                bad = std::max(bad, e);
        if (bad >= 0) {
            std::ostringstream s;
            s << "element " << bad << " (layer " << law_of_[bad] << ", centre x = " << element_x(bad)
              << ", y = " << element_y(bad) << " m) inverted at t = " << time_ + dt << " s in step "
              << steps_ + 1;
            throw StructureFailure(s.str());
        }
        double work = 0;
#pragma omp parallel for schedule(static) reduction(+ : work) if (parallel_)
        for (long i = 0; i < n; ++i) {
            vx_[i] = dux_[i] / dt;
            vy_[i] = duy_[i] / dt;
            work += wx_[i] * dux_[i] + wy_[i] * duy_[i];
        }
        // Element updates at the mid-step configuration.
        double internal = 0, plastic = 0, viscous = 0;
        const bool axi = plane_ == Plane::Axisymmetric;
#pragma omp parallel for schedule(static) reduction(+ : internal, plastic, viscous) if (parallel_)
        for (long e = 0; e < ne; ++e) {
            const auto& q = quads_[e];
            double xm[4], ym[4], dx[4], dy[4];
            for (int k = 0; k < 4; ++k) {
                dx[k] = dux_[q[k]], dy[k] = duy_[q[k]];
                xm[k] = X_[q[k]] + ux_[q[k]] + 0.5 * dx[k];
                ym[k] = Y_[q[k]] + uy_[q[k]] + 0.5 * dy[k];
            }
            const Shape s = shape(xm, ym);
            double exx = 0, eyy = 0, gxy = 0, w = 0;
            for (int k = 0; k < 4; ++k) {
                exx += s.bx[k] * dx[k];
                eyy += s.by[k] * dy[k];
                gxy += s.by[k] * dx[k] + s.bx[k] * dy[k];
                w += 0.5 * (s.bx[k] * dy[k] - s.by[k] * dx[k]);
            }
            const double rc = 0.25 * (xm[0] + xm[1] + xm[2] + xm[3]);
            const double ezz = axi ? 0.25 * (dx[0] + dx[1] + dx[2] + dx[3]) / rc : 0.0;
            PointState& p = points_[e];
            rotate(p.stress, w);
            const Voigt s0 = p.stress;
            const double wp0 = p.plastic_work;
            const Voigt de = {exx, eyy, ezz, gxy, 0, 0};
            laws_[law_of_[e]]->update(de, dt, p);
            double dw = 0;
            for (int k = 0; k < 4; ++k)
                dw += 0.5 * (s0[k] + p.stress[k]) * de[k];
            const double V = s.area * (axi ? rc : 1.0);
            internal += dw * V;
            plastic += (p.plastic_work - wp0) * V;
            e_internal_[e] += dw * V;
            e_plastic_[e] += (p.plastic_work - wp0) * V;
            if (bulk_.on()) {
                const double dv = exx + eyy + ezz, rate = dv / dt;
                double q = 0;
                if (rate < 0) {
                    const MaterialLaw& law = *laws_[law_of_[e]];
                    const double L = std::sqrt(s.area), rho = 4 * mshare_[e] / V;
                    const double c = std::sqrt(law.wave_modulus() / law.density());
                    q = rho * L * (bulk_.quadratic * bulk_.quadratic * L * rate * rate - bulk_.linear * c * rate);
                }
                const double dq = -0.5 * (q_[e] + q) * dv * V;
                viscous += dq;
                e_viscous_[e] += dq;
                q_[e] = q;
                rate_v_[e] = rate;
            }
        }
        en_.internal += internal;
        en_.plastic += plastic;
        en_.viscous += viscous;
#pragma omp parallel for schedule(static) if (parallel_)
        for (long i = 0; i < n; ++i) {
            ux_[i] += dux_[i];
            uy_[i] += duy_[i];
        }
        time_ += dt;
        last_dt_ = dt;
        ++steps_;
        // The fluid's load of this step stays in the accelerations of the new state (for its kinetic energy
        // and output); the next step solves it anew. Its work is F_k · Δx_k = A_k p_I u_I Δt.
        if (fluid) {
            wet_fx_.swap(load_x), wet_fy_.swap(load_y);
        } else {
            std::fill(wet_fx_.begin(), wet_fx_.end(), 0.0);
            std::fill(wet_fy_.begin(), wet_fy_.end(), 0.0);
        }
        forces(time_);
#pragma omp parallel for schedule(static) reduction(+ : work) if (parallel_)
        for (long i = 0; i < n; ++i)
            work += wx_[i] * dux_[i] + wy_[i] * duy_[i];
        en_.external += 0.5 * work + fluid_work;
        en_.coupling += fluid_work - delivered;
        en_.kinetic = kinetic(dt);
        return out;
    }

  public:
    // Output (solid/run_structure.hpp lists the datasets).
    std::vector<Field> mesh_fields() const override {
        Field xy{"nodes", Field::Centre::Mesh, 2, {}, {}}, quads{"quads", Field::Centre::Mesh, 4, {}, {}},
            layer{"layer", Field::Centre::Mesh, 1, {}, law_of_};
        for (size_t i = 0; i < nodes(); ++i)
            xy.values.insert(xy.values.end(), {X_[i], Y_[i]});
        for (const auto& q : quads_)
            quads.integers.insert(quads.integers.end(), q.begin(), q.end());
        return {xy, quads, layer};
    }
    std::vector<Field> state_fields() const override {
        const size_t n = nodes();
        Field position{"position", Field::Centre::Node, 2, std::vector<double>(2 * n), {}};
        for (size_t i = 0; i < n; ++i)
            position.values[2 * i] = X_[i] + ux_[i], position.values[2 * i + 1] = Y_[i] + uy_[i];
        std::vector<Field> f = {position,
                                {"u_x", Field::Centre::Node, 1, ux_, {}},
                                {"u_y", Field::Centre::Node, 1, uy_, {}},
                                {"v_x", Field::Centre::Node, 1, vx_, {}},
                                {"v_y", Field::Centre::Node, 1, vy_, {}},
                                {"a_x", Field::Centre::Node, 1, ax_, {}},
                                {"a_y", Field::Centre::Node, 1, ay_, {}}};
        // The same as vectors of three components (z = 0), which ParaView's Warp By Vector takes.
        auto vector_field = [&](const char* name, const std::vector<double>& x,
                                const std::vector<double>& y) {
            Field v{name, Field::Centre::Node, 3, std::vector<double>(3 * n, 0.0), {}};
            for (size_t i = 0; i < n; ++i)
                v.values[3 * i] = x[i], v.values[3 * i + 1] = y[i];
            f.push_back(std::move(v));
        };
        vector_field("displacement", ux_, uy_);
        vector_field("velocity", vx_, vy_);
        auto element_field = [&](const char* name, auto pick) {
            Field e{name, Field::Centre::Element, 1, {}, {}};
            for (size_t k = 0; k < quads_.size(); ++k)
                e.values.push_back(pick(k));
            f.push_back(std::move(e));
        };
        static const char* const stress[4] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy"};
        for (int k = 0; k < 4; ++k)
            element_field(stress[k], [&](size_t e) { return points_[e].stress[k]; });
        element_field("von_mises", [&](size_t e) { return von_mises(points_[e].stress); });
        element_field("peeq", [&](size_t e) { return points_[e].peeq; });
        element_field("peeq_rate", [&](size_t e) { return points_[e].peeq_rate; });
        element_field("hourglass_energy", [&](size_t e) { return ehg_[e]; });
        return f;
    }
    std::vector<std::string> gauge_columns() const override {
        return {"u_x",       "u_y",       "v_x",       "v_y",       "a_x", "a_y",
                "stress_xx", "stress_yy", "stress_zz", "stress_xy", "peeq"};
    }
    // The nearest node, and the element containing the point: on a structured grid the one left of and
    // below it where it lies on an element edge; otherwise the first whose bounding box holds it.
    GaugeSite locate(double x, double y) const override {
        GaugeSite g;
        double best = 1e300;
        for (size_t i = 0; i < nodes(); ++i) {
            const double d = std::hypot(X_[i] - x, Y_[i] - y);
            if (d < best) best = d, g.node = i;
        }
        if (grid_nx_ > 0) {
            int i = 0, j = 0;
            while (i + 1 < grid_nx_ && X_[i + 1] < x)
                ++i;
            while (j + 1 < grid_ny_ && Y_[(j + 1) * (grid_nx_ + 1)] < y)
                ++j;
            g.element = static_cast<size_t>(j) * grid_nx_ + i;
            return g;
        }
        for (size_t e = 0; e < quads_.size(); ++e) {
            const auto& q = quads_[e];
            const auto [x0, x1] = std::minmax({X_[q[0]], X_[q[1]], X_[q[2]], X_[q[3]]});
            const auto [y0, y1] = std::minmax({Y_[q[0]], Y_[q[1]], Y_[q[2]], Y_[q[3]]});
            if (x >= x0 && x <= x1 && y >= y0 && y <= y1) return g.element = e, g;
        }
        return g;
    }
    void gauge_values(const GaugeSite& g, std::vector<double>& row) const override {
        const auto& s = points_[g.element];
        const size_t n = g.node;
        row.insert(row.end(), {ux_[n], uy_[n], vx_[n], vy_[n], ax_[n], ay_[n], s.stress[0], s.stress[1],
                               s.stress[2], s.stress[3], s.peeq});
    }

  private:
    struct Shape {
        double area, bx[4], by[4];
    };
    struct Geometry : Shape {
        double rc;
    };
    struct Load {
        std::vector<std::array<int, 2>> edges;
        std::function<double(double)> p;
    };
    Plane plane_;
    BulkViscosity bulk_;
    std::vector<std::shared_ptr<const MaterialLaw>> laws_;
    std::vector<double> X_, Y_;
    std::vector<std::array<int, 4>> quads_;
    std::vector<int> law_of_;
    std::vector<double> ux_, uy_, vx_, vy_, ax_, ay_, mass_;
    std::vector<double> wx_, wy_;   // external force on each node: loads and reactions of constraints
    std::vector<double> dux_, duy_; // the increments of the current step
    std::vector<char> cx_, cy_;
    std::vector<PointState> points_;
    std::vector<std::array<double, 4>> gamma_;
    std::vector<double> kx_, ky_, efx_, efy_, ehg_;
    std::vector<int> incidence_start_, incidence_;
    std::vector<Load> loads_;
    int grid_nx_ = 0, grid_ny_ = 0;
    std::vector<int> wet_;                // wet nodes: face 0 in order along it, then face 1, ...
    std::vector<int> wet_index_;          // per node: its place in wet_, or −1 (empty: no wet face)
    std::vector<int> wet_face_;           // per wet node: its face
    std::vector<char> face_left_;         // per face: the structure lies left of the direction of its nodes
    std::vector<double> wet_fx_, wet_fy_; // per wet node: the fluid's load A p_I n of the last step
    std::vector<double> other_fx_, other_fy_; // per wet node: every other force at the present state
    // Threads only for meshes large enough to repay the start of a parallel loop (several per step).
    bool parallel_ = false;
    Energies en_;
    double time_ = 0, last_dt_ = 0;
    std::vector<double> e_internal_, e_plastic_; // per element, accumulated like en_
    std::vector<double> e_viscous_;               // per element: the bulk viscosity's work
    std::vector<double> q_, rate_v_;              // per element: bulk viscosity pressure, volumetric rate
    std::vector<double> mshare_;                 // per element: the mass it lumps to each of its nodes
    long steps_ = 0;

    double sum(size_t e, const double* v) const {
        const auto& q = quads_[e];
        return v[q[0]] + v[q[1]] + v[q[2]] + v[q[3]];
    }

    // Area and uniform-gradient matrix of a quadrilateral (Flanagan–Belytschko).
    static Shape shape(const double* x, const double* y) {
        Shape s;
        s.area = 0.5 * ((x[2] - x[0]) * (y[3] - y[1]) + (x[1] - x[3]) * (y[2] - y[0]));
        const double f = 0.5 / s.area;
        s.bx[0] = f * (y[1] - y[3]), s.bx[1] = f * (y[2] - y[0]), s.bx[2] = f * (y[3] - y[1]),
        s.bx[3] = f * (y[0] - y[2]);
        s.by[0] = f * (x[3] - x[1]), s.by[1] = f * (x[0] - x[2]), s.by[2] = f * (x[1] - x[3]),
        s.by[3] = f * (x[2] - x[0]);
        return s;
    }
    // Geometry of element e at X + u (u may be null).
    Geometry geometry(size_t e, const double* X, const double* Y, const double* ux, const double* uy) const {
        const auto& q = quads_[e];
        double x[4], y[4];
        for (int k = 0; k < 4; ++k) {
            x[k] = X[q[k]] + (ux ? ux[q[k]] : 0.0);
            y[k] = Y[q[k]] + (uy ? uy[q[k]] : 0.0);
        }
        Geometry g;
        static_cast<Shape&>(g) = shape(x, y);
        g.rc = 0.25 * (x[0] + x[1] + x[2] + x[3]);
        return g;
    }
    // Whether the four corner areas of element e at X + u + f·du are positive (a convex, unfolded quad).
    bool corners_positive(long e, const double* X, const double* Y, const double* ux, const double* uy,
                          double f) const {
        const auto& q = quads_[e];
        double x[4], y[4];
        for (int k = 0; k < 4; ++k) {
            x[k] = X[q[k]] + (ux ? ux[q[k]] + f * dux_[q[k]] : 0.0);
            y[k] = Y[q[k]] + (uy ? uy[q[k]] + f * duy_[q[k]] : 0.0);
        }
        for (int k = 0; k < 4; ++k) {
            const int a = (k + 1) % 4, b = (k + 3) % 4;
            if (!((x[a] - x[k]) * (y[b] - y[k]) - (y[a] - y[k]) * (x[b] - x[k]) > 0)) return false;
        }
        return true;
    }
    // Rotates the in-plane stress by the spin increment w (counter-clockwise), with the rotation
    // (1 − W/2)⁻¹(1 + W/2) of Hughes and Winget: cos and sin of the angle 2 atan(w/2).
    static void rotate(Voigt& s, double w) {
        if (w == 0) return;
        const double t = 0.5 * w, f = 1 / (1 + t * t), c = (1 - t * t) * f, n = 2 * t * f;
        const double xx = s[0], yy = s[1], xy = s[3];
        s[0] = c * c * xx + n * n * yy - 2 * c * n * xy;
        s[1] = n * n * xx + c * c * yy + 2 * c * n * xy;
        s[3] = c * n * (xx - yy) + (c * c - n * n) * xy;
    }

    struct WetMotion {
        double vx, vy; // the velocity of the half step
        InterfaceSolution s;
    };
    // Wet node k's equation of motion along its normal n (unit, of the start of the step) with the
    // impedance relation p_I = p_L − Z_L (u_I − u_L) − geometric, u_I = n · v, in closed form, then
    // p_I ≥ p_floor. A free node: interface_node.hpp along n, and the other forces alone along the tangent.
    // A node held in x and y: its velocity stays, p_I follows from it. A node free along one axis e only
    // (a symmetry plane or the axis): with c = n · e and u_f the part of u_I from the held component,
    //     m (v_e − v_e⁻) = h (F_e + A c p_I),   p_I = p_L − Z_L (c v_e + u_f − u_L) − geometric,
    // so v_e = [m v_e⁻ + h (F_e + A c (p_L + Z_L (u_L − u_f) − geometric))] / (m + h A Z_L c²).
    WetMotion solve_wet_node(size_t k, double nx, double ny, double A, double h,
                             const FluidCharacteristic& f) const {
        const int i = wet_[k];
        const double m = mass_[i], Fx = other_fx_[k], Fy = other_fy_[k];
        WetMotion r{vx_[i], vy_[i], {}};
        if (cx_[i] && cy_[i]) {
            r.s.p_I = f.p_L - f.Z_L * (nx * r.vx + ny * r.vy - f.u_L) - f.geometric;
            if (r.s.p_I < f.p_floor) r.s.p_I = f.p_floor, r.s.cavitating = true;
            return r;
        }
        if (cx_[i] || cy_[i]) {
            const bool along_y = cx_[i];
            const double c = along_y ? ny : nx, u_f = along_y ? nx * r.vx : ny * r.vy;
            const double v0 = along_y ? r.vy : r.vx, F = along_y ? Fy : Fx;
            double v = (m * v0 + h * (F + A * c * (f.p_L + f.Z_L * (f.u_L - u_f) - f.geometric))) /
                       (m + h * A * f.Z_L * c * c);
            r.s.p_I = f.p_L - f.Z_L * (c * v + u_f - f.u_L) - f.geometric;
            if (r.s.p_I < f.p_floor) {
                r.s.p_I = f.p_floor, r.s.cavitating = true;
                v = v0 + h * (F + A * c * r.s.p_I) / m;
            }
            (along_y ? r.vy : r.vx) = v;
            return r;
        }
        r.s = solve_interface_node(m, nx * r.vx + ny * r.vy, h, nx * Fx + ny * Fy, A, f);
        r.vx += h * (Fx + A * r.s.p_I * nx) / m;
        r.vy += h * (Fy + A * r.s.p_I * ny) / m;
        return r;
    }

    // Internal, hourglass and applied forces at the present configuration; accelerations; the external
    // force (loads and reactions) on every node for the work of the next step.
    void forces(double t) {
        const long n = static_cast<long>(X_.size()), ne = static_cast<long>(quads_.size());
        const bool axi = plane_ == Plane::Axisymmetric;
        double hourglass = 0;
#pragma omp parallel for schedule(static) reduction(+ : hourglass) if (parallel_)
        for (long e = 0; e < ne; ++e) {
            const auto& q = quads_[e];
            double x[4], y[4];
            for (int k = 0; k < 4; ++k)
                x[k] = X_[q[k]] + ux_[q[k]], y[k] = Y_[q[k]] + uy_[q[k]];
            const Shape s = shape(x, y);
            const double rc = 0.25 * (x[0] + x[1] + x[2] + x[3]);
            const double V = s.area * (axi ? rc : 1.0);
            const Voigt& st = points_[e].stress;
            const double qv = q_[e]; // the bulk viscosity's pressure (0 without)
            const double sig[4] = {st[0] - qv, st[1] - qv, st[2] - qv, st[3]};
            const double hoop = axi ? 0.25 * s.area * sig[2] : 0.0;
            const auto& g = gamma_[e];
            double qx = 0, qy = 0;
            for (int k = 0; k < 4; ++k)
                qx += g[k] * ux_[q[k]], qy += g[k] * uy_[q[k]];
            for (int k = 0; k < 4; ++k) {
                efx_[4 * e + k] = -V * (s.bx[k] * sig[0] + s.by[k] * sig[3]) - hoop - kx_[e] * qx * g[k];
                efy_[4 * e + k] = -V * (s.bx[k] * sig[3] + s.by[k] * sig[1]) - ky_[e] * qy * g[k];
            }
            ehg_[e] = 0.5 * (kx_[e] * qx * qx + ky_[e] * qy * qy);
            hourglass += ehg_[e];
        }
        en_.hourglass = hourglass;
        std::fill(wx_.begin(), wx_.end(), 0.0);
        std::fill(wy_.begin(), wy_.end(), 0.0);
        for (const auto& load : loads_) {
            const double p = load.p(t);
            for (const auto& edge : load.edges) {
                const int i = edge[0], j = edge[1];
                const double xi = X_[i] + ux_[i], xj = X_[j] + ux_[j];
                const double fx = -p * (Y_[j] + uy_[j] - Y_[i] - uy_[i]), fy = p * (xj - xi);
                const double si = axi ? (2 * xi + xj) / 6 : 0.5, sj = axi ? (xi + 2 * xj) / 6 : 0.5;
                wx_[i] += fx * si, wy_[i] += fy * si;
                wx_[j] += fx * sj, wy_[j] += fy * sj;
            }
        }
#pragma omp parallel for schedule(static) if (parallel_)
        for (long i = 0; i < n; ++i) {
            double fx = 0, fy = 0;
            for (int k = incidence_start_[i]; k < incidence_start_[i + 1]; ++k)
                fx += efx_[incidence_[k]], fy += efy_[incidence_[k]];
            // A wet node: the forces but the fluid's, for the next step's interface solve, and the fluid's
            // load of the last step.
            const int w = wet_index_.empty() ? -1 : wet_index_[i];
            double lx = 0, ly = 0;
            if (w >= 0) {
                other_fx_[w] = fx + wx_[i], other_fy_[w] = fy + wy_[i];
                lx = wet_fx_[w], ly = wet_fy_[w];
            }
            // A constrained component has no acceleration: its reaction cancels the other forces.
            if (cx_[i])
                ax_[i] = 0, wx_[i] = -(fx + lx);
            else
                ax_[i] = (fx + wx_[i] + lx) / mass_[i];
            if (cy_[i])
                ay_[i] = 0, wy_[i] = -(fy + ly);
            else
                ay_[i] = (fy + wy_[i] + ly) / mass_[i];
        }
    }

    // Kinetic energy at the integer step from the half-step velocity and the new acceleration.
    double kinetic(double dt) const {
        double k = 0;
        const long n = static_cast<long>(X_.size());
#pragma omp parallel for schedule(static) reduction(+ : k) if (parallel_)
        for (long i = 0; i < n; ++i) {
            const double vx = vx_[i] + 0.5 * dt * ax_[i], vy = vy_[i] + 0.5 * dt * ay_[i];
            k += 0.5 * mass_[i] * (vx * vx + vy * vy);
        }
        return k;
    }
};

} // namespace undex::solid
