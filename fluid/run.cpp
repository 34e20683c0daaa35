#include "fluid/run.hpp"

#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "base/run_driver.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "coupler/participant.hpp"
#include "fluid/output.hpp"
#include "fluid/ranks.hpp"
#include "fluid/setup.hpp"
#include "fluid/wet_faces.hpp"
#include "proto/case.pb.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <iostream>
#include <limits>
#include <numeric>
#include <optional>
#include <ostream>
#include <sstream>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace undex::fluid {

namespace {

// A stop request (SIGINT, SIGTERM, SIGHUP) ends the coupling's waits, but not the wait for the structure's
// Answer: the fluid has moved its wet faces to the step's offer by then, and the structure answers a Grant
// without waiting. The step is finished and the run stops at its end, where it can be checkpointed.
bool in_exchange = false;
bool stop_wait() {
    return stop_requested() && !in_exchange;
}

bool coupled_case(const CaseFile& c) {
    if (c.get().geometry() == config::PLANAR_2D || c.get().geometry() == config::AXISYMMETRIC_2D)
        return c.get().has_structure();
    return c.get().boundaries().x_max().type() == config::Boundary::STRUCTURE;
}

// Many ranks: the root talks to the structure, and what it learns reaches every rank (docs/scale_out.md).
// The root runs `talk`, which returns numbers; every rank gets them, or the root's failure, thrown again on
// every rank (a RunFailure with its exit status, anything else as a coupling error). One rank: talk().
std::vector<double> relay(const Ranks* ranks, const std::function<std::vector<double>()>& talk) {
    if (!ranks) return talk();
    std::vector<double> v;
    std::exception_ptr error;
    double status = 0; // 0: fine, > 0: a RunFailure's exit status, −1: another error
    std::string why;
    if (ranks->root()) {
        try {
            v = talk();
        } catch (const RunFailure& f) {
            error = std::current_exception(), status = f.status, why = f.what();
        } catch (const std::exception& e) {
            error = std::current_exception(), status = -1, why = e.what();
        }
    }
    v.push_back(status);
    v = ranks->broadcast(v, 0);
    status = v.back();
    v.pop_back();
    if (status == 0) return v;
    why = ranks->broadcast(why, 0);
    if (error) std::rethrow_exception(error);
    if (status > 0) throw RunFailure(static_cast<int>(status), why);
    throw coupling::CouplingError(why);
}

// The structure, through the coupling library. In 1D its one interface node sits at x_max (physics.md §5);
// in 2D its wet faces lie inside the fluid domain and move (physics.md §5.1, the solver's WetSolver part).
// On many ranks (ranks not null) the root talks to the structure, and the wet nodes reach every rank.
class StructureLink {
  public:
    StructureLink(const RunPlan& p, const std::string& endpoint, FluidSolver& solver, std::ostream& log,
                  const coupling::Start& start, const Ranks* ranks) {
        const Mesh& m = solver.mesh();
        coupling::Interface iface;
        const std::vector<double> nodes = relay(ranks, [&] {
            const coupling::Options o{endpoint, p.coupling_timeout_ms, p.handshake_timeout_ms, stop_wait};
            link_ = std::make_unique<coupling::FluidParticipant>(o, "undex-fluid", "0.1.0");
            log << "undex-fluid: waiting for the structure solver on " << link_->endpoint() << std::endl;
            iface = link_->initialize(m.dim, m.alpha, p.end_time, start);
            std::vector<double> v(iface.face.begin(), iface.face.end());
            for (const auto* a : {&iface.x, &iface.y, &iface.normal_x, &iface.normal_y})
                v.insert(v.end(), a->begin(), a->end());
            return v;
        });
        peer_ = ranks ? ranks->broadcast(link_ ? link_->peer_solver() : "", 0) : link_->peer_solver();
        if (!link_) { // another rank than the root: the wet nodes as the root received them
            const long n = static_cast<long>(nodes.size() / 5);
            auto part = [&](long q) {
                return std::vector<double>(nodes.begin() + q * n, nodes.begin() + (q + 1) * n);
            };
            iface.face.assign(nodes.begin(), nodes.begin() + n);
            iface.x = part(1), iface.y = part(2), iface.normal_x = part(3), iface.normal_y = part(4);
        }
        if (m.dim == 1) {
            if (iface.size() != 1)
                refuse("the structure solver (" + peer_ + ") has " +
                       std::to_string(iface.size()) + " interface nodes; a 1D fluid couples to one");
            if (std::abs(iface.normal_x[0] - 1) > 1e-9)
                refuse("the structure solver (" + peer_ + ") gives its wet face the normal (" +
                       std::to_string(iface.normal_x[0]) + ", " + std::to_string(iface.normal_y[0]) +
                       "); the fluid lies at x < x_max, so it must be (1, 0)");
            x0_I_ = {iface.x[0]};
        } else {
            wet_ = dynamic_cast<WetSolver*>(&solver);
            const double tol = 1e-9 * std::max(m.x_max - m.x_min, m.y_max - m.y_min);
            for (size_t k = 0; k < iface.size(); ++k)
                if (iface.x[k] < m.x_min - tol || iface.x[k] > m.x_max + tol || iface.y[k] < m.y_min - tol ||
                    iface.y[k] > m.y_max + tol)
                    refuse(where(iface, k) + " lies outside the fluid domain " + box(m));
            try {
                wet_->attach(iface.face, iface.x, iface.y, iface.normal_x, iface.normal_y);
            } catch (const std::exception& e) {
                refuse("the structure solver (" + peer_ +
                       ") sends wet faces the fluid cannot hold: " + e.what());
            }
            x0_I_ = iface.x, y0_I_ = iface.y;
            log << "undex-fluid: " << wet_->faces().faces() << " wet face(s), " << iface.size()
                << " wet nodes" << std::endl;
        }
        log << "undex-fluid: coupled to " << peer_ << std::endl;
    }
    coupling::FluidParticipant& operator*() { return *link_; }
    coupling::FluidParticipant* operator->() { return link_.get(); }
    // Whether this rank talks to the structure (one rank, or the root of many).
    bool talks() const { return link_ != nullptr; }
    double x0_I() const { return x0_I_[0]; }
    WetSolver* wet() const { return wet_; }

