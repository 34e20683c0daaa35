// The fluid's stable time step against its formula (physics.md §3): Δt_f = CFL / max over cells and
// directions of (|u_d| + a) / Δx_d, computed here from the uniform state's closed-form sound speed.
#include "tests/support/run_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

// A uniform ideal gas (γ = 1.4, ρ = 1.2, p = 1e5) moving at (u, v); a = sqrt(γ p / ρ) = 341.57 m/s.
std::string uniform_case(const std::string& geometry, double u, double v) {
    std::string sides = " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC }";
    if (geometry.find("2D") != std::string::npos)
        sides += " y_min { type: PERIODIC } y_max { type: PERIODIC }";
    return geometry + sides + " }" +
           " materials { name: 'air' stiffened_gas { gamma: 1.4 } }"
           " regions { material: 'air' rho: 1.2 u: " +
           std::to_string(u) + " v: " + std::to_string(v) +
           " p: 1e5 } numerics { degree: 1 cfl: 0.3 threads: 1 } end_time: 1e-3 output { directory: '/tmp' }";
}

} // namespace

// Each velocity component counts in its own direction: a wrong |u| (dropped, or taken from the other
// direction) moves Δt by the factor (|u| + a)/a, 1.29 or more here. Bound: 1e-12 relative (round-off of one
// division and a square root).
TEST(TimeStep, StableDtIsCflOverTheLargestWaveSpeedPerDirection) {
    const double a = std::sqrt(1.4 * 1e5 / 1.2);
    {
        auto s = undex::test::make(
            uniform_case("geometry: PLANAR_1D domain { x_min: 0 x_max: 1 cells_x: 50 }", -100, 0));
        const double expected = 0.3 * (1.0 / 50) / (100 + a);
        EXPECT_NEAR(s->stable_dt(), expected, 1e-12 * expected);
    }
    {
        // Δx = 0.02, Δy = 0.05: the x direction sets the step although |v| > |u|.
        auto s = undex::test::make(uniform_case(
            "geometry: PLANAR_2D domain { x_min: 0 x_max: 1 cells_x: 50 y_min: 0 y_max: 1 cells_y: 20 }", 100,
            300));
        const double expected = 0.3 / std::max((100 + a) / 0.02, (300 + a) / 0.05);
        EXPECT_NEAR(s->stable_dt(), expected, 1e-12 * expected);
    }
    {
        // Δy = 0.01 < Δx = 0.02: the y direction sets the step, with |v|.
        auto s = undex::test::make(uniform_case(
            "geometry: PLANAR_2D domain { x_min: 0 x_max: 1 cells_x: 50 y_min: 0 y_max: 1 cells_y: 100 }",
            300, -100));
        const double expected = 0.3 / std::max((300 + a) / 0.02, (100 + a) / 0.01);
        EXPECT_NEAR(s->stable_dt(), expected, 1e-12 * expected);
    }
}

// Still water (numerics.skip_rest, on by default): cells asleep still count for the step, at the rest
// state's (|u| + a)/Δx; water at rest (Tait, ρ0 1000, p = A = 1e5: a = sqrt(γ B / ρ0)) with transmissive
// sides sleeps everywhere, and the step is the formula's, not unbounded. Bound: 1e-12 relative.
TEST(TimeStep, StillWaterCountsAsleep) {
    auto s = undex::test::make(
        "geometry: PLANAR_2D domain { x_min: 0 x_max: 1 cells_x: 50 y_min: 0 y_max: 1 cells_y: 20 }"
        " boundaries { x_min { type: TRANSMISSIVE } x_max { type: TRANSMISSIVE } y_min { type: TRANSMISSIVE }"
        " y_max { type: TRANSMISSIVE } }"
        " materials { name: 'water' tait { gamma: 7.15 B: 3.31e8 A: 1e5 rho0: 1000 } }"
        " regions { material: 'water' rho: 1000 p: 1e5 } numerics { degree: 1 cfl: 0.3 threads: 1 }"
        " end_time: 1e-3 output { directory: '/tmp' }");
    const double a = std::sqrt(7.15 * 3.31e8 / 1000), expected = 0.3 * 0.02 / a;
    EXPECT_NEAR(s->stable_dt(), expected, 1e-12 * expected);
    s->step(0.5 * expected);
    EXPECT_EQ(s->cell_updates(), 50 * 20);
    EXPECT_EQ(s->cell_updates_skipped(), 50 * 20);
}
