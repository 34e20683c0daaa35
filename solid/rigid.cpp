// undex-rigid CASE [--set key=value]... --couple ENDPOINT: a rigid plate per unit area
// (structure.rigid_plate) driven by the fluid through the coupling protocol: the alternative structure solver
// of the simplest kind.
//     m du/dt = p_I − p_back − k x − c du/dt,   x the displacement along the normal into the plate,
// central differences with the interface condition of physics.md §5 solved together with the plate's
// equation of motion (interface_node.hpp); the dashpot uses the velocity of the last half step.
// Output <dir>/solid.h5: attributes case, status; /gauges/plate with t, u, v, p_I (columns attribute of
// /gauges), so `undex gauges DIR/solid.h5` prints it; /coupling with t, dt, p_I, u_I of every step.
#include "proto/case.pb.h"
#include "solid/rigid.hpp"

#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "solid/interface_node.hpp"
#include "coupler/participant.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "solid/structure_setup.hpp"

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace undex::solid {

namespace {

class RigidOutput {
  public:
    RigidOutput(const std::string& dir, const std::string& case_text) {
        std::filesystem::create_directories(dir);
        path_ = (std::filesystem::path(dir) / "solid.h5").string();
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        file_ = h5::create(path_);
        if (file_ < 0) throw std::runtime_error(path_ + ": cannot create the output file");
        h5::write_attr_string(file_, "case", case_text);
        h5::write_attr_string(file_, "status", "running");
        hid_t g = H5Gcreate2(file_, "gauges", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        h5::write_attr_string(g, "columns", "t,u,v,p_I");
        H5Gclose(g);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    ~RigidOutput() { H5Fclose(file_); }
    std::vector<double> plate, coupling; // rows t, u, v, p_I and t, dt, p_I, u_I
    void write() {
        h5::write_table(file_, "gauges/plate", {"t", "u", "v", "p_I"}, plate);
        h5::write_table(file_, "coupling", {"t", "dt", "p_I", "u_I"}, coupling);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    void set_status(const std::string& s) {
        h5::write_attr_string(file_, "status", s);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
    hid_t file_ = -1;
};

} // namespace

int run_rigid(const CaseFile& c, const std::string& couple) {
    const RigidPlateModel m = make_rigid_plate(c);
    if (couple.empty())
        c.fail("structure.rigid_plate", "a rigid plate is driven by a fluid: run the case with `undex run`");
    const auto plan = undex::plan(c);
    std::cout << "undex-rigid: " << c.path() << ": rigid plate, " << m.mass_per_area << " kg/m², output "
              << plan.directory << "/solid.h5" << std::endl;
    coupling::Options o;
    o.endpoint = couple;
    o.timeout_ms = static_cast<int>(1000 * c.get().coupling().timeout());
    o.handshake_timeout_ms = static_cast<int>(1000 * c.get().coupling().handshake_timeout());
    coupling::StructureParticipant link(o, "undex-rigid", "0.1.0");
    coupling::Interface i;
    i.x = {0.0}, i.y = {0.0}, i.normal_x = {1.0}, i.normal_y = {0.0}, i.area = {1.0};
    link.initialize(i);
    RigidOutput out(plan.directory, c.text());
    double t = 0, x = 0, v = 0, last_dt = 0; // v: velocity of the last half step
    out.plate.insert(out.plate.end(), {t, x, v, m.back_pressure});
    try {
        for (long n = 0;; ++n) {
            if (stop_requested()) {
                link.fail("stopped by a signal (SIGINT or SIGTERM)");
                out.write();
                out.set_status("failed: stopped by a signal (SIGINT or SIGTERM)");
                std::cerr << "undex-rigid: stopped by a signal; the history up to t = " << t << " s is in "
                          << out.path() << std::endl;
                return 4;
            }
            coupling::Grant g;
            if (!link.exchange({m.dt, {x}, {0.0}, {v}}, g)) break;
            const double h = n == 0 ? 0.5 * g.dt : 0.5 * (g.dt + last_dt);
            const double F = -m.back_pressure - m.stiffness * x - m.damping * v;
            const auto s = solve_interface_node(
                m.mass_per_area, v, h, F, 1.0, {g.p_L[0], g.u_L[0], g.Z_L[0], g.geometric[0], g.p_floor});
            v = s.u_I;
            x += g.dt * v;
            link.answer({{s.p_I}, {s.u_I}, {x}, {0.0}});
            out.coupling.insert(out.coupling.end(), {t, g.dt, s.p_I, s.u_I});
            t += g.dt;
            last_dt = g.dt;
            out.plate.insert(out.plate.end(), {t, x, v, s.p_I});
            if (g.output) out.write();
        }
    } catch (const coupling::CouplingError& e) {
        link.fail(e.what());
        out.write();
        out.set_status(std::string("failed: coupling: ") + e.what());
        std::cerr << "undex-rigid: error: coupling: " << e.what()
                  << "\nundex-rigid: the history up to t = " << t << " s is in " << out.path() << std::endl;
        return stop_requested() ? 4 : 3;
    }
    out.write();
    out.set_status("complete");
    std::cout << "undex-rigid: done: t = " << t << " s (" << link.stop_reason() << ")" << std::endl;
    return 0;
}

} // namespace undex::solid
