// Boundary conditions by ghost cells: each ghost cell holds a full polynomial, so that face fluxes and the
// limiter treat boundary cells like interior ones. Sides: 0 x_min, 1 x_max, 2 y_min, 3 y_max.
#pragma once
#include "fluid/basis.hpp"
#include "fluid/eos.hpp"
#include "fluid/euler.hpp"
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
template <int D, int K, EquationOfState Eos>
inline void cell_average_state(const double* in, const Eos& eos, double& rho, double* vel, double& p) {
    const Primitive w = euler::to_primitive<D>(eos, euler::Strided<const double>{in, Basis<D, K>::NB});
    rho = w.rho;
    vel[0] = w.u;
    vel[1] = w.v;
    p = w.p;
}

// Coefficients of the constant state (ρ, velocity, p) in a ghost cell.
template <int D, int K, EquationOfState Eos>
inline void constant_state(double* out, double rho, const double* vel, double p, const Eos& eos) {
    constexpr int NV = D + 2, NB = Basis<D, K>::NB;
    for (int i = 0; i < NV * NB; ++i)
        out[i] = 0.0;
    euler::to_conserved<D>(eos, Primitive{rho, vel[0], vel[1], p}, euler::Strided<double>{out, NB});
}

// Ghost state of a prescribed pressure p_b: density on the isentrope of the interior cell average and
// velocity from the outgoing Riemann invariant u ∓ 2a/(γ−1) (exact for both stiffened gases and Tait water,
// whose isentropes are polytropic in p + P∞). Constant polynomial.
template <int D, int K, EquationOfState Eos>
inline void pressure_ghost(const double* in, double* out, int side, double p_b, const Eos& eos) {
    const int dir = side / 2;
    double rho, vel[2], p;
    cell_average_state<D, K>(in, eos, rho, vel, p);
    const double a = eos.sound_speed(rho, p);
    const double rho_b = eos.isentrope_density(rho, p, p_b);
    const double a_b = eos.sound_speed(rho_b, p_b);
    const double sign = side % 2 == 0 ? 1.0 : -1.0; // low side: u − 2a/(γ−1) leaves; high side: u + 2a/(γ−1)
    vel[dir] += sign * 2.0 * (a_b - a) / (eos.isentropic_exponent() - 1.0);
    constant_state<D, K>(out, rho_b, vel, p_b, eos);
}

// Ghost state of the structure's interface (physics.md §5): the pressure p_I and normal velocity u_I of the
// structure, density on the isentrope of the interior cell average. Between the interior trace and this
// state the face's Riemann problem returns (p_I, u_I) when they satisfy the characteristic relation.
template <int D, int K, EquationOfState Eos>
inline void structure_ghost(const double* in, double* out, int side, double p_I, double u_I, const Eos& eos) {
    const int dir = side / 2;
    double rho, vel[2], p;
    cell_average_state<D, K>(in, eos, rho, vel, p);
    const double rho_b = eos.wall_density(rho, p, p_I);
    vel[dir] = side % 2 == 0 ? -u_I : u_I; // u_I is along the normal into the structure
    constant_state<D, K>(out, rho_b, vel, p_I, eos);
}

} // namespace detail

template <int D, int K, EquationOfState Eos>
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
