// The Zhang–Shu positivity scaling (fluid/scheme.hpp, Scheme::positivity_row) on problems that need it:
// Toro's 123 problem (two rarefactions leaving a near-vacuum, ρ = 0.022 and p = 0.0019 at x = 0.5 by
// t = 0.15) and the same with u = ∓6, where a vacuum opens (u_R − u_L = 12 exceeds 2(a_L + a_R)/(γ − 1) =
// 7.48); ideal gas γ = 1.4, degree 2 with the default limiting (TVB indicator, minmod). The 123 problem
// exercises the pressure part of the scaling, the vacuum the density part as well.
#include "tests/support/exact_riemann.hpp"
#include "tests/support/run_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

// Periodic on [0, 1], so that mass and energy are conserved exactly (no boundary fluxes); the flows
// meeting across x = 0 ≡ 1 make two shocks (speed ±0.62 for u = ∓2) that stay within 0.1 of that point by
// t = 0.15, so the near-vacuum region around x = 0.5 is the exact 123 solution.
std::string rarefactions(double u, bool positivity, double end_time) {
    return "geometry: PLANAR_1D domain { x_min: 0 x_max: 1 cells_x: 200 }"
           " materials { name: 'air' stiffened_gas { gamma: 1.4 } }"
           " regions { material: 'air' rho: 1 u: " +
           std::to_string(-u) +
           " p: 0.4 }"
           " regions { material: 'air' box { x_min: 0.5 } rho: 1 u: " +
           std::to_string(u) +
           " p: 0.4 }"
           " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC } }"
           " numerics { degree: 2 cfl: 0.2 positivity: " +
           (positivity ? "true" : "false") + " } end_time: " + std::to_string(end_time) +
           " output { directory: '/tmp' }";
}

struct Totals {
    long scaled = 0;
    double rho_min = 1e300, p_min = 1e300, dmass = 0, denergy = 0;
};

// Runs to end_time with the scaling on; the smallest ρ and p over the faces and Gauss points of every cell
// (where the scaling enforces positivity) and the relative changes of total mass and energy.
Totals run_with_scaling(undex::fluid::FluidSolver& s, double end_time) {
    Totals r;
    const auto before = s.totals();
    while (s.time() < end_time * (1 - 1e-14)) {
        s.step(std::min(s.stable_dt(), end_time - s.time()));
        r.scaled += s.positivity_scaled_cells();
    }
    const auto after = s.totals();
    const auto& m = s.mesh();
    const double points[5] = {-1.0, -std::sqrt(0.6), 0.0, std::sqrt(0.6), 1.0};
    for (int i = 0; i < m.nx; ++i)
        for (double xi : points) {
            // Just inside the cell at the faces (evaluate picks the cell by position).
            const auto w = s.evaluate(m.xc(i) + 0.5 * m.dx * xi * (1 - 1e-12), 0);
            r.rho_min = std::min(r.rho_min, w.rho);
            r.p_min = std::min(r.p_min, w.p);
        }
    r.dmass = std::abs(after[0] - before[0]) / before[0];
    r.denergy = std::abs(after[2] - before[2]) / before[2];
    return r;
}

} // namespace

// With the scaling on, the run reaches t = 0.15, the scaling acted (it is what keeps the run alive: see
// Toro123AndVacuumFailWithoutTheScaling), density and pressure are positive at the points, mass and energy
// are conserved to round-off (the scaling keeps the cell averages), and the near-vacuum region agrees with
// the exact solution.
TEST(Positivity, Toro123NeedsTheScalingWhichConservesMassAndEnergy) {
    auto s = undex::test::make(rarefactions(2, true, 0.15));
    const Totals r = run_with_scaling(*s, 0.15);
    const exact::Solution ex(exact::stiffened_gas(1.4), {1, -2, 0.4}, exact::stiffened_gas(1.4), {1, 2, 0.4});
    const auto& m = s->mesh();
    double l1_rho = 0, l1_p = 0;
    int n = 0;
    for (int i = 0; i < m.nx; ++i) {
        const double x = m.xc(i);
        if (x < 0.25 || x > 0.75) continue;
        const auto w = s->evaluate(x, 0);
        const auto e = ex.sample((x - 0.5) / 0.15);
        l1_rho += std::abs(w.rho - e.rho), l1_p += std::abs(w.p - e.p), ++n;
    }
    l1_rho /= n, l1_p /= n;
    std::printf("123 problem: %ld cells scaled; min rho %.3e, min p %.3e at the points; mass change %.2e, "
                "energy change %.2e; L1 on [0.25, 0.75] rho %.3e p %.3e\n",
                r.scaled, r.rho_min, r.p_min, r.dmass, r.denergy, l1_rho, l1_p);
    EXPECT_GT(r.scaled, 0) << "the positivity scaling never acted: this test would mean nothing";
    EXPECT_GT(r.rho_min, 0.0);
    EXPECT_GT(r.p_min, 0.0);
    EXPECT_LE(r.dmass, 4e-14);   // measured 2.4e-14 (round-off over 413 steps)
    EXPECT_LE(r.denergy, 4e-14); // measured 2.5e-14
    // Two-sided, within 1.5× of the measured errors: a scaling that acts too much or too little changes them.
    EXPECT_LE(l1_rho, 3.4e-3); // measured 2.30e-3
    EXPECT_GE(l1_rho, 1.5e-3);
    EXPECT_LE(l1_p, 1.6e-3); // measured 1.08e-3
    EXPECT_GE(l1_p, 0.72e-3);
}

// A vacuum opens at x = 0.5 (the exact solution has ρ = p = 0 on 0.5 ± 0.11 at t = 0.05, before the shocks
// from x = 0 ≡ 1 arrive): the scaling acts on the density as well, the run completes with positive density
// and pressure at the points, and mass and energy are conserved.
TEST(Positivity, VacuumNeedsTheScalingWhichConservesMassAndEnergy) {
    auto s = undex::test::make(rarefactions(6, true, 0.05));
    const Totals r = run_with_scaling(*s, 0.05);
    std::printf("vacuum: %ld cells scaled; min rho %.3e, min p %.3e at the points; mass change %.2e, energy "
                "change %.2e\n",
                r.scaled, r.rho_min, r.p_min, r.dmass, r.denergy);
    EXPECT_GT(r.scaled, 0);
    EXPECT_GT(r.rho_min, 0.0);
    EXPECT_GT(r.p_min, 0.0);
    EXPECT_LE(r.dmass, 2.8e-14);   // measured 1.8e-14
    EXPECT_LE(r.denergy, 2.8e-14); // measured 1.9e-14
}

// The same runs with the scaling off fail within a few steps (a negative pressure at a quadrature point
// turns into a non-finite sound speed): the scaling is what the tests above rely on.
TEST(Positivity, Toro123AndVacuumFailWithoutTheScaling) {
    for (double u : {2.0, 6.0}) {
        const double end = u == 2.0 ? 0.15 : 0.05;
        auto s = undex::test::make(rarefactions(u, false, end));
        EXPECT_THROW(undex::test::advance(*s, end), undex::fluid::SolverFailure) << "u = " << u;
        std::printf("u = %g: failed at t = %.3e after %ld steps\n", u, s->time(), s->steps());
    }
}
