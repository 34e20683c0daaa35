// A 2D fluid around a moving structure (physics.md §5.1, paper §3.3): the structure level set φ_s and the
// ghost fluid method at the structure's wet faces.
//
// - One fluid solution per wet face (a plate in water has two: below and above). A cell is real for face f
//   where φ_f < 0, φ_f the signed distance of its centre to face f (< 0 on the fluid side); a cell on the
//   fluid side of two faces is refused (the faces cross). Each solution is solved only in its real cells;
//   cells inside the structure hold no fluid and cost nothing.
// - φ_f is rebuilt every step from the node positions the structure offers (exact, no drift), but only in
//   the cells within `band_cells + 2` cells of a segment (each segment visits the cells of its bounding box
//   grown by that much: a binned search, linear in the segments). A face that ends inside the domain is
//   continued along its end segments by rays to the domain's boundary (WetFaces::to_segment with rays): the
//   structure is taken to span the domain, and the band around a face and its rays separates its sides.
//   Elsewhere only the sign matters; it cannot change while the faces move less than a cell per step (the
//   CFL bound), and it is set once, by a flood fill from the band, when the structure attaches.
// - The ghost band 0 ≤ φ_f < band_cells · h (h = max(Δx, Δy)) of each face is set at every stage, as the
//   domain's ghost cells are: pressure and normal velocity (p_I, u_I) of the structure interpolated along the
//   face at the cell's closest point, tangential velocity of the fluid (slip), density on the fluid's wall
//   isentrope (EquationOfState::wall_density) from p to p_I: the state along the normal is constant, the
//   constant extension of paper eq. 33. The fluid state it starts from is the cell average of the first real
//   cell met walking from the closest point into the fluid along the normal; a plate thinner than the band
//   has cells that are ghost cells of both faces, each with its own state in its own solution, and each real
//   cell's fluxes see the ghost state of its own side.
// - Cells uncovered by the structure were in the band: they hold the ghost state of the last stage.
// - The fluid of a face is one Scheme, or two fluids with their own level set φ (TwoFluid: a gas bubble in
//   water). φ_s and φ live together: the face's real cells are the region where either fluid may be, so a
//   cell inside the structure is never gas nor water; the gas–water interface is treated within the region
//   only; the structure's ghost band is set in both fluids' schemes, each from its own state at the source
//   cell, so a bubble that reaches the plate meets it as water does. A structure that crosses the second
//   fluid when it attaches is refused.
#pragma once
#include "fluid/scheme.hpp"
#include "fluid/two_fluid.hpp"
#include "fluid/wet_faces.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

