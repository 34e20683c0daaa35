// Whole-solver verification: conservation, the paper's case 4.2, geometric sources, and failure handling.
#include "base/case_file.hpp"
#include "tests/support/exact_riemann.hpp"
#include "tests/support/run_case.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

using undex::fluid::Primitive;

// On a closed (periodic) planar domain every RK stage, the WENO limiter (which keeps cell averages) and the
// positivity scaling (likewise) conserve mass, momentum and energy; only round-off may change the totals.
// Bound: 1e-13 relative to the total (about 500 ulps after ~100 steps of sums over 6400 cells).
TEST(Conservation, PeriodicBlastKeepsTotalsToRoundOff) {
    auto s = undex::test::make(
        "geometry: PLANAR_2D domain { x_min: 0 x_max: 1 cells_x: 80 y_min: 0 y_max: 1 cells_y: 80 }"
        " materials { name: 'air' stiffened_gas { gamma: 1.4 } } regions { material: 'air' rho: 1 u: 0.3 v: "
        "-0.2 p: 0.1 }"
        " regions { material: 'air' ball { x: 0.4 y: 0.6 radius: 0.2 } rho: 2 u: 0.3 v: -0.2 p: 10 }"
        " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC } y_min { type: PERIODIC } y_max { "
        "type: PERIODIC } }"
        " numerics { degree: 2 cfl: 0.2 } end_time: 0.05 output { directory: '/tmp' }");
    const auto before = s->totals();
    long troubled = 0;
    while (s->time() < 0.05 * (1 - 1e-14)) {
        s->step(std::min(s->stable_dt(), 0.05 - s->time()));
        troubled += s->troubled_cells();
    }
    const auto after = s->totals();
    EXPECT_GT(troubled, 0) << "the limiter must be active for this test to mean anything";
    const char* names[4] = {"mass", "x-momentum", "y-momentum", "energy"};
    const double scale[4] = {before[0], std::abs(before[1]), std::abs(before[2]), before[3]};
    for (int v = 0; v < 4; ++v) {
        std::printf("%s: %.17g -> %.17g (relative change %.2e)\n", names[v], before[v], after[v],
                    std::abs(after[v] - before[v]) / scale[v]);
        EXPECT_LE(std::abs(after[v] - before[v]), 1e-13 * scale[v]) << names[v];
    }
}

namespace {
std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream b;
    b << in.rdbuf();
    return b.str();
}
} // namespace

// The paper's case 4.2 (cases/cavitation_tube_1d.case): the exact solution is symmetric about x = 0.5,
// cavitates at the centre (pressure far below p_cav = 2338 Pa there, void fraction well above α0) and
// has p ≥ 0 everywhere (the mixture pressure cannot be negative).
TEST(CavitationTube, SymmetricPositiveAndCavitatingAtTheCentre) {
    auto c = undex::CaseFile::from_text(read_file(std::string(UNDEX_CASES) + "/cavitation_tube_1d.case"));
    auto s = undex::fluid::make_solver(c);
    undex::test::advance(*s, 1e-4);
    const auto& m = s->mesh();
    double p_min = 1e300, p_max = 0, rho_min = 1e300, asym_u = 0, asym_p = 0;
    for (int i = 0; i < m.nx; ++i) {
        const Primitive w = s->cell_average(i, 0), r = s->cell_average(m.nx - 1 - i, 0);
        p_min = std::min(p_min, w.p);
        p_max = std::max(p_max, w.p);
        rho_min = std::min(rho_min, w.rho);
        // Mirror symmetry: u(x) = −u(1 − x), p(x) = p(1 − x).
        asym_u += std::abs(w.u + r.u) / m.nx;
        asym_p += std::abs(w.p - r.p) / m.nx;
    }
    const Primitive centre = s->cell_average(m.nx / 2, 0);
    std::printf("p_min %.3e Pa, rho_min %.3f, centre p %.3e Pa rho %.3f void %.3e; L1 asymmetry u %.3e m/s, "
                "p %.3e Pa (peak %.3e Pa)\n",
                p_min, rho_min, centre.p, centre.rho, s->void_fraction(centre.p), asym_u, asym_p, p_max);
    EXPECT_GE(p_min, 0.0);
    EXPECT_GT(rho_min, 0.0);
    EXPECT_LT(centre.p, 2338.0);
    EXPECT_GT(s->void_fraction(centre.p), 100 * 1e-5);
    // Symmetry: every operator rounds alike in mirror-image cells (fluid/basis.hpp, Basis::mode_sum), so the
    // run is an exact mirror image; 1e-10 of the peak leaves room for nothing but that (an operator that
    // breaks the symmetry by one rounding gives 1e-2 here: the limiter amplifies it at the wall shocks).
    EXPECT_LE(asym_p, 1e-10 * p_max);
    EXPECT_LE(asym_u, 1e-10 * 200.0);
}

