// Level-set function φ at the cell centres of a Mesh (physics.md §4): a signed distance with φ < 0 in one
// fluid. Advection and reinitialisation use fifth-order WENO derivatives in Hamilton–Jacobi form (Jiang and
// Peng, SISC 21, 2000) with TVD-RK3 (Shu–Osher); reinitialisation follows Sussman, Smereka and Osher
// (JCP 114, 1994); constant extrapolation across the interface is first-order upwind (Aslam, JCP 193, 2004).
// In 2D φ may live in a narrow band (Peng et al., JCP 155, 1999): the tube of cells with |φ| < tube_cells·h
// is advected and reinitialised, and every cell outside holds ±tube_cells·h exactly, its side of the
// interface; the work of a step then grows with the interface's length, not with the mesh.
#pragma once
#include "fluid/mesh.hpp"
#include "fluid/ranks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace undex::fluid {

class LevelSet {
  public:
    static constexpr int G = 3; // ghost layers of the WENO5 stencils

    explicit LevelSet(const Mesh& mesh)
        : dim_(mesh.dim), nx_(mesh.nx), ny_(mesh.dim == 2 ? mesh.ny : 1), px_(nx_ + 2 * G), dx_(mesh.dx),
          dy_(mesh.dim == 2 ? mesh.dy : mesh.dx), phi_(static_cast<size_t>(nx_) * ny_, 0.0),
          pad_(static_cast<size_t>(px_) * (dim_ == 2 ? ny_ + 2 * G : 1), 0.0) {
        rebuild_tube(true);
    }

    int nx() const { return nx_; }
    int ny() const { return ny_; }
    template <class S> void state(S& s) {
        s.io("phi", phi_);
        s.io("pad", pad_);
        s.io("stage", stage_);
        s.io("rate", rate_);
        s.io("tube_cells", tube_cells_);
        s.io("tube", tube_);
        s.io("near", near_);
        grouped_ = false;
        s.io("reads", reads_);
        s.io("mark", mark_);
    }

    // The narrow band: `cells` > 0 keeps φ in the tube |φ| < cells·h (2D only; 1D φ is redistanced exactly
    // over the whole line), 0 over the whole mesh. Clamps φ outside the tube. Also to be called after φ
    // was written through operator() or set().
    void set_tube(int cells) {
        tube_cells_ = dim_ == 2 ? cells : 0;
        rebuild_tube(true);
    }
    // Half-width of the tube (infinite without one).
    double tube_width() const {
        return tube_cells_ > 0 ? tube_cells_ * std::max(dx_, dy_) : std::numeric_limits<double>::infinity();
    }
    // The cells of the tube (every cell without one), in increasing index (row-major), and the cells within
    // one cell of the tube, its 8-neighbours included (in no order): φ changes in these only, and a
    // neighbour of a tube cell always lies among them.
    const std::vector<int>& tube() const { return tube_; }
    const std::vector<int>& near_tube() const { return near_; }
    // Sets φ everywhere (its size: the mesh's), then the tube from it.
    void set(const std::vector<double>& phi) {
        std::copy(phi.begin(), phi.end(), phi_.begin());
        rebuild_tube(true);
    }
    double& operator()(int i, int j) { return phi_[static_cast<size_t>(j) * nx_ + i]; }
    double operator()(int i, int j) const { return phi_[static_cast<size_t>(j) * nx_ + i]; }
    const std::vector<double>& values() const { return phi_; }