  private:
    std::unique_ptr<coupling::FluidParticipant> link_; // null on the ranks but the root
    std::string peer_;                                  // the structure solver's name
    std::vector<double> x0_I_, y0_I_;
    WetSolver* wet_ = nullptr;
    static std::string box(const Mesh& m) {
        std::ostringstream s;
        s << "[" << m.x_min << ", " << m.x_max << "] x [" << m.y_min << ", " << m.y_max << "] m";
        return s.str();
    }
    std::string where(const coupling::Interface& i, size_t k) const {
        std::ostringstream s;
        s << "the structure solver (" << peer_ << ") puts wet node " << k << " of face "
          << i.face[k] << " at (" << i.x[k] << ", " << i.y[k] << "), which";
        return s.str();
    }
    // After the Welcome: the structure is told why.
    [[noreturn]] void refuse(const std::string& why) {
        if (link_) link_->fail(why);
        throw coupling::CouplingError(why);
    }
};

// A fluid run for the driver (base/run_driver.hpp), coupled or not.
class FluidRun : public Run {
  public:
    // A new run (resume: nothing), or one continued from a checkpoint (its solver, attached to the same wet
    // nodes, restored here).
    // ranks: many ranks (fluid/ranks.hpp), the solver divided by them; null for one. The root writes the
    // output.
    FluidRun(const CaseFile& c, const RunPlan& p, std::unique_ptr<FluidSolver> solver,
             std::unique_ptr<StructureLink> link, State* resume, Ranks* ranks, std::ostream& log)
        : solver_(std::move(solver)), link_(std::move(link)), case_text_(c.text()), directory_(p.directory),
          ranks_(ranks), log_(log), gauges_(p.gauges) {
        const auto& o = c.get().output();
        const Mesh& m = solver_->mesh();
        frame_interval_ = m.dim == 2 ? o.frame_interval() : 0.0;
        frame_stride_ = std::max(1, static_cast<int>(std::lround(o.frame_cell() / std::max(m.dx, m.dy))));
        // The structure waits for the first grant meanwhile: heartbeats, as for an output (at the paper's
        // resolution the first fields take longer than one coupling timeout to write).
        std::optional<h5::WriteHook> keep_waiting;
        if (link_) keep_waiting.emplace([this] { beat(); }, 1.0);
        beat();
        if (resume) {
            state(*resume);
            State o = resume->scope("output");
            out_ = std::make_unique<Output>(p.directory, *solver_, p.gauges, o);
            write_history(); // the tables as they were at the checkpoint
            return;
        }
        if (ranks_) agree({}); // the first step and the gauges at the start
        if (root()) {
            out_ = std::make_unique<Output>(p.directory, c.text(), *solver_, p.gauges,
                                            ranks_ ? ranks_->size() : 1);
            remove_checkpoints(p.directory, "fluid"); // of an older run in the directory
        }
        if (ranks_) part_ = std::make_unique<OutputPart>(p.directory, ranks_->rank(), c.text());
        record();
        write_fields();
        if (ranks_) start_measuring(); // the steps' time, not the set-up's
    }
    bool stopping() const override { return ranks_ ? stop_ : stop_requested(); }