namespace {

// The exact solution of case 4.2 until the waves meet (t < 1.5e-4 s), written from physics.md §2 without
// the solver's code. Each half is a Riemann problem of its own: at each wall the water moving into it
// stops behind a Tait shock (tests/support/exact_riemann.hpp, the wall as the mirror-image state); at the
// centre two rarefactions leave the water at rest, and since Tait water holds no tension each one is a
// liquid fan from 1e5 Pa down to p_cav (u − 2a/(γ−1) constant), a constant state at p_cav while the sound
// speed falls from the liquid's (1537 m/s) to the saturated mixture's (536 m/s), and a mixture fan along the
// mixture's ρ(p) (du = −dp/(ρa), a² = dp/dρ). The mixture can take up only 0.03 m/s of the 100 m/s
// (its density stays near the liquid's down to 1e-3 Pa, where a is already below 1 cm/s): behind the fan,
// from ξ = (x − 0.5)/t ≈ −99.9 m/s to +99.9 m/s, lies a cavity of (near) zero density. (The band of
// densities between the saturated mixture and the liquid at p_cav, of relative width α0, is left out: it
// moves pressures near p_cav by under p_cav and u by under 1e-2 m/s.)
struct CavitationTubeExact {
    static constexpr double gw = 7.15, B = 3.31e8, A = 1e5, rho0 = 1000, p0 = 1e5, u0 = 100;
    static constexpr double p_cav = 2338, rho_g_cav = 0.0173, gg = 1.4, alpha0 = 1e-5;
    static constexpr int N = 20000;
    exact::Solution wall{
        exact::tait(gw, B, A, rho0), {rho0, u0, p0}, exact::tait(gw, B, A, rho0), {rho0, -u0, p0}};
    std::vector<double> lnp, u, xi; // the mixture fan, from p_cav down to e^−60 p_cav, by ln p

    static double liquid_density(double p) { return rho0 * std::pow((p + B - A) / B, 1 / gw); }
    static double liquid_sound_speed(double p) { return std::sqrt(gw * (p + B - A) / liquid_density(p)); }
    // Mixture of fixed vapour mass fraction Y (α = α0 at p_cav): 1/ρ = Y/ρg + (1 − Y)/ρl, both isentropic.
    static double mixture_density(double p) {
        const double rho_l_cav = liquid_density(p_cav);
        const double Y = alpha0 * rho_g_cav / (alpha0 * rho_g_cav + (1 - alpha0) * rho_l_cav);
        return 1 / (Y / (rho_g_cav * std::pow(p / p_cav, 1 / gg)) + (1 - Y) / liquid_density(p));
    }
    // a² = dp/dρ of the mixture: dρ/dp = ρ² [Y/(ρg γg p) + (1 − Y)/(ρl γw p̄)].
    static double mixture_sound_speed(double p) {
        const double rho_l_cav = liquid_density(p_cav);
        const double Y = alpha0 * rho_g_cav / (alpha0 * rho_g_cav + (1 - alpha0) * rho_l_cav);
        const double rho = mixture_density(p), rho_g = rho_g_cav * std::pow(p / p_cav, 1 / gg);
        return 1 / std::sqrt(rho * rho *
                             (Y / (rho_g * gg * p) + (1 - Y) / (liquid_density(p) * gw * (p + B - A))));
    }
    double u_cav() const { return -u0 + 2 / (gw - 1) * (liquid_sound_speed(p0) - liquid_sound_speed(p_cav)); }

