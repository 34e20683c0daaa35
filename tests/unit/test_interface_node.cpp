// The fluid–structure interface node of physics.md §5 and docs/protocol.md §4 (solid/interface_node.hpp),
// in closed form. The test writes the two conditions as a linear system in (u_I, p_I),
//     m u_I − h A p_I = m u⁻ + h F                (the node's central-difference equation of motion)
//     Z_L u_I + p_I  = p_L + Z_L u_L − g         (the fluid characteristic, g its geometric term),
// and solves it by Cramer's rule; g = α Δt ρ_L a_L² u_L / x_I is computed here from a spherical (α = 2)
// state near the centre, so that it is a large share of p_L. With cavitation the pressure is held at the
// floor and the node moves under it alone: u_I = u⁻ + h (F + A p_floor) / m.
#include "solid/interface_node.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace undex::solid;

namespace {

// A light node (m comparable to h A Z_L, so that both equations shape the answer) in water.
const double m = 2.0, h = 1e-6, F = -4e5, A = 0.5;
const double rho_L = 1000, a_L = 1450, u_L = 1.0, Z_L = rho_L * a_L;
const double alpha = 2, dt = 1e-6, x_I = 0.01;
const double g = alpha * dt * rho_L * a_L * a_L * u_L / x_I; // 4.205e5 Pa

struct Exact {
    double u, p;
};
Exact cramer(double u_minus, double p_L, double geometric) {
    const double r1 = m * u_minus + h * F, r2 = p_L + Z_L * u_L - geometric;
    const double det = m * 1 - (-h * A) * Z_L;
    return {(r1 * 1 - (-h * A) * r2) / det, (m * r2 - Z_L * r1) / det};
}

} // namespace

// No cavitation, with and without the geometric term: u_I and p_I equal Cramer's solution, both conditions
// hold, and the geometric term lowers p_I by g m / (m + h A Z_L) (the node yields a little to it). Bound
// 1e-12 relative: round-off of a 2 × 2 solve.
TEST(InterfaceNode, ClosedFormWithTheGeometricTerm) {
    const double u_minus = 3.0, p_L = 5e6, p_floor = 2338;
    for (const double geometric : {0.0, g}) {
        const InterfaceSolution s =
            solve_interface_node(m, u_minus, h, F, A, {p_L, u_L, Z_L, geometric, p_floor});
        const Exact e = cramer(u_minus, p_L, geometric);
        EXPECT_FALSE(s.cavitating);
        EXPECT_NEAR(s.u_I, e.u, 1e-12 * std::abs(e.u)) << "g = " << geometric;
        EXPECT_NEAR(s.p_I, e.p, 1e-12 * p_L) << "g = " << geometric;
        EXPECT_NEAR(m * (s.u_I - u_minus), h * (F + A * s.p_I), 1e-12 * m * std::abs(u_minus));
        EXPECT_NEAR(s.p_I, p_L - Z_L * (s.u_I - u_L) - geometric, 1e-12 * p_L);
    }
    const FluidCharacteristic without{p_L, u_L, Z_L, 0.0, p_floor}, with{p_L, u_L, Z_L, g, p_floor};
    const double drop = solve_interface_node(m, u_minus, h, F, A, without).p_I -
                        solve_interface_node(m, u_minus, h, F, A, with).p_I;
    EXPECT_NEAR(drop, g * m / (m + h * A * Z_L), 1e-9 * g); // 3.086e5 Pa of g = 4.205e5 Pa
}

// The cavitation floor: a node moving away from the water (u⁻ = 20 m/s against u_L = 1 m/s) would pull
// the pressure far below p_cav, and so would the node of the first test once the geometric term lowers its
// pressure (u⁻ = 1.75 m/s, p_L = 1e6 Pa: p_I = 1.486e5 Pa without g, −1.600e5 Pa with g, floor 2338 Pa).
// Then p_I is p_floor exactly and u_I follows from the equation of motion under p_floor alone (bound 1e-12
// relative); without g the same node is not cavitating and takes Cramer's solution.
TEST(InterfaceNode, CavitationFloorHoldsThePressure) {
    const double p_floor = 2338;
    struct Case {
        double u_minus, p_L, geometric;
        bool cavitating;
    };
    for (const Case c : {Case{20.0, 5e6, 0.0, true}, Case{1.75, 1e6, g, true}, Case{1.75, 1e6, 0.0, false}}) {
        const InterfaceSolution s =
            solve_interface_node(m, c.u_minus, h, F, A, {c.p_L, u_L, Z_L, c.geometric, p_floor});
        const Exact free = cramer(c.u_minus, c.p_L, c.geometric);
        EXPECT_EQ(free.p < p_floor, c.cavitating) << "the case itself: p " << free.p;
        EXPECT_EQ(s.cavitating, c.cavitating) << "u- " << c.u_minus << ", g " << c.geometric;
        if (c.cavitating) {
            EXPECT_EQ(s.p_I, p_floor);
            const double u = c.u_minus + h * (F + A * p_floor) / m;
            EXPECT_NEAR(s.u_I, u, 1e-12 * std::abs(u));
        } else {
            EXPECT_NEAR(s.p_I, free.p, 1e-12 * c.p_L);
            EXPECT_NEAR(s.u_I, free.u, 1e-12 * std::abs(free.u));
            EXPECT_NEAR(s.p_I, 1.486e5, 0.001e5); // the margin the comment states
        }
    }
}
