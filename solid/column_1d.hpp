// Layered 1D column of two-node elements through the thickness of a plate or sandwich (physics.md §6):
// lumped mass, central-difference integration, per unit area. Each layer has its own material law, thickness
// and element count; layers are perfectly bonded (they share their interface node). Node 0 is the front
// (wet) face at x = 0, the last node the back face.
// Kinematics: uniaxial stress (a bar: the lateral stresses are held at zero by iterating the lateral
// strains, so σ = E ε for an elastic layer) or uniaxial strain (a laterally confined plate: σ = (λ + 2μ) ε).
// Laws that are uniaxial by construction (Foam1D) see only the axial strain in both cases.
// Strain increments are logarithmic: Δε = Δl / l over the mean length of the step, so large foam
// compressions are measured correctly.
// A fluid may wet the front face, the back face or both: each wet face node is solved with the interface
// condition of physics.md §5 along its normal (+x at the front, −x at the back), wetted area 1.
#pragma once
#include "solid/interface_node.hpp"
#include "solid/material.hpp"
#include "solid/structure.hpp"

#include <cmath>
#include <functional>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace undex::solid {

enum class Kinematics1D { UniaxialStress, UniaxialStrain };
enum class Face1D { Free, Fixed };

struct Layer1D {
    std::shared_ptr<const MaterialLaw> law;
    double thickness = 0;
    int elements = 0;
    bool uniaxial_law = false; // the law uses the xx components only
};

class Column1D : public Structure {
  public:
    Column1D(const std::vector<Layer1D>& layers, Kinematics1D kin) : kin_(kin) {
        require(!layers.empty(), "a column needs at least one layer");
        x_.push_back(0.0);
        for (size_t l = 0; l < layers.size(); ++l) {
            const auto& L = layers[l];
            const std::string where = "layer " + std::to_string(l) + ": ";
            if (!L.law) throw MaterialError(where + "no material law");
            if (!(L.thickness > 0)) throw MaterialError(where + "thickness must be positive");
            if (L.elements < 1)
                throw MaterialError(where + "needs at least one element (a layer thinner than one element)");
            const double h = L.thickness / L.elements;
            for (int e = 0; e < L.elements; ++e) {
                elements_.push_back({L.law.get(), L.uniaxial_law, h, static_cast<int>(l)});
                x_.push_back(x_.back() + h);
            }
            laws_.push_back(L.law);
        }
        const size_t n = x_.size();
        mass_.assign(n, 0.0);
        for (size_t e = 0; e < elements_.size(); ++e) {
            const double m = elements_[e].law->density() * elements_[e].length0 / 2;
            mass_[e] += m;
            mass_[e + 1] += m;
        }
        u_.assign(n, 0.0);
        v_.assign(n, 0.0);
        a_.assign(n, 0.0);
        force_.assign(n, 0.0);
        points_.assign(elements_.size(), PointState{});
    }

    size_t nodes() const override { return x_.size(); }
    size_t element_count() const override { return elements_.size(); }
    double node_x(size_t i) const { return x_[i]; }
    double element_x(size_t e) const { return 0.5 * (x_[e] + x_[e + 1]); }
    double displacement(size_t i) const { return u_[i]; }
    double velocity(size_t i) const { return v_[i]; } // at the last half step
    double acceleration(size_t i) const { return a_[i]; }
    const PointState& point(size_t e) const { return points_[e]; }
    double time() const override { return time_; }
    long steps() const override { return steps_; }
    const Energies& energies() const override { return en_; }
    void state(State& s) override {
        s.io("x", x_), s.io("u", u_), s.io("v", v_), s.io("a", a_), s.io("force", force_);
        s.io("points", points_), s.io("energies", en_), s.io("time", time_), s.io("last_dt", last_dt_);
        s.io("front_load", front_load_), s.io("back_load", back_load_), s.io("steps", steps_);
    }
    std::string description() const override {
        return "1D column, " + std::to_string(elements_.size()) + " elements";
    }
    int dimension() const override { return 1; }

