// Two fluids separated by a sharp interface (physics.md §4): a level set φ marks the fluids (the "minus"
// fluid where φ < 0, the "plus" fluid where φ ≥ 0), each fluid is solved by its own RKDG scheme in its real
// region and a ghost band of `band_cells` cells beyond the interface, and the ghost fluid method couples
// them once per step:
//   real GFM (Wang, Liu and Khoo 2006): the two-material Riemann problem along the normal between the real
//     states on either side gives (p*, u*, ρ*_minus, ρ*_plus); it redefines the real cell next to the
//     interface and, extrapolated at constant value along the normal (paper eq. 33), fills the ghost band;
//   modified GFM (Liu, Khoo and Yeo 2003): the same interface states fill the ghost band only; the real
//     cells keep their own solution;
//   original GFM (Fedkiw et al. 1999): ghost cells take pressure and velocity from the real fluid there and
//     the entropy of their own fluid, extrapolated from the interface.
// The level set moves with the extension of the interface velocity u*·n and is reinitialised periodically.
#pragma once
#include "fluid/eos.hpp"
#include "fluid/interface_riemann.hpp"
#include "fluid/level_set.hpp"
#include "fluid/ranks.hpp"
#include "fluid/scheme.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace undex::fluid {

enum class GhostMethod { Real, Modified, Original };

struct InterfaceSettings {
    GhostMethod method = GhostMethod::Modified;
    InterfaceRiemann riemann = InterfaceRiemann::DoubleShock;
    int band_cells = 3;        // ghost cells solved beyond the interface
    int reinit_every = 5;      // steps between reinitialisations of φ (0: never)
    int reinit_iterations = 3; // pseudo-time iterations per reinitialisation
    int tube_cells = 0; // half-width of the level set's narrow band in 2D (LevelSet::set_tube), 0: none
};

template <int D, int K, EquationOfState EosM, EquationOfState EosP>
class TwoFluid final : public FluidSolver {
  public:
    TwoFluid(const Mesh& mesh, const EosM& eos_m, const EosP& eos_p, const Settings& s,
             const std::array<Boundary, 4>& bc, const InterfaceSettings& is, const std::string& minus_name,
             const std::string& plus_name)
        : mesh_(mesh), set_(is), names_{minus_name, plus_name}, minus_(mesh, eos_m, without_rest(s), bc),
          plus_(mesh, eos_p, s, bc), phi_(mesh), mat_m_(eos_m.riemann_material()),
          mat_p_(eos_p.riemann_material()) {
        active_m_.assign(mesh_.padded_cells(), 0);
        active_p_.assign(mesh_.padded_cells(), 0);
        minus_.set_active(&active_m_);
        plus_.set_active(&active_p_);
    }

