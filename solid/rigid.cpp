// The run of undex-rigid: a rigid plate per unit area
// (structure.rigid_plate) driven by the fluid through the coupling protocol: the alternative structure solver
// of the simplest kind.
//     m du/dt = p_I − p_back − k x − c du/dt,   x the displacement along the normal into the plate,
// central differences with the interface condition of physics.md §5 solved together with the plate's
// equation of motion (interface_node.hpp); the dashpot uses the velocity of the last half step.
// In 1D the plate is one wet node of area 1 per unit area. In 2D it is the front face of structure.plate: its
// nodes along x at y = y_front, each with its wetted area A_k (docs/protocol.md: per unit depth, or per
// radian in axisymmetry) and the normal +y, moving together as one body of mass m Σ A_k along +y; the
// impedance relation of every node and the body's equation of motion are solved together
// (solve_rigid_face), the forces per unit area act on Σ A_k.
// Output <dir>/solid.h5: datasets case, status (as in fluid.h5); /gauges/plate with t, u, v, p_I (columns
// attribute of /gauges; in 2D p_I is the mean Σ A_k p_I,k / Σ A_k), so `undex gauges DIR/solid.h5` prints
// it; /coupling with t, dt, p_I, u_I and the step offered dt_s of every step and wet node; /energies with t
// and the external work of the fluid, Σ over steps and nodes of A_k p_I,k u_I Δt.
#include "solid/rigid.hpp"

#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "base/run_driver.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "base/solver_cli.hpp"
#include "coupler/participant.hpp"
#include "solid/interface_node.hpp"
#include "solid/structure_setup.hpp"

#include <iostream>
#include <string>
#include <vector>

namespace undex::solid {

namespace {

class RigidOutput {
  public:
    RigidOutput(const std::string& dir, const std::string& case_text) : file_(dir, "solid.h5", case_text) {
        h5::Object g = h5::create_group(file_.id(), "gauges");
        h5::write_attr_string(g.id(), "columns", "t,u,v,p_I");
        g.close();
        file_.flush();
    }
    // rows t, u, v, p_I; t, dt, p_I, u_I, dt_s; t, external
    std::vector<double> plate, coupling, energies;
    void write() {
        h5::write_table(file_.id(), "gauges/plate", {"t", "u", "v", "p_I"}, plate);
        file_.write_table("coupling", {"t", "dt", "p_I", "u_I", "dt_s"}, coupling);
        h5::write_table(file_.id(), "energies", {"t", "external"}, energies);
    }
    void complete() { file_.complete(); }
    void fail(const std::string& why) {
        file_.fail(why, [&] { write(); });
    }
    const std::string& path() const { return file_.path(); }

