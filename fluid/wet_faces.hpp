// The structure's wet faces as the fluid sees them in 2D (physics.md §5.1, docs/protocol.md §2): one
// polyline per face through its wet nodes, in the order the structure sent them. From the node positions of
// each step: the area vector of every node, a_k = Σ_s n_s ∫_s N_k r ds over the segments s of its face
// (n_s the unit normal of the segment, from the fluid into the structure; r = x in axisymmetry, 1 in plane
// strain), its wetted area A_k = |a_k| and normal n_k = a_k / A_k, exactly as the structure computes them;
// and, per face, the signed distance φ of the cell centres near it (φ < 0 on the fluid side).
#pragma once
#include "fluid/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex::fluid {

// The geometric term of the impedance relation (physics.md §5): α Δt ρ_L a_L² u_r / r, with u_r the radial
// (x) velocity of the fluid next to the interface and r the interface's radius. Within `axis_band` of the
// axis (r < axis_band) the term is dropped: there u_r / r tends to the finite ∂u_r/∂r, and the term is one of
// order Δt; 0 in planar cases (α = 0).
inline double geometric_term(int alpha, double dt, double rho, double a, double u_r, double r,
                             double axis_band = 0) {
    if (alpha == 0 || r < axis_band) return 0.0;
    return alpha * dt * rho * a * a * u_r / r;
}

// The closest point of a face to a point: the segment (from node `a` to node a + 1), the parameter t ∈ [0, 1]
// along it, the distance, and the normal there (the segment's, or at a node the normalised mean of its
// segments' normals: the sign of the distance is then right on both sides of a corner).
struct ClosestPoint {
    int a = -1;
    double t = 0, distance = std::numeric_limits<double>::infinity(), nx = 0, ny = 0;
};

class WetFaces {
  public:
    // face[k]: the face of node k (0, 1, ..., nodes of a face consecutive); the reference positions and
    // normals of the Hello fix each face's orientation (which side of the polyline is the structure).
    WetFaces(const std::vector<int>& face, const std::vector<double>& x, const std::vector<double>& y,
             const std::vector<double>& normal_x, const std::vector<double>& normal_y, int alpha)
        : face_(face), alpha_(alpha) {
        const int n = static_cast<int>(face.size());
        begin_.push_back(0);
        for (int k = 1; k < n; ++k)
            if (face[k] != face[k - 1]) begin_.push_back(k);
        begin_.push_back(n);
        for (int f = 0; f < faces(); ++f)
            if (end(f) - begin(f) < 2)
                throw std::invalid_argument("wet face " + std::to_string(f) + " has " +
                                            std::to_string(end(f) - begin(f)) +
                                            " node; a face in 2D needs at least two");
        set_positions(x, y);
        // Orientation: the left normal (−t_y, t_x) of each segment, turned by sign_[f] = ±1, points into
        // the structure; the sign agrees with the Hello's normals summed over the face.
        sign_.assign(faces(), 1.0);
        for (int f = 0; f < faces(); ++f) {
            double dot = 0;
            for (int k = begin(f); k < end(f); ++k)
                dot += nx_[k] * normal_x[k] + ny_[k] * normal_y[k];
            sign_[f] = dot >= 0 ? 1.0 : -1.0;
        }
        set_positions(x, y);
    }

    int faces() const { return static_cast<int>(begin_.size()) - 1; }
    int nodes() const { return static_cast<int>(face_.size()); }
    int begin(int f) const { return begin_[f]; }
    int end(int f) const { return begin_[f + 1]; }
    int face(int k) const { return face_[k]; }
    double x(int k) const { return x_[k]; }
    double y(int k) const { return y_[k]; }
    double area(int k) const { return area_[k]; }
    std::array<double, 2> normal(int k) const { return {nx_[k], ny_[k]}; }
    // Unit normal of the segment from node a to a + 1 (into the structure).
    std::array<double, 2> segment_normal(int a) const { return {snx_[a], sny_[a]}; }

    // New node positions: segment normals, area vectors, node normals. Throws std::invalid_argument for a
    // segment of zero length.
    void set_positions(const std::vector<double>& x, const std::vector<double>& y) {
        const int n = nodes();
        x_ = x, y_ = y;
        snx_.assign(n, 0.0), sny_.assign(n, 0.0);
        std::vector<double> ax(n, 0.0), ay(n, 0.0);
        for (int f = 0; f < faces(); ++f) {
            const double s = sign_.empty() ? 1.0 : sign_[f];
            for (int a = begin(f); a + 1 < end(f); ++a) {
                const double tx = x_[a + 1] - x_[a], ty = y_[a + 1] - y_[a];
                const double len = std::hypot(tx, ty);
                if (!(len > 0))
                    throw std::invalid_argument("wet nodes " + std::to_string(a) + " and " +
                                                std::to_string(a + 1) + " of face " + std::to_string(f) +
                                                " coincide");
                const double nx = -s * ty / len, ny = s * tx / len;
                snx_[a] = nx, sny_[a] = ny;
                // ∫ N_a r ds and ∫ N_b r ds over the segment (r = x in axisymmetry, 1 in plane strain).
                double wa = 0.5 * len, wb = 0.5 * len;
                if (alpha_ == 1) {
                    wa = len * (2 * x_[a] + x_[a + 1]) / 6;
                    wb = len * (x_[a] + 2 * x_[a + 1]) / 6;
                }
                ax[a] += nx * wa, ay[a] += ny * wa;
                ax[a + 1] += nx * wb, ay[a + 1] += ny * wb;
            }
        }
        area_.assign(n, 0.0), nx_.assign(n, 0.0), ny_.assign(n, 0.0);
        for (int k = 0; k < n; ++k) {
            area_[k] = std::hypot(ax[k], ay[k]);
            if (area_[k] > 0) nx_[k] = ax[k] / area_[k], ny_[k] = ay[k] / area_[k];
        }
    }