    CavitationTubeExact() {
        // du/d(−ln p) = p/(ρa), by the trapezoidal rule on 20000 steps of 0.003 (error ~1e-8 m/s).
        const double h = 60.0 / N;
        auto f = [](double s) {
            const double p = std::exp(s);
            return p / (mixture_density(p) * mixture_sound_speed(p));
        };
        double s = std::log(p_cav), v = u_cav();
        for (int k = 0; k <= N; ++k, s -= h) {
            if (k > 0) v += 0.5 * h * (f(s) + f(s + h));
            lnp.push_back(s);
            u.push_back(v);
            xi.push_back(v - mixture_sound_speed(std::exp(s)));
        }
    }

    // The left half (x ≤ 0.5); the right half is its mirror image.
    Primitive left_half(double x, double t) const {
        if (x < 0.25) { // the wall's Riemann problem
            const exact::State w = wall.sample(x / t);
            return {w.rho, w.u, 0, w.p};
        }
        const double z = (x - 0.5) / t;
        const double c0 = liquid_sound_speed(p0), c_cav = liquid_sound_speed(p_cav);
        if (z <= -u0 - c0) return {rho0, -u0, 0, p0};
        if (z <= u_cav() - c_cav) { // liquid fan of the left wave: u − a = ξ, u + 2a/(γ−1) constant
            const double c = (-u0 + 2 * c0 / (gw - 1) - z) * (gw - 1) / (gw + 1);
            const double pbar = B * std::pow(c * c * rho0 / (gw * B), gw / (gw - 1));
            return {rho0 * std::pow(pbar / B, 1 / gw), z + c, 0, pbar - B + A};
        }
        if (z <= xi.front()) return {liquid_density(p_cav), u_cav(), 0, p_cav};
        if (z >= xi.back()) return {0, u.back(), 0, 0};                        // the cavity
        const long k = std::upper_bound(xi.begin(), xi.end(), z) - xi.begin(); // xi[k−1] ≤ z < xi[k]
        const double f = (z - xi[k - 1]) / (xi[k] - xi[k - 1]);
        const double p = std::exp(lnp[k - 1] + f * (lnp[k] - lnp[k - 1]));
        return {mixture_density(p), u[k - 1] + f * (u[k] - u[k - 1]), 0, p};
    }
    Primitive at(double x, double t) const {
        if (x <= 0.5) return left_half(x, t);
        Primitive w = left_half(1 - x, t);
        w.u = -w.u;
        return w;
    }
};

} // namespace

