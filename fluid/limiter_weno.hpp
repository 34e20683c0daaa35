// Simple WENO limiter of Zhong and Shu (JCP 232, 2013) for a troubled cell, in local characteristic
// variables (physics.md §3). The new polynomial is a convex combination of the cell's own polynomial and
// its face neighbours' polynomials, each shifted to the cell's average, with nonlinear weights from the
// smoothness indicators β = Σ_{1≤|α|≤k} ∫_K |K|^{2|α|−1} (D^α p)² (scale-free on the reference cell).
#pragma once
#include "fluid/basis.hpp"

#include <stdexcept>

namespace undex::fluid {

template <int D, int K> struct WenoTables {
    using B = Basis<D, K>;
    static constexpr int NB = B::NB;
    static constexpr int NN = 2 * D; // face neighbours: −x, +x, −y, +y
    double shift[NN][NB][NB];        // coefficients of a neighbour's polynomial in this cell's basis
    double smooth[NB][NB];           // β = cᵀ S c
    double smooth_diag[NB];          // its diagonal: S is diagonal for this orthogonal basis (checked)

    WenoTables() {
        // 3-point Gauss per direction integrates products of degree-2 polynomials exactly.
        const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
        const double w[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
        const int nq2 = D == 1 ? 1 : 3;
        const double off[4][2] = {{-2, 0}, {2, 0}, {0, -2}, {0, 2}}; // neighbour centre in this cell's ξ, η
        for (int nb = 0; nb < NN; ++nb)
            for (int l = 0; l < NB; ++l)
                for (int m = 0; m < NB; ++m) {
                    double s = 0;
                    for (int i = 0; i < 3; ++i)
                        for (int j = 0; j < nq2; ++j) {
                            const double xi = g[i], eta = D == 1 ? 0.0 : g[j];
                            const double wq = D == 1 ? w[i] : w[i] * w[j];
                            s += wq * B::phi(l, xi, eta) * B::phi(m, xi - off[nb][0], eta - off[nb][1]);
                        }
                    shift[nb][l][m] = s / B::norm(l);
                }
        // Smoothness: first derivatives scaled by 2 (ξ = 2x/Δx), second derivatives by 4.
        for (int l = 0; l < NB; ++l)
            for (int m = 0; m < NB; ++m) {
                double s = 0;
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < nq2; ++j) {
                        const double xi = g[i], eta = D == 1 ? 0.0 : g[j];
                        const double wq = D == 1 ? w[i] : w[i] * w[j];
                        const double h =
                            1e-3; // second derivatives of quadratics by exact central differences
                        auto d = [&](int f, int a, int b) {
                            // ∂^{a+b} φ_f /∂ξ^a ∂η^b at (xi, eta); quadratics make these differences exact
                            // up to round-off.
                            if (a == 0 && b == 0) return B::phi(f, xi, eta);
                            if (a == 1 && b == 0) return B::dphi_dxi(f, xi, eta);
                            if (a == 0 && b == 1) return B::dphi_deta(f, xi, eta);
                            if (a == 2)
                                return (B::dphi_dxi(f, xi + h, eta) - B::dphi_dxi(f, xi - h, eta)) / (2 * h);
                            if (b == 2)
                                return (B::dphi_deta(f, xi, eta + h) - B::dphi_deta(f, xi, eta - h)) /
                                       (2 * h);
                            return (B::dphi_dxi(f, xi, eta + h) - B::dphi_dxi(f, xi, eta - h)) / (2 * h);
                        };
                        s += wq * 4.0 * d(l, 1, 0) * d(m, 1, 0);
                        if (D == 2) s += wq * 4.0 * d(l, 0, 1) * d(m, 0, 1);
                        if (K >= 2) {
                            s += wq * 16.0 * d(l, 2, 0) * d(m, 2, 0);
                            if (D == 2) {
                                s += wq * 16.0 * d(l, 1, 1) * d(m, 1, 1);
                                s += wq * 16.0 * d(l, 0, 2) * d(m, 0, 2);
                            }
                        }
                    }
                smooth[l][m] = s;
            }
        symmetrise();
        // Derivatives of the modes are orthogonal too (∂ξ of 1, ξ, η, ξη, ξ² − 1/3, η² − 1/3 are 0, 1, 0, η,
        // 2ξ, 0), so S is diagonal: the limiter sums the diagonal alone.
        for (int l = 0; l < NB; ++l) {
            smooth_diag[l] = smooth[l][l];
            for (int m = 0; m < NB; ++m)
                if (m != l && smooth[l][m] != 0.0)
                    throw std::logic_error("WENO smoothness matrix is not diagonal");
        }
    }

  private:
    // The quadratures above round differently for mirror-image entries (and leave round-off where an entry
    // is zero by parity). Exact copies make the tables as symmetric as the exact ones, so that mirror-image
    // cells are limited alike to the last bit: entries odd under ξ → −ξ or η → −η are zero, the +x
    // neighbour is the mirror image of the −x one, the ±y ones are the ±x ones with ξ ↔ η, and the
    // smoothness matrix is symmetric and invariant under ξ ↔ η.
    void symmetrise() {
        auto sw = [](int l) { return B::swap_xy(l); };
        for (int l = 0; l < NB; ++l)
            for (int m = 0; m < NB; ++m)
                if (B::parity_y(l) * B::parity_y(m) < 0) shift[0][l][m] = 0.0;
        for (int l = 0; l < NB; ++l)
            for (int m = 0; m < NB; ++m)
                shift[1][l][m] = B::parity_x(l) * B::parity_x(m) * shift[0][l][m];
        if constexpr (D == 2)
            for (int l = 0; l < NB; ++l)
                for (int m = 0; m < NB; ++m) {
                    shift[2][l][m] = shift[0][sw(l)][sw(m)];
                    shift[3][l][m] = shift[1][sw(l)][sw(m)];
                }
        double s[NB][NB];
        for (int l = 0; l < NB; ++l)
            for (int m = 0; m < NB; ++m) {
                // The value of the first of the equivalent entries (l, m), (m, l) and their ξ ↔ η images.
                const int c[4][2] = {{l, m}, {m, l}, {sw(l), sw(m)}, {sw(m), sw(l)}};
                int best = 0;
                for (int k = 1; k < 4; ++k)
                    if (c[k][0] < c[best][0] || (c[k][0] == c[best][0] && c[k][1] < c[best][1])) best = k;
                const bool odd = B::parity_x(l) * B::parity_x(m) < 0 || B::parity_y(l) * B::parity_y(m) < 0;
                s[l][m] = odd ? 0.0 : smooth[c[best][0]][c[best][1]];
            }
        for (int l = 0; l < NB; ++l)
            for (int m = 0; m < NB; ++m)
                smooth[l][m] = s[l][m];
    }
};

} // namespace undex::fluid