namespace undex::fluid {

// M: the fluid of one face, Scheme<2, K, Eos> or TwoFluid<2, K, EosM, EosP>; `make` builds it with the
// initial data (once before the structure attaches, and once more per wet face beyond the first).
template <int K, class M> class WetFluid final : public WetSolver {
  public:
    WetFluid(const Mesh& mesh, std::function<std::unique_ptr<M>()> make, int band_cells = 3)
        : mesh_(mesh), band_cells_(band_cells), make_(std::move(make)), base_(make_()) {
        // The reach of the ghost bands from the start: the rows each rank reads beyond its block (halo)
        // are known when the ranks divide the mesh, before the structure attaches.
        base_->for_each_scheme([this](auto& sc) { sc.set_stage_ghosts(nullptr, ghost_reach()); });
    }

    // ---- the structure ------------------------------------------------------------------------------
    void attach(const std::vector<int>& face, const std::vector<double>& x, const std::vector<double>& y,
                const std::vector<double>& normal_x, const std::vector<double>& normal_y) override {
        if (!base_ || base_->steps() != 0) throw std::logic_error("WetFluid::attach twice or after a step");
        faces_.emplace(face, x, y, normal_x, normal_y, mesh_.alpha);
        const long n = cells();
        p_I_.assign(faces_->nodes(), 0.0);
        u_I_.assign(faces_->nodes(), 0.0);
        interface_set_ = false;
        nearest_.assign(n, Nearest{});
        for (int f = 0; f < faces_->faces(); ++f) {
            auto side = std::make_unique<Side>();
            side->scheme = f == 0 ? std::move(base_) : make_();
            if (f > 0 && ranks_) side->scheme->divide(ranks_);
            side->mask.assign(mesh_.padded_cells(), 0);
            side->phi.assign(n, 0.0);
            sides_.push_back(std::move(side));
        }
        for (auto& sd : sides_)
            std::fill(sd->phi.begin(), sd->phi.end(), std::numeric_limits<double>::quiet_NaN());
        for (int f = 0; f < faces_->faces(); ++f) {
            Side& sd = *sides_[f];
            sd.scheme->set_active(&sd.mask);
            sd.scheme->for_each_scheme([this, f](auto& sc) {
                sc.set_stage_ghosts([this, f, &sc](double* U) { fill_band(f, sc, U); }, ghost_reach());
            });
        }
        rebuild(true);
        refuse_second_fluid_inside();
        keep_own_second_fluid();
    }

    // On a geometry it cannot hold, the faces, φ and the real cells are those of the last good positions
    // again before the failure is thrown, so that the last good state is written with them.
    void move(const std::vector<double>& x, const std::vector<double>& y) override {
        const WetFaces good = *faces_;
        try {
            faces_->set_positions(x, y);
            rebuild();
        } catch (const std::exception& e) {
            *faces_ = good;
            rebuild();
            if (const auto* f = dynamic_cast<const SolverFailure*>(&e)) throw *f;
            fail(e.what());
        }
    }

    const WetFaces& faces() const override { return *faces_; }

    // On many ranks each node's sample is taken by the rank whose block holds the node's probe cell (its
    // neighbours across an edge are in the halo) and reaches every rank through one reduction (max, the
    // others giving −∞): bitwise the one-rank sample.
    std::vector<WetSample> sample() const override {
        const WetFaces& w = *faces_;
        std::vector<WetSample> out(w.nodes());
        std::vector<double> all(ranks_ ? 5 * w.nodes() : 0, -std::numeric_limits<double>::infinity());
        for (int k = 0; k < w.nodes(); ++k) {
            const auto n = w.normal(k);
            const int f = w.face(k);
            double px, py;
            if (!probe(f, w.x(k), w.y(k), n[0], n[1], px, py)) {
                std::ostringstream s;
                s << "wet node " << k << " of face " << f << " at (" << w.x(k) << ", " << w.y(k)
                  << ") has no fluid within " << band_cells_ << " cells along its normal";
                fail(s.str());
            }
            // The trace along the normal of the real cell(s) at the probe point: from the cell's centre along
            // n to the node's level, averaged along the face's direction across the cell (chord_mean: for a
            // face along the mesh, the mean over the cell's face, the 1D trace of a plane wave; the
            // polynomial's variation along the face would feed back through p_I into the ghost band and
            // grow). A probe point on a cell edge takes the mean of the real cells on both sides, so that
            // mirror-image nodes see mirror-image cells.
            // Summed in mirror-symmetric pairs ((c0 + c1) + (c2 + c3), absent cells adding 0), so that
            // mirror-image nodes get bitwise mirror-image samples.
            double v[4][5] = {};
            int used = 0;
            const std::array<long, 4> cells = cells_at(px, py);
            if (ranks_ && !mine(static_cast<int>(cells[0] / mesh_.nx))) continue;
            for (int m = 0; m < 4; ++m) {
                const long c = cells[m];
                if (c < 0 || !(sides_[f]->phi[c] < 0)) continue;
                const int ci = static_cast<int>(c % mesh_.nx), cj = static_cast<int>(c / mesh_.nx);
                const double xc = mesh_.xc(ci), yc = mesh_.yc(cj);
                const double d = (w.x(k) - xc) * n[0] + (w.y(k) - yc) * n[1];
                sides_[f]->scheme->scheme_at(ci, cj, [&](const auto& sc) {
                    const Primitive p =
                        chord_mean_of(sc, mesh_, ci, cj, xc + d * n[0], yc + d * n[1], -n[1], n[0]);
                    const double q[5] = {p.p, p.u * n[0] + p.v * n[1], p.rho,
                                         sc.eos().sound_speed(p.rho, p.p), p.u};
                    std::copy_n(q, 5, v[m]);
                });
                ++used;
            }
            double acc[5];
            for (int q = 0; q < 5; ++q)
                acc[q] = ((v[0][q] + v[1][q]) + (v[2][q] + v[3][q])) / used;
            out[k] = {acc[0], acc[1], acc[2], acc[3], acc[4]};
            if (ranks_) std::copy_n(acc, 5, all.begin() + 5 * k);
        }
        if (!ranks_) return out;
        ranks_->max(all);
        for (int k = 0; k < w.nodes(); ++k)
            out[k] = {all[5 * k], all[5 * k + 1], all[5 * k + 2], all[5 * k + 3], all[5 * k + 4]};
        return out;
    }

    void set_interface(const std::vector<double>& p_I, const std::vector<double>& u_I) override {
        p_I_ = p_I;
        u_I_ = u_I;
        interface_set_ = true;
    }

    // After attach (the same wet nodes as the run that wrote the checkpoint): the faces where the structure
    // put them, and per face its fluid, real cells, distances and ghost band.
    void state(State& s) override {
        if (sides_.empty()) {
            State b = s.scope("base");
            return base_->state(b);
        }
        State f = s.scope("faces");
        faces_->state(f);
        for (size_t k = 0; k < sides_.size(); ++k) {
            Side& sd = *sides_[k];
            State side = s.scope("side" + std::to_string(k)), scheme = side.scope("scheme");
            sd.scheme->state(scheme);
            side.io("mask", sd.mask);
            side.io("phi", sd.phi);
            side.io("near", sd.near);
            side.io("ghosts", sd.ghosts);
        }
        s.io("p_I", p_I_);
        s.io("u_I", u_I_);
        s.io("interface_set", interface_set_);
    }

    std::vector<double> structure_level_set() const override {
        if (sides_.empty()) return {};
        std::vector<double> out(cells());
        for (long c = 0; c < cells(); ++c) {
            double v = far();
            for (const auto& sd : sides_)
                v = std::min(v, sd->phi[c]);
            out[c] = v;
        }
        return out;
    }

    // ---- the fluid ----------------------------------------------------------------------------------
    const Mesh& mesh() const override { return mesh_; }
    int degree() const override { return K; }
    int variables() const override { return 4; }
    int basis_functions() const override { return Basis<2, K>::NB; }
    double time() const override { return first().time(); }
    long steps() const override { return first().steps(); }
    double stable_dt() const override {
        if (sides_.empty()) return base_->stable_dt();
        double dt = std::numeric_limits<double>::infinity();
        for (const auto& sd : sides_)
            dt = std::min(dt, sd->scheme->stable_dt());
        return dt;
    }
    void step(double dt) override {
        if (sides_.empty()) return base_->step(dt);
        if (!interface_set_) throw std::logic_error("WetFluid::step before set_interface");
        step_phased(*this, ranks_, dt);
    }
    // The step in phases (step_phased): every face's fluid in lockstep, each phase's exchanges together
    // (so that a rank whose rows hold mostly one face's fluid does not wait on the others for each face's).
    void begin_step(double dt) {
        for (auto& sd : sides_)
            sd->scheme->begin_step(dt);
    }
    void phase(int k, int part) {
        for (auto& sd : sides_)
            sd->scheme->phase(k, part);
    }
    void exchanges_after(int k, std::vector<Ranks::Rows>& x) {
        for (auto& sd : sides_)
            sd->scheme->exchanges_after(k, x);
    }
    // A face's fluid that fails: the others' steps are taken back.
    void end_step() {
        std::optional<SolverFailure> failure;
        std::vector<char> stepped(sides_.size(), 0);
        for (size_t f = 0; f < sides_.size(); ++f) {
            try {
                sides_[f]->scheme->end_step();
                stepped[f] = 1;
            } catch (const SolverFailure& e) {
                if (!failure)
                    failure = SolverFailure("fluid of wet face " + std::to_string(f) + ": " + e.what());
            }
        }
        if (!failure) return;
        for (size_t f = 0; f < sides_.size(); ++f)
            if (stepped[f]) sides_[f]->scheme->revert_step();
        throw *failure;
    }
    void revert_step() override {
        if (sides_.empty()) return base_->revert_step();
        for (auto& sd : sides_)
            sd->scheme->revert_step();
    }
    void project(const std::function<void(double, double, double*)>&) override {
        throw std::logic_error("a WetFluid takes its initial data from the function that builds its fluid");
    }
    std::vector<double> coefficients() const override {
        if (sides_.empty()) return base_->coefficients();
        std::vector<double> out = sides_[0]->scheme->coefficients();
        const int nc = variables() * basis_functions();
        for (size_t f = 1; f < sides_.size(); ++f) {
            const auto c = sides_[f]->scheme->coefficients();
            for (long k = 0; k < cells(); ++k)
                if (owner(k) == static_cast<int>(f))
                    std::copy_n(c.begin() + k * nc, nc, out.begin() + k * nc);
        }
        return out;
    }
    void set_coefficients(const std::vector<double>& c, double time) override {
        if (sides_.empty()) return base_->set_coefficients(c, time);
        for (auto& sd : sides_)
            sd->scheme->set_coefficients(c, time);
    }
    Primitive evaluate(double x, double y) const override {
        if (sides_.empty()) return base_->evaluate(x, y);
        return sides_[owner(cell_of(x, y))]->scheme->evaluate(x, y);
    }
    Primitive cell_average(int i, int j) const override {
        if (sides_.empty()) return base_->cell_average(i, j);
        return sides_[owner(at(i, j))]->scheme->cell_average(i, j);
    }
    double void_fraction(double p) const override { return first().void_fraction(p); }
    bool has_cavitation() const override { return first().has_cavitation(); }
    double cell_void_fraction(int i, int j) const override {
        if (sides_.empty()) return base_->cell_void_fraction(i, j);
        return sides_[owner(at(i, j))]->scheme->cell_void_fraction(i, j);
    }
    // The second fluid's level set φ (TwoFluid), from the fluid that owns each cell; empty for one fluid.
    std::vector<double> level_set() const override {
        if (sides_.empty()) return base_->level_set();
        std::vector<std::vector<double>> phi;
        for (const auto& sd : sides_)
            phi.push_back(sd->scheme->level_set());
        if (phi[0].empty()) return {};
        std::vector<double> out(cells());
        for (long c = 0; c < cells(); ++c)
            out[c] = phi[owner(c)][c];
        return out;
    }

    void set_level_set(const std::vector<double>& phi) override {
        if (sides_.empty()) return base_->set_level_set(phi);
        for (auto& sd : sides_) {
            sd->scheme->set_level_set(phi);
            sd->scheme->active_changed();
        }
    }

    // Mass, momentum and energy of the real cells of every face's fluid.
    std::vector<double> row_totals(int j0, int j1) const override {
        if (sides_.empty()) return base_->row_totals(j0, j1);
        std::vector<double> t(4L * (j1 - j0), 0.0);
        for (int j = j0; j < j1; ++j)
            for (const auto& sd : sides_)
                for (int i = 0; i < mesh_.nx; ++i) {
                    if (!(sd->phi[at(i, j)] < 0)) continue;
                    double q[4];
                    sd->scheme->scheme_at(i, j, [&](const auto& sc) {
                        euler::to_conserved<2>(sc.eos(), sc.cell_average(i, j), q);
                    });
                    for (int v = 0; v < 4; ++v)
                        t[4 * (j - j0) + v] += q[v] * mesh_.dx * mesh_.dy;
                }
        return t;
    }
    long troubled_cells() const override {
        return sum([](const M& s) { return s.troubled_cells(); });
    }
    long positivity_scaled_cells() const override {
        return sum([](const M& s) { return s.positivity_scaled_cells(); });
    }
    long cell_updates() const override {
        return sum([](const M& s) { return s.cell_updates(); });
    }
    long cell_updates_skipped() const override {
        return sum([](const M& s) { return s.cell_updates_skipped(); });
    }
    double sound_speed(double x, double y) const override {
        if (sides_.empty()) return base_->sound_speed(x, y);
        return sides_[owner(cell_of(x, y))]->scheme->sound_speed(x, y);
    }
    double pressure_floor() const override { return first().pressure_floor(); }
    void set_structure_state(double, double) override {}

    // Many ranks (fluid/ranks.hpp): every face's fluid divided alike. The faces, φ_s, the real cells and
    // the ghost bands are every rank's, bit for bit the same (they follow from the node positions alone); a
    // ghost cell is set by the ranks whose stage reads it, from its source cell in their block or its halo
    // (Scheme::stage_depth covers the band's reach).
    bool divisible() const override { return first().divisible(); }
    void divide(const Ranks* r) override {
        ranks_ = r && r->many() ? r : nullptr;
        if (sides_.empty()) return base_->divide(r);
        for (auto& sd : sides_)
            sd->scheme->divide(r);
    }
    int halo() const override { return first().halo(); }
    void share() override {
        if (sides_.empty()) return base_->share();
        for (auto& sd : sides_)
            sd->scheme->share();
    }
    std::vector<double> row_cost() const override {
        if (sides_.empty()) return base_->row_cost();
        std::vector<double> c = sides_[0]->scheme->row_cost();
        for (size_t f = 1; f < sides_.size(); ++f) {
            const std::vector<double> more = sides_[f]->scheme->row_cost();
            for (size_t j = 0; j < c.size(); ++j)
                c[j] += more[j];
        }
        return c;
    }

    // Whether interior cell (i, j) is real for face f (for tests).
    bool real(int f, int i, int j) const { return sides_[f]->phi[at(i, j)] < 0; }
    double phi(int f, int i, int j) const { return sides_[f]->phi[at(i, j)]; }

  private:
    // A ghost cell of a face: where it is, its closest point on the face (segment a, parameter t, normal n)
    // and the real cell it takes the fluid state from.
    struct Ghost {
        int i, j, a;
        double t, nx, ny;
        int si, sj;
    };
    struct Side {
        std::unique_ptr<M> scheme; // the fluid of the face: one scheme or two
        std::vector<char> mask;    // padded cells: real
        std::vector<double> phi;   // interior cells: signed distance to the face (±far() beyond the band)
        std::vector<long> near;    // cells whose distance was computed at the last rebuild
        std::vector<Ghost> ghosts; // the band set at every stage
        int rows[2] = {0, -1};     // the rows of the cells near the face at the last two rebuilds
    };
    struct Nearest { // the nearest segment a cell has met, by the square of its distance
        double distance2 = std::numeric_limits<double>::infinity();
        int a = -1;
    };

    Mesh mesh_;
    int band_cells_;
    std::function<std::unique_ptr<M>()> make_;
    std::unique_ptr<M> base_; // the fluid before the structure attaches (initial data)
    std::optional<WetFaces> faces_;
    std::vector<std::unique_ptr<Side>> sides_;
    std::vector<Nearest> nearest_; // scratch of the rebuild, reset after use
    std::vector<double> p_I_, u_I_;
    bool interface_set_ = false;
    const Ranks* ranks_ = nullptr; // many ranks, else null

    // How far a ghost value reads the fluid, in cells: a ghost cell lies within far() of its face and reads
    // the first real cell within band_cells + 1 of the face along the normal (first_real).
    int ghost_reach() const { return 2 * band_cells_ + 3; }
    bool mine(int j) const { return j >= ranks_->begin() && j < ranks_->end(); }

    long cells() const { return static_cast<long>(mesh_.nx) * mesh_.ny; }
    long at(int i, int j) const { return static_cast<long>(j) * mesh_.nx + i; }
    double h() const { return std::max(mesh_.dx, mesh_.dy); }
    // |φ| beyond the cells whose distance is computed.
    double far() const { return (band_cells_ + 2) * h(); }
    const M& first() const { return sides_.empty() ? *base_ : *sides_[0]->scheme; }
    template <class F> long sum(F&& f) const {
        if (sides_.empty()) return f(*base_);
        long n = 0;
        for (const auto& sd : sides_)
            n += f(*sd->scheme);
        return n;
    }
    long cell_of(double x, double y) const {
        const int i = std::clamp(static_cast<int>(std::floor((x - mesh_.x_min) / mesh_.dx)), 0, mesh_.nx - 1);
        const int j = std::clamp(static_cast<int>(std::floor((y - mesh_.y_min) / mesh_.dy)), 0, mesh_.ny - 1);
        return at(i, j);
    }
    // The face whose fluid owns a cell: the one it is real for, or else (inside the structure) the nearest.
    int owner(long c) const {
        int best = 0;
        for (size_t f = 0; f < sides_.size(); ++f) {
            if (sides_[f]->phi[c] < 0) return static_cast<int>(f);
            if (sides_[f]->phi[c] < sides_[best]->phi[c]) best = static_cast<int>(f);
        }
        return best;
    }

    [[noreturn]] void fail(const std::string& what) const {
        std::ostringstream s;
        s << what << " (t = " << time() << " s, step " << steps() << ")";
        throw SolverFailure(s.str());
    }

    // The mean of cell (i, j)'s polynomial along the chord through (x, y) (clamped into the cell) in the
    // direction (tx, ty), over the part of the chord inside the cell: three Gauss points, exact for the
    // degrees used.
    template <class S>
    static Primitive chord_mean_of(const S& sc, const Mesh& m, int i, int j, double x, double y, double tx,
                                   double ty) {
        const double x0 = m.xc(i) - 0.5 * m.dx, x1 = m.xc(i) + 0.5 * m.dx;
        const double y0 = m.yc(j) - 0.5 * m.dy, y1 = m.yc(j) + 0.5 * m.dy;
        x = std::clamp(x, x0, x1), y = std::clamp(y, y0, y1);
        double s0 = -1e300, s1 = 1e300;
        auto clip = [&](double p, double d, double lo, double hi) {
            if (std::abs(d) < 1e-14) return;
            const double a = (lo - p) / d, b = (hi - p) / d;
            s0 = std::max(s0, std::min(a, b)), s1 = std::min(s1, std::max(a, b));
        };
        clip(x, tx, x0, x1);
        clip(y, ty, y0, y1);
        if (!(s1 > s0)) return sc.evaluate_in(i, j, x, y);
        const double mid = 0.5 * (s0 + s1), half = 0.5 * (s1 - s0), g = std::sqrt(0.6) * half;
        const Primitive a = sc.evaluate_in(i, j, x + (mid - g) * tx, y + (mid - g) * ty);
        const Primitive b = sc.evaluate_in(i, j, x + mid * tx, y + mid * ty);
        const Primitive c = sc.evaluate_in(i, j, x + (mid + g) * tx, y + (mid + g) * ty);
        // The outer points summed first: the mean is the same bitwise whichever way the chord runs.
        auto mean = [](double l, double m, double r) { return 5.0 / 18 * (l + r) + 8.0 / 18 * m; };
        return {mean(a.rho, b.rho, c.rho), mean(a.u, b.u, c.u), mean(a.v, b.v, c.v), mean(a.p, b.p, c.p)};
    }

    // The first point along −n from (x, y), in quarter cells up to the band's width, whose cell is real for
    // face f; false if there is none.
    bool probe(int f, double x, double y, double nx, double ny, double& px, double& py) const {
        const Side& sd = *sides_[f];
        for (int m = 0; m <= 4 * band_cells_; ++m) {
            const double d = 0.25 * m * h();
            px = x - d * nx, py = y - d * ny;
            for (const long c : cells_at(px, py)) // all cells of an edge: mirror-image nodes alike
                if (c >= 0 && sd.phi[c] < 0) return true;
        }
        return false;
    }
    // The cell containing (x, y), and its neighbour across an edge that (x, y) lies on (up to four cells).
    // Order: (i, j), (i − 1, j), (i, j − 1), (i − 1, j − 1); −1 for a cell that is not there. "On an edge" is
    // within 1e-9 cells of it: the structure's node coordinates and the fluid's cell edges are computed
    // differently (x0 + span·i/n against x_min + i·Δx), and a node and its mirror image must both be on it.
    std::array<long, 4> cells_at(double x, double y) const {
        const double fx = (x - mesh_.x_min) / mesh_.dx, fy = (y - mesh_.y_min) / mesh_.dy;
        const double rx = std::round(fx), ry = std::round(fy);
        // On an edge between two cells of the domain (not on the domain's own edge).
        const bool ex = std::abs(fx - rx) < 1e-9 && rx > 0 && rx < mesh_.nx;
        const bool ey = std::abs(fy - ry) < 1e-9 && ry > 0 && ry < mesh_.ny;
        const int i =
            ex ? static_cast<int>(rx) : std::clamp(static_cast<int>(std::floor(fx)), 0, mesh_.nx - 1);
        const int j =
            ey ? static_cast<int>(ry) : std::clamp(static_cast<int>(std::floor(fy)), 0, mesh_.ny - 1);
        return {at(i, j), ex ? at(i - 1, j) : -1, ey ? at(i, j - 1) : -1, ex && ey ? at(i - 1, j - 1) : -1};
    }
    bool first_real(int f, double x, double y, double nx, double ny, int& ci, int& cj) const {
        double px, py;
        if (!probe(f, x, y, nx, ny, px, py)) return false;
        for (const long c : cells_at(px, py)) // the first real cell of those at the probe point
            if (c >= 0 && sides_[f]->phi[c] < 0) {
                ci = static_cast<int>(c % mesh_.nx), cj = static_cast<int>(c / mesh_.nx);
                return true;
            }
        return false;
    }

    // φ of every face near its segments, the real cells and the ghost bands, from the current positions.
    // At attach (first): the cells beyond the computed band take the side of the band cells they connect
    // to (a flood fill: the band around a face and its rays, 5 cells thick, separates the sides).
    void rebuild(bool first = false) {
        const WetFaces& w = *faces_;
        const double reach = far(), reach2 = reach * reach;
        for (int f = 0; f < w.faces(); ++f) {
            Side& sd = *sides_[f];
            sd.rows[0] = mesh_.ny, sd.rows[1] = -1;
            auto row = [&](long c) {
                const int j = static_cast<int>(c / mesh_.nx);
                sd.rows[0] = std::min(sd.rows[0], j), sd.rows[1] = std::max(sd.rows[1], j);
            };
            for (const long c : sd.near) {
                sd.phi[c] = sd.phi[c] < 0 ? -reach : reach;
                row(c);
            }
            sd.near.clear();
            for (int a = w.begin(f); a + 1 < w.end(f); ++a) {
                // The segment, continued to the domain's far side along a ray at the face's ends.
                const double len = std::hypot(w.x(a + 1) - w.x(a), w.y(a + 1) - w.y(a));
                const double far_t = std::hypot(mesh_.x_max - mesh_.x_min, mesh_.y_max - mesh_.y_min) / len;
                const double t0 = a == w.begin(f) ? -far_t : 0.0, t1 = a + 2 == w.end(f) ? 1.0 + far_t : 1.0;
                const double xa = w.x(a) + t0 * (w.x(a + 1) - w.x(a)),
                             xb = w.x(a) + t1 * (w.x(a + 1) - w.x(a));
                const double ya = w.y(a) + t0 * (w.y(a + 1) - w.y(a)),
                             yb = w.y(a) + t1 * (w.y(a + 1) - w.y(a));
                const double x0 = std::min(xa, xb) - reach, x1 = std::max(xa, xb) + reach;
                const double y0 = std::min(ya, yb) - reach, y1 = std::max(ya, yb) + reach;
                const int i0 = std::max(0, static_cast<int>(std::floor((x0 - mesh_.x_min) / mesh_.dx)));
                const int i1 =
                    std::min(mesh_.nx - 1, static_cast<int>(std::floor((x1 - mesh_.x_min) / mesh_.dx)));
                const int j0 = std::max(0, static_cast<int>(std::floor((y0 - mesh_.y_min) / mesh_.dy)));
                const int j1 =
                    std::min(mesh_.ny - 1, static_cast<int>(std::floor((y1 - mesh_.y_min) / mesh_.dy)));
                for (int j = j0; j <= j1; ++j)
                    for (int i = i0; i <= i1; ++i) {
                        const double d2 = w.distance2(a, mesh_.xc(i), mesh_.yc(j), true);
                        if (d2 >= reach2) continue;
                        Nearest& nb = nearest_[at(i, j)];
                        if (nb.a < 0) sd.near.push_back(at(i, j));
                        if (d2 < nb.distance2) nb = {d2, a};
                    }
            }
            sd.ghosts.clear();
            const double band = band_cells_ * h();
            for (const long c : sd.near) {
                const int i = static_cast<int>(c % mesh_.nx), j = static_cast<int>(c / mesh_.nx);
                const ClosestPoint cp = w.to_segment(nearest_[c].a, mesh_.xc(i), mesh_.yc(j), true);
                nearest_[c] = Nearest{};
                const double d = w.signed_distance(cp, mesh_.xc(i), mesh_.yc(j));
                sd.phi[c] = d;
                row(c);
                if (d >= 0 && d < band) sd.ghosts.push_back({i, j, cp.a, cp.t, cp.nx, cp.ny, -1, -1});
            }
        }
        if (first)
            for (auto& sd : sides_)
                flood_sides(*sd);
        // Real cells; a cell on the fluid side of two faces means the faces cross (or, for faces that end
        // inside the domain, that the water of both meets around an end).
        for (int f = 0; f < w.faces(); ++f) {
            Side& sd = *sides_[f];
            for (const long c : first ? all_cells() : sd.near)
                for (int g = 0; g < w.faces(); ++g)
                    if (g != f && sd.phi[c] < 0 && sides_[g]->phi[c] < 0) {
                        std::ostringstream s;
                        s << "cell (" << c % mesh_.nx << ", " << c / mesh_.nx
                          << ") at x = " << mesh_.xc(c % mesh_.nx)
                          << ", y = " << mesh_.yc(static_cast<int>(c / mesh_.nx))
                          << " lies on the fluid side of wet faces " << std::min(f, g) << " and "
                          << std::max(f, g) << ": the faces cross (a structure turned inside out?)";
                        fail(s.str());
                    }
            // φ changed near the face only (at this rebuild's and the last one's cells), unless first.
            const int j0 = first ? 0 : sd.rows[0], j1 = first ? mesh_.ny - 1 : sd.rows[1];
            for (int j = j0; j <= j1; ++j)
                for (int i = 0; i < mesh_.nx; ++i)
                    sd.mask[mesh_.index(i, j)] = sd.phi[at(i, j)] < 0;
            if (first)
                sd.scheme->active_changed();
            else if (j1 >= j0)
                sd.scheme->active_changed(j0, j1);
            // Each ghost cell's source: the first real cell along the normal from its closest point.
            for (Ghost& g : sd.ghosts) {
                const double cx = w.x(g.a) + g.t * (w.x(g.a + 1) - w.x(g.a));
                const double cy = w.y(g.a) + g.t * (w.y(g.a + 1) - w.y(g.a));
                if (!first_real(f, cx, cy, g.nx, g.ny, g.si, g.sj)) g.si = g.sj = -1;
            }
        }
    }

    std::vector<long> all_cells() const {
        std::vector<long> c(cells());
        for (long k = 0; k < cells(); ++k)
            c[k] = k;
        return c;
    }
    // Cells whose φ is not set (NaN) take ±far() of the set cells they connect to, breadth first.
    void flood_sides(Side& sd) const {
        std::vector<long> queue(sd.near.begin(), sd.near.end());
        for (size_t q = 0; q < queue.size(); ++q) {
            const long c = queue[q];
            const int i = static_cast<int>(c % mesh_.nx), j = static_cast<int>(c / mesh_.nx);
            const double side = sd.phi[c] < 0 ? -far() : far();
            const int ni[4] = {i - 1, i + 1, i, i}, nj[4] = {j, j, j - 1, j + 1};
            for (int m = 0; m < 4; ++m) {
                if (ni[m] < 0 || ni[m] >= mesh_.nx || nj[m] < 0 || nj[m] >= mesh_.ny) continue;
                const long n = at(ni[m], nj[m]);
                if (!std::isnan(sd.phi[n])) continue;
                sd.phi[n] = side;
                queue.push_back(n);
            }
        }
        for (double& v : sd.phi)
            if (std::isnan(v)) v = far(); // no face near: a region cut off from the water (none in practice)
    }

    // A structure that crosses the second fluid (φ < 0 in a cell of no face's fluid) when it attaches.
    void refuse_second_fluid_inside() const {
        if constexpr (requires(const M& m) { m.minus_name(); }) {
            const std::vector<double> phi = sides_[0]->scheme->level_set();
            for (int j = 0; j < mesh_.ny; ++j)
                for (int i = 0; i < mesh_.nx; ++i) {
                    if (!(phi[at(i, j)] < 0)) continue;
                    bool fluid = false;
                    for (const auto& sd : sides_)
                        fluid |= sd->phi[at(i, j)] < 0;
                    if (fluid) continue;
                    std::ostringstream s;
                    s << "the structure crosses the " << sides_[0]->scheme->minus_name() << " in cell (" << i
                      << ", " << j << ") at x = " << mesh_.xc(i) << ", y = " << mesh_.yc(j)
                      << ": a cell inside the structure holds no fluid (move the structure or the "
                      << sides_[0]->scheme->minus_name() << " region apart)";
                    fail(s.str());
                }
        }
    }

    // Each face's fluid is built from the whole case: its φ also marks the second fluid on the other faces'
    // sides. There it is set to the first fluid (φ = +far), so that a face's fluid holds only its own side's
    // bubble (no gas scheme active next to a thin plate for the other side's gas).
    void keep_own_second_fluid() {
        if constexpr (requires(const M& m) { m.minus_name(); }) {
            if (sides_.size() < 2) return;
            for (size_t f = 0; f < sides_.size(); ++f) {
                std::vector<double> phi = sides_[f]->scheme->level_set();
                for (long c = 0; c < cells(); ++c)
                    for (size_t g = 0; g < sides_.size(); ++g)
                        if (g != f && sides_[g]->phi[c] < 0) phi[c] = std::max(phi[c], far());
                sides_[f]->scheme->set_level_set(phi);
                sides_[f]->scheme->active_changed();
            }
        }
    }

    // The ghost band of face f in the stage coefficients U of one of its fluid's schemes (called by the
    // scheme at every stage).
    // On many ranks, only from source cells in the rows the stage's exchange keeps current (the others'
    // ghost cells are beyond what the rank's stage reads).
    template <class S> void fill_band(int f, const S& sc, double* U) const {
        const int lo = ranks_ ? ranks_->begin() - sc.stage_depth() : 0;
        const int hi = ranks_ ? ranks_->end() + sc.stage_depth() : mesh_.ny;
        for (const Ghost& g : sides_[f]->ghosts) {
            if (g.si < 0) continue; // no fluid next to it: keeps its last state
            if (g.sj < lo || g.sj >= hi) continue;
            const Primitive s = sc.average_in(U, g.si, g.sj);
            const double t = std::clamp(g.t, 0.0, 1.0); // on a ray: the end node's values
            const double p_I = (1 - t) * p_I_[g.a] + t * p_I_[g.a + 1];
            const double u_I = (1 - t) * u_I_[g.a] + t * u_I_[g.a + 1];
            const double un = s.u * g.nx + s.v * g.ny;
            const double rho = sc.eos().wall_density(s.rho, s.p, p_I);
            sc.set_state_in(U, g.i, g.j, {rho, s.u + (u_I - un) * g.nx, s.v + (u_I - un) * g.ny, p_I});
        }
    }
};

} // namespace undex::fluid