    // Many ranks (fluid/ranks.hpp): the rates of advection and reinitialisation are computed by the rank
    // that solves each row, and the new values of every stage gathered to every rank (one MPI_Allgatherv
    // per stage), so that every rank holds the same φ, bit for bit, and the same tube. Null: one rank.
    void divide(const Ranks* r) {
        ranks_ = r && r->many() ? r : nullptr;
        owner_.clear();
        grouped_ = false;
        if (!ranks_) return;
        owner_.resize(ny_);
        for (int k = 0; k < ranks_->size(); ++k)
            for (int j = ranks_->begin(k); j < ranks_->end(k); ++j)
                owner_[j] = k;
    }
    // Many ranks: the rank that solves each row (empty on one).
    const std::vector<int>& row_owner() const { return owner_; }
    // Many ranks: the values of `fields` (per interior cell) in the cells of near_tube() of this rank's rows
    // to every rank, and theirs into this rank's (one MPI_Allgatherv, listed in the order of near_tube()).
    void gather_near(const std::vector<double*>& fields) const {
        if (!ranks_) return;
        group();
        const int me = ranks_->rank(), nf = static_cast<int>(fields.size());
        std::vector<int> count(ranks_->size());
        for (int r = 0; r < ranks_->size(); ++r)
            count[r] = (group_[r + 1] - group_[r]) * nf;
        send_.resize(own_.size() * nf);
        for (size_t k = 0; k < own_.size(); ++k)
            for (int f = 0; f < nf; ++f)
                send_[k * nf + f] = fields[f][own_[k]];
        ranks_->gather_all(send_, count, recv_);
        // recv_ holds the groups of by_rank_ in its order, nf values per cell.
        for (int r = 0; r < ranks_->size(); ++r) {
            if (r == me) continue;
            for (int k = group_[r]; k < group_[r + 1]; ++k)
                for (int f = 0; f < nf; ++f)
                    fields[f][by_rank_[k]] = recv_[static_cast<long>(k) * nf + f];
        }
    }

    // Unit normal ∇φ/|∇φ| by central differences, one-sided at the domain edges; {1, 0} if ∇φ vanishes.
    std::array<double, 2> normal(int i, int j) const {
        const std::array<double, 2> g = gradient(i, j);
        const double norm = std::sqrt(g[0] * g[0] + g[1] * g[1]);
        if (!(norm > 1e-12)) return {1.0, 0.0};
        return {g[0] / norm, g[1] / norm};
    }

    // One TVD-RK3 step of φ_t + w·∇φ = 0, each derivative upwinded by the sign of its velocity component.
    // In a tube, w must vanish outside it; the tube follows φ afterwards.
    void advect(const std::vector<double>& wx, const std::vector<double>& wy, double dt) {
        own_cells();
        rk3(dt, [&](const std::vector<double>& phi, std::vector<double>& rate) {
            fill_padded(phi);
            const long n = static_cast<long>(work().size());
            const int* cells = work().data();
#pragma omp parallel for if (dim_ == 2)
            for (long k = 0; k < n; ++k) {
                const int c = cells[k], i = c % nx_, j = c / nx_, p = padded(i, j);
                if (wx[c] == 0.0 && (dim_ == 1 || wy[c] == 0.0)) {
                    rate[c] = 0.0; // at rest: no derivative needed
                    continue;
                }
                double r = -wx[c] * weno(p, 1, dx_, wx[c] < 0);
                if (dim_ == 2) r -= wy[c] * weno(p, px_, dy_, wy[c] < 0);
                rate[c] = r;
            }
        });
        rebuild_tube(false);
    }

    // Pseudo-time steps of φ_τ + S(φ0)(|∇φ| − 1) = 0 with the Godunov Hamiltonian. The smoothed sign
    // S = φ0/sqrt(φ0² + |∇φ0|² h²) (Peng et al., JCP 155, 1999) smears over one cell of distance even when
    // φ0 is far from a distance function; for |∇φ0| = 1 it is φ0/sqrt(φ0² + h²).
    // In 1D the distance is exact and cheap: φ becomes the signed distance to the nearest zero crossing
    // (linear between cell centres), so `iterations` plays no part there.
    void reinitialise(int iterations) {
        if (dim_ == 1) {
            redistance_1d();
            return;
        }
        const double h = dim_ == 2 ? std::max(dx_, dy_) : dx_;
        const double dtau = 0.3 * (dim_ == 2 ? std::min(dx_, dy_) : dx_);
        std::vector<double>& sign0 = sign0_;
        sign0.resize(phi_.size());
        own_cells();
        for (const int c : work()) {
            const std::array<double, 2> g = gradient(c % nx_, c / nx_);
            const double r = std::sqrt(phi_[c] * phi_[c] + (g[0] * g[0] + g[1] * g[1]) * h * h);
            sign0[c] = r > 0 ? phi_[c] / r : 0.0;
        }
        for (int it = 0; it < iterations; ++it)
            rk3(dtau, [&](const std::vector<double>& phi, std::vector<double>& rate) {
                fill_padded(phi);
                const long w = static_cast<long>(work().size());
                const int* cells = work().data();
#pragma omp parallel for if (dim_ == 2)
                for (long k = 0; k < w; ++k) {
                    const int c = cells[k], p = padded(c % nx_, c / nx_);
                    const double s = sign0[c];
                    double grad2 = godunov2(weno(p, 1, dx_, false), weno(p, 1, dx_, true), s);
                    if (dim_ == 2) grad2 += godunov2(weno(p, px_, dy_, false), weno(p, px_, dy_, true), s);
                    rate[c] = -s * (std::sqrt(grad2) - 1.0);
                }
            });
        rebuild_tube(false);
    }