    // Initial data: φ at cell centres and each fluid's conserved state q(x, y) continued over the whole
    // domain; then the first interface treatment.
    void initialise(const std::function<double(double, double)>& phi,
                    const std::function<void(double, double, double*)>& minus_at,
                    const std::function<void(double, double, double*)>& plus_at) {
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i)
                phi_(i, j) = phi(mesh_.xc(i), mesh_.yc(j));
        phi_.set_tube(set_.tube_cells);
        minus_.set_active(nullptr);
        plus_.set_active(nullptr);
        minus_.project(minus_at);
        plus_.project(plus_at);
        minus_.set_active(&active_m_);
        plus_.set_active(&active_p_);
        update_masks();
        treat_interface();
        minus_.wake_cells(); // the ghost bands just written count for the first step's Δt
        plus_.wake_cells();
    }

    const Mesh& mesh() const override { return mesh_; }
    int degree() const override { return K; }
    int variables() const override { return D + 2; }
    int basis_functions() const override { return Basis<D, K>::NB; }
    double time() const override { return minus_.time(); }
    long steps() const override { return minus_.steps(); }
    long troubled_cells() const override { return minus_.troubled_cells() + plus_.troubled_cells(); }
    long positivity_scaled_cells() const override {
        return minus_.positivity_scaled_cells() + plus_.positivity_scaled_cells();
    }
    long cell_updates() const override { return minus_.cell_updates() + plus_.cell_updates(); }
    long cell_updates_skipped() const override {
        return minus_.cell_updates_skipped() + plus_.cell_updates_skipped();
    }
    bool has_cavitation() const override { return minus_.has_cavitation() || plus_.has_cavitation(); }
    double void_fraction(double p) const override {
        return plus_.has_cavitation() ? plus_.void_fraction(p) : minus_.void_fraction(p);
    }

    double cell_void_fraction(int i, int j) const override {
        return phi_(i, j) < 0 ? minus_.cell_void_fraction(i, j) : plus_.cell_void_fraction(i, j);
    }

    double stable_dt() const override { return std::min(minus_.stable_dt(), plus_.stable_dt()); }

    void step(double dt) override {
        step_phased(*this, ranks_, dt);
    }
    // The step in phases (step_phased): the interface treatment, both fluids' schemes in lockstep (each
    // phase's exchanges together), then the level set.
    void begin_step(double dt) {
        treat_interface();
        phi_.save(phi_before_);
        step_ = steps() + 1; // the same on every rank, whichever fluid fails where
        dt_ = dt;
        minus_.begin_step(dt);
        plus_.begin_step(dt);
    }
    void phase(int k, int part) {
        minus_.phase(k, part);
        plus_.phase(k, part);
    }
    void exchanges_after(int k, std::vector<Ranks::Rows>& x) {
        minus_.exchanges_after(k, x);
        plus_.exchanges_after(k, x);
    }
    // On many ranks a rank whose fluid fails still takes part in every gather of the level set, which the
    // other ranks wait on, and then takes the step back.
    void end_step() {
        std::optional<SolverFailure> failure;
        bool stepped[2] = {false, false};
        auto fluid_end = [&](auto& scheme, int f) {
            try {
                scheme.end_step();
                stepped[f] = true;
            } catch (const SolverFailure& e) {
                if (!failure) failure = SolverFailure(names_[f] + ": " + e.what());
            }
        };
        fluid_end(minus_, 0);
        fluid_end(plus_, 1);
        if (!failure || ranks_) {
            phi_.advect(wx_, wy_, dt_);
            if (set_.reinit_every > 0 && step_ % set_.reinit_every == 0)
                phi_.reinitialise(set_.reinit_iterations);
            update_masks(phi_.tube());
        }
        if (failure) {
            if (stepped[0]) minus_.revert_step();
            if (stepped[1]) plus_.revert_step();
            if (ranks_) {
                phi_.restore(phi_before_);
                update_masks();
            }
            throw *failure;
        }
    }

    // Takes back the last step (used when the fluid of another wet face fails in the same step): the state
    // after the step's interface treatment, which the real GFM had already redefined next to the interface.
    void revert_step() override {
        minus_.revert_step();
        plus_.revert_step();
        phi_.restore(phi_before_);
        update_masks();
    }

    // Cells outside `region` (padded-cell flags, see Mesh::index) hold neither fluid: the inside of a
    // structure (fluid/wet_fluid.hpp). Neither fluid is solved there, and the interface treatment neither
    // reads nor writes them. Null: the whole domain. Named as Scheme's, whose cells outside the mask hold no
    // fluid either.
    void set_active(const std::vector<char>* region) {
        region_ = region;
        update_masks();
    }
    void active_changed() { update_masks(); }
    // The region changed in rows j0 … j1 only.
    void active_changed(int j0, int j1) { update_masks(j0, j1); }
    // The two schemes, and the scheme of the fluid in cell (i, j) (for code written for one or two fluids).
    template <class F> void for_each_scheme(F&& f) {
        f(minus_);
        f(plus_);
    }
    template <class F> decltype(auto) scheme_at(int i, int j, F&& f) const {
        return phi_(i, j) < 0 ? f(minus_) : f(plus_);
    }
    const std::string& minus_name() const { return names_[0]; }

    // Many ranks (fluid/ranks.hpp): both fluids solve the rows of this rank's block, and the level set's
    // rates are computed by the rank of each row (LevelSet::divide). Every rank holds the whole φ, the
    // masks and the ghost bands, bit for bit the same: the interface treatment is every rank's, over the
    // whole tube, from the cell averages near it gathered from their owners (LevelSet::gather_near). Its
    // work grows with the interface's length, not with the mesh (docs/scale_out.md).
    bool divisible() const override { return D == 2; }
    void divide(const Ranks* r) override {
        ranks_ = r && r->many() ? r : nullptr;
        minus_.divide(r);
        plus_.divide(r);
        phi_.divide(r);
    }
    int halo() const override { return std::max(minus_.halo(), plus_.halo()); }
    void share() override {
        minus_.share();
        plus_.share();
    }
    std::vector<double> row_cost() const override {
        std::vector<double> c = minus_.row_cost();
        const std::vector<double> p = plus_.row_cost();
        for (size_t j = 0; j < c.size(); ++j)
            c[j] += p[j];
        return c;
    }

    void project(const std::function<void(double, double, double*)>&) override {
        throw std::logic_error("a two-fluid solver is initialised with initialise(), not project()");
    }

    std::vector<double> coefficients() const override {
        auto m = minus_.coefficients();
        const auto p = plus_.coefficients();
        const int nc = variables() * basis_functions();
        for (int j = 0; j < mesh_.ny; ++j)
            for (int i = 0; i < mesh_.nx; ++i)
                if (phi_(i, j) >= 0) {
                    const long k = (static_cast<long>(j) * mesh_.nx + i) * nc;
                    std::copy_n(p.begin() + k, nc, m.begin() + k);
                }
        return m;
    }
    void set_coefficients(const std::vector<double>& c, double time) override {
        minus_.set_coefficients(c, time);
        plus_.set_coefficients(c, time);
    }
    std::vector<double> level_set() const override { return phi_.values(); }
    void state(State& s) override {
        State m = s.scope("minus"), p = s.scope("plus"), phi = s.scope("phi");
        minus_.state(m);
        plus_.state(p);
        phi_.state(phi);
        s.io("active_m", active_m_);
        s.io("active_p", active_p_);
        s.io("wx", wx_);
        s.io("wy", wy_);
    }
    void set_level_set(const std::vector<double>& phi) override {
        if (phi.size() != phi_.values().size()) throw std::runtime_error("level set does not match the mesh");
        phi_.set(phi);
    }

    // Whether the point (x, y) lies in the minus fluid (by φ of its cell).
    bool in_minus(double x, double y) const {
        int i = static_cast<int>(std::floor((x - mesh_.x_min) / mesh_.dx));
        int j = D == 2 ? static_cast<int>(std::floor((y - mesh_.y_min) / mesh_.dy)) : 0;
        i = std::clamp(i, 0, mesh_.nx - 1);
        j = std::clamp(j, 0, mesh_.ny - 1);
        return phi_(i, j) < 0;
    }
    Primitive evaluate(double x, double y) const override {
        return in_minus(x, y) ? minus_.evaluate(x, y) : plus_.evaluate(x, y);
    }
    double sound_speed(double x, double y) const override {
        return in_minus(x, y) ? minus_.sound_speed(x, y) : plus_.sound_speed(x, y);
    }
    double pressure_floor() const override {
        return std::max(minus_.pressure_floor(), plus_.pressure_floor());
    }
    void set_structure_state(double p_I, double u_I) override {
        minus_.set_structure_state(p_I, u_I);
        plus_.set_structure_state(p_I, u_I);
    }

    Primitive cell_average(int i, int j) const override {
        return phi_(i, j) < 0 ? minus_.cell_average(i, j) : plus_.cell_average(i, j);
    }
    std::vector<double> row_totals(int j0, int j1) const override {
        const int nv = variables(), nb = basis_functions(), nc = nv * nb;
        std::vector<double> t(static_cast<size_t>(nv) * (j1 - j0), 0.0);
        const auto c = coefficients();
        const double vol = mesh_.dx * (D == 2 ? mesh_.dy : 1.0);
        for (int j = j0; j < j1; ++j)
            for (int i = 0; i < mesh_.nx; ++i) {
                const long k = static_cast<long>(j) * mesh_.nx + i;
                for (int v = 0; v < nv; ++v)
                    t[nv * (j - j0) + v] += c[k * nc + v * nb] * vol;
            }
        return t;
    }

  private:
    // The still water of Settings::skip_rest is the plus fluid's (regions[0]'s).
    static Settings without_rest(Settings s) {
        s.skip_rest = false;
        return s;
    }
    Mesh mesh_;
    InterfaceSettings set_;
    std::array<std::string, 2> names_; // materials of the minus and plus fluid, for messages
    Scheme<D, K, EosM> minus_;
    Scheme<D, K, EosP> plus_;
    LevelSet phi_;
    RiemannMaterial mat_m_, mat_p_;
    std::vector<char> active_m_, active_p_;
    std::vector<double> wx_, wy_;   // extension velocity of the level set
    LevelSet::Snapshot phi_before_; // φ at the start of the last step
    long step_ = 0;    // the number of the step under way (begin_step)
    double dt_ = 0;    // its Δt
    const std::vector<char>* region_ = nullptr;
    const Ranks* ranks_ = nullptr; // many ranks (divide), else null
    // Work arrays of the interface treatment, kept between steps: allocating them afresh at every step cost
    // more than the treatment itself (zeroing and first-touch page faults, on one thread).
    std::vector<double> un_;
    std::vector<char> un_known_, cut_;

    bool in_region(int i, int j) const { return !region_ || (*region_)[mesh_.index(i, j)]; }

    long at(int i, int j) const { return static_cast<long>(j) * mesh_.nx + i; }
    double h() const { return D == 2 ? std::max(mesh_.dx, mesh_.dy) : mesh_.dx; }

    // Each fluid is active in its real region and within band_cells cells beyond the interface.
    void update_masks() { update_masks(0, mesh_.ny - 1); }
    void mask_cell(int i, int j, double band) {
        const double f = phi_(i, j);
        const bool in = in_region(i, j);
        active_m_[mesh_.index(i, j)] = in && (f < 0 || f <= band);
        active_p_[mesh_.index(i, j)] = in && (f >= 0 || -f <= band);
    }
    // Rows j0 … j1.
    void update_masks(int j0, int j1) {
        const double band = set_.band_cells * h();
        j0 = std::max(0, j0), j1 = std::min(mesh_.ny - 1, j1);
#pragma omp parallel for schedule(static) if (D == 2)
        for (int j = j0; j <= j1; ++j)
            for (int i = 0; i < mesh_.nx; ++i)
                mask_cell(i, j, band);
        minus_.active_changed(j0, j1);
        plus_.active_changed(j0, j1);
    }
    // The cells of `tube` (sorted) after φ changed, with the region unchanged: outside the level set's tube
    // φ keeps its sign and lies beyond the band, so no other cell's mask changes.
    void update_masks(const std::vector<int>& tube) {
        if (tube.empty()) return;
        const double band = set_.band_cells * h();
        const long n = static_cast<long>(tube.size());
#pragma omp parallel for schedule(static) if (D == 2)
        for (long k = 0; k < n; ++k)
            mask_cell(tube[k] % mesh_.nx, tube[k] / mesh_.nx, band);
        minus_.active_changed(tube.front() / mesh_.nx, tube.back() / mesh_.nx);
        plus_.active_changed(tube.front() / mesh_.nx, tube.back() / mesh_.nx);
    }

    // Fields of one fluid during the interface treatment: primitive state per interior cell.
    struct Fields {
        std::vector<double> rho, u, v, p;
        std::vector<char> known;
        std::vector<double*> all() { return {rho.data(), u.data(), v.data(), p.data()}; }
    };
    Fields fm_, fp_; // the minus and plus fluid's (work arrays, as un_)

    // The cells near the level set's tube (all cells without one) are written: the interface treatment
    // reads no other. On many ranks the states of this rank's rows only (LevelSet::gather_near brings the
    // others').
    template <class S> void read_fields(const S& scheme, bool minus, Fields& f) const {
        const size_t n = static_cast<size_t>(mesh_.nx) * mesh_.ny;
        for (auto* a : {&f.rho, &f.u, &f.v, &f.p})
            if (a->size() != n) a->resize(n);
        if (f.known.size() != n) f.known.resize(n);
        const std::vector<int>& cells = phi_.near_tube();
        const long m = static_cast<long>(cells.size());
#pragma omp parallel for schedule(static) if (D == 2)
        for (long c = 0; c < m; ++c) {
            const int k = cells[c], i = k % mesh_.nx, j = k / mesh_.nx;
            f.known[k] = in_region(i, j) && (phi_(i, j) < 0) == minus;
            if (ranks_ && phi_.row_owner()[j] != ranks_->rank()) continue;
            const Primitive w = scheme.cell_average(i, j);
            f.rho[k] = w.rho, f.u[k] = w.u, f.v[k] = w.v, f.p[k] = w.p;
        }
    }
    // Weighted mean of the other fluid's real states around cell (i, j), favouring the cells that lie
    // across the interface along the normal (sign +1: towards φ > 0).
    bool across(const Fields& other, int i, int j, const std::array<double, 2>& n, double sign,
                Primitive& w) const {
        // Neighbours in pairs of mirror images, (−x, +x), (−y, +y), (−x−y, +x+y), (+x−y, −x+y), summed as
        // ((e0 + e1) + (e2 + e3)) + ((c0 + c1) + (c2 + c3)): mirror-image cells round alike.
        constexpr int off[8][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-1, -1}, {1, 1}, {1, -1}, {-1, 1}};
        double tw[8] = {}, tq[4][8] = {}, tany[4][8] = {};
        double any = 0;
        for (int m = 0; m < (D == 2 ? 8 : 2); ++m) {
            const int a = off[m][0], b = off[m][1];
            const int ni = i + a, nj = j + b;
            if (ni < 0 || ni >= mesh_.nx || nj < 0 || nj >= mesh_.ny) continue;
            const long k = at(ni, nj);
            if (!other.known[k]) continue;
            const double ex = a * mesh_.dx, ey = b * mesh_.dy, len = std::hypot(ex, ey);
            const double wk = std::max(0.0, sign * (n[0] * ex + n[1] * ey) / len);
            const double q[4] = {other.rho[k], other.u[k], other.v[k], other.p[k]};
            for (int c = 0; c < 4; ++c)
                tq[c][m] = wk * q[c], tany[c][m] = q[c];
            tw[m] = wk;
            any += 1;
        }
        if (any == 0) return false;
        auto sum8 = [](const double* t) {
            return ((t[0] + t[1]) + (t[2] + t[3])) + ((t[4] + t[5]) + (t[6] + t[7]));
        };
        double acc[4], acc_any[4];
        for (int c = 0; c < 4; ++c)
            acc[c] = sum8(tq[c]), acc_any[c] = sum8(tany[c]);
        const double wsum = sum8(tw);
        const double* s = wsum > 1e-12 ? acc : acc_any;
        const double d = wsum > 1e-12 ? wsum : any;
        w = {s[0] / d, s[1] / d, s[2] / d, s[3] / d};
        return true;
    }

    [[noreturn]] void fail(int i, int j, const std::string& what) const {
        std::ostringstream s;
        s << what << " at the interface in cell (" << i;
        if (D == 2) s << ", " << j;
        s << ") at x = " << mesh_.xc(i);
        if (D == 2) s << ", y = " << mesh_.yc(j);
        s << ", t = " << time() << " s";
        throw SolverFailure(s.str());
    }

    // Interface cells: real cells with a 4-neighbour of the other fluid (within the region), all in the
    // level set's tube. Found in parallel, listed in row-major order.
    std::vector<std::array<int, 2>> interface_cells() {
        const int nx = mesh_.nx, ny = mesh_.ny;
        cut_.resize(static_cast<size_t>(nx) * ny);
        const std::vector<int>& tube = phi_.tube();
        const long m = static_cast<long>(tube.size());
#pragma omp parallel for schedule(static) if (D == 2)
        for (long t = 0; t < m; ++t) {
            const int i = tube[t] % nx, j = tube[t] / nx;
            cut_[at(i, j)] = 0;
            if (!in_region(i, j)) continue;
            const bool neg = phi_(i, j) < 0;
            auto other = [&](int a, int b) { return in_region(a, b) && (phi_(a, b) < 0) != neg; };
            bool cut = false;
            if (i > 0) cut |= other(i - 1, j);
            if (i + 1 < nx) cut |= other(i + 1, j);
            if (D == 2 && j > 0) cut |= other(i, j - 1);
            if (D == 2 && j + 1 < ny) cut |= other(i, j + 1);
            cut_[at(i, j)] = cut;
        }
        std::vector<std::array<int, 2>> cells;
        for (const int k : tube)
            if (cut_[k]) cells.push_back({k % nx, k / nx});
        return cells;
    }

    // Within `band` of the interface: the extension velocity un·n, and the other fluid's ghost cells from
    // the extrapolated interface states (real and modified GFM) or from the real fluid's pressure and
    // velocity with the ghost fluid's extrapolated entropy sm, sp (original GFM).
    void fill_bands(const Fields& fm, const Fields& fp, const std::vector<double>& sm,
                    const std::vector<double>& sp, const std::vector<double>& un, double band) {
        const int nx = mesh_.nx, ny = mesh_.ny;
        const size_t n = static_cast<size_t>(nx) * ny;
        if (wx_.size() != n) wx_.resize(n);
        if (wy_.size() != n) wy_.resize(n);
        // w vanishes outside the band: a cell leaves near_tube() only from beyond it.
        const std::vector<int>& cells = phi_.near_tube();
        const long m = static_cast<long>(cells.size());
        // On many ranks, the rows a stage of this rank reads (its block and the stage's depth beyond): w is
        // read in the rank's own rows, the ghost cells as deep as a stage reads; the others' are theirs.
        const int depth = std::max(minus_.stage_depth(), plus_.stage_depth());
        const int ja = ranks_ ? ranks_->begin() - depth : 0, jb = ranks_ ? ranks_->end() + depth : ny;
#pragma omp parallel for schedule(static) if (D == 2)
        for (long c = 0; c < m; ++c) {
            const int k = cells[c], i = k % nx, j = k / nx;
            if (j < ja || j >= jb) continue;
            const double f = phi_(i, j);
            wx_[k] = wy_[k] = 0.0;
            if (std::abs(f) > band || !in_region(i, j)) continue;
            std::array<double, 2> nrm = phi_.normal(i, j);
            if (D == 1) nrm = {nrm[0] >= 0 ? 1.0 : -1.0, 0.0};
            wx_[k] = un[k] * nrm[0];
            wy_[k] = un[k] * nrm[1];
            const bool neg = f < 0;
            if (set_.method != GhostMethod::Original) {
                // Ghost cells of the other fluid here.
                if (neg)
                    plus_.set_cell_state(i, j, {fp.rho[k], fp.u[k], fp.v[k], fp.p[k]});
                else
                    minus_.set_cell_state(i, j, {fm.rho[k], fm.u[k], fm.v[k], fm.p[k]});
            } else {
                // Pressure and velocity of the real fluid, entropy of the ghost fluid.
                const Fields& real = neg ? fm : fp;
                const RiemannMaterial& gm = neg ? mat_p_ : mat_m_;
                const double s = neg ? sp[k] : sm[k];
                const double pbar = std::max(real.p[k] + gm.pi, 1e-6 * (std::abs(real.p[k]) + gm.pi + 1.0));
                const double rho =
                    neg ? plus_.eos().entropy_density(s, pbar) : minus_.eos().entropy_density(s, pbar);
                const Primitive g{rho, real.u[k], real.v[k], pbar - gm.pi};
                if (neg)
                    plus_.set_cell_state(i, j, g);
                else
                    minus_.set_cell_state(i, j, g);
            }
        }
    }

    // Interface states, ghost bands and the extension velocity (physics.md §4, paper §3.2).
    void treat_interface() {
        const int nx = mesh_.nx, ny = mesh_.ny;
        const long n = static_cast<long>(nx) * ny;
        Fields &fm = fm_, &fp = fp_;
        read_fields(minus_, true, fm);
        read_fields(plus_, false, fp);
        // Many ranks: the states near the tube of the other ranks' rows.
        phi_.gather_near({fm.rho.data(), fm.u.data(), fm.v.data(), fm.p.data(), fp.rho.data(),
                          fp.u.data(), fp.v.data(), fp.p.data()});
        std::vector<double>& un = un_;
        std::vector<char>& un_known = un_known_;
        un.resize(n);
        un_known.resize(n);
        const std::vector<int>& near = phi_.near_tube();
        const long m = static_cast<long>(near.size());
#pragma omp parallel for schedule(static) if (D == 2)
        for (long c = 0; c < m; ++c)
            un[near[c]] = 0.0, un_known[near[c]] = 0;
        // Original GFM: the entropy function of each fluid (EquationOfState::entropy), extrapolated from its
        // side.
        std::vector<double> sm, sp;
        if (set_.method == GhostMethod::Original) {
            sm.resize(n), sp.resize(n);
            for (const int k : near) {
                sm[k] = minus_.eos().entropy(fm.rho[k], fm.p[k]);
                sp[k] = plus_.eos().entropy(fp.rho[k], fp.p[k]);
            }
        }
        const std::vector<std::array<int, 2>> cells = interface_cells();
        std::vector<Primitive> redefined(cells.size());
        for (size_t c = 0; c < cells.size(); ++c) {
            const int i = cells[c][0], j = cells[c][1];
            const long k = at(i, j);
            const bool neg = phi_(i, j) < 0;
            std::array<double, 2> nrm = phi_.normal(i, j);
            if (D == 1) nrm = {nrm[0] >= 0 ? 1.0 : -1.0, 0.0};
            const Fields& own = neg ? fm : fp;
            const Primitive w_own{own.rho[k], own.u[k], own.v[k], own.p[k]};
            Primitive w_other;
            if (!across(neg ? fp : fm, i, j, nrm, neg ? 1.0 : -1.0, w_other)) continue;
            const Primitive& wl = neg ? w_own : w_other; // minus side is "left" along n
            const Primitive& wr = neg ? w_other : w_own;
            const double unl = wl.u * nrm[0] + wl.v * nrm[1], unr = wr.u * nrm[0] + wr.v * nrm[1];
            if (set_.method == GhostMethod::Original) {
                un[k] = 0.5 * (unl + unr);
                un_known[k] = 1;
                continue;
            }
            InterfaceState st;
            try {
                st = solve_interface(mat_m_, {wl.rho, unl, wl.p}, mat_p_, {wr.rho, unr, wr.p}, set_.riemann);
            } catch (const std::runtime_error& e) {
                fail(i, j, e.what());
            }
            if (!std::isfinite(st.p) || !std::isfinite(st.u)) fail(i, j, "non-finite interface state");
            un[k] = st.u;
            un_known[k] = 1;
            const double ut_u = w_own.u - (neg ? unl : unr) * nrm[0],
                         ut_v = w_own.v - (neg ? unl : unr) * nrm[1];
            redefined[c] = {neg ? st.rho_l : st.rho_r, ut_u + st.u * nrm[0],
                            D == 2 ? ut_v + st.u * nrm[1] : 0.0, st.p};
        }
        // The interface states replace the real states only once every interface cell is solved: each
        // Riemann problem sees the real states of both sides, whatever the order the cells are visited in
        // (written in place, a cell's neighbours across would be redefined or not by their index, and
        // mirror-image cells would differ).
        for (size_t c = 0; c < cells.size(); ++c) {
            if (!(redefined[c].rho > 0)) continue;
            const long k = at(cells[c][0], cells[c][1]);
            Fields& f = phi_(cells[c][0], cells[c][1]) < 0 ? fm : fp;
            f.rho[k] = redefined[c].rho, f.u[k] = redefined[c].u, f.v[k] = redefined[c].v,
            f.p[k] = redefined[c].p;
        }
        // Ghost bands by constant extrapolation along the normal, one cell wider than the active band so
        // that the outermost active cells see fresh neighbours.
        const double cells_wide = set_.band_cells + 1, band = cells_wide * h();
        if (set_.method != GhostMethod::Original) {
            phi_.extrapolate(fm.all(), fm.known, cells_wide);
            phi_.extrapolate(fp.all(), fp.known, cells_wide);
        } else {
            phi_.extrapolate({sm.data()}, fm.known, cells_wide);
            phi_.extrapolate({sp.data()}, fp.known, cells_wide);
        }
        phi_.extrapolate({un.data()}, un_known, cells_wide);
        fill_bands(fm, fp, sm, sp, un, band);
        if (set_.method == GhostMethod::Real)
            for (size_t c = 0; c < cells.size(); ++c) {
                const int i = cells[c][0], j = cells[c][1];
                if (!(redefined[c].rho > 0)) continue; // no state across (isolated cell)
                if (phi_(i, j) < 0)
                    minus_.set_cell_state(i, j, redefined[c]);
                else
                    plus_.set_cell_state(i, j, redefined[c]);
            }
    }
};

} // namespace undex::fluid
