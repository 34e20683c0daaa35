// Locally orthogonal modal basis and Gauss quadrature on one Cartesian cell (physics.md §3).
// ξ = 2(x − x_K)/Δx, η = 2(y − y_K)/Δy; 2D: 1, ξ, η, ξη, ξ² − 1/3, η² − 1/3; 1D: 1, ξ, ξ² − 1/3.
// The mass matrix is diagonal: M_l = |K| · norm(l). Quadrature weights are normalised to sum to one.
#pragma once
#include <array>
#include <cmath>

namespace undex::fluid {

template <int D, int K> struct Basis {
    static_assert(D == 1 || D == 2, "1D or 2D");
    static_assert(K >= 0 && K <= 2, "degree 0, 1 or 2");
    static constexpr int NB = D == 1 ? K + 1 : (K + 1) * (K + 2) / 2; // basis functions
    static constexpr int NQ1 = K + 1;                                 // Gauss points per direction
    static constexpr int NQV = D == 1 ? NQ1 : NQ1 * NQ1;              // volume points
    static constexpr int NQF = D == 1 ? 1 : NQ1;                      // points per face

    // Which monomial each basis function is: degree in ξ and in η.
    static constexpr int px(int l) { return D == 1 ? l : std::array<int, 6>{0, 1, 0, 1, 2, 0}[l]; }
    static constexpr int py(int l) { return D == 1 ? 0 : std::array<int, 6>{0, 0, 1, 1, 0, 2}[l]; }

    static double p1(int n, double s) { return n == 0 ? 1.0 : n == 1 ? s : s * s - 1.0 / 3.0; }
    static double dp1(int n, double s) { return n == 0 ? 0.0 : n == 1 ? 1.0 : 2.0 * s; }
    // Mean of p1(n)² over [−1, 1].
    static double norm1(int n) { return n == 0 ? 1.0 : n == 1 ? 1.0 / 3.0 : 4.0 / 45.0; }

    static double phi(int l, double xi, double eta) { return p1(px(l), xi) * p1(py(l), eta); }
    static double dphi_dxi(int l, double xi, double eta) { return dp1(px(l), xi) * p1(py(l), eta); }
    static double dphi_deta(int l, double xi, double eta) { return p1(px(l), xi) * dp1(py(l), eta); }
    static double norm(int l) { return norm1(px(l)) * norm1(py(l)); }

    // Sums in an order that a mirror image (x = y: ξ ↔ η; an axis: ξ → −ξ or η → −η) maps onto itself up to
    // the commutativity of +, so that mirror-image cells round alike and a symmetric problem stays
    // symmetric to the last bit.
    // Over the basis functions: ((1 + (ξ + η)) + ξη) + (ξ² + η²).
    template <class T> static double mode_sum(const T& t) {
        if constexpr (D == 1) {
            double s = 0;
            for (int l = 0; l < NB; ++l)
                s += t[l];
            return s;
        } else if constexpr (NB == 1)
            return t[0];
        else if constexpr (NB == 3)
            return t[0] + (t[1] + t[2]);
        else
            return ((t[0] + (t[1] + t[2])) + t[3]) + (t[4] + t[5]);
    }
    // Over the volume points q = i + NQ1·j: centre, edge midpoints, corners, each orbit of the square's
    // symmetries summed in pairs.
    template <class T> static double point_sum(const T& t) {
        if constexpr (D == 1)
            return segment_sum<NQ1>(t);
        else if constexpr (NQ1 == 1)
            return t[0];
        else if constexpr (NQ1 == 2)
            return (t[0] + t[3]) + (t[1] + t[2]);
        else
            return (t[4] + ((t[3] + t[5]) + (t[1] + t[7]))) + ((t[0] + t[8]) + (t[2] + t[6]));
    }
    // Over N Gauss points of a segment (symmetric about its centre): the points of a face, and the volume
    // points in 1D.
    template <int N, class T> static double segment_sum(const T& t) {
        if constexpr (N == 1)
            return t[0];
        else if constexpr (N == 2)
            return t[0] + t[1];
        else
            return (t[0] + t[2]) + t[1];
    }
    template <class T> static double face_sum(const T& t) { return segment_sum<NQF>(t); }
    // Basis function of the mirror image about x = y (ξ ↔ η) and parities under ξ → −ξ, η → −η.
    static constexpr int swap_xy(int l) { return D == 1 ? l : std::array<int, 6>{0, 2, 1, 3, 5, 4}[l]; }
    static constexpr double parity_x(int l) { return px(l) % 2 ? -1.0 : 1.0; }
    static constexpr double parity_y(int l) { return py(l) % 2 ? -1.0 : 1.0; }

    // Gauss–Legendre points on [−1, 1] and weights normalised to sum to one.
    static std::array<double, NQ1> gauss_points() {
        if constexpr (NQ1 == 1)
            return {0.0};
        else if constexpr (NQ1 == 2)
            return {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
        else
            return {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    }
    static std::array<double, NQ1> gauss_weights() {
        if constexpr (NQ1 == 1)
            return {1.0};
        else if constexpr (NQ1 == 2)
            return {0.5, 0.5};
        else
            return {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    }
};

// Tables of one basis, filled once: values and derivatives at volume points, values at face points.
template <int D, int K> struct BasisTables {
    using B = Basis<D, K>;
    static constexpr int NB = B::NB, NQV = B::NQV, NQF = B::NQF;
    double wv[NQV];             // volume weights
    double xiv[NQV], etav[NQV]; // volume points
    double phiv[NQV][NB];       // φ_l at volume points
    double dxiv[NQV][NB];       // ∂φ_l/∂ξ
    double detav[NQV][NB];      // ∂φ_l/∂η
    double wf[NQF];             // face weights
    double sf[NQF];             // face point coordinate along the face
    // face[dir][side][g][l]: φ_l on face side (0: ξ or η = −1, 1: = +1) of direction dir at point g.
    double face[2][2][NQF][NB];
    double inv_norm[NB];

    BasisTables() {
        const auto g = B::gauss_points();
        const auto w = B::gauss_weights();
        for (int q = 0; q < NQV; ++q) {
            const int i = q % B::NQ1, j = q / B::NQ1;
            xiv[q] = g[i];
            etav[q] = D == 1 ? 0.0 : g[j];
            wv[q] = D == 1 ? w[i] : w[i] * w[j];
            for (int l = 0; l < NB; ++l) {
                phiv[q][l] = B::phi(l, xiv[q], etav[q]);
                dxiv[q][l] = B::dphi_dxi(l, xiv[q], etav[q]);
                detav[q][l] = B::dphi_deta(l, xiv[q], etav[q]);
            }
        }
        for (int f = 0; f < NQF; ++f) {
            sf[f] = D == 1 ? 0.0 : g[f];
            wf[f] = D == 1 ? 1.0 : w[f];
            for (int side = 0; side < 2; ++side)
                for (int l = 0; l < NB; ++l) {
                    const double e = side == 0 ? -1.0 : 1.0;
                    face[0][side][f][l] = B::phi(l, e, sf[f]);
                    face[1][side][f][l] = B::phi(l, sf[f], e);
                }
        }
        for (int l = 0; l < NB; ++l)
            inv_norm[l] = 1.0 / B::norm(l);
    }
};

} // namespace undex::fluid
