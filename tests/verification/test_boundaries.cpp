// Reflective walls against the exact solution: gas running into a wall is the Riemann problem of the gas
// against its own mirror image (velocity reversed), whose exact solution (tests/support/exact_riemann.hpp,
// independent of the solver) holds on the gas's side of the wall.
#include "tests/support/exact_riemann.hpp"
#include "tests/support/run_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace {

// Ideal gas (γ = 1.4) at ρ = 1, p = 1, moving at 1 towards the wall: a shock of p* = 2.93 leaves the wall.
const exact::Solution reflection(exact::stiffened_gas(1.4), {1.0, 1.0, 1.0}, exact::stiffened_gas(1.4),
                                 {1.0, -1.0, 1.0});

struct Errors {
    double rho = 0, u = 0, p = 0;
};

// Mean absolute errors at 100 points spread over distances d = 0 … 0.5 from the wall (d ≥ 0 into the gas);
// `at(d)` returns ρ, the velocity component towards the wall and p at distance d.
template <class At> Errors errors(At&& at, int cells, double t) {
    Errors e;
    for (int c = 0; c < cells; ++c) {
        const double d = (c + 0.5) * 0.5 / cells;
        const exact::State w = reflection.sample(-d / t);
        const auto [rho, u, p] = at(d);
        e.rho += std::abs(rho - w.rho) / cells;
        e.u += std::abs(u - w.u) / cells;
        e.p += std::abs(p - w.p) / cells;
    }
    return e;
}

const char* gas = " materials { name: 'gas' stiffened_gas { gamma: 1.4 } }"
                  " numerics { degree: 1 cfl: 0.3 threads: 1 } end_time: 0.2 output { directory: '/tmp' }";

} // namespace

// Bounds: 1.5× the measured mean errors (in the comments), which come from the smeared shock. A wall that
// lets the normal momentum through, or reverses another component, leaves p at 1 near the wall: errors of
// order 1.
TEST(Wall, GasRunningIntoAWallReflectsAsTheExactShock1D) {
    auto s = undex::test::make(std::string("geometry: PLANAR_1D domain { x_min: 0 x_max: 1 cells_x: 200 }"
                                           " boundaries { x_min { type: TRANSMISSIVE } x_max { type: WALL } }"
                                           " regions { material: 'gas' rho: 1 u: 1 p: 1 }") +
                               gas);
    undex::test::advance(*s, 0.2);
    const Errors e = errors(
        [&](double d) {
            const auto w = s->evaluate(1.0 - d, 0);
            return std::tuple{w.rho, w.u, w.p};
        },
        100, 0.2);
    std::printf("1D wall: mean |error| rho %.3e  u %.3e  p %.3e (p* = %.4f)\n", e.rho, e.u, e.p,
                reflection.p_star());
    EXPECT_LT(e.rho, 6.8e-3); // measured 4.53e-3
    EXPECT_LT(e.u, 6.5e-3);   // measured 4.33e-3
    EXPECT_LT(e.p, 1.05e-2);  // measured 6.96e-3
}

// The same in 2D, the wall at y_min and the gas moving in −y (periodic in x): the y momentum must be the one
// reversed.
TEST(Wall, GasRunningIntoAWallReflectsAsTheExactShock2D) {
    auto s = undex::test::make(
        std::string(
            "geometry: PLANAR_2D domain { x_min: 0 x_max: 0.04 cells_x: 4 y_min: 0 y_max: 1 cells_y: 200 }"
            " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC } y_min { type: WALL }"
            " y_max { type: TRANSMISSIVE } } regions { material: 'gas' rho: 1 u: 0 v: -1 p: 1 }") +
        gas);
    undex::test::advance(*s, 0.2);
    const Errors e = errors(
        [&](double d) {
            const auto w = s->evaluate(0.015, d);
            return std::tuple{w.rho, -w.v, w.p};
        },
        100, 0.2);
    std::printf("2D wall: mean |error| rho %.3e  v %.3e  p %.3e\n", e.rho, e.u, e.p);
    EXPECT_LT(e.rho, 6.8e-3); // measured 4.53e-3
    EXPECT_LT(e.u, 6.5e-3);   // measured 4.33e-3
    EXPECT_LT(e.p, 1.05e-2);  // measured 6.96e-3
}
