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
#pragma once

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

} // namespace undex::solid
