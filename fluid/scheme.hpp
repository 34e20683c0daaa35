// RKDG scheme for one dimension D, degree K and equation of state Eos (physics.md §1, §3): HLLC fluxes,
// geometric source, TVD-RK3 (Shu–Osher), and after every stage the troubled-cell indicator, the simple
// WENO limiter in characteristic variables and the Zhang–Shu positivity scaling.
#pragma once
#ifdef _OPENMP
#include <omp.h>
#endif
#include "fluid/basis.hpp"
#include "fluid/boundary.hpp"
#include "fluid/characteristic.hpp"
#include "fluid/eos.hpp"
#include "fluid/euler.hpp"
#include "fluid/flux_hllc.hpp"
#include "fluid/indicator_tvb.hpp"
#include "fluid/limiter_weno.hpp"
#include "fluid/ranks.hpp"
#include "fluid/solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

namespace undex::fluid {

// A step in phases (Scheme::begin_step, phase, exchanges_after, end_step; TwoFluid's and WetFluid's alike):
// the phases of S, each followed by one exchange among the ranks of all that it leaves (none on one rank);
// end_step throws the step's SolverFailure. Each phase comes in two parts: part 0 computes the rows that
// the exchange sends (near the block's edges), part 1 the rows between while the messages travel, so that
// a rank waits only for the neighbours' edge rows, not for the slower rank's whole phase (the phases are
// unbalanced in both directions: one rank's rows hold more cells to update, the other's more to limit).
inline constexpr int step_phases = 6;
template <class S> void step_phased(S& s, const Ranks* ranks, double dt) {
    s.begin_step(dt);
    std::vector<Ranks::Rows> x;
    for (int k = 0; k < step_phases; ++k) {
        s.phase(k, 0);
        x.clear();
        s.exchanges_after(k, x);
        if (ranks) ranks->post(x);
        s.phase(k, 1);
        if (ranks) ranks->complete();
    }
    s.end_step();
}

template <int D, int K, EquationOfState Eos> class Scheme final : public FluidSolver {
  public:
    using B = Basis<D, K>;
    static constexpr int NB = B::NB, NV = D + 2, NC = NV * NB, NQV = B::NQV, NQF = B::NQF;
    static constexpr int E = NV - 1;

    Scheme(const Mesh& mesh, const Eos& eos, const Settings& s, const std::array<Boundary, 4>& bc)
        : mesh_(mesh), eos_(eos), lane_eos_(eos), set_(s), bc_(bc) {
        const long n = static_cast<long>(mesh_.padded_cells()) * NC;
        u_.assign(n, 0.0);
        u0_.assign(n, 0.0);
        stage_.assign(n, 0.0);
        rhs_.assign(n, 0.0);
        troubled_flag_.assign(mesh_.padded_cells(), 0);
        if (s.skip_rest) set_rest(s.rest);
        active_changed();
        const double gx = 2.0 / mesh_.dx, gy = 2.0 / mesh_.dy;
        for (int l = 0; l < NB; ++l) {
            for (int q = 0; q < NQV; ++q) {
                vol_.phi[l][q] = tab_.phiv[q][l];
                vol_.wdx[l][q] = tab_.wv[q] * gx * tab_.dxiv[q][l];
                vol_.wdy[l][q] = tab_.wv[q] * gy * tab_.detav[q][l];
                points_[l][q] = tab_.phiv[q][l];
            }
            for (int dir = 0, k = NQV; dir < D; ++dir)
                for (int side = 0; side < 2; ++side)
                    for (int g = 0; g < NQF; ++g)
                        points_[l][k++] = tab_.face[dir][side][g][l];
            point_max_[l] = 0.0;
            for (int k = 0; k < NP; ++k)
                point_max_[l] = std::max(point_max_[l], std::abs(points_[l][k]));
        }
    }

    const Mesh& mesh() const override { return mesh_; }
    int degree() const override { return K; }
    int variables() const override { return NV; }
    int basis_functions() const override { return NB; }
    double time() const override { return time_; }
    long steps() const override { return steps_; }
    long troubled_cells() const override { return troubled_; }
    long positivity_scaled_cells() const override { return scaled_; }
    long cell_updates() const override { return updates_; }
    long cell_updates_skipped() const override { return skipped_; }
    bool has_cavitation() const override { return eos_.has_cavitation(); }
    double void_fraction(double p) const override { return eos_.void_fraction(p); }

    // Initial data: L2 projection of a pointwise conserved state onto the basis, by quadrature.
    void project(const std::function<void(double, double, double*)>& conserved_at) override {
        // Six Gauss points per direction: exact for the polynomials and resolves initial jumps better.
        constexpr int NP = 6;
        const double gp[NP] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                               0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
        const double wp[NP] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                               0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
        check_all_ = true;
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i) {
                double* c = cell(u_.data(), i, j);
                std::fill(c, c + NC, 0.0);
                constexpr int NPY = D == 1 ? 1 : NP;
                double T[NP][NPY][NC]; // the quadrature terms
                for (int a = 0; a < NP; ++a)
                    for (int b = 0; b < NPY; ++b) {
                        const double xi = gp[a], eta = D == 1 ? 0.0 : gp[b];
                        const double wq = D == 1 ? wp[a] / 2 : wp[a] * wp[b] / 4;
                        double q[NV];
                        conserved_at(mesh_.xc(i) + 0.5 * mesh_.dx * xi, mesh_.yc(j) + 0.5 * mesh_.dy * eta,
                                     q);
                        for (int v = 0; v < NV; ++v)
                            for (int l = 0; l < NB; ++l)
                                T[a][b][v * NB + l] = wq * q[v] * B::phi(l, xi, eta) / B::norm(l);
                    }
                if constexpr (D == 1) {
                    for (int k = 0; k < NC; ++k)
                        for (int a = 0; a < NP / 2; ++a)
                            c[k] += T[a][0][k] + T[NP - 1 - a][0][k];
                } else {
                    // Summed by orbits of the square's symmetries, each in pairs (see Basis::mode_sum), so
                    // that mirror-image cells of symmetric data round alike. ā = NP − 1 − a.
                    for (int k = 0; k < NC; ++k)
                        for (int a = 0; a < NP / 2; ++a)
                            for (int b = a; b < NP / 2; ++b) {
                                auto quad = [&](int x, int y) {
                                    const int xb = NP - 1 - x, yb = NP - 1 - y;
                                    return (T[x][y][k] + T[xb][yb][k]) + (T[xb][y][k] + T[x][yb][k]);
                                };
                                c[k] += a == b ? quad(a, a) : quad(a, b) + quad(b, a);
                            }
                }
            }
        wake(); // before the limiter, which solves awake cells only
        limit(u_, 0.0, "initial data");
        capture_layers();
    }