    double time() const override { return solver_->time(); }
    long steps() const override { return solver_->steps(); }

    std::optional<Step> next_step(const OutputClock& clock, bool checkpoint_due) override {
        if (link_) receive_offer();
        at_step_end_ = false; // until the step is taken
        if (link_ && link_->wet()) {
            try {
                timed(faces_wall_, [&] { return link_->wet()->move(offer_.x, offer_.y), true; });
            } catch (const SolverFailure& f) {
                throw RunFailure(exit_method_failed, f.what());
            }
        }
        double dt = dt_f_ = ranks_ ? next_dt_ : solver_->stable_dt();
        if (link_) dt = std::min(dt, offer_.dt);
        Step s = clock.clip(time(), dt);
        s.checkpoint = checkpoint_due;
        if (!link_ || !clock.admissible(s)) return s; // the driver refuses a step that collapsed
        {
            struct Exchanging { // no return before the Answer, even on an exception
                Exchanging() { in_exchange = true; }
                ~Exchanging() { in_exchange = false; }
            } exchanging;
            exchange(s);
        }
        return Step{dt_, s.output, s.checkpoint};
    }

    void advance(const Step& s) override {
        std::optional<std::string> failure;
        try {
            solver_->step(s.dt);
        } catch (const SolverFailure& f) {
            if (!ranks_) throw RunFailure(exit_method_failed, f.what());
            failure = f.what();
        }
        if (ranks_) agree(failure);
        at_step_end_ = true;
    }
    bool at_step_end() const override { return at_step_end_; }
    std::string write_checkpoint() override {
        // The structure waits meanwhile: heartbeats, as for an output (the partner may be gone after a
        // failure: then none).
        std::optional<h5::WriteHook> keep_waiting;
        if (link_) keep_waiting.emplace([this] { beat(); }, 1.0);
        beat();
        State s = State::create(directory_, "fluid", link_ ? "solid" : "", steps(), time(), case_text_);
        state(s);
        State o = s.scope("output");
        out_->state(o);
        return s.commit();
    }
    void beat() noexcept {
        try {
            if (talks()) (*link_)->heartbeat();
        } catch (const std::exception&) {
        }
    }
    void record() override {
        if (ranks_ && root()) out_->record_gauges(solver_->time(), gauge_values_);
        if (!ranks_) out_->record_gauges(*solver_);
        if (frame_interval_ > 0 && solver_->time() >= next_frame_ * (1 - 1e-12)) {
            if (ranks_) { // each rank's rows to the root, not the whole state to every rank
                const auto cells = ranks_->gather(frame_cells(*solver_, ranks_->begin(), ranks_->end()));
                root_writes([&] { out_->write_frame(cells, solver_->time(), frame_stride_); });
                rebalance();
            } else {
                out_->write_frame(*solver_, frame_stride_);
            }
            next_frame_ = frame_interval_ * (std::floor(solver_->time() / frame_interval_ * (1 + 1e-12)) + 1);
        }
    }
    void write_output() override {
        // The structure's wait restarts: an output may take a while (a heartbeat before it and between its
        // datasets, at most once a second).
        std::optional<h5::WriteHook> keep_waiting;
        if (talks()) {
            (*link_)->heartbeat();
            keep_waiting.emplace([this] { (*link_)->heartbeat(); }, 1.0);
        }
        write_fields();
        root_writes([&] {
            if (link_ && link_->wet() && !last_answer_.p_I.empty()) {
                const WetFaces& f = link_->wet()->faces();
                for (int k = 0; k < f.nodes(); ++k)
                    wet_rows_.insert(wet_rows_.end(),
                                     {solver_->time(), double(k), double(f.face(k)), last_answer_.x[k],
                                      last_answer_.y[k], last_grant_.p_L[k], last_grant_.u_L[k],
                                      last_answer_.p_I[k], last_answer_.u_I[k], f.area(k)});
            }
            write_history();
        });
        rebalance();
    }
    void finish() override {
        if (talks()) (*link_)->finalize("end time reached");
    }
    void complete() override {
        if (part_) part_->complete();
        root_writes([&] {
            out_->write_gauges();
            write_history();
            out_->complete();
            remove_checkpoints(directory_, "fluid"); // a complete run needs none
        });
    }
    void fail(const std::string& why) override {
        if (talks()) (*link_)->fail(why); // best effort: the peer learns the cause
        if (!ranks_) {
            return out_->fail(why, [&] {
                out_->write_fields(*solver_, true);
                write_history();
                out_->write_gauges();
            });
        }
        // Every rank is here (a failure is every rank's, agree and relay): each writes its rows.
        std::vector<double> totals;
        try {
            part_->write_fields(*solver_, ranks_->begin(), ranks_->end());
            totals = solver_->row_totals(ranks_->begin(), ranks_->end());
            part_->fail(why);
        } catch (const std::exception& e) {
            std::cerr << "undex-fluid: error: rank " << ranks_->rank() << ": " << e.what() << std::endl;
        }
        const std::vector<double> rows = ranks_->gather(totals);
        if (!root()) return;
        out_->fail(why, [&] {
            if (rows.size() != static_cast<size_t>(solver_->variables()) * solver_->mesh().ny)
                throw h5::Error(output_path() + ": the last good state: a rank could not write its rows");
            out_->write_fields(*solver_, first_rows(), rows, true);
            write_history();
            out_->write_gauges();
        });
    }
    std::string output_path() const override { return directory_ + "/fluid.h5"; }
    std::string summary(double wall) const override {
        std::string out;
        const long updates = ranks_ ? ranks_->sum(solver_->cell_updates()) : solver_->cell_updates();
        const long skipped =
            ranks_ ? ranks_->sum(solver_->cell_updates_skipped()) : solver_->cell_updates_skipped();
        if (skipped > 0)
            out += format("; %.1f %% of %.4g cell updates skipped (still water)", 100.0 * skipped / updates,
                          double(updates));
        if (ranks_) {
            out += format("; %g ranks, rows divided %g time(s)", ranks_->size(), divisions_);
            // Each rank's idle time (up to 4 ranks; beyond, the least and the most idle).
            const std::vector<double> w = ranks_->gather(ranks_->waits());
            const int n = Ranks::wait_kinds;
            std::vector<std::pair<double, int>> idle;
            for (int r = 0; r * n < static_cast<int>(w.size()); ++r)
                idle.push_back({std::accumulate(w.begin() + r * n, w.begin() + (r + 1) * n, 0.0), r});
            if (idle.size() > 4) {
                std::sort(idle.begin(), idle.end());
                idle = {idle.front(), idle.back()};
            }
            for (const auto& [total, r] : idle)
                out += format("; rank %g waited %.3f s", r, total) +
                       format(" (halo %.3f, reductions %.3f, broadcasts %.3f, gathers %.3f)", w[r * n],
                              w[r * n + 1], w[r * n + 2], w[r * n + 3]);
        }
        if (!link_) return out.empty() ? out : " (" + out.substr(2) + ")";
        out = format("coupling %.3f s, %.1f %%", coupling_wall_, 100 * coupling_wall_ / wall) + out;
        if (link_->wet()) out += format("; wet faces %.3f s, %.1f %%", faces_wall_, 100 * faces_wall_ / wall);
        return " (" + out + ")";
    }
    bool coupling_error(const std::exception& e) const override {
        return dynamic_cast<const coupling::CouplingError*>(&e) != nullptr;
    }

