#include "base/run_driver.hpp"

#include "base/h5.hpp"
#include "base/signals.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace undex {

std::string format(const char* fmt, double a, double b, double c, double d, double e) {
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, a, b, c, d, e);
    return buf;
}

OutputClock::OutputClock(const RunPlan& plan, double start_time)
    : times_(plan.output_times), end_time_(plan.end_time) {
    while (next_ < times_.size() && times_[next_] <= start_time)
        ++next_;
}

Step OutputClock::clip(double t, double dt) const {
    if (!(dt > 0) || !std::isfinite(dt)) return {dt, false}; // refused by the driver, naming it
    if (next_ >= times_.size()) return {dt, false}; // past the last output (the driver stops at done())
    const double target = times_[next_];
    if (t + dt >= target * (1 - 1e-12)) return {target - t, true};
    return {dt, false};
}

bool OutputClock::admissible(const Step& s) const {
    return s.dt > 0 && std::isfinite(s.dt) && (s.output || s.dt >= dt_floor());
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// One progress line: step, time, share of the end time, step size, wall time and the time left (from the
// pace since t0, the time this process started from: 0, or a checkpoint's).
void progress_line(std::ostream& log, const Run& run, const RunPlan& plan, double t0, double dt,
                   double wall) {
    const double frac = run.time() / plan.end_time;
    const double done = (run.time() - t0) / (plan.end_time - t0);
    log << "step " << run.steps()
        << format("  t = %.4e s (%5.1f%%)  dt = %.3e s  wall %.1f s  left ~%.1f s", run.time(), 100 * frac,
                  dt, wall, done > 0 ? wall * (1 - done) / done : 0.0)
        << run.progress() << std::endl;
}

void checkpoint(Run& run, const std::string& name, std::ostream& log) {
    const auto start = Clock::now();
    const std::string path = run.write_checkpoint();
    if (path.empty()) return; // a side that keeps none (undex-rigid)
    log << name << ": checkpoint at step " << run.steps() << format(" (t = %.9g s) in ", run.time()) << path
        << format(" (%.1f s)", seconds_since(start)) << std::endl;
}

// The steps of a run until its end; throws RunFailure or what the run throws.
void step_to_end(Run& run, const RunPlan& plan, const std::string& name, std::ostream& log,
                 Clock::time_point start) {
    OutputClock clock(plan, run.time());
    const double t0 = run.time();
    auto last_progress = start, last_checkpoint = start;
    for (;;) {
        if (run.owns_clock() && clock.done(run.time())) break;
        if (run.stopping()) throw RunFailure(exit_stopped, stop_reason());
        if (run.owns_clock() && run.steps() >= plan.max_steps) // a partner's clock is the partner's to stop
            throw RunFailure(exit_method_failed,
                             "stopped: numerics.max_steps = " + std::to_string(plan.max_steps) +
                                 " reached at t = " + format("%.6g", run.time()) + " s");
        const bool due =
            plan.checkpoint_seconds > 0 &&
            std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= plan.checkpoint_seconds;
        const std::optional<Step> s = run.next_step(clock, due);
        if (!s) break;
        // A partner's step was checked against the same floor by the coupling library.
        if (!(run.owns_clock() ? clock.admissible(*s) : s->dt > 0 && std::isfinite(s->dt)))
            throw RunFailure(exit_method_failed,
                             "time step " + format("%g", s->dt) + " s at t = " + format("%.6g", run.time()) +
                                 " s, step " + std::to_string(run.steps()) +
                                 " is not positive and finite or below the floor " +
                                 format("%g s (%g × end_time)", clock.dt_floor(), dt_floor_fraction));
        run.advance(*s);
        if (run.steps() % plan.gauge_every == 0 || s->output) run.record();
        if (s->output) {
            run.write_output();
            clock.passed();
        }
        if (s->checkpoint) {
            // A checkpoint that cannot be written (a full disk) costs the run nothing but the checkpoint: the
            // one before stays, and a coupled partner's newer one is passed over by --resume.
            try {
                checkpoint(run, name, log);
            } catch (const std::exception& e) {
                log << name << ": error: the checkpoint at step " << run.steps()
                    << " could not be written (the run goes on; the last one stays): " << e.what() << std::endl;
            }
            last_checkpoint = Clock::now();
        }
        const auto now = Clock::now();
        if (std::chrono::duration<double>(now - last_progress).count() >= plan.progress_seconds ||
            clock.done(run.time())) {
            progress_line(log, run, plan, t0, s->dt, std::chrono::duration<double>(now - start).count());
            last_progress = now;
        }
    }
    run.finish();
}

} // namespace

int drive(Run& run, const RunPlan& plan, const std::string& name, std::ostream& log) {
    const auto start = Clock::now();
    std::string why;
    int status = exit_complete;
    try {
        step_to_end(run, plan, name, log, start);
        run.complete();
    } catch (const RunFailure& f) {
        why = f.what(), status = f.status;
    } catch (const h5::Error& e) { // an output that cannot be written ends the run (docs/protocol.md)
        why = e.what(), status = exit_method_failed;
    } catch (const std::exception& e) {
        // A signal that ends a wait of the coupling, or any ZeroMQ call (EINTR), is the stop it asked for.
        const bool coupling = run.coupling_error(e);
        if (!coupling && !stop_requested()) throw;
        status = stop_requested() ? exit_stopped : exit_coupling_failed;
        why =
            (status == exit_stopped ? stop_reason() + "; " : "") + (coupling ? "coupling: " : "") + e.what();
    }
    if (status != exit_complete) {
        log << name << ": error: " << why << std::endl;
        // Stopped (a signal, or the partner's failure) at the end of a step: the run can be resumed from
        // here.
        if (status != exit_method_failed && plan.checkpoint_seconds > 0 && run.at_step_end() &&
            run.steps() > 0) {
            try {
                checkpoint(run, name, log);
            } catch (const std::exception& e) {
                log << name << ": error: the checkpoint could not be written: " << e.what() << std::endl;
            }
        }
        try {
            run.fail(why);
            log << name << ": the last good state (t = " << format("%.9g", run.time()) << " s, step "
                << run.steps() << ") is in " << run.output_path() << std::endl;
        } catch (const std::exception& e) { // e.g. the disk is still full: what was flushed before stays
            log << name << ": error: the last good state could not be written: " << e.what() << "\n"
                << name << ": " << run.output_path() << " holds the outputs written before" << std::endl;
        }
        return status;
    }
    const double wall = seconds_since(start);
    log << name << ": done: " << run.steps() << " steps, wall " << format("%.3f", wall) << " s"
        << run.summary(wall) << std::endl;
    return exit_complete;
}

} // namespace undex
