// The Zhang–Shu positivity scaling (fluid/scheme.hpp, Scheme::positivity) on a problem that needs it:
// Toro's 123 problem (two rarefactions leaving a near-vacuum, ρ ≈ 0.02 and p ≈ 0.004 at x = 0.5 by
// t = 0.15), ideal gas γ = 1.4, degree 2 with the default limiting (TVB indicator, minmod).
#include "tests/support/exact_riemann.hpp"
#include "tests/support/run_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

// Periodic on [0, 1], so that mass and energy are conserved exactly (no boundary fluxes); the flows
// meeting across x = 0 ≡ 1 make two shocks (speed ±0.62) that stay within 0.1 of that point by t = 0.15, so
// the near-vacuum region around x = 0.5 is the exact 123 solution.
std::string toro123(bool positivity) {
    return std::string("geometry: PLANAR_1D domain { x_min: 0 x_max: 1 cells_x: 200 }"
                       " materials { name: 'air' stiffened_gas { gamma: 1.4 } }"
                       " regions { material: 'air' rho: 1 u: -2 p: 0.4 }"
                       " regions { material: 'air' box { x_min: 0.5 } rho: 1 u: 2 p: 0.4 }"
                       " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC } }"
                       " numerics { degree: 2 cfl: 0.2 positivity: ") +
           (positivity ? "true" : "false") + " } end_time: 0.15 output { directory: '/tmp' }";
}

} // namespace

// With the scaling on, the run reaches t = 0.15, the scaling acted (it is what keeps the run alive: see the
// next test), density and pressure are positive at every point where the scaling enforces it (the Gauss
// points and the faces of every cell), mass and energy are conserved to round-off (the scaling keeps the
// cell averages), and the near-vacuum region agrees with the exact solution.
TEST(Positivity, Toro123NeedsTheScalingWhichConservesMassAndEnergy) {
    auto s = undex::test::make(toro123(true));
    const auto before = s->totals();
    long scaled = 0;
    while (s->time() < 0.15 * (1 - 1e-14)) {
        s->step(std::min(s->stable_dt(), 0.15 - s->time()));
        scaled += s->positivity_scaled_cells();
    }
    const auto after = s->totals();
    const auto& m = s->mesh();
    const double points[5] = {-1.0, -std::sqrt(0.6), 0.0, std::sqrt(0.6), 1.0}; // ξ of faces and Gauss points
    double rho_min = 1e300, p_min = 1e300, l1_rho = 0, l1_p = 0;
    int n_l1 = 0;
    const exact::Solution ex(exact::stiffened_gas(1.4), {1, -2, 0.4}, exact::stiffened_gas(1.4), {1, 2, 0.4});
    for (int i = 0; i < m.nx; ++i) {
        for (double xi : points) {
            // Just inside the cell at the faces (evaluate picks the cell by position).
            const double x = m.xc(i) + 0.5 * m.dx * xi * (1 - 1e-12);
            const auto w = s->evaluate(x, 0);
            rho_min = std::min(rho_min, w.rho);
            p_min = std::min(p_min, w.p);
        }
        const double x = m.xc(i);
        if (x > 0.25 && x < 0.75) {
            const auto w = s->evaluate(x, 0);
            const auto r = ex.sample((x - 0.5) / 0.15);
            l1_rho += std::abs(w.rho - r.rho), l1_p += std::abs(w.p - r.p), ++n_l1;
        }
    }
    l1_rho /= n_l1, l1_p /= n_l1;
    const double dmass = std::abs(after[0] - before[0]) / before[0];
    const double denergy = std::abs(after[2] - before[2]) / before[2];
    std::printf("123 problem: %ld cells scaled; min rho %.3e, min p %.3e at the points; mass change %.2e, "
                "energy change %.2e; L1 on [0.25, 0.75] rho %.3e p %.3e (exact rho, p at 0.5: %.3e %.3e)\n",
                scaled, rho_min, p_min, dmass, denergy, l1_rho, l1_p, ex.sample(0).rho, ex.sample(0).p);
    EXPECT_GT(scaled, 0) << "the positivity scaling never acted: this test would mean nothing";
    EXPECT_GT(rho_min, 0.0);
    EXPECT_GT(p_min, 0.0);
    EXPECT_LE(dmass, 4e-14);   // measured 2.4e-14 (round-off over 413 steps)
    EXPECT_LE(denergy, 4e-14); // measured 2.5e-14
    // Two-sided, within 1.5× of the measured errors: a scaling that acts too much (e.g. towards the average
    // of a neighbour, or on smooth cells) or too little changes them.
    EXPECT_LE(l1_rho, 3.4e-3); // measured 2.30e-3
    EXPECT_GE(l1_rho, 1.5e-3);
    EXPECT_LE(l1_p, 1.6e-3); // measured 1.08e-3
    EXPECT_GE(l1_p, 0.72e-3);
}

// The same run with the scaling off fails within a few steps (a negative pressure at a quadrature point
// turns into a non-finite sound speed): the scaling is what the previous test relies on.
TEST(Positivity, Toro123FailsWithoutTheScaling) {
    auto s = undex::test::make(toro123(false));
    EXPECT_THROW(undex::test::advance(*s, 0.15), undex::fluid::SolverFailure);
    std::printf("failed at t = %.3e after %ld steps\n", s->time(), s->steps());
}