  private:
    std::unique_ptr<FluidSolver> solver_;
    std::unique_ptr<StructureLink> link_;
    std::string case_text_, directory_;
    std::unique_ptr<Output> out_;      // on the root only
    std::unique_ptr<OutputPart> part_; // many ranks: this rank's rows of the field outputs
    Ranks* ranks_;                // many ranks, else null
    std::ostream& log_;
    std::vector<GaugePoint> gauges_;
    // Many ranks: what the ranks agreed at the end of the last step (agree).
    double next_dt_ = 0;
    bool stop_ = false;
    std::vector<Primitive> gauge_values_;
    int divisions_ = 1;
    bool root() const { return !ranks_ || ranks_->root(); }
    bool talks() const { return link_ && link_->talks(); } // to the structure: the root
    // What the root alone writes. On many ranks a write that fails (a full disk) cannot take the failure
    // path, whose gather needs ranks that are already past the write: it ends every rank at once, saying
    // why; the file keeps the outputs flushed before.
    template <class F> void root_writes(F&& f) {
        if (!root()) return;
        if (!ranks_) return f();
        try {
            f();
        } catch (const std::exception& e) {
            ranks_->abort("undex-fluid: error: " + std::string(e.what()) + "; every rank ends; " +
                              output_path() + " holds the outputs written before",
                          exit_method_failed);
        }
    }
    // A field output. Many ranks: each writes its rows to its part and flushes it, then the root joins
    // them in fluid.h5 (after the gather: fluid.h5 never points at rows not yet flushed).
    void write_fields() {
        if (!ranks_) return out_->write_fields(*solver_);
        std::vector<double> totals;
        try {
            part_->write_fields(*solver_, ranks_->begin(), ranks_->end());
            totals = solver_->row_totals(ranks_->begin(), ranks_->end());
        } catch (const std::exception& e) {
            ranks_->abort("undex-fluid: error: rank " + std::to_string(ranks_->rank()) + ": " + e.what() +
                              "; every rank ends; " + output_path() + " holds the outputs written before",
                          exit_method_failed);
        }
        const std::vector<double> rows = ranks_->gather(totals);
        root_writes([&] { out_->write_fields(*solver_, first_rows(), rows); });
    }
    std::vector<int> first_rows() const {
        std::vector<int> f;
        for (int r = 0; r < ranks_->size(); ++r)
            f.push_back(ranks_->begin(r));
        f.push_back(ranks_->end(ranks_->size() - 1));
        return f;
    }
    // Many ranks, at the end of every step (and before the first): one MPI_Allreduce (max) agrees on the next
    // Δt (−Δt_f), on whether a rank failed in the step (its number + 1) or was asked to stop, and carries
    // the gauges' states from the ranks that hold them (the others give −∞). A failure is every rank's:
    // the others take their step back, and all end with the failed rank's message.
    void agree(const std::optional<std::string>& failure) {
        const double none = -std::numeric_limits<double>::infinity();
        const Mesh& m = solver_->mesh();
        ranks_->at_step(std::max(1L, solver_->steps())); // the step this reduction ends
        std::vector<double> v = {-solver_->stable_dt(), failure ? ranks_->rank() + 1.0 : 0.0,
                                 stop_requested() ? 1.0 : 0.0};
        for (const GaugePoint& g : gauges_) {
            const int j = std::clamp(static_cast<int>(std::floor((g.y - m.y_min) / m.dy)), 0, m.ny - 1);
            const bool mine = j >= ranks_->begin() && j < ranks_->end();
            const Primitive w = mine ? solver_->evaluate(g.x, g.y) : Primitive{};
            for (double x : {w.rho, w.u, w.v, w.p})
                v.push_back(mine ? x : none);
        }
        ranks_->max(v);
        ranks_->at_step(solver_->steps() + 1);
        next_dt_ = -v[0];
        stop_ = v[2] > 0;
        gauge_values_.resize(gauges_.size());
        for (size_t k = 0; k < gauges_.size(); ++k)
            gauge_values_[k] = {v[3 + 4 * k], v[4 + 4 * k], v[5 + 4 * k], v[6 + 4 * k]};
        if (v[1] == 0) return;
        const int from = static_cast<int>(v[1]) - 1;
        const std::string why = ranks_->broadcast(failure.value_or(""), from);
        if (!failure) solver_->revert_step();
        throw RunFailure(exit_method_failed, "fluid rank " + std::to_string(from) + ": " + why);
    }
    // Many ranks, after an output or a frame: the rows divided again when the busiest rank has more than
    // `threshold` times the mean cost. A row costs the cells it updates, weighted by its rank's measured
    // time per cell update since the last division (relative to the mean): cells near an interface or the
    // structure cost more than open water, the root also writes the output, and cores differ in speed.
    // No new division before a step was measured since the last (an output and a frame at the same time):
    // without measured times the weights would fall back to 1 and move the rows back.
    static constexpr double threshold = 1.05;
    void rebalance() {
        if (!ranks_ || solver_->steps() == steps_at_division_) return;
        const std::vector<double> speed = time_per_update();
        std::vector<double> cost = solver_->row_cost();
        for (double& c : cost)
            c *= speed[ranks_->rank()]; // rows of other ranks are 0 here
        ranks_->max(cost);
        const double before = ranks_->imbalance(cost);
        if (before <= threshold) return;
        solver_->share(); // a new division needs the whole state on every rank
        ranks_->divide(cost, solver_->halo());
        solver_->divide(ranks_);
        ++divisions_;
        steps_at_division_ = solver_->steps();
        std::string weights;
        for (size_t r = 0; r < speed.size() && r < 8; ++r)
            weights += format(r ? ", %.3f" : "%.3f", speed[r]);
        log_ << "undex-fluid: rows divided again at t = " << format("%.6g", solver_->time())
             << format(" s: busiest rank %.3f of the mean, now %.3f", before, ranks_->imbalance(cost))
             << " (time per cell update by rank, relative: " << weights << (speed.size() > 8 ? ", …" : "")
             << ")" << std::endl;
        start_measuring();
    }
    // Since the last division: when it was, this rank's waits and cell updates then.
    std::chrono::steady_clock::time_point divided_at_ = std::chrono::steady_clock::now();
    double waited_at_division_ = 0;
    long solved_at_division_ = 0, steps_at_division_ = -1;
    long solved() const { return solver_->cell_updates() - solver_->cell_updates_skipped(); }
    void start_measuring() {
        divided_at_ = std::chrono::steady_clock::now();
        const auto w = ranks_->waits();
        waited_at_division_ = std::accumulate(w.begin(), w.end(), 0.0);
        solved_at_division_ = solved();
    }
    // Every rank's wall time less its waits, per cell it updated, since the last division, over the mean of
    // the ranks (1 for a rank that updated none).
    std::vector<double> time_per_update() const {
        const auto w = ranks_->waits();
        const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - divided_at_;
        const double busy = wall.count() - (std::accumulate(w.begin(), w.end(), 0.0) - waited_at_division_);
        const long cells = solved() - solved_at_division_;
        const double none = -std::numeric_limits<double>::infinity();
        std::vector<double> t(ranks_->size(), none);
        if (cells > 0 && busy > 0) t[ranks_->rank()] = busy / cells;
        ranks_->max(t);
        double sum = 0;
        int n = 0;
        for (double x : t)
            if (x > none) sum += x, ++n;
        for (double& x : t)
            x = n > 0 && x > none ? x / (sum / n) : 1.0;
        return t;
    }
    bool at_step_end_ = true; // false from the structure's offer (the wet faces moved) to the step's end
    // The solver and the run's own records (the output's are Output::state).
    void state(State& s) {
        State solver = s.scope("solver");
        solver_->state(solver);
        s.io("next_frame", next_frame_);
        s.io("history", history_);
        s.io("work", work_);
        s.io("wet_rows", wet_rows_);
    }
    coupling::Offer offer_;
    // The structure's offer of the next step (on many ranks, relayed from the root).
    void receive_offer() {
        const std::vector<double> v = relay(ranks_, [&] {
            if (!timed(coupling_wall_, [&] { return (*link_)->receive_offer(offer_); }))
                throw RunFailure(exit_coupling_failed, "the structure solver stopped the run at step " +
                                                           std::to_string((*link_)->step()) + ": " +
                                                           (*link_)->stop_reason());
            if (!ranks_) return std::vector<double>{};
            std::vector<double> v = {offer_.dt};
            v.insert(v.end(), offer_.x.begin(), offer_.x.end());
            v.insert(v.end(), offer_.y.begin(), offer_.y.end());
            return v;
        });
        if (talks()) return;
        const long n = static_cast<long>(v.size() - 1) / 2;
        offer_.dt = v[0];
        offer_.x.assign(v.begin() + 1, v.begin() + 1 + n);
        offer_.y.assign(v.begin() + 1 + n, v.end());
    }
    double frame_interval_ = 0; // output.frame_interval (2D), 0: no frames
    int frame_stride_ = 1;      // cells per frame block along each axis
    double next_frame_ = 0;     // the time of the next frame
    double dt_ = 0;             // the step agreed with the structure
    double dt_f_ = 0;           // the fluid's own stable step Δt_f of the step being agreed
    double coupling_wall_ = 0;  // inside the coupling library: waiting for and exchanging with the structure
    double faces_wall_ = 0; // 2D: rebuilding the structure level set and the ghost bands (WetSolver::move)
    // Runs f, adding its wall time to `into`; returns what f returns.
    template <class F> static bool timed(double& into, F&& f) {
        const auto start = std::chrono::steady_clock::now();
        const bool r = f();
        into += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return r;
    }
    // t, dt, p_L, u_L, Z_L, p_I, u_I, displacement, dt_f, dt_s per step (dt_f the fluid's own stable step,
    // dt_s the structure's offer: the tests check dt = min(dt_f, dt_s) unless the step ends on an output
    // time).
    std::vector<double> history_;
    double work_ = 0; // 2D: Σ over steps and wet nodes of p_I u_I A Δt
    // 2D, at every fields output: t, node, face, x, y (end of the step), p_L, u_L, p_I, u_I, area per wet
    // node
    std::vector<double> wet_rows_;
    coupling::Grant last_grant_;
    coupling::Answer last_answer_;