  private:
    h5::OutputFile file_;
};

// The wetted area of each node of a 2D plate's flat face (docs/protocol.md): half of each neighbouring
// segment per unit depth, or ∫ N_k r dr per radian: L (2 r_a + r_b) / 6 to a, L (r_a + 2 r_b) / 6 to b.
std::vector<double> areas(const RigidPlateModel& m) {
    std::vector<double> A(m.x.size(), 0.0);
    for (size_t k = 0; k + 1 < m.x.size(); ++k) {
        const double a = m.x[k], b = m.x[k + 1], L = b - a;
        A[k] += m.alpha == 1 ? L * (2 * a + b) / 6 : 0.5 * L;
        A[k + 1] += m.alpha == 1 ? L * (a + 2 * b) / 6 : 0.5 * L;
    }
    return A;
}

// The plate for the driver (base/run_driver.hpp): it follows the fluid's clock.
class RigidRun : public Run {
  public:
    RigidRun(const CaseFile& c, const RunPlan& p, const RigidPlateModel& m,
             std::unique_ptr<coupling::StructureParticipant> link)
        : m_(m), link_(std::move(link)), out_(p.directory, c.text()), area_(areas(m)) {
        if (!area_.empty()) total_area_ = 0;
        for (double a : area_)
            total_area_ += a;
        out_.plate.insert(out_.plate.end(), {t_, x_, v_, m_.back_pressure});
        out_.energies.insert(out_.energies.end(), {t_, work_});
    }
    double time() const override { return t_; }
    long steps() const override { return n_; }
    bool owns_clock() const override { return false; }
    std::optional<Step> next_step(const OutputClock&, bool) override {
        if (m_.dimension == 2) {
            const size_t n = m_.x.size();
            if (!link_->exchange(
                    {m_.dt, m_.x, std::vector<double>(n, m_.y_front + x_), std::vector<double>(n, v_)}, g_))
                return std::nullopt;
            return Step{g_.dt, g_.output};
        }
        if (!link_->exchange({m_.dt, {x_}, {0.0}, {v_}}, g_)) return std::nullopt;
        return Step{g_.dt, g_.output};
    }
    void advance(const Step& s) override {
        if (m_.dimension == 2) return advance_face(s);
        const double h = n_ == 0 ? 0.5 * s.dt : 0.5 * (s.dt + last_dt_);
        const double F = -m_.back_pressure - m_.stiffness * x_ - m_.damping * v_;
        const auto w = solve_interface_node(m_.mass_per_area, v_, h, F, 1.0,
                                            {g_.p_L[0], g_.u_L[0], g_.Z_L[0], g_.geometric[0], g_.p_floor});
        v_ = w.u_I;
        x_ += s.dt * v_;
        link_->answer({{w.p_I}, {w.u_I}, {x_}, {0.0}});
        out_.coupling.insert(out_.coupling.end(), {t_, s.dt, w.p_I, w.u_I, m_.dt});
        work_ += w.p_I * w.u_I * s.dt;
        t_ += s.dt;
        last_dt_ = s.dt;
        ++n_;
        out_.plate.insert(out_.plate.end(), {t_, x_, v_, w.p_I});
        out_.energies.insert(out_.energies.end(), {t_, work_});
    }
    // The 2D face: every node at the body's velocity along +y.
    void advance_face(const Step& s) {
        const size_t n = m_.x.size();
        const double h = n_ == 0 ? 0.5 * s.dt : 0.5 * (s.dt + last_dt_);
        const double F = (-m_.back_pressure - m_.stiffness * x_ - m_.damping * v_) * total_area_;
        std::vector<FluidCharacteristic> f(n);
        for (size_t k = 0; k < n; ++k)
            f[k] = {g_.p_L[k], g_.u_L[k], g_.Z_L[k], g_.geometric[k], g_.p_floor};
        const auto w = solve_rigid_face(m_.mass_per_area * total_area_, v_, h, F, area_, f);
        v_ = w[0].u_I;
        x_ += s.dt * v_;
        coupling::Answer a;
        double force = 0;
        for (size_t k = 0; k < n; ++k) {
            a.p_I.push_back(w[k].p_I), a.u_I.push_back(w[k].u_I);
            out_.coupling.insert(out_.coupling.end(), {t_, s.dt, w[k].p_I, w[k].u_I, m_.dt});
            force += area_[k] * w[k].p_I;
            work_ += area_[k] * w[k].p_I * w[k].u_I * s.dt;
        }
        a.x = m_.x;
        a.y.assign(n, m_.y_front + x_);
        link_->answer(a);
        t_ += s.dt;
        last_dt_ = s.dt;
        ++n_;
        out_.plate.insert(out_.plate.end(), {t_, x_, v_, force / total_area_});
        out_.energies.insert(out_.energies.end(), {t_, work_});
    }
    void record() override {} // the plate's history has a row per step (advance)
    void write_output() override { out_.write(); }
    void complete() override {
        out_.write();
        out_.complete();
    }
    void fail(const std::string& why) override {
        link_->fail(why); // best effort: the peer learns the cause
        out_.fail(why);
    }
    std::string output_path() const override { return out_.path(); }
    std::string write_checkpoint() override { return ""; } // none: see run_rigid
    std::string summary(double) const override { return " (" + link_->stop_reason() + ")"; }
    bool coupling_error(const std::exception& e) const override {
        return dynamic_cast<const coupling::CouplingError*>(&e) != nullptr;
    }

  private:
    RigidPlateModel m_;
    std::unique_ptr<coupling::StructureParticipant> link_;
    RigidOutput out_;
    coupling::Grant g_;
    std::vector<double> area_;                   // 2D: the wetted area of each node
    double total_area_ = 1;                      // 1D: per unit area
    double t_ = 0, x_ = 0, v_ = 0, last_dt_ = 0; // v_: velocity of the last half step
    double work_ = 0;                            // the fluid's work on the plate
    long n_ = 0;
};

} // namespace

int run_rigid(const CaseFile& c, const std::string& couple, const std::string& resume) {
    const RigidPlateModel m = make_rigid_plate(c);
    if (!resume.empty())
        throw UsageError("undex-rigid keeps no checkpoints (a run of a rigid plate takes seconds): run the "
                         "case again instead of --resume");
    if (couple.empty())
        c.fail("structure.rigid_plate", "a rigid plate is driven by a fluid: run the case with `undex run`");
    const auto plan = undex::plan(c);
    std::cout << "undex-rigid: " << c.path() << ": rigid plate"
              << (m.dimension == 2 ? ", 2D face of " + std::to_string(m.x.size()) + " nodes" : std::string())
              << ", " << m.mass_per_area << " kg/m², output " << plan.directory << "/solid.h5" << std::endl;
    const coupling::Options o{couple, plan.coupling_timeout_ms, plan.handshake_timeout_ms, stop_requested};
    auto link = std::make_unique<coupling::StructureParticipant>(o, "undex-rigid", "0.1.0");
    coupling::Interface i;
    if (m.dimension == 2) {
        i.dimension = 2, i.alpha = m.alpha;
        i.x = m.x, i.area = areas(m);
        const size_t n = m.x.size();
        i.y.assign(n, m.y_front), i.normal_x.assign(n, 0.0), i.normal_y.assign(n, 1.0), i.face.assign(n, 0);
    } else {
        i.x = {0.0}, i.y = {0.0}, i.normal_x = {1.0}, i.normal_y = {0.0}, i.area = {1.0};
    }
    link->initialize(i);
    RigidRun r(c, plan, m, std::move(link));
    return drive(r, plan, "undex-rigid", std::cout);
}

} // namespace undex::solid