    void set_face(int side, Face1D f) { face_[side] = f; }
    // A fluid wets face side (0 front, 1 back).
    void set_wet(int side) { wet_[side] = true; }
    // Pressure p(t) on a face (side 0 front, 1 back), pushing into the column.
    void set_pressure(int side, std::function<double(double)> p) { pressure_[side] = std::move(p); }
    // Initial velocity of every node (before the first step).
    void set_velocity(const std::function<double(double)>& v0) {
        for (size_t i = 0; i < x_.size(); ++i)
            v_[i] = v0(x_[i]);
        en_.kinetic = kinetic();
    }

    // Largest stable step: min over elements of l / sqrt(M/ρ) (physics.md §6), without safety factor, M the
    // element's present elastic modulus (MaterialLaw::wave_modulus_at) for a strain step of twice what the
    // present strain rate gives over the step that modulus allows.
    double stable_dt() const override {
        double dt = 1e300;
        for (size_t e = 0; e < elements_.size(); ++e) {
            const auto& el = elements_[e];
            const double l = x_[e + 1] + u_[e + 1] - x_[e] - u_[e], rho = el.law->density();
            const double rate = std::abs(v_[e + 1] - v_[e]) / l;
            const double dt_now = l / std::sqrt(el.law->wave_modulus_at(points_[e], 0.0) / rho);
            const double M = el.law->wave_modulus_at(points_[e], 2 * rate * dt_now);
            dt = std::min(dt, l / std::sqrt(M / rho));
        }
        return dt;
    }

    // Wet nodes: node 0 (normal +x) when the front is wet, the last node (normal −x) when the back is.
    std::vector<WetNode> wet_nodes() const override {
        std::vector<WetNode> w;
        const size_t n = x_.size();
        if (wet_[0]) w.push_back({x_[0] + u_[0], 0.0, 1.0, 0.0, 1.0, v_[0]});
        if (wet_[1]) w.push_back({x_[n - 1] + u_[n - 1], 0.0, -1.0, 0.0, 1.0, -v_[n - 1], wet_[0] ? 1 : 0});
        return w;
    }
    std::vector<InterfaceSolution> step(double dt, std::span<const FluidCharacteristic> fluid) override {
        const size_t wet = (wet_[0] ? 1 : 0) + (wet_[1] ? 1 : 0);
        if (fluid.size() != wet)
            throw std::invalid_argument("Column1D::step: " + std::to_string(fluid.size()) +
                                        " fluid states for " + std::to_string(wet) + " wet nodes");
        const FluidCharacteristic* front = wet_[0] ? &fluid[0] : nullptr;
        const FluidCharacteristic* back = wet_[1] ? &fluid[wet - 1] : nullptr;
        const auto [at_front, at_back] = step_faces(dt, front, back);
        std::vector<InterfaceSolution> out;
        if (front) out.push_back(at_front);
        if (back) out.push_back(at_back);
        return out;
    }

    // One central-difference step: v^{n+1/2} = v^{n−1/2} + Δt a^n (half a step at the start), then
    // u^{n+1} = u^n + Δt v^{n+1/2}, then the forces and accelerations at n+1. With a fluid on the front
    // face, node 0 is solved with the interface condition of physics.md §5 (interface_node.hpp, wetted area
    // 1 per unit area) and the interface pressure and velocity of the step are returned.
    InterfaceSolution step(double dt, const FluidCharacteristic* fluid = nullptr) {
        return step_faces(dt, fluid, nullptr).first;
    }

