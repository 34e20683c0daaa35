// Unit tests of the fluid building blocks: basis, eigenvectors, equations of state, flux, indicator.
#include "fluid/basis.hpp"
#include "fluid/cavitation.hpp"
#include "fluid/characteristic.hpp"
#include "fluid/eos_stiffened_gas.hpp"
#include "fluid/eos_tait.hpp"
#include "fluid/euler.hpp"
#include "fluid/flux_hllc.hpp"
#include "fluid/indicator_tvb.hpp"
#include "fluid/limiter_weno.hpp"

#include <gtest/gtest.h>

using namespace undex::fluid;

// The modal basis is orthogonal with the stated norms: the mass matrix is diagonal (physics.md §3).
TEST(Basis, OrthogonalWithStatedNorms2D) {
    using B = Basis<2, 2>;
    BasisTables<2, 2> t; // 3-point Gauss, exact for products of quadratics
    for (int l = 0; l < B::NB; ++l)
        for (int m = 0; m < B::NB; ++m) {
            double s = 0;
            for (int q = 0; q < B::NQV; ++q)
                s += t.wv[q] * t.phiv[q][l] * t.phiv[q][m];
            EXPECT_NEAR(s, l == m ? B::norm(l) : 0.0, 1e-14) << l << "," << m;
        }
}

TEST(Basis, ShiftOfNeighbourReproducesAGlobalQuadratic) {
    // A quadratic defined across two cells: its coefficients in the right cell, shifted into the left
    // cell, must equal its own coefficients in the left cell.
    using B = Basis<1, 2>;
    WenoTables<1, 2> w;
    auto f = [](double x) { return 1 + 2 * x + 3 * x * x; }; // x in units of Δx/2, left centre 0
    auto coeffs = [&](double centre) {                       // L2 projection by 3-point Gauss
        std::array<double, 3> c{};
        const double g[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)}, wt[3] = {5 / 18., 8 / 18., 5 / 18.};
        for (int l = 0; l < 3; ++l)
            for (int q = 0; q < 3; ++q)
                c[l] += wt[q] * f(centre + g[q]) * B::phi(l, g[q], 0) / B::norm(l);
        return c;
    };
    const auto left = coeffs(0), right = coeffs(2);
    for (int l = 0; l < 3; ++l) {
        double s = 0;
        for (int m = 0; m < 3; ++m)
            s += w.shift[1][l][m] * right[m]; // neighbour +x seen from the left cell
        EXPECT_NEAR(s, left[l], 1e-12);
    }
}

// Round-off in L·R grows with the condition number of the eigenvector matrix, about (|u| + a)/a.
template <class EV> void expect_inverse(const EV& e, int nv, double condition) {
    for (int i = 0; i < nv; ++i)
        for (int j = 0; j < nv; ++j) {
            double s = 0;
            for (int k = 0; k < nv; ++k)
                s += e.L[i][k] * e.R[k][j];
            EXPECT_NEAR(s, i == j ? 1.0 : 0.0, 1e-14 * condition) << i << "," << j;
        }
}

TEST(Characteristic, LeftAndRightEigenvectorsAreInverse) {
    const double vel[2] = {120.0, -35.0};
    expect_inverse(euler_eigenvectors<4, 0>(1.2, vel, 340.0, 0.4), 4, 10);
    expect_inverse(euler_eigenvectors<4, 1>(1.2, vel, 340.0, 0.4), 4, 10);
    expect_inverse(euler_eigenvectors<3, 0>(1.2, vel, 340.0, 0.4), 3, 10);
    expect_inverse(barotropic_eigenvectors<4, 0>(vel, 1.0e-3), 4, 120.0 / 1.0e-3);
    expect_inverse(barotropic_eigenvectors<4, 1>(vel, 1450.0), 4, 10);
    expect_inverse(barotropic_eigenvectors<3, 0>(vel, 1450.0), 3, 10);
}

TEST(Characteristic, RightEigenvectorsAreEigenvectorsOfTheJacobian) {
    // Ideal gas 1D: check A r = λ r with the Jacobian by central differences of the flux.
    const double g = 1.4, rho = 1.3, u = 50, p = 2e5;
    const double a = std::sqrt(g * p / rho);
    const double vel[1] = {u};
    const auto e = euler_eigenvectors<3, 0>(rho, vel, a, g - 1);
    auto flux = [&](const double* U, double* F) {
        const double uu = U[1] / U[0], pp = (g - 1) * (U[2] - 0.5 * U[0] * uu * uu);
        F[0] = U[1], F[1] = U[1] * uu + pp, F[2] = (U[2] + pp) * uu;
    };
    const double U[3] = {rho, rho * u, p / (g - 1) + 0.5 * rho * u * u};
    const double lambda[3] = {u - a, u, u + a};
    for (int k = 0; k < 3; ++k) {
        const double h = 1e-6 * rho;
        double Up[3], Um[3], Fp[3], Fm[3];
        for (int v = 0; v < 3; ++v)
            Up[v] = U[v] + h * e.R[v][k], Um[v] = U[v] - h * e.R[v][k];
        flux(Up, Fp);
        flux(Um, Fm);
        for (int v = 0; v < 3; ++v)
            EXPECT_NEAR((Fp[v] - Fm[v]) / (2 * h), lambda[k] * e.R[v][k],
                        1e-5 * (1 + std::abs(lambda[k] * e.R[v][k])));
    }
}