    // Grants the step s with the fluid's characteristic state at the interface (the DG trace of the last
    // cell) and applies the structure's answer; dt_ becomes min(Δt_f, Δt_s), the step both sides take.
    void exchange(const Step& s) {
        if (link_->wet()) return exchange_2d(s);
        const Mesh& m = solver_->mesh();
        const double x_I = m.x_max;
        const Primitive w = solver_->evaluate(x_I, 0);
        const double a = solver_->sound_speed(x_I, 0);
        coupling::Grant g;
        g.time = solver_->time();
        g.p_floor = solver_->pressure_floor();
        g.output = s.output;
        g.checkpoint = s.checkpoint;
        g.p_L = {w.p};
        g.u_L = {w.u};
        g.Z_L = {w.rho * a};
        g.geometric = {geometric_term(m.alpha, s.dt, w.rho, a, w.u, x_I)};
        coupling::Answer ans;
        timed(coupling_wall_, [&] { return ans = (*link_)->exchange(s.dt, g), true; });
        dt_ = g.dt;
        solver_->set_structure_state(ans.p_I[0], ans.u_I[0]);
        history_.insert(history_.end(), {solver_->time(), dt_, w.p, w.u, g.Z_L[0], ans.p_I[0], ans.u_I[0],
                                         ans.x[0] - link_->x0_I(), dt_f_, offer_.dt});
    }
    // 2D: the fluid next to every wet node along its normal, the geometric term with r of the node (dropped
    // within one cell of the axis), and the structure's answer for the ghost bands; the history records the
    // step, both offers and the work Σ p_I u_I A Δt with the areas of the offered positions.
    void exchange_2d(const Step& s) {
        WetSolver& wet = *link_->wet();
        std::vector<WetSample> w;
        try {
            w = wet.sample();
        } catch (const SolverFailure& f) {
            throw RunFailure(exit_method_failed, f.what());
        }
        const Mesh& m = solver_->mesh();
        const WetFaces& faces = wet.faces();
        const size_t n = w.size();
        coupling::Grant g;
        g.time = solver_->time();
        g.p_floor = solver_->pressure_floor();
        g.output = s.output;
        g.checkpoint = s.checkpoint;
        g.p_L.resize(n), g.u_L.resize(n), g.Z_L.resize(n), g.geometric.resize(n);
        for (size_t k = 0; k < n; ++k) {
            g.p_L[k] = w[k].p;
            g.u_L[k] = w[k].u_n;
            g.Z_L[k] = w[k].rho * w[k].a;
            g.geometric[k] =
                geometric_term(m.alpha, s.dt, w[k].rho, w[k].a, w[k].u_x, faces.x(k), std::max(m.dx, m.dy));
        }
        // On many ranks the root grants and relays the step and the answer (the positions at the step's end
        // are the root's only: it writes them).
        coupling::Answer ans;
        const std::vector<double> v = relay(ranks_, [&] {
            timed(coupling_wall_, [&] { return ans = (*link_)->exchange(s.dt, g), true; });
            std::vector<double> v = {g.dt};
            if (!ranks_) return v;
            v.insert(v.end(), ans.p_I.begin(), ans.p_I.end());
            v.insert(v.end(), ans.u_I.begin(), ans.u_I.end());
            return v;
        });
        dt_ = v[0];
        if (!talks()) {
            ans.p_I.assign(v.begin() + 1, v.begin() + 1 + n);
            ans.u_I.assign(v.begin() + 1 + n, v.end());
        }
        wet.set_interface(ans.p_I, ans.u_I);
        double work = 0;
        for (size_t k = 0; k < n; ++k)
            work += ans.p_I[k] * ans.u_I[k] * faces.area(k) * dt_;
        work_ += work;
        history_.insert(history_.end(), {solver_->time(), dt_, dt_f_, offer_.dt, work, work_});
        last_grant_ = std::move(g);
        last_answer_ = ans;
    }
    void write_history() {
        if (link_ && link_->wet()) {
            out_->write_table("interface", {"t", "dt", "dt_f", "dt_s", "work", "total_work"}, history_);
            out_->write_table("wet_nodes",
                              {"t", "node", "face", "x", "y", "p_L", "u_L", "p_I", "u_I", "area"}, wet_rows_);
            return;
        }
        if (link_)
            out_->write_table("interface",
                              {"t", "dt", "p_L", "u_L", "Z_L", "p_I", "u_I", "displacement", "dt_f", "dt_s"},
                              history_);
    }
};

// Many ranks: what cannot run on them yet is refused before anything is written; the rows divided by the
// cells each updates in the initial data (RunPlan::checkpoint_seconds: none are written on many ranks).
void divide(const CaseFile& c, RunPlan& p, Ranks& ranks, FluidSolver& solver, bool coupled,
            const std::string& resume, std::ostream& log) {
    const std::string n = std::to_string(ranks.size()) + " ranks";
    if (!solver.divisible())
        c.fail("numerics.ranks", "the fluid runs on " + n + " only in 2D so far; run it on one");
    const double wait = c.get().numerics().rank_wait_seconds();
    if (coupled && wait > 0 && wait <= c.get().coupling().timeout())
        c.fail("numerics.rank_wait_seconds",
               format("%g s must exceed coupling.timeout (%g s): the ranks wait on rank 0 while it waits on "
                      "the structure",
                      wait, c.get().coupling().timeout()));
    if (!resume.empty())
        c.fail("numerics.ranks", "a run on " + n + " cannot be resumed from a checkpoint yet");
    for (const auto* b : {&c.get().boundaries().y_min(), &c.get().boundaries().y_max()})
        if (b->type() == config::Boundary::PERIODIC)
            c.fail("boundaries", "periodic y boundaries are not divided among ranks yet: run on one");
    try {
        ranks.divide(solver.row_cost(), solver.halo());
    } catch (const std::invalid_argument& e) {
        c.fail("numerics.ranks", e.what());
    }
    solver.divide(&ranks);
    if (p.checkpoint_seconds > 0)
        log << "undex-fluid: no checkpoints on " << n << " (output.checkpoint_seconds ignored)" << std::endl;
    p.checkpoint_seconds = 0;
    std::string rows;
    for (int r = 0; r < ranks.size(); ++r)
        rows += (r ? ", " : "") + std::to_string(ranks.end(r) - ranks.begin(r));
    log << "undex-fluid: " << n << ", rows per rank " << rows << std::endl;
}

} // namespace

