// Boundary conditions by ghost cells: each ghost cell holds a full polynomial, so that face fluxes and the
// limiter treat boundary cells like interior ones. Sides: 0 x_min, 1 x_max, 2 y_min, 3 y_max.
#pragma once
#include "fluid/basis.hpp"
#include "fluid/eos.hpp"
#include "fluid/euler.hpp"
#include "fluid/mesh.hpp"
#include "fluid/solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

// Ghost state of an incident plane wave p_inc entering still water at p_amb (BoundaryType::Incident), set
// through the incoming characteristic only. Along the inward normal n, the Riemann invariants
// J± = u_n ± 2a/(γ−1) of the isentropes p + Π ∝ ρ^γ (exact for stiffened gases and Tait water, as in
// pressure_ghost): the outgoing J− is the interior cell average's, the incoming J+ that of the incident
// simple wave, J+ = u_inc + 2a_inc/(γ−1) with u_inc = 2(a_inc − a_amb)/(γ−1) (J− = −2a_amb/(γ−1) of the
// still water). With exact invariants the side stays transparent to strong isentropic waves, where the
// linearised p ± Z u_n with the ambient Z = ρ0 c0 would reflect about (γ+1)/8 · Δp/(ρ0 c0²) of a wave of
// amplitude Δp (half its mean change of impedance): 2 % at 50 MPa in water. Sound speeds come from the
// ambient state on the interior cell's isentrope, a = a_amb (X/X_amb)^((γ−1)/2γ) with X = p + Π and
// X_amb = ρ_amb a_amb²/γ, so that a cavitating Tait cell (whose mixture sound speed is not that of the
// invariants) is read on the liquid branch. Constant polynomial, tangential velocity from the interior.
template <int D, int K, EquationOfState Eos>
inline void incident_ghost(const double* in, double* out, int side, double p_inc, double p_amb,
                           const Eos& eos) {
    const int dir = side / 2;
    const double n = side % 2 == 0 ? 1.0 : -1.0; // inward normal along axis dir
    double rho, vel[2], p;
    cell_average_state<D, K>(in, eos, rho, vel, p);
    const double gamma = eos.isentropic_exponent(), gm1 = gamma - 1.0;
    const double rho_amb = eos.isentrope_density(rho, p, p_amb);
    const double a_amb = eos.sound_speed(rho_amb, p_amb);
    const double X_amb = rho_amb * a_amb * a_amb / gamma; // p_amb + Π
    const double k = gm1 / (2.0 * gamma);
    // a(p) on the isentrope, and its inverse p(a).
    const auto speed = [&](double pr) { return a_amb * std::pow((X_amb + (pr - p_amb)) / X_amb, k); };
    const auto pressure = [&](double a) { return p_amb + (X_amb * std::pow(a / a_amb, 1.0 / k) - X_amb); };
    const double J_out = n * vel[dir] - 2.0 * speed(p) / gm1;
    const double a_inc = speed(p_inc);
    const double J_in = (4.0 * a_inc - 2.0 * a_amb) / gm1;
    // a_g ≤ 0 (an inflow faster than 2(a + a_amb)/(γ−1), about 1000 m/s in water, with no incident wave):
    // the ghost is then a vacuum (ρ = 0) and the step fails naming the cell.
    const double a_g = std::max(0.25 * gm1 * (J_in - J_out), 0.0);
    const double p_g = pressure(a_g);
    vel[dir] = n * (0.5 * (J_in + J_out));
    constant_state<D, K>(out, eos.isentrope_density(rho, p, p_g), vel, p_g, eos);
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

// The ghost cells of the domain's sides, in rows [j0, j1) only (on many ranks, those a rank's stage reads).
template <int D, int K, EquationOfState Eos>
void fill_ghosts(const Mesh& m, double* U, const std::array<Boundary, 4>& bc, const Eos& eos, double t,
                 int j0 = 0, int j1 = std::numeric_limits<int>::max()) {
    constexpr int NC = (D + 2) * Basis<D, K>::NB; // numbers per cell
    const int nsides = 2 * D;
    for (int side = 0; side < nsides; ++side) {
        const int dir = side / 2;
        const bool high = side % 2;
        if (dir == 1 && (high ? j1 < m.ny : j0 > 0)) continue; // a y side beyond the rows
        const int first = dir == 0 ? std::max(0, j0) : 0, count = dir == 0 ? std::min(m.ny, j1) : m.nx;
        const bool history =
            bc[side].type == BoundaryType::Pressure || bc[side].type == BoundaryType::Incident;
        const double p_b = history ? bc[side].pressure(t) : 0.0;
        for (int s = first; s < count; ++s) {
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
            case BoundaryType::Absorbing: // the layer's outer side
                detail::mirror<D, K>(in, g, dir, false);
                break;
            case BoundaryType::Wall:
            case BoundaryType::Symmetry:
                detail::mirror<D, K>(in, g, dir, true);
                break;
            case BoundaryType::Pressure:
                detail::pressure_ghost<D, K>(in, g, side, p_b, eos);
                break;
            case BoundaryType::Incident:
                detail::incident_ghost<D, K>(in, g, side, p_b, bc[side].p_ambient, eos);
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