TEST(Eos, TaitMatchesItsDefinition) {
    Tait w;
    EXPECT_DOUBLE_EQ(w.pressure(1000.0, 0), 1e5);
    EXPECT_NEAR(w.pressure(1100.0, 0), 3.31e8 * (std::pow(1.1, 7.15) - 1) + 1e5, 1e-3);
    EXPECT_NEAR(w.density(w.pressure(1234.0, 0)), 1234.0, 1e-9);
    EXPECT_NEAR(w.sound_speed(1000.0, 1e5), std::sqrt(7.15 * 3.31e8 / 1000.0), 1e-9);
}

TEST(Eos, StiffenedGasRoundTrip) {
    StiffenedGas w{7.15, 3.309e8};
    const double rho = 1000, p = 1e5;
    EXPECT_NEAR(w.pressure(rho, w.internal_energy(rho, p)), p, 1e-6);
    EXPECT_NEAR(w.sound_speed(rho, p), std::sqrt(7.15 * (p + 3.309e8) / rho), 1e-9);
}

// Both models satisfy the concept; a type lacking a member does not (a compile-time check).
struct NoSoundSpeed : StiffenedGas {
    double sound_speed(double, double) const = delete;
};
static_assert(EquationOfState<StiffenedGas> && EquationOfState<Tait>);
static_assert(!EquationOfState<NoSoundSpeed>);

TEST(Eos, IsentropeDensityStaysOnTheIsentrope) {
    StiffenedGas g{1.4, 1e5};
    const double rho = 1.2, p = 2e5, p_new = 7e5;
    const double r = g.isentrope_density(rho, p, p_new);
    EXPECT_NEAR((p_new + 1e5) / std::pow(r, 1.4), (p + 1e5) / std::pow(rho, 1.4), 1e-9 * (p + 1e5));
    Tait w;
    EXPECT_NEAR(w.pressure(w.isentrope_density(1000.0, 1e5, 5e7), 0), 5e7, 1e-3);
}

// Conserved -> primitive -> conserved is the identity to rounding, for both models and in 2D.
TEST(Euler, ConservedPrimitiveRoundTrip) {
    const double q[4] = {1.3, 1.3 * 40, 1.3 * -25, 3e5};
    auto check = [&](const auto& eos) {
        const Primitive w = euler::to_primitive<2>(eos, q);
        EXPECT_NEAR(euler::pressure<2>(eos, q), w.p, 1e-9 * std::abs(w.p) + 1e-6);
        double back[4];
        euler::to_conserved<2>(eos, w, back);
        for (int v = 0; v < 4; ++v)
            EXPECT_NEAR(back[v], q[v], 1e-12 * std::abs(q[v]));
    };
    check(StiffenedGas{1.4, 0});
    check(StiffenedGas{7.15, 1e5});
}

TEST(Cavitation, MixtureMeetsLiquidAndInvertsMonotonically) {
    CavitationModel c;
    c.finalize();
    // At p_cav the mixture density meets the liquid's up to the reference void fraction α0.
    EXPECT_NEAR(c.rho_sat / c.rho_l_cav, 1.0, 2 * c.alpha0);
    // ρ(p) increases with p, and pressure(ρ) inverts it.
    double prev = 0;
    for (double p : {1e-6, 1e-3, 1.0, 100.0, 1000.0, 2000.0}) {
        const double rho = c.mixture_density(p);
        EXPECT_GT(rho, prev);
        prev = rho;
        EXPECT_NEAR(c.pressure(rho) / p, 1.0, 1e-9) << "p = " << p;
    }
    // Wood's sound speed lies far below both the liquid's and the vapour's (the classic mixture dip).
    EXPECT_LT(c.mixture_sound_speed(1000.0), 1450.0);
    EXPECT_GT(c.mixture_sound_speed(1000.0), 0.0);
}

TEST(Flux, HllcIsConsistent) {
    StiffenedGas g{1.4, 0};
    const double U[4] = {1.2, 1.2 * 30, 1.2 * -10, 2.5e5 + 0.5 * 1.2 * 1000};
    const double p = g.pressure(1.2, U[3] - 0.5 * 1.2 * 1000);
    double F[4];
    hllc_flux<4, 0>(g, U, p, U, p, F);
    EXPECT_NEAR(F[0], U[1], 1e-12);
    EXPECT_NEAR(F[1], U[1] * 30 + p, 1e-9);
    EXPECT_NEAR(F[2], U[2] * 30, 1e-9);
    EXPECT_NEAR(F[3], (U[3] + p) * 30, 1e-6);
    hllc_flux<4, 1>(g, U, p, U, p, F);
    EXPECT_NEAR(F[0], U[2], 1e-12);
    EXPECT_NEAR(F[2], U[2] * -10 + p, 1e-9);
}

// A wall is a mirror state: the mass flux through it vanishes up to round-off of the momentum flux scale.
TEST(Flux, MirrorStatesGiveNoMassFlux) {
    Tait w;
    const double UL[3] = {1000, 1000 * 20, 1e9}, UR[3] = {1000, -1000 * 20, 1e9};
    double F[3];
    hllc_flux<3, 0>(w, UL, 1e5, UR, 1e5, F);
    EXPECT_LE(std::abs(F[0]), 1e-13 * 1000 * 20 * 1500);
}

TEST(Indicator, MinmodFlagsOnlyModifiedSlopes) {
    EXPECT_FALSE(tvb_modifies(0.1, 0.3, 0.2, 0.0));  // monotone, smaller than both differences
    EXPECT_TRUE(tvb_modifies(0.5, 0.3, 0.2, 0.0));   // steeper than the neighbours
    EXPECT_TRUE(tvb_modifies(0.1, -0.3, 0.2, 0.0));  // extremum
    EXPECT_FALSE(tvb_modifies(0.1, -0.3, 0.2, 0.2)); // below the TVB threshold
}