// Case 4.2 against its exact solution at three times before the waves meet, by 8 samples of the DG
// polynomials per cell on the case's 400 cells. The norms, each over both halves (ξ = (x − 0.5)/t):
// - shocks, x < 0.25 or x > 0.75: ∫|p − p_ex| / ∫p_ex, and the signed ∫(p − p_ex) / ∫p_ex, which changes sign
//   with a shock too fast or too slow;
// - fans, 300 ≤ |ξ| ≤ 1200 m/s (the constant state at p_cav and the mixture fan): mean |u − u_ex| and mean
//   |p − p_ex|. Not nearer the rarefaction heads: the initial velocity jump, which the TVB indicator does not
//   see (ρ and E are continuous), leaves unlimited oscillations of up to 1e6 Pa that travel with the heads;
// - cavity, |ξ| < 130 m/s: the mass ∫ρ against the exact one (two-sided), and ρ at x = 0.5 (exact: 0).
// The solution is self-similar, so the three times are three resolutions of one profile.
TEST(CavitationTube, MatchesTheExactSolutionBeforeTheWavesMeet) {
    const CavitationTubeExact ex;
    std::printf(
        "exact: wall shock p* %.4e Pa, speed %.1f m/s; u at p_cav %.4f m/s; mixture fan xi %.1f .. %.2f "
        "m/s, cavity |xi| < %.3f m/s\n",
        ex.wall.p_star(), ex.wall.right_wave().head, ex.u_cav(), ex.xi.front(), ex.xi.back(), -ex.u.back());
    auto s = undex::fluid::make_solver(
        undex::CaseFile::from_text(read_file(std::string(UNDEX_CASES) + "/cavitation_tube_1d.case")));
    const int cells = s->mesh().nx, per = 8;
    struct Bounds {
        double t, shock, shock_signed;
    };
    // Measured: relative L1 3.26e-2, 1.62e-2, 8.11e-3 (first order, as across a shock); signed −1.63e-3,
    // −3.36e-3, −3.80e-4.
    const Bounds bounds[3] = {{2.5e-5, 4.9e-2, 2.4e-3}, {5e-5, 2.4e-2, 5.0e-3}, {1e-4, 1.2e-2, 5.7e-4}};
    for (const Bounds& b : bounds) {
        const double t = b.t;
        undex::test::advance(*s, t);
        double shock = 0, shock_signed = 0, shock_ref = 0, fan_u = 0, fan_p = 0, mass = 0, mass_ref = 0;
        int fan_n = 0;
        for (int k = 0; k < cells * per; ++k) {
            const double x = (k + 0.5) / (cells * per), dx = 1.0 / (cells * per), xi = std::abs(x - 0.5) / t;
            const Primitive n = s->evaluate(x, 0), e = ex.at(x, t);
            if (x < 0.25 || x > 0.75) {
                shock += std::abs(n.p - e.p), shock_signed += n.p - e.p, shock_ref += e.p;
            } else if (xi >= 300 && xi <= 1200) {
                fan_u += std::abs(n.u - e.u), fan_p += std::abs(n.p - e.p), ++fan_n;
            } else if (xi < 130) {
                mass += n.rho * dx, mass_ref += e.rho * dx;
            }
        }
        shock /= shock_ref, shock_signed /= shock_ref, fan_u /= fan_n, fan_p /= fan_n;
        const double centre_rho = s->evaluate(0.5, 0).rho;
        std::printf(
            "t = %.2e: shocks relative L1 p %.3e, signed %.3e; fans mean |du| %.3e m/s, |dp| %.1f Pa; "
            "cavity mass / exact %.4f, centre rho %.3f\n",
            t, shock, shock_signed, fan_u, fan_p, mass / mass_ref, centre_rho);
        EXPECT_LE(shock, b.shock) << "t = " << t;
        EXPECT_LE(std::abs(shock_signed), b.shock_signed) << "t = " << t;
        if (t == 1e-4) { // before, the fans and the cavity span too few cells (the last time is the finest)
            EXPECT_LE(fan_u, 1.4e-3);                // measured 9.3e-4 m/s
            EXPECT_LE(fan_p, 1000.0);                // measured 683 Pa
            EXPECT_NEAR(mass / mass_ref, 1.0, 0.13); // measured 1.087
            EXPECT_LE(centre_rho, 29.0);             // measured 19.5 kg/m³
        }
    }
}

