// The run loop every solver executable shares (undex-fluid, undex-solid, undex-rigid): the output clock, the
// end-of-run test, the progress line with its estimate of the time left, and the one way a run fails: the
// partner told why, the last good state written and marked, a message naming it, an exit status.
//
// One step of a run, in this order (docs/architecture.md):
//   1. end?      a side that owns the clock stops at end_time; a side that follows its partner's clock stops
//                when the partner says so (next_step gives nothing)
//   2. stop?     SIGINT, SIGTERM or SIGHUP (base/signals.hpp), or numerics.max_steps reached (by the side
//   that owns
//                the clock)
//   3. next_step the side's largest step, cut to land on the next output time (OutputClock::clip); a
//                coupled side agrees on it with its partner: Δt = min(Δt_f, Δt_s)
//   4. advance   the step itself (a coupled side exchanges interface data here)
//   5. record    gauges and energies every output.gauge_every steps and at every output
//   6. output    fields at an output time
//   7. progress  a line every output.progress_seconds and at the end
//   8. checkpoint when the step was marked for one (base/checkpoint.hpp): every output.checkpoint_seconds of
//                wall time; the side that owns the clock marks it, a coupled structure learns it from the
//                Grant. A run stopped by a signal, or by its partner's failure, at the end of a step writes
//                one before its last good state.
#pragma once
#include "base/exit_status.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"

#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>

namespace undex {

// A failure that ends a run: what happened, and the exit status it gives.
struct RunFailure : std::runtime_error {
    RunFailure(int status, const std::string& what) : std::runtime_error(what), status(status) {}
    int status;
};

struct Step {
    double dt = 0;
    bool output = false;     // the step ends on an output time
    bool checkpoint = false; // a checkpoint is written at its end
};

// The Δt floor: a step shorter than dt_floor_fraction · end_time is refused, unless it was shortened to end
// on an output time (which plan() keeps at least that far apart). A run at 1e12 steps would never end, and
// far below it t + Δt == t. The coupling library refuses the same floor in a peer's Offer and Grant
// (coupler/messages.hpp, docs/protocol.md).
constexpr double dt_floor_fraction = 1e-12;

// The plan's output times after the start of a run.
class OutputClock {
  public:
    OutputClock(const RunPlan& plan, double start_time);
    // Whether the driver takes step s: Δt positive and finite, and not below the floor unless s ends on an
    // output time.
    bool admissible(const Step& s) const;
    double dt_floor() const { return dt_floor_fraction * end_time_; }
    // Whether a run at time t has reached the end time, within the tolerance of clip: a step that clip marks
    // as ending on the last output time ends the run even when the step the peer granted is the partner's
    // Δt_s, rounding below that time (Δt_s a divisor of the output interval: t = end_time − 4e-14 end_time
    // after 2 000 steps of 5e-7 s).
    bool done(double t) const { return !(t < end_time_ * (1 - 1e-12)); }
    // A step of at most dt from t, shortened to end on the next output time when it reaches it (a dt that is
    // not positive and finite is returned as it is, for the driver to refuse).
    Step clip(double t, double dt) const;
    void passed() { ++next_; }

  private:
    const std::vector<double>& times_;
    double end_time_;
    size_t next_ = 0;
};

// What a solver gives the driver.
class Run {
  public:
    virtual ~Run() = default;
    virtual double time() const = 0;
    virtual long steps() const = 0;
    // Whether a stop was asked for (base/signals.hpp); a side of many processes answers what they agreed.
    virtual bool stopping() const { return stop_requested(); }
    // Whether this side stops at end_time itself (false: its partner's Stop ends the run).
    virtual bool owns_clock() const { return true; }
    // The next step (3. above); nothing when the partner ended the run. Throws RunFailure. checkpoint_due:
    // the side that owns the clock asks for a checkpoint at the end of the step (a coupled fluid tells the
    // structure in its Grant); a side that follows sets Step::checkpoint as its partner says.
    virtual std::optional<Step> next_step(const OutputClock& clock, bool checkpoint_due) = 0;
    // Advances by exactly s.dt; throws RunFailure and then leaves the last good state in place.
    virtual void advance(const Step& s) = 0;
    virtual void record() = 0;
    virtual void write_output() = 0;
    // After the last step: tells the partner (if any) that the run is over.
    virtual void finish() {}
    // Writes what is left (histories), marks the output complete and closes it. An output that cannot be
    // written (h5::Error, here or in write_output) is a failure of the run: exit status 2.
    virtual void complete() = 0;
    // After a failure: tells the partner why (best effort), writes the last good state and marks the output
    // failed with the message; throws when that cannot be written (the driver says so).
    virtual void fail(const std::string& why) = 0;
    virtual std::string output_path() const = 0;
    // Writes a checkpoint of the state at the end of the last step and returns its path (base/checkpoint.hpp).
    virtual std::string write_checkpoint() = 0;
    // Whether the state is that of the end of a step, as a checkpoint must hold it (false while a step is
    // half taken: a fluid that has moved its wet faces to the structure's offer).
    virtual bool at_step_end() const { return true; }
    // Appended to the progress line and to the closing line.
    virtual std::string progress() const { return ""; }
    virtual std::string summary(double /*wall_seconds*/) const { return ""; }
    // Whether an exception from next_step/advance/finish is a coupling failure (exit status 3).
    virtual bool coupling_error(const std::exception&) const { return false; }
};

// Runs to the end or to the first failure; returns the exit status. `name` prefixes the messages on log.
int drive(Run& run, const RunPlan& plan, const std::string& name, std::ostream& log);

// printf-style formatting of numbers for messages.
std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0, double e = 0);

} // namespace undex
