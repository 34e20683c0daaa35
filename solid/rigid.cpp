// The run of undex-rigid: a rigid plate per unit area
// (structure.rigid_plate) driven by the fluid through the coupling protocol: the alternative structure solver
// of the simplest kind.
//     m du/dt = p_I − p_back − k x − c du/dt,   x the displacement along the normal into the plate,
// central differences with the interface condition of physics.md §5 solved together with the plate's
// equation of motion (interface_node.hpp); the dashpot uses the velocity of the last half step.
// Output <dir>/solid.h5: datasets case, status (as in fluid.h5); /gauges/plate with t, u, v, p_I (columns
// attribute of /gauges), so `undex gauges DIR/solid.h5` prints it; /coupling with t, dt, p_I, u_I and the
// step offered dt_s of every step.
#include "solid/rigid.hpp"

#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "base/run_driver.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
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
    std::vector<double> plate, coupling; // rows t, u, v, p_I and t, dt, p_I, u_I, dt_s
    void write() {
        h5::write_table(file_.id(), "gauges/plate", {"t", "u", "v", "p_I"}, plate);
        file_.write_table("coupling", {"t", "dt", "p_I", "u_I", "dt_s"}, coupling);
    }
    void complete() { file_.complete(); }
    void fail(const std::string& why) {
        file_.fail(why, [&] { write(); });
    }
    const std::string& path() const { return file_.path(); }

  private:
    h5::OutputFile file_;
};

// The plate for the driver (base/run_driver.hpp): it follows the fluid's clock.
class RigidRun : public Run {
  public:
    RigidRun(const CaseFile& c, const RunPlan& p, const RigidPlateModel& m,
             std::unique_ptr<coupling::StructureParticipant> link)
        : m_(m), link_(std::move(link)), out_(p.directory, c.text()) {
        out_.plate.insert(out_.plate.end(), {t_, x_, v_, m_.back_pressure});
    }
    double time() const override { return t_; }
    long steps() const override { return n_; }
    bool owns_clock() const override { return false; }
    std::optional<Step> next_step(const OutputClock&) override {
        if (!link_->exchange({m_.dt, {x_}, {0.0}, {v_}}, g_)) return std::nullopt;
        return Step{g_.dt, g_.output};
    }
    void advance(const Step& s) override {
        const double h = n_ == 0 ? 0.5 * s.dt : 0.5 * (s.dt + last_dt_);
        const double F = -m_.back_pressure - m_.stiffness * x_ - m_.damping * v_;
        const auto w = solve_interface_node(m_.mass_per_area, v_, h, F, 1.0,
                                            {g_.p_L[0], g_.u_L[0], g_.Z_L[0], g_.geometric[0], g_.p_floor});
        v_ = w.u_I;
        x_ += s.dt * v_;
        link_->answer({{w.p_I}, {w.u_I}, {x_}, {0.0}});
        out_.coupling.insert(out_.coupling.end(), {t_, s.dt, w.p_I, w.u_I, m_.dt});
        t_ += s.dt;
        last_dt_ = s.dt;
        ++n_;
        out_.plate.insert(out_.plate.end(), {t_, x_, v_, w.p_I});
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
    std::string summary(double) const override { return " (" + link_->stop_reason() + ")"; }
    bool coupling_error(const std::exception& e) const override {
        return dynamic_cast<const coupling::CouplingError*>(&e) != nullptr;
    }

  private:
    RigidPlateModel m_;
    std::unique_ptr<coupling::StructureParticipant> link_;
    RigidOutput out_;
    coupling::Grant g_;
    double t_ = 0, x_ = 0, v_ = 0, last_dt_ = 0; // v_: velocity of the last half step
    long n_ = 0;
};

} // namespace

int run_rigid(const CaseFile& c, const std::string& couple) {
    const RigidPlateModel m = make_rigid_plate(c);
    if (couple.empty())
        c.fail("structure.rigid_plate", "a rigid plate is driven by a fluid: run the case with `undex run`");
    const auto plan = undex::plan(c);
    std::cout << "undex-rigid: " << c.path() << ": rigid plate, " << m.mass_per_area << " kg/m², output "
              << plan.directory << "/solid.h5" << std::endl;
    const coupling::Options o{couple, plan.coupling_timeout_ms, plan.handshake_timeout_ms, stop_requested};
    auto link = std::make_unique<coupling::StructureParticipant>(o, "undex-rigid", "0.1.0");
    coupling::Interface i;
    i.x = {0.0}, i.y = {0.0}, i.normal_x = {1.0}, i.normal_y = {0.0}, i.area = {1.0};
    link->initialize(i);
    RigidRun r(c, plan, m, std::move(link));
    return drive(r, plan, "undex-rigid", std::cout);
}

} // namespace undex::solid