    // The step with a fluid on the front and/or the back face (nullptr: that face is dry).
    std::pair<InterfaceSolution, InterfaceSolution> step_faces(double dt, const FluidCharacteristic* fluid,
                                                               const FluidCharacteristic* back_fluid) {
        if (steps_ == 0) forces(time_, u_); // a^0
        const size_t n = x_.size();
        const double h = steps_ == 0 ? 0.5 * dt : 0.5 * (dt + last_dt_);
        // Trial velocities and increments; the state is changed only once every element is known to stay
        // valid, so that a failure leaves the last good state in place.
        std::vector<double> v(n), du(n);
        InterfaceSolution wet, wet_back;
        for (size_t i = 0; i < n; ++i) {
            v[i] = v_[i] + h * a_[i];
            if (i == 0 && fluid) {
                wet = solve_interface_node(mass_[0], v_[0], h, force_[0] - front_load_, 1.0, *fluid);
                v[0] = wet.u_I;
            }
            if (i + 1 == n && back_fluid) { // along the back's normal −x
                wet_back =
                    solve_interface_node(mass_[i], -v_[i], h, -(force_[i] + back_load_), 1.0, *back_fluid);
                v[i] = -wet_back.u_I;
            }
            if ((i == 0 && face_[0] == Face1D::Fixed) || (i + 1 == n && face_[1] == Face1D::Fixed)) v[i] = 0;
            du[i] = dt * v[i];
            if (!std::isfinite(du[i])) {
                std::ostringstream s;
                s << "node " << i << " (x = " << x_[i]
                  << " m) has a non-finite velocity at t = " << time_ + dt << " s in step " << steps_ + 1;
                throw StructureFailure(s.str());
            }
        }
        for (size_t e = 0; e < elements_.size(); ++e)
            if (!(x_[e + 1] + u_[e + 1] + du[e + 1] - x_[e] - u_[e] - du[e] > 0)) {
                std::ostringstream s;
                s << "element " << e << " (layer " << elements_[e].layer << ", x = " << element_x(e)
                  << " m) inverted at t = " << time_ + dt << " s in step " << steps_ + 1;
                throw StructureFailure(s.str());
            }
        v_.swap(v);
        // External work of the face pressures over the step (trapezoidal in time).
        for (int side = 0; side < 2; ++side) {
            if (!pressure_[side]) continue;
            const size_t i = side == 0 ? 0 : n - 1;
            const double sign = side == 0 ? 1.0 : -1.0;
            en_.external += 0.5 * (pressure_[side](time_) + pressure_[side](time_ + dt)) * sign * du[i];
        }
        front_load_ = fluid ? wet.p_I : 0.0;
        en_.external += front_load_ * du[0];
        back_load_ = back_fluid ? wet_back.p_I : 0.0;
        en_.external -= back_load_ * du[n - 1];
        // Element updates: strain increments over the mean length, stress, internal and plastic work.
        for (size_t e = 0; e < elements_.size(); ++e) {
            const auto& el = elements_[e];
            const double l0 = x_[e + 1] + u_[e + 1] - x_[e] - u_[e];
            const double l1 = l0 + du[e + 1] - du[e];
            const double deps = (du[e + 1] - du[e]) / (0.5 * (l0 + l1));
            PointState& p = points_[e];
            const double sigma0 = p.stress[0], wp0 = p.plastic_work;
            update_point(el, deps, dt, p);
            const double lm = 0.5 * (l0 + l1);
            en_.internal += 0.5 * (sigma0 + p.stress[0]) * deps * lm;
            en_.plastic += (p.plastic_work - wp0) * lm;
        }
        for (size_t i = 0; i < n; ++i)
            u_[i] += du[i];
        time_ += dt;
        last_dt_ = dt;
        ++steps_;
        forces(time_, u_);
        en_.kinetic = kinetic_at_step(dt);
        return {wet, wet_back};
    }

    // Output (solid/run_structure.hpp lists the datasets).
    std::vector<Field> mesh_fields() const override {
        Field x{"x", Field::Centre::Mesh, 1, x_, {}}, xe{"element_x", Field::Centre::Mesh, 1, {}, {}};
        for (size_t e = 0; e < elements_.size(); ++e)
            xe.values.push_back(element_x(e));
        return {x, xe};
    }
    std::vector<Field> state_fields() const override {
        auto element_field = [&](const char* name, auto pick) {
            Field f{name, Field::Centre::Element, 1, {}, {}};
            for (const auto& p : points_)
                f.values.push_back(pick(p));
            return f;
        };
        return {{"u", Field::Centre::Node, 1, u_, {}},
                {"v", Field::Centre::Node, 1, v_, {}},
                {"a", Field::Centre::Node, 1, a_, {}},
                element_field("stress_xx", [](const PointState& p) { return p.stress[0]; }),
                element_field("strain_xx", [](const PointState& p) { return p.strain[0]; }),
                element_field("plastic_strain_xx", [](const PointState& p) { return p.plastic_strain[0]; }),
                element_field("peeq", [](const PointState& p) { return p.peeq; }),
                element_field("peeq_rate", [](const PointState& p) { return p.peeq_rate; })};
    }
    std::vector<std::string> gauge_columns() const override { return {"u", "v", "a", "stress_xx", "peeq"}; }
    // The node nearest to depth x and the element containing it.
    GaugeSite locate(double x, double /*y*/) const override {
        GaugeSite g;
        for (size_t i = 1; i < nodes(); ++i)
            if (std::abs(node_x(i) - x) < std::abs(node_x(g.node) - x)) g.node = i;
        while (g.element + 1 < element_count() && node_x(g.element + 1) < x)
            ++g.element;
        return g;
    }
    void gauge_values(const GaugeSite& g, std::vector<double>& row) const override {
        const auto& s = points_[g.element];
        row.insert(row.end(), {u_[g.node], v_[g.node], a_[g.node], s.stress[0], s.peeq});
    }