    double stable_dt() const override {
        double inv = 0.0;
#pragma omp parallel for reduction(max : inv) schedule(static) if (D == 2)
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = lo_[j]; i < hi_[j]; ++i) {
                if (!active(i, j)) continue;
                const double* c = cell(u_.data(), i, j);
                double q[NV];
                for (int v = 0; v < NV; ++v)
                    q[v] = c[v * NB];
                const Primitive w = primitive(q);
                const double a = eos_.sound_speed(w.rho, w.p);
                double r = (std::abs(w.u) + a) / mesh_.dx;
                if (D == 2) r = std::max(r, (std::abs(w.v) + a) / mesh_.dy);
                inv = std::max(inv, r);
            }
        if (asleep_ > 0) inv = std::max(inv, rest_rate_); // the still water's own (|u| + a)/Δx
        return std::min(set_.cfl / inv, 1.0 / sigma_max_); // σΔt ≤ 1 in the absorbing layers
    }

    void step(double dt) override {
        step_phased(*this, ranks_, dt);
    }
    // The step in phases (step_phased), so that schemes stepped together (the fluids of TwoFluid and of
    // every wet face) share each phase's exchange among the ranks: each rank then waits once per phase for
    // the work of all its schemes, instead of once per scheme for that scheme's share of its rows.
    // Phases: the three stages' updates and limiters; the last also copies the step's result.
    void begin_step(double dt) {
        // u0 = stage = u over the cells the step can read or write (copy_spans); cells farther out keep
        // their values in u through the stages. Over the whole mesh the copies took 15 % of a two-fluid step
        // with most of the water asleep (perf, the application at 0.01 m, one thread).
        wake();
        updates_ += solved_ + asleep_;
        skipped_ += asleep_;
        copy_spans();
        copy_region(u0_, u_, &stage_);
        troubled_ = 0;
        scaled_ = 0;
        dt_ = dt;
        failure_.reset();
    }
    // On many ranks (divide) each stage's result is exchanged with the neighbours' blocks before the
    // limiter and the next stage read it, as deep as they read (stage_depth); a rank that meets a state it
    // cannot hold does no more work in the step but still takes part in every exchange, so that its
    // neighbours finish the step too. Part 0 of a phase computes the rows the exchange sends, part 1 the
    // others (part_rows); the rows received are neither read nor written in part 1.
    void phase(int k, int part) {
        auto work = [&](auto&& f) {
            if (failure_) return;
            try {
                f();
            } catch (const SolverFailure& e) {
                failure_ = e;
            }
        };
        const double dt = dt_;
        switch (k) {
        case 0: // stage 1: U1 = U + dt L(U)
            return work([&] { stage_update(u_, time_, {stage_, 1.0, u0_, 0.0, dt}, part); });
        case 1:
            return work([&] { limit(stage_, time_ + dt, "stage 1", part); });
        case 2: // stage 2: U2 = 3/4 U + 1/4 (U1 + dt L(U1))
            return work([&] { stage_update(stage_, time_ + dt, {u_, 0.75, u0_, 0.25, 0.25 * dt}, part); });
        case 3:
            return work([&] { limit(u_, time_ + 0.5 * dt, "stage 2", part); });
        case 4: // stage 3: U = 1/3 U + 2/3 (U2 + dt L(U2))
            return work([&] {
                stage_update(u_, time_ + 0.5 * dt, {stage_, 1.0 / 3.0, u0_, 2.0 / 3.0, 2.0 / 3.0 * dt}, part);
            });
        default:
            work([&] { limit(stage_, time_ + dt, "stage 3", part); });
            // the step's result (after a failure end_step restores its start, once the exchange is over)
            if (!failure_) copy_region(u_, stage_, nullptr, part);
        }
    }
    // The rows of part `part` of a phase, as two ranges [r[0], r[1]) and [r[2], r[3]). Part 0: the rows
    // within stage_depth() + inner of the block's edges (every row on one rank, or in a block too thin to
    // divide); part 1: the rows between. `inner` widens part 0 into the block (the limiter's: a row's
    // neighbours are limited before its own limited values replace the old).
    std::array<int, 4> part_rows(int part, int inner) const {
        const int b0 = row_begin(), b1 = row_end(), d = stage_depth() + inner;
        const bool split = ranks_ && b1 - b0 > 2 * (stage_depth() + 1) + 2;
        if (!split) return part == 0 ? std::array<int, 4>{b0, b1, b1, b1} : std::array<int, 4>{b1, b1, b1, b1};
        if (part == 0) return {b0, b0 + d, b1 - d, b1};
        return {b0 + d, b1 - d, b1 - d, b1 - d};
    }
    // Lets the messages of the phase's exchange advance (Ranks::progress) during its part 1: on the thread
    // that posted them only (MPI_THREAD_FUNNELED).
    void progress() const {
        if (!ranks_) return;
#ifdef _OPENMP
        if (omp_get_thread_num() != 0) return;
#endif
        ranks_->progress();
    }
    static std::vector<int> rows_in(const std::array<int, 4>& r) {
        std::vector<int> rows;
        for (int j = r[0]; j < r[1]; ++j)
            rows.push_back(j);
        for (int j = r[2]; j < r[3]; ++j)
            rows.push_back(j);
        return rows;
    }
    // What phase k leaves for the neighbours.
    void exchanges_after(int k, std::vector<Ranks::Rows>& x) {
        if (!ranks_) return;
        std::vector<double>& U = k == 0 || k == 1 || k == 4 ? stage_ : u_;
        x.push_back({U.data(), row_doubles(), stage_depth()});
    }
    void end_step() {
        if (failure_) {
            copy_region(u_, u0_); // the step's start again
            std::ostringstream s;
            s << failure_->what() << " in step " << steps_ + 1 << " from t = " << time_
              << " s with dt = " << dt_ << " s";
            throw SolverFailure(s.str());
        }
        time_ += dt_;
        ++steps_;
        last_dt_ = dt_;
    }

    // Still water (Settings::skip_rest): wakes the cells a disturbance can reach within a step (below).
    // Called by step() and project(), and by whoever writes cells between steps before the first one.
    void wake_cells() {
        wake();
    }

    // Takes back the last step (used when the other fluid of a two-fluid step fails, or another rank's).
    void revert_step() override {
        copy_region(u_, u0_);
        time_ -= last_dt_;
        --steps_;
    }

    // Cells outside the mask (padded-cell flags, see Mesh::index) are skipped: no flux, limiting or time-step
    // restriction, and their values stay as set. Null: every cell is active. Two-fluid runs use it to solve
    // each fluid only in its real region and its ghost band.
    void set_active(const std::vector<char>* mask) {
        active_ = mask;
        active_changed();
    }
    // To be called whenever the mask's contents change: loops run over each row's span of active cells.
    void active_changed() { active_changed(0, mesh_.ny - 1); }
    // The same when the mask (or the awake cells) changed in rows j0 … j1 only.
    void active_changed(int j0, int j1) {
        const int nx = mesh_.nx, ny = mesh_.ny;
        if (static_cast<int>(row_solved_.size()) != ny || static_cast<int>(lo_.size()) != ny) {
            lo_.assign(ny, 0), hi_.assign(ny, 0), row_solved_.assign(ny, 0), row_asleep_.assign(ny, 0);
            j0 = 0, j1 = ny - 1;
        }
        j0 = std::max(0, j0), j1 = std::min(ny - 1, j1);
#pragma omp parallel for schedule(static) if (D == 2)
        for (int j = j0; j <= j1; ++j) {
            int lo = nx, hi = 0, solved = 0, asleep = 0;
            const int n = j >= row_begin() && j < row_end() ? nx : 0; // another rank's row: none here
            for (int i = 0; i < n; ++i) {
                const long k = mesh_.index(i, j);
                if (active_ && !(*active_)[k]) continue;
                if (skip_ && !awake_[k]) {
                    ++asleep;
                    continue;
                }
                ++solved;
                lo = std::min(lo, i), hi = i + 1;
            }
            lo_[j] = hi > lo ? lo : 0, hi_[j] = hi > lo ? hi : 0;
            row_solved_[j] = solved, row_asleep_[j] = asleep;
        }
        solved_ = asleep_ = 0;
        for (int j = 0; j < ny; ++j)
            solved_ += row_solved_[j], asleep_ += row_asleep_[j];
    }

    // Many ranks (fluid/ranks.hpp): from now on this rank solves the rows of its block of r; the state must
    // be current in every row (as after project() or share()). Null: all rows.
    bool divisible() const override { return D == 2; }
    void divide(const Ranks* r) override {
        ranks_ = r && r->many() ? r : nullptr;
        active_changed();
        check_all_ = true; // rows newly in reach of the still-water test are read afresh
    }
    // The rows a rank needs beyond its block, and so the fewest rows of a block: a stage's (stage_depth),
    // and with still water the neighbours' marks of the test that wakes cells (wake: reach() + 1 rows) and
    // one more.
    int halo() const override { return std::max(stage_depth(), skip_ ? reach() + 2 : 1); }
    // The rows a stage reads beyond the block: one through a face or the limiter's neighbours, and the
    // fluid that the stage ghosts in that row read (set_stage_ghosts).
    int stage_depth() const { return 1 + ghost_reach_; }
    // The rows whose domain ghost cells a stage fills: [ghost_rows(0), ghost_rows(1)), all on one rank.
    int ghost_rows(int end) const {
        if (!ranks_) return end ? mesh_.ny : 0;
        return end ? row_end() + stage_depth() : row_begin() - stage_depth();
    }
    // The whole state on every rank (before an output or a new division).
    void share() override {
        if (!ranks_) return;
        ranks_->share(u_.data(), row_doubles());
        if (skip_) ranks_->share(awake_.data(), mesh_.padded_nx());
        check_all_ = true;
    }
    // The cells each row of this rank's block updates (others 0): what a division balances.
    std::vector<double> row_cost() const override {
        std::vector<double> c(mesh_.ny, 0.0);
        for (int j = row_begin(); j < row_end(); ++j)
            c[j] = row_solved_[j] + 1.0; // + 1: a row costs a little even with every cell asleep
        return c;
    }

    // Sets cell (i, j) to the constant polynomial of a primitive state.
    void set_cell_state(int i, int j, const Primitive& w) {
        set_state_in(u_.data(), i, j, w);
    }

    // Cells that a coupling sets at every stage, as the domain's ghost cells are (the structure's ghost band,
    // fluid/wet_fluid.hpp): f(U) is called with the coefficients of the stage after the domain's ghost cells
    // are filled and before the fluxes and the limiter read them; it must write inactive cells only.
    // `reach`: the farthest a ghost value reads the fluid, in cells (it sets how far a disturbance can travel
    // in one step, Scheme::wake).
    void set_stage_ghosts(std::function<void(double*)> f, int reach) {
        stage_ghosts_ = std::move(f);
        ghost_reach_ = reach;
    }
    // This scheme as the one scheme of its fluid (TwoFluid has two), for code written for one or two fluids.
    template <class F> void for_each_scheme(F&& f) {
        f(*this);
    }
    template <class F> decltype(auto) scheme_at(int, int, F&& f) const {
        return f(*this);
    }
    // The cell-average state of cell (i, j) of stage coefficients U, and a constant state written there.
    Primitive average_in(const double* U, int i, int j) const {
        return euler::to_primitive<D>(eos_, euler::Strided<const double>{cell(U, i, j), NB});
    }
    void set_state_in(double* U, int i, int j, const Primitive& w) const {
        if (skip_ && U == u_.data()) written_[mesh_.index(i, j)] = 1;
        double* c = cell(U, i, j);
        std::fill(c, c + NC, 0.0);
        euler::to_conserved<D>(eos_, w, euler::Strided<double>{c, NB});
    }

    const Eos& eos() const {
        return eos_;
    }

    void state(State& s) override {
        check_all_ = true; // after loading, whatever was written
        s.io("u", u_);
        s.io("time", time_);
        s.io("last_dt", last_dt_);
        s.io("steps", steps_);
        s.io("troubled_flag", troubled_flag_);
        s.io("troubled", troubled_);
        s.io("scaled", scaled_);
        s.io("lo", lo_);
        s.io("hi", hi_);
        s.io("awake", awake_);
        s.io("all_awake", all_awake_);
        s.io("solved", solved_);
        s.io("asleep", asleep_);
        s.io("updates", updates_);
        s.io("skipped", skipped_);
        for (int k = 0; k < 4; ++k) { // the structure's interface state of a STRUCTURE side
            s.io("bc" + std::to_string(k) + ".p_I", bc_[k].p_I);
            s.io("bc" + std::to_string(k) + ".u_I", bc_[k].u_I);
        }
        s.io("layer_cell", layer_cell_);
        if (s.loading()) {
            layer_of_.assign(mesh_.padded_cells(), -1);
            for (size_t k = 0; k < layer_cell_.size(); ++k)
                layer_of_[layer_cell_[k]] = static_cast<int>(k);
        }
        s.io("layer_sigma", layer_sigma_);
        s.io("layer_ref", layer_ref_);
        s.io("sigma_max", sigma_max_);
    }

    std::vector<double> coefficients() const override {
        std::vector<double> out(static_cast<long>(mesh_.nx) * mesh_.ny * NC);
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i) {
                const double* c = cell(u_.data(), i, j);
                std::copy(c, c + NC, out.begin() + (static_cast<long>(j) * mesh_.nx + i) * NC);
            }
        return out;
    }

    void set_coefficients(const std::vector<double>& in, double time) override {
        if (in.size() != static_cast<size_t>(mesh_.nx) * mesh_.ny * NC)
            throw std::runtime_error("coefficient array does not match the mesh and degree");
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i)
                std::copy_n(in.begin() + (static_cast<long>(j) * mesh_.nx + i) * NC, NC,
                            cell(u_.data(), i, j));
        time_ = time;
        check_all_ = true;
    }

    Primitive evaluate(double x, double y) const override {
        int i = static_cast<int>(std::floor((x - mesh_.x_min) / mesh_.dx));
        int j = D == 2 ? static_cast<int>(std::floor((y - mesh_.y_min) / mesh_.dy)) : 0;
        i = std::clamp(i, 0, mesh_.nx - 1);
        j = std::clamp(j, 0, mesh_.ny - 1);
        return evaluate_in(i, j, x, y);
    }

    // The polynomial of interior cell (i, j) at the point of the cell nearest to (x, y).
    Primitive evaluate_in(int i, int j, double x, double y) const {
        const double xi = std::clamp(2.0 * (x - mesh_.xc(i)) / mesh_.dx, -1.0, 1.0);
        const double eta = D == 2 ? std::clamp(2.0 * (y - mesh_.yc(j)) / mesh_.dy, -1.0, 1.0) : 0.0;
        const double* c = cell(u_.data(), i, j);
        double q[NV];
        for (int v = 0; v < NV; ++v) {
            double t[NB];
            for (int l = 0; l < NB; ++l)
                t[l] = c[v * NB + l] * B::phi(l, xi, eta);
            q[v] = B::mode_sum(t);
        }
        return primitive(q);
    }

    double sound_speed(double x, double y) const override {
        const Primitive w = evaluate(x, y);
        return eos_.sound_speed(w.rho, w.p);
    }

    double pressure_floor() const override {
        return eos_.pressure_floor();
    }

    void set_structure_state(double p_I, double u_I) override {
        for (auto& b : bc_)
            if (b.type == BoundaryType::Structure) b.p_I = p_I, b.u_I = u_I;
    }

    Primitive cell_average(int i, int j) const override {
        const double* c = cell(u_.data(), i, j);
        double q[NV];
        for (int v = 0; v < NV; ++v)
            q[v] = c[v * NB];
        return primitive(q);
    }

    std::vector<double> row_totals(int j0, int j1) const override {
        std::vector<double> t(static_cast<size_t>(NV) * (j1 - j0), 0.0);
        const double vol = mesh_.dx * (D == 2 ? mesh_.dy : 1.0);
        for (int j = j0; j < j1; ++j)
            for (int i = 0; i < mesh_.nx; ++i)
                for (int v = 0; v < NV; ++v)
                    t[NV * (j - j0) + v] += cell(u_.data(), i, j)[v * NB] * vol;
        return t;
    }

  private:
    Mesh mesh_;
    Eos eos_;
    typename LaneForm<Eos>::type lane_eos_; // of the SIMD lanes (faces_flux, cells_rhs)
    Settings set_;
    std::array<Boundary, 4> bc_;
    BasisTables<D, K> tab_;
    WenoTables<D, K> weno_;
    // Point-major copies of the tables for the vectorised loops: φ_l and the weighted, scaled derivatives
    // w_q (2/Δx) ∂φ_l/∂ξ, w_q (2/Δy) ∂φ_l/∂η at the volume points.
    struct {
        double phi[NB][NQV], wdx[NB][NQV], wdy[NB][NQV];
    } vol_;
    // φ_l at every volume and face quadrature point: the points where positivity is enforced.
    static constexpr int NP = NQV + 2 * D * NQF;
    double points_[NB][NP];
    double point_max_[NB]; // max over the points of |φ_l|
    std::vector<double> u_, u0_, stage_, rhs_;
    const Ranks* ranks_ = nullptr; // many ranks: this rank solves the rows of its block only (divide)
    int row_begin() const { return ranks_ ? ranks_->begin() : 0; }
    int row_end() const { return ranks_ ? ranks_->end() : mesh_.ny; }
    long row_doubles() const { return static_cast<long>(mesh_.padded_nx()) * NC; }
    // The first and last `depth` rows of this rank's block of U to the neighbours, theirs into the rows
    // beyond it.
    void exchange(std::vector<double>& U, int depth) {
        if (ranks_) ranks_->exchange(U.data(), row_doubles(), depth);
    }
    std::vector<std::vector<double>> band_faces_; // per thread: the face fluxes of its band (compute_rhs)
    std::vector<char> troubled_flag_;
    double time_ = 0.0, last_dt_ = 0.0;
    double dt_ = 0.0;                        // of the step under way (begin_step)
    std::optional<SolverFailure> failure_; // of the step under way
    long steps_ = 0;
    const std::vector<char>* active_ = nullptr;
    std::vector<int> lo_, hi_;                // per row: the active cells lie in [lo, hi)
    std::vector<int> row_solved_, row_asleep_; // per row: its share of solved_ and asleep_
    std::function<void(double*)> stage_ghosts_;

    // Absorbing layers (BoundaryType::Absorbing): per layer cell, its padded index, relaxation rate σ and
    // reference coefficients (the initial data).
    std::vector<long> layer_cell_;
    std::vector<int> layer_of_; // per padded cell: its index among the layer cells, −1 outside the layers
    std::vector<double> layer_sigma_, layer_ref_;
    double sigma_max_ = 0.0;

    // σ of every cell inside a layer, summed over the sides (corners take both), from the initial data.
    void capture_layers() {
        layer_cell_.clear(), layer_sigma_.clear(), layer_ref_.clear();
        layer_of_.assign(mesh_.padded_cells(), -1);
        sigma_max_ = 0.0;
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i) {
                double shape = 0.0; // Σ strength (d/L)² / L over the sides whose layer holds the cell
                for (int side = 0; side < 2 * D; ++side) {
                    const Boundary& b = bc_[side];
                    if (b.type != BoundaryType::Absorbing || b.layer_cells <= 0) continue;
                    const int n = side / 2 == 0 ? mesh_.nx : mesh_.ny, k = side / 2 == 0 ? i : j;
                    const double depth = side % 2 ? k + 0.5 - (n - b.layer_cells) : b.layer_cells - k - 0.5;
                    if (depth <= 0) continue;
                    const double L = b.layer_cells * (side / 2 == 0 ? mesh_.dx : mesh_.dy);
                    const double r = depth / b.layer_cells;
                    shape += b.strength * r * r / L;
                }
                if (shape == 0.0) continue;
                const double* c = cell(u_.data(), i, j);
                double q[NV];
                for (int v = 0; v < NV; ++v)
                    q[v] = c[v * NB];
                const Primitive w = primitive(q);
                const double sigma = shape * eos_.sound_speed(w.rho, w.p);
                layer_cell_.push_back(mesh_.index(i, j));
                layer_sigma_.push_back(sigma);
                layer_ref_.insert(layer_ref_.end(), c, c + NC);
                sigma_max_ = std::max(sigma_max_, sigma);
            }
        for (size_t k = 0; k < layer_cell_.size(); ++k)
            layer_of_[layer_cell_[k]] = static_cast<int>(k);
    }

    bool active(int i, int j) const {
        const long k = mesh_.index(i, j);
        return (!active_ || (*active_)[k]) && (!skip_ || awake_[k]);
    }

    // Still water (Settings::skip_rest). A cell sleeps (is not updated) while every cell within reach() of it
    // holds the rest state to 1e-14 relative: one step can carry a disturbance no farther (per stage, one
    // cell through the face fluxes and one through the limiter's neighbours, plus what a ghost band reads).
    // A cell that wakes stays awake.
    bool skip_ = false, all_awake_ = false;
    double rest_[NC] = {}, rest_tol_[NV] = {}, rest_rate_ = 0;
    std::vector<char> awake_, near_; // awake_: padded cells; near_: work array of wake()
    // Cells not awake change only by what others write (wake): written_ (padded cells) marks those written
    // into u by set_state_in since the last wake, check_all_ new data everywhere; per row, the cells not
    // awake lie in [sleep_lo_, sleep_hi_).
    mutable std::vector<char> written_;
    bool check_all_ = true;
    std::vector<int> sleep_lo_, sleep_hi_;
    void sleep_span(int j) {
        const char* a = awake_.data() + mesh_.index(0, j);
        int lo = mesh_.nx, hi = 0;
        for (int i = 0; i < mesh_.nx; ++i)
            if (!a[i]) lo = std::min(lo, i), hi = i + 1;
        sleep_lo_[j] = hi > lo ? lo : 0, sleep_hi_[j] = hi > lo ? hi : 0;
    }
    int woken_rows_[2] = {0, -1};    // work of wake(): the first and last row with a cell woken
    long solved_ = 0, asleep_ = 0;   // cells solved and cells asleep in the fluid's region (active_)
    long updates_ = 0, skipped_ = 0; // Σ over steps
    int ghost_reach_ = 0;
    int reach() const { return 3 * (2 + ghost_reach_); }

    void set_rest(const Primitive& w) {
        skip_ = true;
        euler::to_conserved<D>(eos_, w, euler::Strided<double>{rest_, NB});
        const double a = eos_.sound_speed(w.rho, w.p);
        const double scale[3] = {w.rho, w.rho * a, std::max(std::abs(rest_[E * NB]), w.rho * a * a)};
        for (int v = 0; v < NV; ++v)
            rest_tol_[v] = 1e-14 * scale[v == 0 ? 0 : v == E ? 2 : 1];
        rest_rate_ = a / mesh_.dx;
        if (D == 2) rest_rate_ = std::max(rest_rate_, a / mesh_.dy);
        awake_.assign(mesh_.padded_cells(), 0);
        written_.assign(mesh_.padded_cells(), 0);
        check_all_ = true;
    }
    // Whether cell (i, j) may change within a step even if all around it is at rest: it is not at rest, or
    // it lies on a side whose ghost cells hold data from outside (pressure, incident wave, 1D structure,
    // periodic partner).
    bool disturbed(int i, int j) const {
        auto outside = [&](int side) {
            const BoundaryType t = bc_[side].type;
            return t == BoundaryType::Pressure || t == BoundaryType::Incident || t == BoundaryType::Structure ||
                   t == BoundaryType::Periodic;
        };
        if ((i == 0 && outside(0)) || (i == mesh_.nx - 1 && outside(1))) return true;
        if (D == 2 && ((j == 0 && outside(2)) || (j == mesh_.ny - 1 && outside(3)))) return true;
        // All NC coefficients compared without an early exit, so that the loop vectorises (most cells
        // checked are at rest).
        const double* c = cell(u_.data(), i, j);
        bool off = false;
        for (int k = 0; k < NC; ++k)
            off |= !(std::abs(c[k] - rest_[k]) <= rest_tol_[k / NB]); // NaN too
        return off;
    }
    // Wakes every cell within reach() (a square) of a disturbed cell: at the start of a step, after whatever
    // set the step's data (the interface treatment, the structure's answer) and before a stage reads a cell.
    void wake() {
        if (!skip_ || all_awake_) return;
        if (stage_ghosts_) stage_ghosts_(u_.data()); // the band as stage 1 will see it
        const int nx = mesh_.nx, ny = mesh_.ny, R = reach();
        near_.resize(static_cast<long>(nx) * (ny + 2)); // row j at j + 1, as exchange() has them
        auto marks = [&](int j) { return near_.data() + static_cast<long>(j + 1) * nx; };
        if (check_all_ || static_cast<int>(sleep_lo_.size()) != ny) {
            sleep_lo_.assign(ny, 0), sleep_hi_.assign(ny, 0);
            for (int j = 0; j < ny; ++j)
                sleep_span(j);
        }
        // Only a cell within R (a square) of a cell not awake can wake one: per row, the columns within R
        // of the cells not awake in the rows within R. There, a cell not awake is read only if something
        // other than its own update may have changed it (it is not updated): written since the last wake
        // (set_state_in into u, marked in written_), in the last step's copy spans, or all after new data.
        // On many ranks each rank marks the rows of its block [b0, b1) and receives the neighbours' marks of
        // the R + 1 rows beyond: their owners read those rows as one rank would, and a row of marks is a byte
        // per cell where the coefficients are NC doubles. The spans of cells not awake in rows of other
        // ranks are those of the last division (share) or later: cells only wake, so they hold every cell
        // not awake there. It then wakes the cells of its block and of the row beyond each edge (a face flux
        // there asks whether the cell across is awake): the rows [wa, wb).
        const int b0 = row_begin(), b1 = row_end();
        const int wa = ranks_ ? std::max(0, b0 - 1) : 0, wb = ranks_ ? std::min(ny, b1 + 1) : ny;
        std::vector<int> from(ny), to(ny);
        for (int j = b0; j < b1; ++j) {
            int a = nx, b = 0;
            for (int r = std::max(0, j - R); r <= std::min(ny - 1, j + R); ++r)
                if (sleep_hi_[r] > sleep_lo_[r]) a = std::min(a, sleep_lo_[r]), b = std::max(b, sleep_hi_[r]);
            from[j] = std::max(0, a - R), to[j] = std::min(nx, b + R);
        }
        // Along x: marks = 1 within R cells of a disturbed cell of the row.
#pragma omp parallel for schedule(static) if (D == 2)
        for (int j = b0; j < b1; ++j) {
            char* h = marks(j);
            std::fill(h, h + nx, 0);
            const int a = from[j], b = to[j];
            if (b <= a) continue;
            const int r = D == 2 ? j + 1 : 0;
            const int c0 = copy_lo_.empty() ? 0 : copy_lo_[r], c1 = copy_lo_.empty() ? 0 : copy_hi_[r];
            int last = -2 * R - 2;
            for (int i = a; i < b; ++i) {
                const long k = mesh_.index(i, j);
                const bool read = check_all_ || awake_[k] || written_[k] || (i >= c0 && i < c1);
                written_[k] = 0;
                h[i] = read && disturbed(i, j);
                if (h[i]) last = i;
                h[i] |= i - last <= R ? 2 : 0;
            }
            int next = nx + 2 * R + 2;
            for (int i = b - 1; i >= a; --i) {
                if (h[i] & 1) next = i;
                h[i] = (h[i] & 2) || next - i <= R;
            }
        }
        check_all_ = false;
        if (ranks_) ranks_->exchange(near_.data(), nx, R + 1);
        // Along y: a cell wakes if a row within R of its own is marked, counted per column over a window of
        // rows that slides along each thread's block of rows (one pass over the marks, not 2R + 1).
        const int ma = std::max(0, wa - R), mb = std::min(ny, wb + R); // the rows marked or received
        long woken = 0;
        woken_rows_[0] = ny, woken_rows_[1] = -1;
#pragma omp parallel reduction(+ : woken) if (D == 2)
        {
            int threads = 1, thread = 0;
#ifdef _OPENMP
            threads = omp_get_num_threads(), thread = omp_get_thread_num();
#endif
            const int j0 = wa + static_cast<int>(static_cast<long>(wb - wa) * thread / threads);
            const int j1 = wa + static_cast<int>(static_cast<long>(wb - wa) * (thread + 1) / threads);
            std::vector<int> count(nx, 0);
            auto add = [&](int r, int sign) {
                const char* h = marks(r);
                for (int i = 0; i < nx; ++i)
                    count[i] += sign * h[i];
            };
            for (int r = std::max(ma, j0 - R); r < std::min(mb, j0 + R); ++r)
                add(r, 1);
            int first = ny, last = -1; // rows with cells woken
            for (int j = j0; j < j1; ++j) {
                if (j + R < mb) add(j + R, 1); // the window is now rows [j − R, j + R]
                char* a = awake_.data() + mesh_.index(0, j);
                long row = 0;
                for (int i = 0; i < nx; ++i) {
                    const char any = count[i] > 0;
                    row += any && !a[i];
                    a[i] |= any;
                }
                if (row > 0) first = std::min(first, j), last = j, sleep_span(j);
                woken += row;
                if (j - R >= ma) add(j - R, -1);
            }
#pragma omp critical(undex_wake_rows)
            woken_rows_[0] = std::min(woken_rows_[0], first), woken_rows_[1] = std::max(woken_rows_[1], last);
        }
        if (woken == 0) return;
        active_changed(woken_rows_[0], woken_rows_[1]);
        // On many ranks the test goes on: every rank takes part in each exchange of marks.
        all_awake_ = !ranks_ && awake_count() == static_cast<long>(nx) * ny; // no more scans
    }
    long awake_count() const {
        long n = 0;
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i)
                n += awake_[mesh_.index(i, j)];
        return n;
    }
    long troubled_ = 0;
    long scaled_ = 0; // cells changed by the positivity scaling in this step

    // The cells a step reads or writes, per padded row r = j + 1 (a single row in 1D): the padded columns
    // [copy_lo_[r], copy_hi_[r]) (index −1 … nx). They are the active spans widened by M cells along x and
    // y, with M one more than the farthest a stage reads (a neighbour through a face or the limiter) or a
    // stage ghost lies from the fluid it reads (ghost_reach_). Every other cell is neither read nor
    // written by a stage, so the step's copies (u0 = stage = u before it, u = stage after it) skip them.
    std::vector<int> copy_lo_, copy_hi_;
    void copy_spans() {
        const int M = std::max(ghost_reach_, 1) + 1, nx = mesh_.nx, ny = mesh_.ny;
        const int rows = D == 2 ? ny + 2 : 1;
        copy_lo_.assign(rows, nx + 1);
        copy_hi_.assign(rows, -1);
        for (int j = 0; j < ny; ++j) {
            if (hi_[j] <= lo_[j]) continue;
            const int a = std::max(-1, lo_[j] - M), b = std::min(nx + 1, hi_[j] + M);
            const int r0 = D == 2 ? std::max(-1, j - M) + 1 : 0, r1 = D == 2 ? std::min(ny, j + M) + 1 : 0;
            for (int r = r0; r <= r1; ++r)
                copy_lo_[r] = std::min(copy_lo_[r], a), copy_hi_[r] = std::max(copy_hi_[r], b);
        }
        // On many ranks, the block's rows within M of its edges in full: their stage ghosts may read fluid
        // that only a neighbour solves.
        if (ranks_)
            for (int j = row_begin(); j < row_end(); ++j)
                if (j < row_begin() + M || j >= row_end() - M) copy_lo_[j + 1] = -1, copy_hi_[j + 1] = nx + 1;
    }
    // dst = src (and *also = src) over the cells of copy_spans().
    // part (phase): 0, every row outside part 1's; 1, part 1's rows only; −1: every row.
    void copy_region(std::vector<double>& dst, const std::vector<double>& src,
                     std::vector<double>* also = nullptr, int part = -1) {
        const int rows = static_cast<int>(copy_lo_.size());
        double* d2 = also ? also->data() : nullptr;
        const std::array<int, 4> inner = part_rows(1, 0);
#pragma omp parallel for schedule(static) if (D == 2)
        for (int r = 0; r < rows; ++r) {
            if (copy_hi_[r] <= copy_lo_[r]) continue;
            const int j = D == 2 ? r - 1 : 0;
            if (part >= 0 && (D == 2 && j >= inner[0] && j < inner[1]) != (part == 1)) continue;
            const long k0 = static_cast<long>(mesh_.index(copy_lo_[r], j)) * NC;
            const long k1 = static_cast<long>(mesh_.index(copy_hi_[r] - 1, j) + 1) * NC;
            std::copy(src.begin() + k0, src.begin() + k1, dst.begin() + k0);
            if (d2) std::copy(src.begin() + k0, src.begin() + k1, d2 + k0);
        }
    }

    double* cell(double* U, int i, int j) const {
        return U + static_cast<long>(mesh_.index(i, j)) * NC;
    }
    const double* cell(const double* U, int i, int j) const {
        return U + static_cast<long>(mesh_.index(i, j)) * NC;
    }

    Primitive primitive(const double* q) const {
        return euler::to_primitive<D>(eos_, q);
    }
    double pressure(const double* q) const {
        return euler::pressure<D>(eos_, q);
    }

    // A Runge–Kutta stage from U: out = a·x + b·U + bdt·L(U) (b·dt folded into bdt), U neither x nor out.
    struct Stage {
        std::vector<double>& out;
        double a;
        const std::vector<double>& x;
        double b, bdt;
    };
    // The update is written by the volume loop of compute_rhs as each cell's L(U) is known, the absorbing
    // layers' relaxation −σ (U − U_ref) included (no pass over the arrays of its own).
    void stage_update(std::vector<double>& U, double t, const Stage& st, int part = 0) {
        compute_rhs(U, t, st, part);
    }

    // The hot loop of the solver, over bands of BAND rows: a band computes the fluxes through the x faces of
    // its rows and through the y faces below, between and above them (faces_flux) into its thread's buffer,
    // then the volume and face integrals with the source of its cells (cells_rhs), over blocks of LANES
    // faces or cells of a row; the stage st is written straight from L(U). The band's faces stay in cache
    // from one to the other (no array of all the faces); a y face between two bands is computed by both,
    // the same value.
    static constexpr int BAND = 8;
    // Part 0 (phase) also fills the ghost cells.
    void compute_rhs(std::vector<double>& Uvec, double t, const Stage& st, int part) {
        double* U = Uvec.data();
        double* out = st.out.data();
        const double* xs = st.x.data();
        const double sa = st.a, sb = st.b, sbdt = st.bdt;
        if (part == 0) {
            fill_ghosts<D, K, Eos>(mesh_, U, bc_, eos_, t, ghost_rows(0), ghost_rows(1));
            if (stage_ghosts_) stage_ghosts_(U);
        }
        // Bands of at most BAND rows over the part's two ranges of rows.
        const std::array<int, 4> r = part_rows(part, 0);
        std::vector<std::array<int, 2>> band_rows;
        for (int q = 0; q < 4; q += 2)
            for (int j = r[q]; j < r[q + 1]; j += BAND)
                band_rows.push_back({j, std::min(r[q + 1], j + BAND)});
        const int nx = mesh_.nx, bands = static_cast<int>(band_rows.size());
        const long xrow = static_cast<long>(nx + 1) * NQF * NV, yrow = static_cast<long>(nx) * NQF * NV;
#ifdef _OPENMP
        const size_t threads = D == 2 ? omp_get_max_threads() : 1;
#else
        const size_t threads = 1;
#endif
        if (band_faces_.size() < threads) band_faces_.resize(threads);
// Rows differ in cost (the gas, cavitating water and shocked water lie in some rows only): dynamic.
#pragma omp parallel if (D == 2)
        {
#ifdef _OPENMP
            std::vector<double>& faces = band_faces_[omp_get_thread_num()];
#else
            std::vector<double>& faces = band_faces_[0];
#endif
            faces.resize(BAND * xrow + (D == 2 ? (BAND + 1) * yrow : 0)); // once per thread
#pragma omp for schedule(dynamic, 1)
            for (int b = 0; b < bands; ++b) {
                const int j0 = band_rows[b][0], j1 = band_rows[b][1];
                if (part == 1) progress();
                double* fx = faces.data();     // x faces of row j at fx + (j − j0)·xrow
                double* fy = fx + BAND * xrow; // y faces of face row j (j0 … j1) at fy + (j − j0)·yrow
                for (int j = j0; j < j1; ++j)
                    x_faces(U, j, fx + (j - j0) * xrow);
                if constexpr (D == 2)
                    for (int j = j0; j <= j1; ++j)
                        y_faces(U, j, fy + (j - j0) * yrow);
                for (int j = j0; j < j1; ++j)
                    cells_row(U, out, xs, sa, sb, sbdt, j, fx + (j - j0) * xrow, fy + (j - j0) * yrow,
                              fy + (j - j0 + 1) * yrow);
            }
        }
    }
    // Fluxes through the x faces of row j (face i lies between cells i − 1 and i) whose fluxes are needed,
    // in blocks of LANES faces, into frow (face i at i·NQF·NV).
    void x_faces(const double* U, int j, double* frow) {
        if (hi_[j] <= lo_[j]) return;
        auto needed = [&](int i) { return active(i - 1, j) || active(i, j); };
        for (int i = lo_[j]; i <= hi_[j];) {
            if (!needed(i)) {
                ++i;
                continue;
            }
            int n = 1;
            while (n < LANES && i + n <= hi_[j] && needed(i + n))
                ++n;
            if (n == LANES)
                faces_flux<0, LANES>(U, i, j, frow), i += LANES;
            else
                faces_flux<0, 1>(U, i, j, frow), ++i;
        }
    }
    // Fluxes through the y faces of face row j (between cells (i, j − 1) and (i, j)), as x_faces.
    void y_faces(const double* U, int j, double* frow) {
        const int nx = mesh_.nx, ny = mesh_.ny;
        // Faces of this row touch the cells of rows j − 1 and j.
        int i0 = nx, i1 = 0;
        for (int r : {j - 1, j})
            if (r >= 0 && r < ny && hi_[r] > lo_[r]) i0 = std::min(i0, lo_[r]), i1 = std::max(i1, hi_[r]);
        auto needed = [&](int i) { return active(i, j - 1) || active(i, j); };
        for (int i = i0; i < i1;) {
            if (!needed(i)) {
                ++i;
                continue;
            }
            int n = 1;
            while (n < LANES && i + n < i1 && needed(i + n))
                ++n;
            if (n == LANES)
                faces_flux<1, LANES>(U, i, j, frow), i += LANES;
            else
                faces_flux<1, 1>(U, i, j, frow), ++i;
        }
    }
    // Volume integrals and the stage of row j, over blocks of LANES active cells (cells_rhs), from the
    // fluxes of its x faces (fx) and of the y faces below (fb) and above (ft) it; a cell asleep keeps its
    // value through the stage (an absorbing layer's cell of the fluid's region still relaxes, by 0 at rest).
    void cells_row(const double* U, double* out, const double* xs, double sa, double sb, double sbdt, int j,
                   const double* fx, const double* fb, const double* ft) const {
        const bool layered = !layer_cell_.empty();
        for (int i = lo_[j]; i < hi_[j]; ++i) {
            if (!active(i, j)) {
                const long k0 = static_cast<long>(mesh_.index(i, j)) * NC;
                const int layer = layered ? layer_of_[mesh_.index(i, j)] : -1;
                const bool relax = layer >= 0 && (!active_ || (*active_)[mesh_.index(i, j)]);
                for (long k = k0; k < k0 + NC; ++k) {
                    double r = 0.0;
                    if (relax) r -= layer_sigma_[layer] * (U[k] - layer_ref_[layer * NC + (k - k0)]);
                    out[k] = sa * xs[k] + sb * U[k] + sbdt * r;
                }
                continue;
            }
            int n = 1; // a block of LANES active cells, or this cell alone
            while (n < LANES && i + n < hi_[j] && active(i + n, j))
                ++n;
            if (n == LANES) {
                cells_rhs<LANES>(U, out, xs, sa, sb, sbdt, i, j, fx, fb, ft);
                i += LANES - 1;
            } else {
                cells_rhs<1>(U, out, xs, sa, sb, sbdt, i, j, fx, fb, ft);
            }
        }
    }

    // Cells (faces) per block of the volume (face) loops: one per SIMD lane. Tait water runs in them through
    // its LaneForm (TaitLiquid, without the table's range test and the cavitation branch); a block it does
    // not hold goes one cell at a time (lanes_hold).
    static constexpr int LANES = 8;

    // The equation of state of a block of W cells or faces: LaneForm's for W > 1 (without branches, so that
    // the loops over the lanes vectorise), Eos itself for one.
    template <int W> const auto& lane_eos() const {
        if constexpr (W > 1)
            return lane_eos_;
        else
            return eos_;
    }
    // Whether LaneForm's equation of state holds at the N·W densities rho[n·W + w] of a block (always, for
    // an Eos without a LaneForm of its own); a block where it does not goes one cell at a time.
    template <int W, int N> bool lanes_hold(const double* rho) const {
        if constexpr (W == 1 || LaneForm<Eos>::always) {
            return true;
        } else {
            bool hold = true;
            for (int k = 0; k < N * W; ++k)
                hold &= lane_eos_.holds(rho[k]);
            return hold;
        }
    }

    // The HLLC fluxes at the NQF points of W consecutive faces of direction Dir, one per SIMD lane: the x
    // faces i … i + W − 1 of row j (between cells i + w − 1 and i + w) or the y faces of row j (between
    // cells (i + w, j − 1) and (i + w, j)), into the row's fluxes frow (face i at i·NQF·NV). Each lane
    // computes what W = 1 computes, to the last bit.
    template <int Dir, int W> void faces_flux(const double* U, int i, int j, double* frow) {
        const double* lo0 = Dir == 0 ? cell(U, i - 1, j) : cell(U, i, j - 1); // lane w's cells at w·NC
        const double* hi0 = cell(U, i, j);
        double cl[NC][W], cr[NC][W];
        for (int k = 0; k < NC; ++k)
            for (int w = 0; w < W; ++w) {
                cl[k][w] = lo0[w * NC + k];
                cr[k][w] = hi0[w * NC + k];
            }
        double* f0 = frow + static_cast<long>(i) * NQF * NV;
        for (int g = 0; g < NQF; ++g) {
            double ql[NV][W], qr[NV][W], pl[W], pr[W], F[NV][W];
            for (int v = 0; v < NV; ++v)
                for (int w = 0; w < W; ++w) {
                    double t[NB];
                    for (int l = 0; l < NB; ++l)
                        t[l] = cl[v * NB + l][w] * tab_.face[Dir][1][g][l];
                    ql[v][w] = B::mode_sum(t);
                    for (int l = 0; l < NB; ++l)
                        t[l] = cr[v * NB + l][w] * tab_.face[Dir][0][g][l];
                    qr[v][w] = B::mode_sum(t);
                }
            if (!lanes_hold<W, 1>(ql[0]) || !lanes_hold<W, 1>(qr[0])) {
                // Water cavitating or outside the table somewhere in the block: its faces one at a time.
                for (int w = 0; w < W; ++w)
                    faces_flux<Dir, 1>(U, i + w, j, frow);
                return;
            }
            const auto& eos = lane_eos<W>();
            for (int w = 0; w < W; ++w) {
                const euler::Strided<const double> L{&ql[0][w], W}, R{&qr[0][w], W};
                pl[w] = euler::pressure<D>(eos, L);
                pr[w] = euler::pressure<D>(eos, R);
                hllc_flux<NV, Dir, (W > 1)>(eos, L, pl[w], R, pr[w], euler::Strided<double>{&F[0][w], W});
            }
            for (int w = 0; w < W; ++w)
                for (int v = 0; v < NV; ++v)
                    f0[(w * NQF + g) * NV + v] = F[v][w];
        }
    }

    // The stage out = sa·xs + sb·U + sbdt·L(U) of W consecutive active cells of row j from cell i, one per
    // SIMD lane (the arrays' last index), from the row's face fluxes (cells_row). Each lane performs the
    // operations of the one-cell case W = 1 in the same order, so that the result does not depend on W, to
    // the last bit.
    template <int W>
    void cells_rhs(const double* U, double* out, const double* xs, double sa, double sb, double sbdt, int i,
                   int j, const double* fxrow, const double* fbrow, const double* ftrow) const {
        const double* c0 = cell(U, i, j); // the W cells follow at strides of NC
        double c[NC][W];
        for (int k = 0; k < NC; ++k)
            for (int w = 0; w < W; ++w)
                c[k][w] = c0[w * NC + k];
        double acc[NV][NB][W] = {};
        // Point-major layout (variable, point, lane).
        double s[NV][NQV][W], F[NV][NQV][W], G[NV][NQV][W], P[NQV][W];
        for (int v = 0; v < NV; ++v)
            for (int q = 0; q < NQV; ++q)
                for (int w = 0; w < W; ++w) {
                    double t[NB];
                    for (int l = 0; l < NB; ++l)
                        t[l] = c[v * NB + l][w] * vol_.phi[l][q];
                    s[v][q][w] = B::mode_sum(t);
                }
        if (!lanes_hold<W, NQV>(&s[0][0][0])) { // as faces_flux
            for (int w = 0; w < W; ++w)
                cells_rhs<1>(U, out, xs, sa, sb, sbdt, i + w, j, fxrow, fbrow, ftrow);
            return;
        }
        for (int q = 0; q < NQV; ++q)
            for (int w = 0; w < W; ++w) {
                const Primitive p = euler::to_primitive<D>(lane_eos<W>(), euler::AtLane{s, q, w});
                P[q][w] = p.p;
                euler::flux<NV, 0>(euler::AtLane{s, q, w}, p.u, p.p, euler::AtLane{F, q, w});
                if constexpr (D == 2) euler::flux<NV, 1>(euler::AtLane{s, q, w}, p.v, p.p, euler::AtLane{G, q, w});
            }
        // ∫ F ∂φ/∂x + G ∂φ/∂y: ∂φ/∂x vanishes for the modes constant in ξ and ∂φ/∂y for those constant
        // in η (tabulated as exact zeros), so only the other term is summed (the same value).
        if constexpr (K > 0)
            for (int l = 1; l < NB; ++l) {
                const bool in_x = B::px(l) > 0, in_y = D == 2 && B::py(l) > 0;
                for (int v = 0; v < NV; ++v) {
                    // The branch outside the loop over the lanes, so that it vectorises.
                    if (in_x && in_y)
                        for (int w = 0; w < W; ++w) {
                            double t[NQV];
                            for (int q = 0; q < NQV; ++q)
                                t[q] = F[v][q][w] * vol_.wdx[l][q] + G[v][q][w] * vol_.wdy[l][q];
                            acc[v][l][w] = B::point_sum(t);
                        }
                    else if (in_x)
                        for (int w = 0; w < W; ++w) {
                            double t[NQV];
                            for (int q = 0; q < NQV; ++q)
                                t[q] = F[v][q][w] * vol_.wdx[l][q];
                            acc[v][l][w] = B::point_sum(t);
                        }
                    else
                        for (int w = 0; w < W; ++w) {
                            double t[NQV];
                            for (int q = 0; q < NQV; ++q)
                                t[q] = G[v][q][w] * vol_.wdy[l][q];
                            acc[v][l][w] = B::point_sum(t);
                        }
                }
            }
        if (mesh_.alpha != 0.0) {
            // S = −(α/x)(ρu, ρu², ρuv, (E+p)u): the x flux without its pressure term.
            double S[NV][NQV][W];
            for (int q = 0; q < NQV; ++q)
                for (int w = 0; w < W; ++w) {
                    const double x = mesh_.xc(i + w) + 0.5 * mesh_.dx * tab_.xiv[q];
                    const double f = -mesh_.alpha / x * tab_.wv[q];
                    for (int v = 0; v < NV; ++v)
                        S[v][q][w] = f * F[v][q][w];
                    S[1][q][w] = f * (F[1][q][w] - P[q][w]);
                }
            for (int v = 0; v < NV; ++v)
                for (int l = 0; l < NB; ++l)
                    for (int w = 0; w < W; ++w) {
                        double t[NQV];
                        for (int q = 0; q < NQV; ++q)
                            t[q] = S[v][q][w] * tab_.phiv[q][l];
                        acc[v][l][w] += B::point_sum(t); // mirror-symmetric in z (Basis::point_sum)
                    }
        }
        // Face integrals: the x and y faces summed apart and then added, so that a mirror image about
        // x = y rounds alike. The face fluxes are first copied lane-minor: fx of the W + 1 x faces (lane w's
        // left face is w, its right face w + 1), fy of the W faces below and above.
        const double idx = 1.0 / mesh_.dx, idy = 1.0 / mesh_.dy;
        constexpr int NF = NQF * NV; // values per face
        double fx[NF][W + 1], fb[NF][W], ft[NF][W];
        const double* fx0 = fxrow + static_cast<long>(i) * NF;
        for (int k = 0; k < NF; ++k)
            for (int w = 0; w <= W; ++w)
                fx[k][w] = fx0[w * NF + k];
        if constexpr (D == 2) {
            const double* fb0 = fbrow + static_cast<long>(i) * NF;
            const double* ft0 = ftrow + static_cast<long>(i) * NF;
            for (int k = 0; k < NF; ++k)
                for (int w = 0; w < W; ++w) {
                    fb[k][w] = fb0[w * NF + k];
                    ft[k][w] = ft0[w * NF + k];
                }
        }
        for (int v = 0; v < NV; ++v)
            for (int l = 0; l < NB; ++l)
                for (int w = 0; w < W; ++w) {
                    double t[NQF];
                    for (int g = 0; g < NQF; ++g)
                        t[g] = idx * tab_.wf[g] *
                               (fx[g * NV + v][w] * tab_.face[0][0][g][l] -
                                fx[g * NV + v][w + 1] * tab_.face[0][1][g][l]);
                    double faces = B::face_sum(t);
                    if constexpr (D == 2) {
                        for (int g = 0; g < NQF; ++g)
                            t[g] = idy * tab_.wf[g] *
                                   (fb[g * NV + v][w] * tab_.face[1][0][g][l] -
                                    ft[g * NV + v][w] * tab_.face[1][1][g][l]);
                        faces += B::face_sum(t);
                    }
                    acc[v][l][w] += faces;
                }
        const bool layered = !layer_cell_.empty();
        for (int w = 0; w < W; ++w) {
            const long k0 = static_cast<long>(mesh_.index(i + w, j)) * NC;
            const int layer = layered ? layer_of_[mesh_.index(i + w, j)] : -1;
            if (layer < 0)
                for (int v = 0; v < NV; ++v)
                    for (int l = 0; l < NB; ++l) {
                        const long k = k0 + v * NB + l;
                        out[k] = sa * xs[k] + sb * c[v * NB + l][w] + sbdt * (acc[v][l][w] * tab_.inv_norm[l]);
                    }
            else // an absorbing layer's cell: L(U) − σ (U − U_ref)
                for (int v = 0; v < NV; ++v)
                    for (int l = 0; l < NB; ++l) {
                        const long k = k0 + v * NB + l;
                        double r = acc[v][l][w] * tab_.inv_norm[l];
                        r -= layer_sigma_[layer] * (c[v * NB + l][w] - layer_ref_[layer * NC + v * NB + l]);
                        out[k] = sa * xs[k] + sb * c[v * NB + l][w] + sbdt * r;
                    }
        }
    }

    // Indicator + limiter + positivity on Uvec; throws SolverFailure for a cell that cannot be made
    // admissible.
    // Two passes over the rows: the indicator and the limiter of each row (the limited polynomials go to
    // rhs_, free at this point, so that every cell is limited from its neighbours' unlimited ones), then the
    // copy back and the positivity of each row; one barrier between them instead of one per sweep.
    // In parts (phase): part 0 limits the rows within stage_depth() + 1 of the block's edges and replaces
    // those within stage_depth(); part 1 the others. A cell that cannot be held throws at the end of part 1
    // (the lowest-numbered such cell of both parts, as in one pass).
    void limit(std::vector<double>& Uvec, double t, const char* stage, int part = -1) {
        if (part < 0) {
            limit(Uvec, t, stage, 0);
            return limit(Uvec, t, stage, 1);
        }
        double* U = Uvec.data();
        double* out = rhs_.data();
        const bool limiting = K > 0 && set_.limiter != Limiter::None && set_.indicator != Indicator::None;
        if (part == 0) {
            bad_ = BadCell{};
            if (stage_ghosts_) stage_ghosts_(U); // also leaves the band fresh in the step's result
            if (limiting) fill_ghosts<D, K, Eos>(mesh_, U, bc_, eos_, t, ghost_rows(0), ghost_rows(1));
        }
        const std::vector<int> limited = rows_in(part_rows(part, 1)), replaced = rows_in(part_rows(part, 0));
        if (limiting) {
            long count = 0;
            const int n = static_cast<int>(limited.size());
#pragma omp parallel for reduction(+ : count) schedule(dynamic, 8) if (D == 2)
            for (int m = 0; m < n; ++m) {
                const int j = limited[m];
                if (part == 1 && m % 8 == 0) progress();
                count += mark_row(U, j);
                if (set_.limiter == Limiter::Weno)
                    weno_row(U, out, j);
                else
                    minmod_row(U, out, j);
            }
            troubled_ += count;
        }
        // Always: positivity also detects inadmissible cell averages.
        BadCell& bad = bad_;
        long count = 0;
        const int n = static_cast<int>(replaced.size());
#pragma omp parallel for reduction(+ : count) schedule(dynamic, 8) if (D == 2)
        for (int m = 0; m < n; ++m) {
            const int j = replaced[m];
            if (limiting)
                for (int i = lo_[j]; i < hi_[j]; ++i)
                    if (troubled_flag_[mesh_.index(i, j)]) std::copy_n(cell(out, i, j), NC, cell(U, i, j));
            count += positivity_row(U, j, stage, bad);
        }
        scaled_ += count;
        if (part == 1 && bad.i >= 0) fail_cell(bad.i, bad.j, bad.what, t);
    }

    // The troubled cells of row j (troubled_flag_); returns their number.
    long mark_row(const double* U, int j) {
        const double lx = mesh_.x_max - mesh_.x_min, ly = mesh_.y_max - mesh_.y_min;
        const double hx2 = (mesh_.dx / lx) * (mesh_.dx / lx), hy2 = (mesh_.dy / ly) * (mesh_.dy / ly);
        long count = 0;
        for (int i = lo_[j]; i < hi_[j]; ++i) {
            bool bad = set_.indicator == Indicator::All && active(i, j);
            const double* c = cell(U, i, j);
            if constexpr (D == 2) {
                // The row above, a few cells ahead, is fetched before use: the loop reads two lines of
                // each of three rows' cells, a pattern the hardware prefetcher misses (perf: 60 % of
                // the loop's time stalled on those loads; 9 % of the PID run's time saved).
                const double* ahead = cell(U, std::min(i + 8, mesh_.nx), j + 1);
                __builtin_prefetch(ahead);
                __builtin_prefetch(ahead + E * NB);
            }
            if (!active(i, j)) {
                troubled_flag_[mesh_.index(i, j)] = 0;
                continue;
            }
            for (int dir = 0; dir < D && !bad; ++dir) {
                const double* lo = dir == 0 ? cell(U, i - 1, j) : cell(U, i, j - 1);
                const double* hi = dir == 0 ? cell(U, i + 1, j) : cell(U, i, j + 1);
                const double h2 = dir == 0 ? hx2 : hy2;
                for (int v : {0, E}) {
                    const double* cv = c + v * NB;
                    const double avg = cv[0];
                    // Face-centre values on the high and low faces of this direction.
                    double up = 0, dn = 0;
                    for (int l = 1; l < NB; ++l) {
                        const int pw = dir == 0 ? B::px(l) : B::py(l);
                        const int po = dir == 0 ? B::py(l) : B::px(l);
                        if (pw == 0) continue;
                        const double val = po == 0 ? 1.0 : (po == 1 ? 0.0 : -1.0 / 3.0);
                        const double f = B::p1(pw, 1.0) * val;
                        const double fm = B::p1(pw, -1.0) * val;
                        up += cv[l] * f;
                        dn += cv[l] * fm;
                    }
                    // Modes constant along dir shift both faces equally and are left out.
                    const double fwd = hi[v * NB] - avg, bwd = avg - lo[v * NB];
                    const double thr = set_.tvb_m * h2 * std::abs(avg);
                    if (tvb_modifies(up, fwd, bwd, thr) || tvb_modifies(-dn, fwd, bwd, thr)) {
                        bad = true;
                        break;
                    }
                }
            }
            troubled_flag_[mesh_.index(i, j)] = bad;
            count += bad;
        }
        return count;
    }

    // Long on purpose (about 110 lines): the per-troubled-cell hot loop of the limiter in one piece.
    // The troubled cells of row j limited into out.
    void weno_row(const double* U, double* out, int j) const {
        const double g_nb = set_.weno_neighbour_weight, eps = set_.weno_epsilon;
        const double g_c = 1.0 - 2 * D * g_nb;
        for (int i = lo_[j]; i < hi_[j]; ++i) {
            if (!troubled_flag_[mesh_.index(i, j)]) continue;
            const double* c = cell(U, i, j);
            // Candidate polynomials: own, then neighbours −x, +x, −y, +y shifted to this cell's average.
            constexpr int NCAND = 1 + 2 * D;
            double cand[NCAND][NV][NB];
            for (int v = 0; v < NV; ++v)
                for (int l = 0; l < NB; ++l)
                    cand[0][v][l] = c[v * NB + l];
            for (int nb = 0; nb < 2 * D; ++nb) {
                const int ni = i + (nb == 0 ? -1 : nb == 1 ? 1 : 0);
                const int nj = j + (nb == 2 ? -1 : nb == 3 ? 1 : 0);
                const double* n = cell(U, ni, nj);
                for (int v = 0; v < NV; ++v) {
                    cand[1 + nb][v][0] = c[v * NB]; // shifted to this cell's average
                    for (int l = 1; l < NB; ++l) {
                        double t[NB];
                        for (int m = 0; m < NB; ++m)
                            t[m] = weno_.shift[nb][l][m] * n[v * NB + m];
                        cand[1 + nb][v][l] = B::mode_sum(t);
                    }
                }
            }
            double q[NV];
            for (int v = 0; v < NV; ++v)
                q[v] = c[v * NB];
            const Primitive w = primitive(q);
            const double a = eos_.sound_speed(w.rho, w.p);
            const double vel[2] = {w.u, w.v};
            double result[NV][NB] = {};
            for (int dir = 0; dir < D; ++dir) {
                const Eigenvectors<NV> ev = eigenvectors(dir, w.rho, vel, a);
                double limited[NV][NB];
                for (int m = 0; m < NV; ++m) {
                    // The candidates share their average (cand[k][v][0]): only the own one's is projected.
                    double ch[NCAND][NB];
                    for (int k = 0; k < NCAND; ++k)
                        for (int l = k == 0 ? 0 : 1; l < NB; ++l) {
                            double t[NV];
                            for (int v = 0; v < NV; ++v)
                                t[v] = ev.L[m][v] * cand[k][v][l];
                            ch[k][l] = variable_sum(t);
                        }
                    // β = cᵀ S c with S diagonal for this basis (WenoTables::smooth_diag, checked there).
                    double wk[NCAND];
                    for (int k = 0; k < NCAND; ++k) {
                        double beta = 0;
                        if constexpr (D == 1) {
                            for (int l = 1; l < NB; ++l)
                                beta += ch[k][l] * weno_.smooth_diag[l] * ch[k][l];
                        } else {
                            double outer[NB] = {};
                            for (int l = 1; l < NB; ++l)
                                outer[l] = ch[k][l] * (weno_.smooth_diag[l] * ch[k][l]);
                            beta = B::mode_sum(outer);
                        }
                        const double lin = k == 0 ? g_c : g_nb;
                        wk[k] = lin / ((eps + beta) * (eps + beta));
                    }
                    const double wsum = candidate_sum(wk);
                    for (int l = 1; l < NB; ++l) {
                        double t[NCAND];
                        for (int k = 0; k < NCAND; ++k)
                            t[k] = wk[k] * ch[k][l];
                        limited[m][l] = candidate_sum(t) / wsum;
                    }
                }
                for (int v = 0; v < NV; ++v)
                    for (int l = 1; l < NB; ++l) { // the average is kept (below)
                        double t[NV];
                        for (int m = 0; m < NV; ++m)
                            t[m] = ev.R[v][m] * limited[m][l];
                        result[v][l] += wave_sum(t) / D;
                    }
            }
            double* o = cell(out, i, j);
            for (int v = 0; v < NV; ++v) {
                o[v * NB] = c[v * NB]; // the average is kept exactly
                for (int l = 1; l < NB; ++l)
                    o[v * NB + l] = result[v][l];
            }
            // Keep the density of the limited polynomial within the range of this and the neighbouring
            // cell averages, as a MUSCL reconstruction would: WENO alone does not rule out overshoots,
            // and barotropic water turns a 1 % density overshoot into tens of MPa.
            double lo = c[0], hi = c[0];
            for (int nb = 0; nb < 2 * D; ++nb) {
                const int ni = i + (nb == 0 ? -1 : nb == 1 ? 1 : 0);
                const int nj = j + (nb == 2 ? -1 : nb == 3 ? 1 : 0);
                lo = std::min(lo, cell(U, ni, nj)[0]);
                hi = std::max(hi, cell(U, ni, nj)[0]);
            }
            double theta = 1.0;
            for_each_point(o, [&](const double* qp) {
                if (qp[0] > hi) theta = std::min(theta, (hi - c[0]) / (qp[0] - c[0]));
                if (qp[0] < lo) theta = std::min(theta, (lo - c[0]) / (qp[0] - c[0]));
            });
            if (theta < 1.0)
                for (int v = 0; v < NV; ++v)
                    for (int l = 1; l < NB; ++l)
                        o[v * NB + l] *= theta;
        }
    }

    // Troubled cells become linear: in the characteristic variables of each direction the slope is the
    // minmod of the own slope and the differences of the neighbouring averages (Cockburn and Shu 1989);
    // the quadratic and mixed modes are dropped.
    void minmod_row(const double* U, double* out, int j) const {
        for (int i = lo_[j]; i < hi_[j]; ++i) {
            if (!troubled_flag_[mesh_.index(i, j)]) continue;
            const double* c = cell(U, i, j);
            double q[NV];
            for (int v = 0; v < NV; ++v)
                q[v] = c[v * NB];
            const Primitive w = primitive(q);
            const double a = eos_.sound_speed(w.rho, w.p);
            const double vel[2] = {w.u, w.v};
            double* o = cell(out, i, j);
            std::fill(o, o + NC, 0.0);
            for (int v = 0; v < NV; ++v)
                o[v * NB] = c[v * NB];
            for (int dir = 0; dir < D; ++dir) {
                const int l = dir == 0 ? 1 : 2; // basis function ξ or η
                const double* lo = dir == 0 ? cell(U, i - 1, j) : cell(U, i, j - 1);
                const double* hi = dir == 0 ? cell(U, i + 1, j) : cell(U, i, j + 1);
                const Eigenvectors<NV> ev = eigenvectors(dir, w.rho, vel, a);
                double lim[NV];
                for (int m = 0; m < NV; ++m) {
                    double s[NV], f[NV], b[NV];
                    for (int v = 0; v < NV; ++v) {
                        s[v] = ev.L[m][v] * c[v * NB + l];
                        f[v] = ev.L[m][v] * (hi[v * NB] - c[v * NB]);
                        b[v] = ev.L[m][v] * (c[v * NB] - lo[v * NB]);
                    }
                    lim[m] = minmod3(variable_sum(s), variable_sum(f), variable_sum(b));
                }
                for (int v = 0; v < NV; ++v) {
                    double x[NV];
                    for (int m = 0; m < NV; ++m)
                        x[m] = ev.R[v][m] * lim[m];
                    o[v * NB + l] = wave_sum(x);
                }
            }
        }
    }

    // Sums of the WENO limiter in an order that mirror images round alike (see Basis::mode_sum). Over the
    // conserved variables: (ρ + (ρu + ρv)) + E.
    static double variable_sum(const double (&t)[NV]) {
        if constexpr (D == 1)
            return (t[0] + t[1]) + t[2];
        else
            return (t[0] + (t[1] + t[2])) + t[3];
    }
    // Over the waves (un − a, [shear,] entropy, un + a): (un − a + un + a) + ([shear +] entropy).
    static double wave_sum(const double (&t)[NV]) {
        if constexpr (D == 1)
            return (t[0] + t[2]) + t[1];
        else
            return (t[0] + t[3]) + (t[1] + t[2]);
    }
    // Over the candidates (own, −x, +x, −y, +y): own + ((−x + +x) + (−y + +y)).
    static double candidate_sum(const double (&t)[1 + 2 * D]) {
        if constexpr (D == 1)
            return t[0] + (t[1] + t[2]);
        else
            return t[0] + ((t[1] + t[2]) + (t[3] + t[4]));
    }

    Eigenvectors<NV> eigenvectors(int dir, double rho, const double* vel, double a) const {
        constexpr int Y = D == 2 ? 1 : 0;
        if constexpr (Eos::barotropic)
            return dir == 0 ? barotropic_eigenvectors<NV, 0>(vel, a) : barotropic_eigenvectors<NV, Y>(vel, a);
        else
            return dir == 0 ? euler_eigenvectors<NV, 0>(rho, vel, a, eos_.gruneisen())
                            : euler_eigenvectors<NV, Y>(rho, vel, a, eos_.gruneisen());
    }

    [[noreturn]] void fail_cell(int i, int j, const std::string& what, double t) const {
        std::ostringstream s;
        s.precision(6);
        s << what << " in cell (" << i;
        if (D == 2) s << ", " << j;
        s << ") at x = " << mesh_.xc(i);
        if (D == 2) s << ", y = " << mesh_.yc(j);
        s << ", t = " << t << " s";
        throw SolverFailure(s.str());
    }

    // Zhang–Shu scaling towards the cell average so that ρ > 0 and p + P∞ > 0 at every quadrature point;
    // a cell whose average is itself inadmissible (or NaN) is a failure, kept in bad if it is the first in
    // the mesh's order (limit() reports it). Row j; returns the number of cells scaled.
    struct BadCell {
        int i = -1, j = -1;
        std::string what;
    };
    BadCell bad_; // limit()'s first cell that cannot be held, over both parts
    long positivity_row(double* U, int j, const char* stage, BadCell& bad) const {
        const int nx = mesh_.nx;
        const bool scale = set_.positivity && K > 0;
        const double eps = set_.positivity_epsilon;
        const double margin = velocity_margin();
        long count = 0;
        for (int i = lo_[j]; i < hi_[j]; ++i) {
            if (!active(i, j)) continue;
            double* c = cell(U, i, j);
            double avg[NV];
            bool finite = true;
            for (int v = 0; v < NV; ++v) {
                avg[v] = c[v * NB];
                for (int l = 0; l < NB; ++l)
                    finite = finite && std::isfinite(c[v * NB + l]);
            }
            std::string what;
            double p_avg = 0;
            if (!finite)
                what = "non-finite value (NaN or Inf)";
            else if (!(avg[0] > 0))
                what = "non-positive density " + std::to_string(avg[0]) + " kg/m^3";
            else {
                p_avg = pressure(avg);
                if (!(eos_.pressure_margin(p_avg) > 0) || !std::isfinite(p_avg))
                    what = "pressure " + std::to_string(p_avg) + " Pa at or below -P_inf";
            }
            if (!what.empty()) {
#pragma omp critical(undex_bad_cell)
                if (bad.i < 0 || j * nx + i < bad.j * nx + bad.i) {
                    bad.i = i, bad.j = j;
                    bad.what = what + " after limiting (" + stage + ")";
                }
                continue;
            }
            if (!scale) continue;
            const double rho_floor = eps * avg[0];
            if (clear_of_floors(c, avg, rho_floor, p_avg, margin)) continue;
            // One pass finds the smallest density and pressure margin over the points; most cells need
            // nothing more.
            double Q[NV][NP];
            at_points(c, points_, Q);
            double rho_min = avg[0], m_min = 1e300;
            for (int k = 0; k < NP; ++k)
                rho_min = std::min(rho_min, Q[0][k]);
            if constexpr (!Eos::barotropic)
                if (rho_min > 0)
                    for (int k = 0; k < NP; ++k) {
                        m_min = std::min(
                            m_min, eos_.pressure_margin(euler::pressure<D>(eos_, euler::AtPoint{Q, k})));
                    }
            const double V = Eos::barotropic ? velocity_bound(avg, margin) : 0.0;
            bool slow = false; // barotropic: a point whose velocity exceeds V
            if constexpr (Eos::barotropic)
                for (int k = 0; k < NP; ++k)
                    for (int d = 0; d < D; ++d)
                        slow = slow || !(std::abs(Q[1 + d][k]) <= V * Q[0][k]);
            if (rho_min >= rho_floor &&
                (Eos::barotropic ? !slow : m_min >= eps * eos_.pressure_margin(p_avg)))
                continue;
            ++count;
            if (rho_min < rho_floor) {
                const double theta = (avg[0] - rho_floor) / (avg[0] - rho_min);
                for (int l = 1; l < NB; ++l)
                    c[l] *= theta;
            }
            // Velocity (barotropic only: its energy does not bound the kinetic energy, so a point whose
            // density sits at the floor can carry any momentum; (542, 1347) of the paper-resolution
            // application had ρ = 4.5e-8 and ρu = −4 055 at a face point, u ≈ −9e10 m/s, and HLLC gave
            // NaN). The slopes are scaled towards the average onto the convex set |ρu|, |ρv| ≤ V ρ, whose
            // constraints are linear in the scaling and hold at the average: θ = g(0)/(g(0) − g(1)) for
            // each violated g = V ρ ∓ ρu_d.
            if constexpr (Eos::barotropic) {
                double theta = 1.0;
                for_each_point(c, [&](const double* q) {
                    for (int d = 0; d < D; ++d)
                        for (const double sign : {1.0, -1.0}) {
                            const double g0 = V * avg[0] - sign * avg[1 + d];
                            const double g1 = V * q[0] - sign * q[1 + d];
                            if (g1 < 0) theta = std::min(theta, g0 / (g0 - g1));
                        }
                });
                if (theta < 1.0)
                    for (int v = 0; v < NV; ++v)
                        for (int l = 1; l < NB; ++l)
                            c[v * NB + l] *= theta;
            }
            // Pressure (stiffened gas only: p + P∞ is concave in U, so the linear estimate is safe).
            if constexpr (!Eos::barotropic) {
                const double m_avg = eos_.pressure_margin(p_avg);
                const double m_floor = eps * m_avg;
                double theta = 1.0;
                for_each_point(c, [&](const double* q) {
                    const double m = eos_.pressure_margin(pressure(q));
                    if (m < m_floor) theta = std::min(theta, (m_avg - m_floor) / (m_avg - m));
                });
                if (theta < 1.0)
                    for (int v = 0; v < NV; ++v)
                        for (int l = 1; l < NB; ++l)
                            c[v * NB + l] *= theta;
            }
        }
        return count;
    }

    // The largest velocity component a point of a barotropic cell may carry: the average's largest component
    // plus `margin`, twice the liquid's sound speed at rest (velocity_margin; water never varies by that much
    // across a cell, near-vacuum points of cavitating water do, through the density floor alone).
    double velocity_bound(const double* avg, double margin) const {
        double u = 0.0;
        for (int d = 0; d < D; ++d)
            u = std::max(u, std::abs(avg[1 + d] / avg[0]));
        return u + margin;
    }
    double velocity_margin() const {
        if constexpr (Eos::barotropic)
            return 2.0 * eos_.liquid_sound_speed(eos_.rho0, eos_.A);
        else
            return 0.0;
    }

    // Whether cell c is admissible at every point by bounds alone, without evaluating it there (positivity's
    // fast path; the same answer as the points give wherever it says yes). Each variable lies within
    // avg ± Σ_l≥1 |c_l| max|φ_l| at the points; the density's lower bound must clear rho_floor, and for the
    // stiffened gas (whose p depends on ρe alone and increases with it) ρe ≥ E_lo − |m|²_hi / (2 ρ_lo) must
    // give a margin that clears the floor; for barotropic water |ρu_d| ≤ V ρ_lo (velocity_bound) must hold at
    // the bounds. Each bound is lowered by 1e-12 of its magnitudes, far above the
    // rounding of these few operations.
    bool clear_of_floors(const double* c, const double* avg, double rho_floor, double p_avg,
                         double margin) const {
        double spread[NV];
        for (int v = 0; v < NV; ++v) {
            double t = 0.0;
            for (int l = 1; l < NB; ++l)
                t += std::abs(c[v * NB + l]) * point_max_[l];
            spread[v] = t;
        }
        const double rho_lo = avg[0] - spread[0] - 1e-12 * (avg[0] + spread[0]);
        if (!(rho_lo >= rho_floor && rho_lo > 0)) return false;
        if constexpr (Eos::barotropic) {
            const double V = velocity_bound(avg, margin);
            for (int d = 0; d < D; ++d)
                if (!(std::abs(avg[1 + d]) + spread[1 + d] <= V * rho_lo)) return false;
            return true;
        } else {
            double m2 = 0.0;
            for (int d = 0; d < D; ++d) {
                const double m = std::abs(avg[1 + d]) + spread[1 + d];
                m2 += m * m;
            }
            const double ke_hi = 0.5 * m2 / rho_lo;
            const double e_lo = avg[E] - spread[E] - ke_hi - 1e-12 * (std::abs(avg[E]) + spread[E] + ke_hi);
            return eos_.pressure_margin(eos_.pressure(rho_lo, e_lo)) >=
                   set_.positivity_epsilon * eos_.pressure_margin(p_avg);
        }
    }

    // The conserved state of cell c at N points, point-major: Q[v][k] = Σ_l c[v][l] φ_l(point k).
    template <int N> static void at_points(const double* c, const double (&phi)[NB][N], double (&Q)[NV][N]) {
        for (int v = 0; v < NV; ++v)
            for (int k = 0; k < N; ++k) {
                double t[NB];
                for (int l = 0; l < NB; ++l)
                    t[l] = c[v * NB + l] * phi[l][k];
                Q[v][k] = B::mode_sum(t);
            }
    }

    // Calls f(q) with the conserved state at every volume and face quadrature point of cell c.
    template <class F> void for_each_point(const double* c, F&& f) const {
        auto eval = [&](const double* phi) {
            double q[NV];
            for (int v = 0; v < NV; ++v) {
                double t[NB];
                for (int l = 0; l < NB; ++l)
                    t[l] = c[v * NB + l] * phi[l];
                q[v] = B::mode_sum(t);
            }
            f(q);
        };
        for (int q = 0; q < NQV; ++q)
            eval(tab_.phiv[q]);
        for (int dir = 0; dir < D; ++dir)
            for (int side = 0; side < 2; ++side)
                for (int g = 0; g < NQF; ++g)
                    eval(tab_.face[dir][side][g]);
    }
};

} // namespace undex::fluid