    // Constant extrapolation I_τ + S(φ) n·∇I = 0 (paper eq. 33) into the unknown cells of the band
    // |φ| ≤ band·h, solved to its steady state: with first-order upwinding along S(φ) n the steady equation
    // makes each cell the weighted mean of its upwind neighbours (weights |n_x|/Δx, |n_y|/Δy), so one sweep
    // in order of increasing |φ| (upwind cells lie closer to the interface) gives the converged values.
    // Known cells never change; a cell without a known or already-set upwind neighbour takes the mean of the
    // set 4-neighbours closer to the interface, and keeps its value if there is none.
    void extrapolate(const std::vector<double*>& fields, const std::vector<char>& known, double band) const {
        const double width = band * (dim_ == 2 ? std::max(dx_, dy_) : dx_);
        if (!(width < tube_width()))
            throw std::logic_error("LevelSet::extrapolate: the band reaches beyond the tube");
        std::vector<int> order;
        for (const int c : tube_)
            if (!known[c] && std::abs(phi_[c]) <= width) order.push_back(c);
        std::sort(order.begin(), order.end(),
                  [&](int a, int b) { return std::abs(phi_[a]) < std::abs(phi_[b]); });
        // set: known or already extrapolated (the cells of `order` visited so far, cleared again below).
        std::vector<char>& visited = visited_;
        visited.resize(phi_.size(), 0);
        auto set = [&](int k) { return known[k] || visited[k]; };
        // A cell takes values only from known cells and from cells clearly closer to the interface (by more
        // than round-off): cells of (nearly) equal |φ|, such as mirror images across a symmetry axis, never
        // use each other's new values, so the visiting order of ties plays no part.
        const double tie = 1e-9 * width;
        auto usable = [&](int k, int c) {
            return set(k) && (known[k] || std::abs(phi_[k]) < std::abs(phi_[c]) - tie);
        };
        for (int c : order) {
            const int i = c % nx_, j = c / nx_;
            const std::array<double, 2> n = normal(i, j);
            const double s = phi_[c] >= 0 ? 1.0 : -1.0;
            const double vx = s * n[0], vy = dim_ == 2 ? s * n[1] : 0.0;
            int up[2] = {-1, -1};
            double w[2] = {std::abs(vx) / dx_, std::abs(vy) / dy_};
            const int iu = vx > 0 ? i - 1 : i + 1, ju = vy > 0 ? j - 1 : j + 1;
            if (w[0] > 0 && iu >= 0 && iu < nx_ && usable(j * nx_ + iu, c)) up[0] = j * nx_ + iu;
            if (w[1] > 0 && ju >= 0 && ju < ny_ && usable(ju * nx_ + i, c)) up[1] = ju * nx_ + i;
            double wsum = (up[0] >= 0 ? w[0] : 0.0) + (up[1] >= 0 ? w[1] : 0.0);
            if (!(wsum > 0)) {
                // No upwind value: the set neighbours closer to the interface, equally weighted.
                const int nb[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
                int found = 0, list[4] = {-1, -1, -1, -1};
                for (int m = 0; m < 4; ++m) {
                    const auto& q = nb[m];
                    if (q[0] >= 0 && q[0] < nx_ && q[1] >= 0 && q[1] < ny_) {
                        const int k = q[1] * nx_ + q[0];
                        if (usable(k, c)) list[m] = k, ++found;
                    }
                }
                if (found == 0) continue;
                // Summed as (−x + +x) + (−y + +y) so that a mirror image of the neighbourhood gives the same
                // rounding.
                for (double* f : fields) {
                    double pair[2] = {0, 0};
                    for (int k = 0; k < 4; ++k)
                        if (list[k] >= 0) pair[k / 2] += f[list[k]];
                    f[c] = (pair[0] + pair[1]) / found;
                }
                visited[c] = 1;
                continue;
            }
            for (double* f : fields) {
                double m = 0;
                for (int d = 0; d < 2; ++d)
                    if (up[d] >= 0) m += w[d] * f[up[d]];
                f[c] = m / wsum;
            }
            visited[c] = 1;
        }
        for (const int c : order)
            visited[c] = 0;
    }

    // Area (2D) or length (1D) of φ < 0 by the smoothed Heaviside of half-width ε = 1.5 h.
    double negative_volume() const {
        const double eps = 1.5 * (dim_ == 2 ? std::max(dx_, dy_) : dx_);
        const double pi = 3.14159265358979323846;
        double v = 0;
        for (double phi : phi_) {
            double heaviside = 1.0;
            if (phi < -eps)
                heaviside = 0.0;
            else if (phi <= eps)
                heaviside = 0.5 * (1.0 + phi / eps + std::sin(pi * phi / eps) / pi);
            v += 1.0 - heaviside;
        }
        return v * dx_ * (dim_ == 2 ? dy_ : 1.0);
    }

  private:
    void redistance_1d() {
        std::vector<double> zeros;
        for (int i = 0; i + 1 < nx_; ++i)
            if ((phi_[i] < 0) != (phi_[i + 1] < 0))
                zeros.push_back(i * dx_ + dx_ * phi_[i] / (phi_[i] - phi_[i + 1])); // offset from cell 0
        if (zeros.empty()) return;
        size_t z = 0;
        for (int i = 0; i < nx_; ++i) {
            const double x = i * dx_;
            while (z + 1 < zeros.size() && std::abs(zeros[z + 1] - x) < std::abs(zeros[z] - x))
                ++z;
            phi_[i] = std::copysign(std::abs(x - zeros[z]), phi_[i] < 0 ? -1.0 : 1.0);
        }
    }

    int dim_, nx_, ny_;
    int px_; // row stride of pad_
    double dx_, dy_;
    std::vector<double> phi_;
    std::vector<double> pad_;           // φ with G ghost layers (in x only in 1D)
    std::vector<double> stage_, rate_;  // Runge–Kutta work arrays
    std::vector<double> sign0_;         // work array of reinitialise
    mutable std::vector<char> visited_; // work array of extrapolate, all 0 between calls

    // The narrow band (set_tube). tube_: |φ| < tube_width(), sorted; near_: the tube and its 8-neighbours,
    // the cells a step changes; reads_: the cells within G + 1 (a square) of the tube, which hold every cell
    // a WENO stencil of near_ reads and every cell two steps of the tube can change. mark_: bit 2 in near_,
    // bit 4 in reads_. Without a tube all three are every cell.
    int tube_cells_ = 0;
    std::vector<int> tube_, near_, reads_;
    std::vector<char> mark_;
    // Many ranks (divide): the rank of each row; in rk3, the cells of near_ this rank computes (own_).
    const Ranks* ranks_ = nullptr;
    std::vector<int> owner_;
    mutable std::vector<int> own_, by_rank_, group_, rank_of_;
    mutable bool grouped_ = false;
    mutable std::vector<double> send_, recv_; // gather_near's messages
    // The cells a rate is computed for (after own_cells): this rank's own, or near_ on one rank.
    const std::vector<int>& work() const { return ranks_ ? own_ : near_; }

  public:
    // φ over reads_ and the lists, enough to take back one step of advection and reinitialisation (which
    // change cells within two of the tube only).
    struct Snapshot {
        std::vector<int> tube, near, reads;
        std::vector<double> values;
    };
    void save(Snapshot& s) const {
        s.tube = tube_, s.near = near_, s.reads = reads_;
        s.values.resize(reads_.size());
        for (size_t k = 0; k < reads_.size(); ++k)
            s.values[k] = phi_[reads_[k]];
    }
    void restore(const Snapshot& s) {
        if (tube_cells_ > 0)
            for (const int c : reads_)
                mark_[c] = 0;
        tube_ = s.tube, near_ = s.near, reads_ = s.reads;
        grouped_ = false;
        for (size_t k = 0; k < reads_.size(); ++k)
            phi_[reads_[k]] = s.values[k];
        if (tube_cells_ > 0) {
            for (const int c : reads_)
                mark_[c] |= 4;
            for (const int c : near_)
                mark_[c] |= 2;
        }
    }

  private:
    // The tube from φ: from every cell (full) or from near_, the only cells whose φ changed since the last
    // rebuild. Cells leaving the tube take ±tube_width(); a NaN stays in the tube, to be seen.
    void rebuild_tube(bool full) {
        grouped_ = false;
        const int n = nx_ * ny_;
        if (tube_cells_ == 0) {
            if (static_cast<int>(tube_.size()) != n) {
                tube_.resize(n);
                for (int c = 0; c < n; ++c)
                    tube_[c] = c;
                near_ = reads_ = tube_;
            }
            return;
        }
        const double w = tube_width();
        auto keep = [&](int c) {
            if (!(std::abs(phi_[c]) >= w)) return true;
            phi_[c] = phi_[c] < 0 ? -w : w;
            return false;
        };
        mark_.resize(n, 0);
        tube_.clear();
        if (full) {
            std::fill(mark_.begin(), mark_.end(), 0);
            for (int c = 0; c < n; ++c)
                if (keep(c)) tube_.push_back(c);
        } else {
            for (const int c : reads_)
                mark_[c] = 0;
            for (const int c : near_)
                if (keep(c)) tube_.push_back(c);
            std::sort(tube_.begin(), tube_.end());
        }
        near_.clear();
        reads_.clear();
        // A tube cell right of the previous one (the tube is sorted) adds only the last column of its square:
        // the others were the previous cell's. The same cells in the same order as visiting every square.
        auto dilate = [&](int r, char bit, std::vector<int>& out) {
            for (size_t t = 0; t < tube_.size(); ++t) {
                const int c = tube_[t], i = c % nx_, j = c / nx_;
                const bool run = t > 0 && i > 0 && tube_[t - 1] == c - 1;
                for (int b = std::max(0, j - r); b <= std::min(ny_ - 1, j + r); ++b)
                    for (int a = run ? i + r : std::max(0, i - r); a <= std::min(nx_ - 1, i + r); ++a) {
                        const int k = b * nx_ + a;
                        if (mark_[k] & bit) continue;
                        mark_[k] |= bit;
                        out.push_back(k);
                    }
            }
        };
        dilate(1, 2, near_);
        dilate(G + 1, 4, reads_);
    }

    int padded(int i, int j) const {
        return (j + (dim_ == 2 ? G : 0)) * px_ + i + G;
    }

    // Central difference of φ at cell c (index k of n along a line of stride s), one-sided at the edges.
    double difference(int k, int n, int s, int c) const {
        if (n < 2) return 0.0;
        if (k == 0) return phi_[c + s] - phi_[c];
        if (k == n - 1) return phi_[c] - phi_[c - s];
        return 0.5 * (phi_[c + s] - phi_[c - s]);
    }

    std::array<double, 2> gradient(int i, int j) const {
        const int c = j * nx_ + i;
        return {difference(i, nx_, 1, c) / dx_, dim_ == 2 ? difference(j, ny_, nx_, c) / dy_ : 0.0};
    }

    // Interior values into pad_, ghosts by linear extrapolation along x, then along y (corners included).
    // In a tube: the cells of reads_ (phi holds them; φ_ the others) and the ghosts next to them, the only
    // values a stencil of near_ reads (corner ghosts are never read).
    void fill_padded(const std::vector<double>& phi) {
        if (tube_cells_ > 0) {
            // On many ranks the rows the rates of this rank's cells read only.
            const int ja = ranks_ ? ranks_->begin() - G : 0, jb = ranks_ ? ranks_->end() + G : ny_;
            const long n = static_cast<long>(reads_.size());
            auto value = [&](int i, int j) {
                const int k = j * nx_ + i;
                return mark_[k] & 4 ? phi[k] : phi_[k];
            };
#pragma omp parallel for
            for (long m = 0; m < n; ++m) {
                const int c = reads_[m], i = c % nx_, j = c / nx_;
                if (j < ja || j >= jb) continue;
                const double v = phi[c];
                double* q = &pad_[padded(i, j)];
                q[0] = v;
                auto ghosts = [&](int s, double inner) {
                    for (int k = 1; k <= G; ++k)
                        q[k * s] = v + k * (v - inner);
                };
                if (i == 0) ghosts(-1, nx_ > 1 ? value(1, j) : v);
                if (i == nx_ - 1) ghosts(1, nx_ > 1 ? value(i - 1, j) : v);
                if (j == 0) ghosts(-px_, ny_ > 1 ? value(i, 1) : v);
                if (j == ny_ - 1) ghosts(px_, ny_ > 1 ? value(i, j - 1) : v);
            }
            return;
        }
        for (int j = 0; j < ny_; ++j) {
            double* row = &pad_[padded(0, j)];
            std::copy(&phi[j * nx_], &phi[j * nx_] + nx_, row);
            for (int k = 1; k <= G; ++k) {
                row[-k] = row[0] + k * (row[0] - row[1]);
                row[nx_ - 1 + k] = row[nx_ - 1] + k * (row[nx_ - 1] - row[nx_ - 2]);
            }
        }
        if (dim_ != 2) return;
        for (int i = -G; i < nx_ + G; ++i) {
            double* col = &pad_[padded(i, 0)];
            const double* top = &pad_[padded(i, ny_ - 1)];
            for (int k = 1; k <= G; ++k) {
                col[-k * px_] = col[0] + k * (col[0] - col[px_]);
                pad_[padded(i, ny_ - 1 + k)] = top[0] + k * (top[0] - top[-px_]);
            }
        }
    }

    // WENO5 Hamilton–Jacobi derivative at padded index p along stride s: left-biased φ⁻ or right-biased φ⁺.
    // The weights are invariant under scaling, so the stencils take undivided differences.
    double weno(int p, int s, double h, bool plus) const {
        const double* q = &pad_[p];
        auto d = [&](int k) { return q[k * s] - q[(k - 1) * s]; }; // h D⁻φ at offset k
        if (plus) return weno5(d(3), d(2), d(1), d(0), d(-1)) / h;
        return weno5(d(-2), d(-1), d(0), d(1), d(2)) / h;
    }

    static double weno5(double v1, double v2, double v3, double v4, double v5) {
        const double p1 = v1 / 3 - 7 * v2 / 6 + 11 * v3 / 6;
        const double p2 = -v2 / 6 + 5 * v3 / 6 + v4 / 3;
        const double p3 = v3 / 3 + 5 * v4 / 6 - v5 / 6;
        const double s1 = 13.0 / 12 * (v1 - 2 * v2 + v3) * (v1 - 2 * v2 + v3) +
                          0.25 * (v1 - 4 * v2 + 3 * v3) * (v1 - 4 * v2 + 3 * v3);
        const double s2 = 13.0 / 12 * (v2 - 2 * v3 + v4) * (v2 - 2 * v3 + v4) + 0.25 * (v2 - v4) * (v2 - v4);
        const double s3 = 13.0 / 12 * (v3 - 2 * v4 + v5) * (v3 - 2 * v4 + v5) +
                          0.25 * (3 * v3 - 4 * v4 + v5) * (3 * v3 - 4 * v4 + v5);
        // ε relative to the largest difference (Fedkiw et al.), so the weights are scale-free; the floor
        // keeps the products below clear of underflow when φ is constant.
        const double eps = 1e-6 * std::max({v1 * v1, v2 * v2, v3 * v3, v4 * v4, v5 * v5}) + 1e-30;
        // Weights 0.1/t1², 0.6/t2², 0.3/t3², all multiplied by (t1 t2 t3)² to need one division only.
        const double t1 = s1 + eps, t2 = s2 + eps, t3 = s3 + eps;
        const double a1 = 0.1 * (t2 * t3) * (t2 * t3);
        const double a2 = 0.6 * (t1 * t3) * (t1 * t3);
        const double a3 = 0.3 * (t1 * t2) * (t1 * t2);
        return (a1 * p1 + a2 * p2 + a3 * p3) / (a1 + a2 + a3);
    }

    // Godunov square of one derivative component from the one-sided values a = φ⁻, b = φ⁺.
    static double godunov2(double a, double b, double s) {
        if (s > 0) {
            const double l = std::max(a, 0.0), r = std::min(b, 0.0);
            return std::max(l * l, r * r);
        }
        const double l = std::min(a, 0.0), r = std::max(b, 0.0);
        return std::max(l * l, r * r);
    }

    // The cells of near_ this rank computes (work()), for the rk3 that follow.
    void own_cells() {
        if (ranks_) group();
    }
    // Many ranks: near_ grouped by the rank of its row, each group in the order of near_ (by_rank_, group r
    // at [group_[r], group_[r + 1])), and this rank's group (own_): made again only after near_ or the
    // division changed (grouped_ false), not at each of a step's gathers.
    void group() const {
        if (grouped_) return;
        const int size = ranks_->size();
        // A cell's rank from its index: the blocks' first cells, in order (no division per cell).
        std::vector<int> first(size + 1);
        for (int r = 0; r <= size; ++r)
            first[r] = r < size ? ranks_->begin(r) * nx_ : nx_ * ny_;
        auto rank_of = [&](int c) {
            return static_cast<int>(std::upper_bound(first.begin() + 1, first.end(), c) - first.begin()) - 1;
        };
        group_.assign(size + 1, 0);
        rank_of_.resize(near_.size());
        for (size_t k = 0; k < near_.size(); ++k)
            ++group_[(rank_of_[k] = rank_of(near_[k])) + 1];
        for (int r = 0; r < size; ++r)
            group_[r + 1] += group_[r];
        std::vector<int> at(group_.begin(), group_.end() - 1);
        by_rank_.resize(near_.size());
        for (size_t k = 0; k < near_.size(); ++k)
            by_rank_[at[rank_of_[k]]++] = near_[k];
        const int me = ranks_->rank();
        own_.assign(by_rank_.begin() + group_[me], by_rank_.begin() + group_[me + 1]);
        grouped_ = true;
    }
    // Shu–Osher TVD-RK3 on phi_ with the rate L(φ) computed by `rate_of(φ, L)` over the cells of work()
    // (own_cells). The rate is needed on near_ only, and changes φ there; in a tube the stage holds φ on
    // reads_ beyond. On many ranks each rank updates its own cells of near_ and gathers the others'
    // (gather_near).
    template <class Rate> void rk3(double dt, Rate&& rate_of) {
        const size_t n = phi_.size();
        stage_.resize(n);
        rate_.resize(n);
        const long m = static_cast<long>(work().size());
        const int* cells = work().data();
        rate_of(phi_, rate_);
        if (tube_cells_ > 0)
            for (const int c : reads_)
                stage_[c] = phi_[c];
#pragma omp parallel for if (dim_ == 2)
        for (long k = 0; k < m; ++k) {
            const int c = cells[k];
            stage_[c] = phi_[c] + dt * rate_[c];
        }
        gather_near({stage_.data()});
        rate_of(stage_, rate_);
#pragma omp parallel for if (dim_ == 2)
        for (long k = 0; k < m; ++k) {
            const int c = cells[k];
            stage_[c] = 0.75 * phi_[c] + 0.25 * (stage_[c] + dt * rate_[c]);
        }
        gather_near({stage_.data()});
        rate_of(stage_, rate_);
#pragma omp parallel for if (dim_ == 2)
        for (long k = 0; k < m; ++k) {
            const int c = cells[k];
            phi_[c] = (phi_[c] + 2.0 * (stage_[c] + dt * rate_[c])) / 3.0;
        }
        gather_near({phi_.data()});
    }
};

} // namespace undex::fluid
