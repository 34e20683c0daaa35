// The fluid–structure interface condition of physics.md §5 for one interface node, solved together with the
// node's central-difference equation of motion. Along the normal n (from the fluid into the structure) the
// fluid characteristic gives
//     p_I = p_L − Z_L (u_I − u_L) − g,
// and the node of lumped mass m and wetted area A obeys
//     m (u_I − u⁻) = h (F + A p_I),
// with u⁻ the velocity of the last half step, h the central-difference interval and F every other force
// along n. Both are linear in u_I, so
//     u_I = [m u⁻ + h (F + A (p_L + Z_L u_L − g))] / (m + h A Z_L).
// The fluid cannot pull harder than p_floor (cavitation): if p_I falls below it, p_I = p_floor and the node
// moves under that pressure alone.
//
// A rigid face of many wet nodes (solve_rigid_face) moves as one body of mass m along the common normal n:
// every node has the same u_I, and node k of area A_k obeys its own impedance relation, so
//     m (u_I − u⁻) = h (F + Σ_k A_k p_I,k),   p_I,k = p_L,k − Z_L,k (u_I − u_L,k) − g_k,
// again linear in u_I:
//     u_I = [m u⁻ + h (F + Σ_k A_k (p_L,k + Z_L,k u_L,k − g_k))] / (m + h Σ_k A_k Z_L,k).
// A node whose p_I,k falls below p_floor holds p_floor and leaves the sum over Z; u_I then rises, which can
// only lower the other nodes' pressures, so the set of such nodes grows until it is settled (at most one
// pass per node).
#pragma once

#include <span>
#include <stdexcept>
#include <vector>

namespace undex::solid {

struct FluidCharacteristic {
    double p_L = 0, u_L = 0, Z_L = 0, geometric = 0, p_floor = 0;
};

struct InterfaceSolution {
    double u_I = 0, p_I = 0;
    bool cavitating = false; // p_I held at p_floor
};

inline InterfaceSolution solve_interface_node(double m, double u_minus, double h, double F, double A,
                                              const FluidCharacteristic& f) {
    InterfaceSolution s;
    s.u_I = (m * u_minus + h * (F + A * (f.p_L + f.Z_L * f.u_L - f.geometric))) / (m + h * A * f.Z_L);
    s.p_I = f.p_L - f.Z_L * (s.u_I - f.u_L) - f.geometric;
    if (s.p_I < f.p_floor) {
        s.p_I = f.p_floor;
        s.u_I = u_minus + h * (F + A * s.p_I) / m;
        s.cavitating = true;
    }
    return s;
}

// The rigid face above: the interface pressure and the common velocity u_I of each node.
inline std::vector<InterfaceSolution> solve_rigid_face(double m, double u_minus, double h, double F,
                                                       std::span<const double> A,
                                                       std::span<const FluidCharacteristic> f) {
    if (A.size() != f.size()) throw std::invalid_argument("solve_rigid_face: one area per fluid state");
    std::vector<InterfaceSolution> s(A.size());
    for (bool settled = false; !settled;) {
        double num = m * u_minus + h * F, den = m;
        for (size_t k = 0; k < A.size(); ++k) {
            if (s[k].cavitating) {
                num += h * A[k] * f[k].p_floor;
            } else {
                num += h * A[k] * (f[k].p_L + f[k].Z_L * f[k].u_L - f[k].geometric);
                den += h * A[k] * f[k].Z_L;
            }
        }
        const double u = num / den;
        settled = true;
        for (size_t k = 0; k < A.size(); ++k) {
            s[k].u_I = u;
            if (s[k].cavitating) {
                s[k].p_I = f[k].p_floor;
                continue;
            }
            s[k].p_I = f[k].p_L - f[k].Z_L * (u - f[k].u_L) - f[k].geometric;
            if (s[k].p_I < f[k].p_floor) s[k].cavitating = true, settled = false;
        }
    }
    return s;
}

} // namespace undex::solid
