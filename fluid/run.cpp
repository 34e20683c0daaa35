#include "run.hpp"

#include "case_file.hpp"
#include "output.hpp"
#include "setup.hpp"

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

} // namespace

int run(const CaseFile& c, std::ostream& log) {
    const RunPlan p = plan(c);
    validate(c);
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

    Output out(p.directory, c.text(), *solver, p.gauges);
    out.record_gauges(*solver);
    out.write_fields(*solver);
    const auto start = std::chrono::steady_clock::now();
    auto last_progress = start;
    size_t next_output = 0;
    while (next_output < p.output_times.size() && p.output_times[next_output] <= solver->time()) ++next_output;
    while (solver->time() < p.end_time * (1 - 1e-14)) {
        if (solver->steps() >= p.max_steps) {
            const std::string msg = "stopped: numerics.max_steps = " + std::to_string(p.max_steps) + " reached at t = " +
                                    format("%.6g", solver->time()) + " s";
            out.write_fields(*solver, true);
            out.set_status("failed: " + msg);
            log << "undex-fluid: error: " << msg << std::endl;
            return 2;
        }
        const double target = p.output_times[next_output];
        double dt = solver->stable_dt();
        if (!(dt > 0) || !std::isfinite(dt)) {
            const std::string msg = "time step " + format("%g", dt) + " s is not positive and finite at t = " +
                                    format("%.6g", solver->time()) + " s, step " + std::to_string(solver->steps());
            out.write_fields(*solver, true);
            out.set_status("failed: " + msg);
            log << "undex-fluid: error: " << msg << std::endl;
            return 2;
        }
        bool hits_output = false;
        if (solver->time() + dt >= target * (1 - 1e-12)) {
            dt = target - solver->time();
            hits_output = true;
        }
        try {
            solver->step(dt);
        } catch (const SolverFailure& f) {
            out.write_fields(*solver, true);
            out.set_status(std::string("failed: ") + f.what());
            log << "undex-fluid: error: " << f.what() << "\nundex-fluid: the last good state (t = "
                << format("%.9g", solver->time()) << " s, step " << solver->steps() << ") is in " << out.path()
                << std::endl;
            return 2;
        }
        if (solver->steps() % p.gauge_every == 0 || hits_output) out.record_gauges(*solver);
        if (hits_output) {
            out.write_fields(*solver);
            ++next_output;
        }
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_progress).count() >= p.progress_seconds ||
            solver->time() >= p.end_time * (1 - 1e-14)) {
            const double wall = std::chrono::duration<double>(now - start).count();
            const double frac = solver->time() / p.end_time;
            log << "step " << solver->steps()
                << format("  t = %.4e s (%5.1f%%)  dt = %.3e s  wall %.1f s  left ~%.1f s", solver->time(),
                          100 * frac, dt, wall, frac > 0 ? wall * (1 - frac) / frac : 0.0)
                << std::endl;
            last_progress = now;
        }
    }
    out.write_gauges();
    out.set_status("complete");
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    log << "undex-fluid: done: " << solver->steps() << " steps, wall " << format("%.3f", wall) << " s" << std::endl;
    return 0;
}

} // namespace undex::fluid