    // Distance from (px, py) to the segment from node a to a + 1, with the closest point's parameter and
    // normal (at an end of the segment: the node's corner normal). With `rays`, a face's first and last
    // segments continue beyond its ends as straight rays (t < 0, t > 1): the structure of a face that ends
    // inside the fluid's domain is taken to continue along its end segments, so that its side is decided
    // near the face and its rays alone (the fluid's use: fluid/wet_fluid.hpp).
    ClosestPoint to_segment(int a, double px, double py, bool rays = false) const {
        double cx, cy;
        const double t = closest(a, px, py, rays, cx, cy);
        ClosestPoint c;
        c.a = a;
        c.t = t;
        c.distance = std::hypot(px - cx, py - cy);
        if (t != 0.0 && t != 1.0) { // inside the segment or on a ray
            c.nx = snx_[a], c.ny = sny_[a];
        } else {
            const std::array<double, 2> n = corner_normal(t == 0.0 ? a : a + 1);
            c.nx = n[0], c.ny = n[1];
        }
        return c;
    }

    // The square of to_segment's distance alone (no root, no normal): for a search of the nearest segment.
    double distance2(int a, double px, double py, bool rays = false) const {
        double cx, cy;
        closest(a, px, py, rays, cx, cy);
        return (px - cx) * (px - cx) + (py - cy) * (py - cy);
    }
    // The closest point (cx, cy) of segment a to (px, py), and its parameter t (to_segment).
    double closest(int a, double px, double py, bool rays, double& cx, double& cy) const {
        const double tx = x_[a + 1] - x_[a], ty = y_[a + 1] - y_[a];
        const int f = face_[a];
        const double lo = rays && a == begin(f) ? -std::numeric_limits<double>::infinity() : 0.0;
        const double hi = rays && a + 2 == end(f) ? std::numeric_limits<double>::infinity() : 1.0;
        const double t = std::clamp(((px - x_[a]) * tx + (py - y_[a]) * ty) / (tx * tx + ty * ty), lo, hi);
        cx = t == 1.0 ? x_[a + 1] : x_[a] + t * tx, cy = t == 1.0 ? y_[a + 1] : y_[a] + t * ty;
        return t;
    }

    // Signed distance of (px, py) to a closest point c: positive on the structure's side.
    double signed_distance(const ClosestPoint& c, double px, double py) const {
        const double cx = closest_x(c), cy = closest_y(c);
        return (px - cx) * c.nx + (py - cy) * c.ny >= 0 ? c.distance : -c.distance;
    }
    double closest_x(const ClosestPoint& c) const {
        return c.t == 1.0 ? x_[c.a + 1] : x_[c.a] + c.t * (x_[c.a + 1] - x_[c.a]);
    }
    double closest_y(const ClosestPoint& c) const {
        return c.t == 1.0 ? y_[c.a + 1] : y_[c.a] + c.t * (y_[c.a + 1] - y_[c.a]);
    }

    // The mean of the unit normals of the segments meeting at node k (one at a face's end), normalised.
    std::array<double, 2> corner_normal(int k) const {
        const int f = face_[k];
        double nx = 0, ny = 0;
        if (k > begin(f)) nx += snx_[k - 1], ny += sny_[k - 1];
        if (k + 1 < end(f)) nx += snx_[k], ny += sny_[k];
        const double len = std::hypot(nx, ny);
        if (!(len > 0)) return {snx_[k > begin(f) ? k - 1 : k], sny_[k > begin(f) ? k - 1 : k]};
        return {nx / len, ny / len};
    }

    template <class S> void state(S& s) {
        s.io("face", face_), s.io("begin", begin_), s.io("alpha", alpha_), s.io("sign", sign_);
        s.io("x", x_), s.io("y", y_), s.io("snx", snx_), s.io("sny", sny_), s.io("area", area_);
        s.io("nx", nx_), s.io("ny", ny_);
    }

  private:
    std::vector<int> face_, begin_;
    int alpha_ = 0;
    std::vector<double> sign_;
    std::vector<double> x_, y_, snx_, sny_, area_, nx_, ny_;
};

} // namespace undex::fluid