  private:
    struct Element {
        const MaterialLaw* law;
        bool uniaxial_law;
        double length0;
        int layer;
    };
    Kinematics1D kin_;
    std::vector<std::shared_ptr<const MaterialLaw>> laws_;
    std::vector<Element> elements_;
    std::vector<double> x_, mass_, u_, v_, a_, force_;
    std::vector<PointState> points_;
    Face1D face_[2] = {Face1D::Free, Face1D::Free};
    std::function<double(double)> pressure_[2];
    Energies en_;
    double time_ = 0, last_dt_ = 0;
    double front_load_ = 0; // the fluid's pressure on the front face in the last step (in a_ as an estimate)
    double back_load_ = 0;  // the same on the back face
    bool wet_[2] = {false, false};
    long steps_ = 0;

    void update_point(const Element& el, double deps, double dt, PointState& p) const {
        if (el.uniaxial_law || kin_ == Kinematics1D::UniaxialStrain) {
            el.law->update({deps, 0, 0, 0, 0, 0}, dt, p);
            return;
        }
        // Uniaxial stress: lateral increments (yy = zz) by secant iteration so that σ_yy = 0.
        auto lateral = [&](double dl) {
            PointState t = p;
            el.law->update({deps, dl, dl, 0, 0, 0}, dt, t);
            return t.stress[1];
        };
        double a = 0, fa = lateral(a), b = -0.3 * deps, fb = lateral(b);
        const double scale = std::abs(p.stress[0]) + 1.0;
        for (int it = 0; it < 50 && std::abs(fb) > 1e-10 * scale && fb != fa; ++it) {
            const double c = b - fb * (b - a) / (fb - fa);
            a = b, fa = fb, b = c, fb = lateral(b);
        }
        el.law->update({deps, b, b, 0, 0, 0}, dt, p);
    }

    void forces(double t, const std::vector<double>&) {
        const size_t n = x_.size();
        std::fill(force_.begin(), force_.end(), 0.0);
        for (size_t e = 0; e < elements_.size(); ++e) {
            const double s = points_[e].stress[0]; // tension pulls the nodes together
            force_[e] += s;
            force_[e + 1] -= s;
        }
        if (pressure_[0]) force_[0] += pressure_[0](t);
        force_[0] += front_load_;
        if (pressure_[1]) force_[n - 1] -= pressure_[1](t);
        force_[n - 1] -= back_load_;
        for (size_t i = 0; i < n; ++i)
            a_[i] = force_[i] / mass_[i];
        if (face_[0] == Face1D::Fixed) a_[0] = 0;
        if (face_[1] == Face1D::Fixed) a_[n - 1] = 0;
    }

    double kinetic() const {
        double k = 0;
        for (size_t i = 0; i < x_.size(); ++i)
            k += 0.5 * mass_[i] * v_[i] * v_[i];
        return k;
    }
    // Kinetic energy at the integer step from the half-step velocity and the new acceleration.
    double kinetic_at_step(double dt) const {
        double k = 0;
        for (size_t i = 0; i < x_.size(); ++i) {
            const double v = v_[i] + 0.5 * dt * a_[i];
            k += 0.5 * mass_[i] * v * v;
        }
        return k;
    }
};

} // namespace undex::solid
