// Boundary conditions by ghost cells: each ghost cell holds a full polynomial, so that face fluxes and the
// limiter treat boundary cells like interior ones. Sides: 0 x_min, 1 x_max, 2 y_min, 3 y_max.
#pragma once
#include "fluid/basis.hpp"
#include "fluid/mesh.hpp"
#include "fluid/solver.hpp"

#include <array>
#include <cmath>

namespace undex::fluid {

namespace detail {

// Ghost = interior polynomial mirrored in the face; the normal momentum negated for walls.
template <int D, int K> inline void mirror(const double* in, double* out, int dir, bool negate_normal) {
    using B = Basis<D, K>;
    constexpr int NV = D + 2;
    for (int v = 0; v < NV; ++v)
        for (int l = 0; l < B::NB; ++l) {
            const int power = dir == 0 ? B::px(l) : B::py(l);
            double s = power % 2 ? -1.0 : 1.0;
            if (negate_normal && v == 1 + dir) s = -s;
            out[v * B::NB + l] = s * in[v * B::NB + l];
        }
}

// The cell-average density, velocity and pressure of an interior cell's coefficients.
template <int D, int K, class Eos>
inline void cell_average_state(const double* in, const Eos& eos, double& rho, double* vel, double& p) {
    constexpr int NV = D + 2, NB = Basis<D, K>::NB;
    rho = in[0];
    vel[0] = in[NB] / rho;
    vel[1] = D == 2 ? in[2 * NB] / rho : 0.0;
    const double ke = 0.5 * rho * (vel[0] * vel[0] + vel[1] * vel[1]);
    p = eos.pressure(rho, in[(NV - 1) * NB] - ke);
}

// Coefficients of the constant state (ρ, velocity, p) in a ghost cell.
template <int D, int K, class Eos>
inline void constant_state(double* out, double rho, const double* vel, double p, const Eos& eos) {
    constexpr int NV = D + 2, NB = Basis<D, K>::NB;
    for (int i = 0; i < NV * NB; ++i)
        out[i] = 0.0;
    out[0] = rho;
    for (int d = 0; d < D; ++d)
        out[(1 + d) * NB] = rho * vel[d];
    out[(NV - 1) * NB] = eos.internal_energy(rho, p) + 0.5 * rho * (vel[0] * vel[0] + vel[1] * vel[1]);
}

// Ghost state of a prescribed pressure p_b: density on the isentrope of the interior cell average and
// velocity from the outgoing Riemann invariant u ∓ 2a/(γ−1) (exact for both stiffened gases and Tait water,
// whose isentropes are polytropic in p + P∞). Constant polynomial.
template <int D, int K, class Eos>
inline void pressure_ghost(const double* in, double* out, int side, double p_b, const Eos& eos) {
    const int dir = side / 2;
    double rho, vel[2], p;
    cell_average_state<D, K>(in, eos, rho, vel, p);
    const double a = eos.sound_speed(rho, p);
    double rho_b;
    if constexpr (Eos::barotropic)
        rho_b = eos.density(p_b);
    else
        rho_b = rho * std::pow((p_b + eos.p_inf) / (p + eos.p_inf), 1.0 / eos.gamma);
    const double a_b = eos.sound_speed(rho_b, p_b);
    const double sign = side % 2 == 0 ? 1.0 : -1.0; // low side: u − 2a/(γ−1) leaves; high side: u + 2a/(γ−1)
    vel[dir] += sign * 2.0 * (a_b - a) / (eos.gamma - 1.0);
    constant_state<D, K>(out, rho_b, vel, p_b, eos);
}

// Ghost state of the structure's interface (physics.md §5): the pressure p_I and normal velocity u_I of the
// structure, density on the isentrope of the interior cell average. Between the interior trace and this
// state the face's Riemann problem returns (p_I, u_I) when they satisfy the characteristic relation.
template <int D, int K, class Eos>
inline void structure_ghost(const double* in, double* out, int side, double p_I, double u_I, const Eos& eos) {
    const int dir = side / 2;
    double rho, vel[2], p;
    cell_average_state<D, K>(in, eos, rho, vel, p);
    double rho_b;
    if constexpr (Eos::barotropic) { // a wall held at the cavitation pressure keeps the mixture's density
        rho_b = eos.cavitation && p_I <= eos.cav.p_cav ? std::min(rho, eos.cav.rho_l_cav) : eos.density(p_I);
    } else {
        rho_b = rho * std::pow((p_I + eos.p_inf) / (p + eos.p_inf), 1.0 / eos.gamma);
    }
    vel[dir] = side % 2 == 0 ? -u_I : u_I; // u_I is along the normal into the structure
    constant_state<D, K>(out, rho_b, vel, p_I, eos);
}

} // namespace detail

template <int D, int K, class Eos>
void fill_ghosts(const Mesh& m, double* U, const std::array<Boundary, 4>& bc, const Eos& eos, double t) {
    constexpr int NC = (D + 2) * Basis<D, K>::NB; // numbers per cell
    const int nsides = 2 * D;
    for (int side = 0; side < nsides; ++side) {
        const int dir = side / 2;
        const bool high = side % 2;
        const int count = dir == 0 ? m.ny : m.nx;
        const double p_b = bc[side].type == BoundaryType::Pressure ? bc[side].pressure(t) : 0.0;
        for (int s = 0; s < count; ++s) {
            int gi, gj, ii, ij; // ghost and interior neighbour
            if (dir == 0) {
                gj = ij = s;
                gi = high ? m.nx : -1;
                ii = high ? m.nx - 1 : 0;
            } else {
                gi = ii = s;
                gj = high ? m.ny : -1;
                ij = high ? m.ny - 1 : 0;
            }
            double* g = U + static_cast<long>(m.index(gi, gj)) * NC;
            const double* in = U + static_cast<long>(m.index(ii, ij)) * NC;
            switch (bc[side].type) {
            case BoundaryType::Transmissive:
                detail::mirror<D, K>(in, g, dir, false);
                break;
            case BoundaryType::Wall:
            case BoundaryType::Symmetry:
                detail::mirror<D, K>(in, g, dir, true);
                break;
            case BoundaryType::Pressure:
                detail::pressure_ghost<D, K>(in, g, side, p_b, eos);
                break;
            case BoundaryType::Structure:
                detail::structure_ghost<D, K>(in, g, side, bc[side].p_I, bc[side].u_I, eos);
                break;
            case BoundaryType::Periodic: {
                const int pi = dir == 0 ? (high ? 0 : m.nx - 1) : s;
                const int pj = dir == 1 ? (high ? 0 : m.ny - 1) : s;
                const double* src = U + static_cast<long>(m.index(pi, pj)) * NC;
                for (int k = 0; k < NC; ++k)
                    g[k] = src[k];
                break;
            }
            }
        }
    }
}

} // namespace undex::fluid