int run(const CaseFile& c, std::ostream& root_log, const std::string& couple, const std::string& resume) {
    validate(c); // first: the plan's output times are counted there before they are made
    RunPlan p = plan(c);
    Ranks& ranks = Ranks::world();
    std::ostream quiet(nullptr); // the ranks but the root say nothing: the root speaks for all
    std::ostream& log = ranks.root() ? root_log : quiet;
    const bool coupled = coupled_case(c);
    const bool two_d =
        c.get().geometry() == config::PLANAR_2D || c.get().geometry() == config::AXISYMMETRIC_2D;
    const char* where = two_d ? "structure" : "boundaries.x_max";
    if (coupled && couple.empty())
        c.fail(where, "the case couples the fluid to a structure: run it with `undex run`, or give "
                      "undex-fluid --couple ENDPOINT and start a structure solver on it");
    if (!coupled && !couple.empty())
        c.fail(where, two_d ? "--couple needs a structure in the case"
                            : "--couple needs a structure in the case (x_max: STRUCTURE)");
#ifdef _OPENMP
    if (p.threads > 0) omp_set_num_threads(p.threads);
    const int threads = omp_get_max_threads();
#else
    const int threads = 1;
#endif
    auto solver = make_solver(c); // may throw SolverFailure for inadmissible initial data
    const Mesh& m = solver->mesh();
    if (ranks.many()) divide(c, p, ranks, *solver, coupled, resume, log);
    log << "undex-fluid: " << c.path() << ": " << m.dim << "D, " << m.nx;
    if (m.dim == 2) log << " x " << m.ny;
    log << " cells, degree " << solver->degree() << ", ";
    if (ranks.many()) log << ranks.size() << " ranks × ";
    log << threads << " thread(s), end time " << p.end_time << " s, output " << p.directory << "/fluid.h5"
        << std::endl;
    std::optional<State> from;
    coupling::Start start;
    if (!resume.empty()) {
        from.emplace(State::open(resume, "fluid"));
        start.step = from->step(), start.time = from->time();
        log << "undex-fluid: resuming from " << resume << " (step " << start.step
            << ", t = " << format("%.9g", start.time) << " s)" << std::endl;
    }
    auto link = coupled ? std::make_unique<StructureLink>(p, couple, *solver, log, start,
                                                          ranks.many() ? &ranks : nullptr)
                        : nullptr;
    // From here on (the handshake waits up to coupling.handshake_timeout on the structure, and the root
    // relays its end to every rank).
    if (ranks.many()) ranks.watch(c.get().numerics().rank_wait_seconds(), &stop_requested);
    FluidRun r(c, p, std::move(solver), std::move(link), from ? &*from : nullptr,
               ranks.many() ? &ranks : nullptr, log);
    const int status = drive(r, p, "undex-fluid", log);
    // The root's status is the run's: mpirun ends every rank as soon as one exits with another than 0, and
    // the root may still be writing the last good state.
    return ranks.root() ? status : 0;
}

} // namespace undex::fluid