// A spherical blast in air computed in 1D spherical geometry (α = 2) and in 2D axisymmetric geometry
// (α = 1, r × z with symmetry at z = 0) must agree along a ray. Norm: mean absolute difference of density
// over r ∈ [0, 0.9] divided by the mean 1D density, along the r axis (first row of cells) and along the
// diagonal z = r, against an 800-cell 1D reference. The thin shell between contact and shock (about
// 0.04 wide, ρ ≈ 3) is not resolved by coarse 2D meshes, so "agree" is tested as convergence: the
// difference must fall by a factor ≥ 1.5 per mesh doubling (L1 order ≥ 0.58, the least expected with
// discontinuities) from 50² to 100² to 200² cells, and end below 3 %.
TEST(GeometricSource, SphericalBlast1DAnd2DAxisymmetricAgree) {
    const std::string common = " materials { name: 'air' stiffened_gas { gamma: 1.4 } }"
                               " numerics { degree: 1 cfl: 0.2 } end_time: 0.15 output { directory: '/tmp' }";
    auto s1 = undex::test::make("geometry: SPHERICAL_1D domain { x_min: 0 x_max: 1 cells_x: 800 }"
                                " regions { material: 'air' rho: 1 p: 0.1 } regions { material: 'air' ball { "
                                "radius: 0.3 } rho: 2 p: 2 }"
                                " boundaries { x_min { type: SYMMETRY } x_max { type: TRANSMISSIVE } }" +
                                common);
    undex::test::advance(*s1, 0.15);
    double previous_axis = 0, previous_diag = 0;
    for (int n : {50, 100, 200}) {
        const std::string cells = std::to_string(n);
        auto s2 = undex::test::make(
            "geometry: AXISYMMETRIC_2D domain { x_min: 0 x_max: 1 cells_x: " + cells +
            " y_min: 0 y_max: 1 cells_y: " + cells +
            " } regions { material: 'air' rho: 1 p: 0.1 } regions { material: 'air' ball { radius: 0.3 } "
            "rho: 2 p: 2 }"
            " boundaries { x_min { type: SYMMETRY } x_max { type: TRANSMISSIVE } y_min { type: SYMMETRY }"
            " y_max { type: TRANSMISSIVE } }" +
            common);
        undex::test::advance(*s2, 0.15);
        double diff = 0, mean = 0, diff_diag = 0;
        const double z0 = s2->mesh().yc(0);
        for (int k = 0; k < 900; ++k) {
            const double r = (k + 0.5) * 0.001;
            const double ref = s1->evaluate(r, 0).rho;
            diff += std::abs(s2->evaluate(std::sqrt(std::max(r * r - z0 * z0, 0.0)), z0).rho - ref);
            const double d = r / std::sqrt(2.0);
            diff_diag += std::abs(s2->evaluate(d, d).rho - ref);
            mean += ref;
        }
        diff /= mean, diff_diag /= mean;
        std::printf("blast %dx%d: along the r axis %.3e, along the diagonal %.3e\n", n, n, diff, diff_diag);
        if (previous_axis > 0) {
            EXPECT_LE(diff, previous_axis / 1.5);
            EXPECT_LE(diff_diag, previous_diag / 1.5);
        }
        if (n == 200) {
            EXPECT_LE(diff, 0.03);
            EXPECT_LE(diff_diag, 0.03);
        }
        previous_axis = diff, previous_diag = diff_diag;
    }
}

// With the limiter and positivity scaling off, a strong shock makes the scheme produce inadmissible states;
// the solver must stop with a message that names the cell, time and step, and keep the last good state.
TEST(Failure, UnlimitedStrongShockStopsWithAClearMessage) {
    auto s = undex::test::make(
        "geometry: PLANAR_1D domain { x_min: 0 x_max: 1 cells_x: 200 }"
        " materials { name: 'air' stiffened_gas { gamma: 1.4 } } regions { material: 'air' rho: 1 p: 1e5 }"
        " regions { material: 'air' box { x_min: 0.5 } rho: 0.01 p: 1e-3 }"
        " boundaries { x_min { type: TRANSMISSIVE } x_max { type: TRANSMISSIVE } }"
        " numerics { degree: 2 cfl: 0.2 indicator: 'none' positivity: false } end_time: 1e-3 output { "
        "directory: '/tmp' }");
    try {
        undex::test::advance(*s, 1e-3);
        FAIL() << "the unlimited run was expected to fail";
    } catch (const undex::fluid::SolverFailure& f) {
        const std::string msg = f.what();
        std::printf("message: %s\n", msg.c_str());
        EXPECT_NE(msg.find("in cell ("), std::string::npos);
        EXPECT_NE(msg.find("in step "), std::string::npos);
        EXPECT_NE(msg.find("t = "), std::string::npos);
    }
    // The solution is the last good state: admissible everywhere.
    for (int i = 0; i < s->mesh().nx; ++i) {
        const auto w = s->cell_average(i, 0);
        ASSERT_TRUE(std::isfinite(w.rho) && std::isfinite(w.p) && w.rho > 0 && w.p > 0) << "cell " << i;
    }
}
