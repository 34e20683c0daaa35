#include "fluid/run.hpp"

#include "proto/case.pb.h"
#include "base/case_file.hpp"
#include "fluid/output.hpp"
#include "coupler/participant.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "fluid/setup.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace undex::fluid {

namespace {

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0, double e = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, a, b, c, d, e);
    return buf;
}

bool coupled_case(const CaseFile& c) {
    return c.get().boundaries().x_max().type() == config::Boundary::STRUCTURE;
}

} // namespace

int run(const CaseFile& c, std::ostream& log, const std::string& couple) {
    const RunPlan p = plan(c);
    validate(c);
    const bool coupled = coupled_case(c);
    if (coupled && couple.empty())
        c.fail("boundaries.x_max",
               "the case couples the fluid to a structure: run it with `undex run`, or give "
               "undex-fluid --couple ENDPOINT and start a structure solver on it");
    if (!coupled && !couple.empty())
        c.fail("boundaries.x_max", "--couple needs a structure in the case (x_max: STRUCTURE)");
#ifdef _OPENMP
    if (p.threads > 0) omp_set_num_threads(p.threads);
    const int threads = omp_get_max_threads();
#else
    const int threads = 1;
#endif
    auto solver = make_solver(c); // may throw SolverFailure for inadmissible initial data
    const Mesh& m = solver->mesh();
    log << "undex-fluid: " << c.path() << ": " << m.dim << "D, " << m.nx;
    if (m.dim == 2) log << " x " << m.ny;
    log << " cells, degree " << solver->degree() << ", " << threads << " thread(s), end time " << p.end_time
        << " s, output " << p.directory << "/fluid.h5" << std::endl;

    // The structure, when there is one: its interface node sits at x_max (physics.md §5).
    std::unique_ptr<coupling::FluidParticipant> link;
    coupling::Offer offer;
    double x0_I = 0;
    std::vector<double> history; // t, dt, p_L, u_L, Z_L, p_I, u_I, displacement per step
    const std::vector<std::string> history_columns = {"t",   "dt",  "p_L", "u_L",
                                                      "Z_L", "p_I", "u_I", "displacement"};
    if (coupled) {
        coupling::Options o;
        o.endpoint = couple;
        o.timeout_ms = static_cast<int>(1000 * c.get().coupling().timeout());
        o.handshake_timeout_ms = static_cast<int>(1000 * c.get().coupling().handshake_timeout());
        link = std::make_unique<coupling::FluidParticipant>(o, "undex-fluid", "0.1.0");
        log << "undex-fluid: waiting for the structure solver on " << link->endpoint() << std::endl;
        const auto iface = link->initialize(1, m.alpha, p.end_time);
        auto refuse = [&](const std::string& why) { // after the Welcome: the structure is told why
            link->fail(why);
            throw coupling::CouplingError(why);
        };
        if (iface.size() != 1)
            refuse("the structure solver (" + link->peer_solver() + ") has " + std::to_string(iface.size()) +
                   " interface nodes; a 1D fluid couples to one");
        if (std::abs(iface.normal_x[0] - 1) > 1e-9)
            refuse("the structure solver (" + link->peer_solver() + ") gives its wet face the normal (" +
                   std::to_string(iface.normal_x[0]) + ", " + std::to_string(iface.normal_y[0]) +
                   "); the fluid lies at x < x_max, so it must be (1, 0)");
        x0_I = iface.x[0];
        log << "undex-fluid: coupled to " << link->peer_solver() << std::endl;
    }

    Output out(p.directory, c.text(), *solver, p.gauges);
    out.record_gauges(*solver);
    out.write_fields(*solver);
    // Ends the run on an error: the last good state is written and marked, the structure told.
    auto fail = [&](const std::string& msg, int code) {
        if (link) link->fail(msg); // best effort: the peer learns the cause
        out.write_fields(*solver, true);
        if (coupled) out.write_table("interface", history_columns, history);
        out.write_gauges();
        out.set_status("failed: " + msg);
        log << "undex-fluid: error: " << msg
            << "\nundex-fluid: the last good state (t = " << format("%.9g", solver->time()) << " s, step "
            << solver->steps() << ") is in " << out.path() << std::endl;
        return code;
    };
    const auto start = std::chrono::steady_clock::now();
    auto last_progress = start;
    double coupling_wall = 0; // inside the coupling library: waiting for and exchanging with the structure
    size_t next_output = 0;
    while (next_output < p.output_times.size() && p.output_times[next_output] <= solver->time())
        ++next_output;
    try {
        while (solver->time() < p.end_time * (1 - 1e-14)) {
            if (stop_requested()) return fail("stopped by a signal (SIGINT or SIGTERM)", 4);
            if (solver->steps() >= p.max_steps)
                return fail("stopped: numerics.max_steps = " + std::to_string(p.max_steps) +
                                " reached at t = " + format("%.6g", solver->time()) + " s",
                            2);
            const auto wait_start = std::chrono::steady_clock::now();
            if (link && !link->receive_offer(offer))
                return fail("the structure solver stopped the run at step " + std::to_string(link->step()) +
                                ": " + link->stop_reason(),
                            3);
            const double target = p.output_times[next_output];
            double dt = solver->stable_dt();
            if (link) dt = std::min(dt, offer.dt);
            if (!(dt > 0) || !std::isfinite(dt))
                return fail("time step " + format("%g", dt) +
                                " s is not positive and finite at t = " + format("%.6g", solver->time()) +
                                " s, step " + std::to_string(solver->steps()),
                            2);
            bool hits_output = false;
            if (solver->time() + dt >= target * (1 - 1e-12)) {
                dt = target - solver->time();
                hits_output = true;
            }
            if (link) {
                // The fluid's characteristic state at the interface, from the DG trace of the last cell.
                const double x_I = m.x_max;
                const Primitive w = solver->evaluate(x_I, 0);
                const double a = solver->sound_speed(x_I, 0);
                coupling::Grant g;
                g.time = solver->time();
                g.p_floor = solver->pressure_floor();
                g.output = hits_output;
                g.p_L = {w.p};
                g.u_L = {w.u};
                g.Z_L = {w.rho * a};
                g.geometric = {m.alpha * dt * w.rho * a * a * w.u / x_I};
                const coupling::Answer ans = link->exchange(dt, g);
                coupling_wall +=
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - wait_start).count();
                dt = g.dt; // = min(Δt_f, Δt_s): the step both sides take
                solver->set_structure_state(ans.p_I[0], ans.u_I[0]);
                history.insert(history.end(), {solver->time(), dt, w.p, w.u, g.Z_L[0], ans.p_I[0], ans.u_I[0],
                                               ans.x[0] - x0_I});
            }
            try {
                solver->step(dt);
            } catch (const SolverFailure& f) {
                return fail(f.what(), 2);
            }
            if (solver->steps() % p.gauge_every == 0 || hits_output) out.record_gauges(*solver);
            if (hits_output) {
                if (link) link->heartbeat(); // the structure's wait restarts: an output may take a while
                out.write_fields(*solver);
                if (coupled) out.write_table("interface", history_columns, history);
                ++next_output;
            }
            const auto now = std::chrono::steady_clock::now();
            if (std::chrono::duration<double>(now - last_progress).count() >= p.progress_seconds ||
                solver->time() >= p.end_time * (1 - 1e-14)) {
                const double wall = std::chrono::duration<double>(now - start).count();
                const double frac = solver->time() / p.end_time;
                log << "step " << solver->steps()
                    << format("  t = %.4e s (%5.1f%%)  dt = %.3e s  wall %.1f s  left ~%.1f s",
                              solver->time(), 100 * frac, dt, wall, frac > 0 ? wall * (1 - frac) / frac : 0.0)
                    << std::endl;
                last_progress = now;
            }
        }
        if (link) link->finalize("end time reached");
    } catch (const coupling::CouplingError& e) {
        return fail(std::string("coupling: ") + e.what(), stop_requested() ? 4 : 3);
    }
    out.write_gauges();
    if (coupled) out.write_table("interface", history_columns, history);
    out.set_status("complete");
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    log << "undex-fluid: done: " << solver->steps() << " steps, wall " << format("%.3f", wall) << " s";
    if (link) log << format(" (coupling %.3f s, %.1f %%)", coupling_wall, 100 * coupling_wall / wall);
    log << std::endl;
    return 0;
}

} // namespace undex::fluid
