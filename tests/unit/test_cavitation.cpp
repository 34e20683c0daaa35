// The cavitating water's sound speed against finite differences of its pressure–density relation, written
// here from physics.md §2 (Tait liquid; the mixture of fixed vapour mass fraction of paper eqs. 5–9), over
// the whole range: compressed and stretched liquid above p_cav, and the mixture from p_cav down to the
// smallest pressure the solver inverts to (fluid/cavitation.hpp brackets ln p ≥ −60).
#include "fluid/eos_tait.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using undex::fluid::Tait;

namespace {

// The model of cases/cavitation_tube_1d.case (the physics.md defaults).
constexpr double gw = 7.15, B = 3.31e8, A = 1e5, rho0 = 1000.0;
constexpr double p_cav = 2338.0, rho_g_cav = 0.0173, gg = 1.4, alpha0 = 1e-5;

Tait cavitating_water() {
    Tait t;
    t.cavitation = true;
    t.cav.p_cav = p_cav;
    t.cav.rho_g_cav = rho_g_cav;
    t.cav.gamma_g = gg;
    t.cav.alpha0 = alpha0;
    t.cav.finalize();
    return t;
}

// Liquid: ρ(p) on the Tait isentrope.
double liquid_density(double p) {
    return rho0 * std::pow((p + B - A) / B, 1 / gw);
}

// Mixture: vapour on its isentrope ρg = ρg_cav (p/p_cav)^(1/γg), liquid on Tait's, and the vapour mass
// fraction Y fixed by α = α0 at p_cav: 1/ρ = Y/ρg + (1 − Y)/ρl (paper eq. 6 in this form).
double mixture_density(double p) {
    const double rho_l_cav = liquid_density(p_cav);
    const double Y = alpha0 * rho_g_cav / (alpha0 * rho_g_cav + (1 - alpha0) * rho_l_cav);
    const double rho_g = rho_g_cav * std::pow(p / p_cav, 1 / gg);
    return 1 / (Y / rho_g + (1 - Y) / liquid_density(p));
}

// dp/dρ = 1 / (dρ/dp) by a fourth-order central difference in p with step δ = 1e-3 p̃, where p̃ is the
// scale on which ρ(p) varies: p for the mixture, p + B − A for the liquid. Truncation ~(1e-3)⁴; rounding
// ~1e-16 ρ / (δ dρ/dp), which is largest (1e-8) near p_cav, where the mixture's density barely changes.
template <class Rho> double fd_sound_speed_squared(Rho&& rho, double p, double scale) {
    const double d = 1e-3 * scale;
    const double drho_dp = (8 * (rho(p + d) - rho(p - d)) - (rho(p + 2 * d) - rho(p - 2 * d))) / (12 * d);
    return 1 / drho_dp;
}

} // namespace

// c² = dp/dρ along the relation: Tait::sound_speed against the finite difference above, at the density the
// relation gives. Mixture points run by factors 1.7 from just below p_cav (p = p_cav (1 − 1e-6)) down to
// 1e-26 Pa, just above the smallest pressure fluid/cavitation.hpp inverts to (e^−60 ≈ 9e-27 Pa), where
// ρ ≈ 1e-13 kg/m³ and 1 − α ≈ 1e-16; liquid points from just above p_cav to 1 GPa. Largest relative error
// of c² measured 2.1e-8 (mixture: rounding of the difference near p_cav) and 1.26e-12 (liquid); bounds 3e-8
// and 1.9e-12. A wrong term of Wood's formula errs by 1e-2 or more somewhere in this range (the liquid term
// is 12 % of a⁻² at p_cav, the vapour term nearly all of it at low p); 1 − α taken as 1 − α after rounding
// α errs by 7e-2 below 1e-22 Pa.
TEST(Cavitation, SoundSpeedIsTheSlopeOfPressureOverTheWholeRange) {
    const Tait water = cavitating_water();
    double worst_mixture = 0, worst_liquid = 0;
    int mixture_points = 0;
    for (double p = p_cav * (1 - 1e-6); p > 1e-26; p /= 1.7, ++mixture_points) {
        const double rho = mixture_density(p);
        // The relation itself: the solver's p(ρ) inverts the same mixture.
        EXPECT_NEAR(water.pressure(rho, 0) / p, 1.0, 1e-9) << "p = " << p << " Pa";
        const double c = water.sound_speed(rho, p), c2 = fd_sound_speed_squared(mixture_density, p, p);
        worst_mixture = std::max(worst_mixture, std::abs(c * c / c2 - 1));
        EXPECT_NEAR(c * c / c2, 1.0, 3e-8) << "mixture at p = " << p << " Pa, rho = " << rho;
    }
    EXPECT_GT(mixture_points, 100); // 128: the whole range was visited
    for (double p = p_cav * (1 + 1e-6); p < 1e9; p *= 1.7) {
        const double rho = liquid_density(p);
        EXPECT_NEAR(water.pressure(rho, 0) / p, 1.0, 1e-9) << "p = " << p << " Pa";
        const double c = water.sound_speed(rho, p), c2 = fd_sound_speed_squared(liquid_density, p, p + B - A);
        worst_liquid = std::max(worst_liquid, std::abs(c * c / c2 - 1));
        EXPECT_NEAR(c * c / c2, 1.0, 1.9e-12) << "liquid at p = " << p << " Pa";
    }
    // At p_cav itself (the saturated mixture, and the band up to the liquid's density at p_cav) the solver
    // uses the mixture's limit from below; measured relative difference of c² 2.7e-9.
    const double c_sat = water.sound_speed(water.cav.rho_sat, p_cav);
    const double c2_sat = fd_sound_speed_squared(mixture_density, p_cav, p_cav);
    std::printf("largest relative error of c^2: mixture %.2e (%d points), liquid %.2e; at p_cav %.2e\n",
                worst_mixture, mixture_points, worst_liquid, std::abs(c_sat * c_sat / c2_sat - 1));
    EXPECT_NEAR(c_sat * c_sat / c2_sat, 1.0, 4e-9);
}

// The mixture's p(ρ) (fluid/cavitation.hpp: a cubic Hermite table in t = kρ/(M − ρ) on octaves of t, and
// Newton in q = (p/p_cav)^(−1/γg) below the table's last octave, 2^−40) against bisection of the density
// relation in long double, in ln p, 200 halvings of [−60, ln p_cav], at the same double ρ. The inversion is
// ill-conditioned next to p_cav (a relative change δ of ρ moves p by about γg δ / α0 ≈ 1.4e5 δ), so ρ's own
// rounding (1e-16) bounds what any solver in double can reach at about 1.5e-11; long double's 1e-19 keeps
// the reference 1000 times closer. Densities run from just below the saturated mixture's (p = p_cav (1 −
// 1e-12)) by factors 1.004 in p down to 1e-26 Pa: about 3 points per table interval near p_cav (128 per
// octave of t, an octave of t about 1.4 of p), so that every interval is visited off its nodes, and the
// Newton branch from about 1e-13 Pa down. Largest relative error measured 4.4e-12 (the table's own at its
// midpoints: 5.1e-12), bound 1e-10. Broken on purpose, it fails: the position in an interval off by 1e-3 of
// it 1.1e-5, the nodes read one interval late 0.86, the Newton start doubled 0.62; a wrong slope column (its
// sign, or the next node's slope dropped) fails finalize's own midpoint check (1.4e-7, 1.7e-4), which leaves
// the table out (Newton everywhere, 3.7e-11), and so the check of 40 octaves below.
TEST(Cavitation, MixturePressureInvertsTheDensityRelationOverTheWholeRange) {
    const Tait water = cavitating_water();
    using LD = long double;
    const LD pbar_cav = LD(p_cav) + B - A, rho_l_cav = rho0 * std::pow(pbar_cav / B, 1 / LD(gw));
    const LD k = LD(alpha0) / (1 - LD(alpha0)), C = k * rho_g_cav + rho_l_cav;
    auto rho_of = [&](LD p) {
        return C / (std::pow((p + B - A) / pbar_cav, -1 / LD(gw)) + k * std::pow(p / p_cav, -1 / LD(gg)));
    };
    double worst = 0;
    int points = 0;
    for (LD p = p_cav * (1 - 1e-12L); p > 1e-26L; p /= 1.004L, ++points) {
        const double rho = double(rho_of(p));
        LD lo = -60, hi = std::log(LD(p_cav));
        for (int i = 0; i < 200; ++i) {
            const LD mid = (lo + hi) / 2;
            (rho_of(std::exp(mid)) > rho ? hi : lo) = mid;
        }
        const LD p_ref = std::exp((lo + hi) / 2);
        const double err = double(std::abs(water.pressure(rho, 0) / p_ref - 1));
        worst = std::max(worst, err);
        EXPECT_LT(err, 1e-10) << "rho = " << rho << " kg/m^3, p = " << double(p_ref) << " Pa";
    }
    EXPECT_GT(points, 16000); // 16 894: the whole range was visited
    std::printf("mixture p(rho): largest relative error %.2e over %d points (table: %d octaves of %d, %.2e)\n",
                worst, points, water.cav.table_octaves, water.cav.table_n, water.cav.table_error);
    EXPECT_EQ(water.cav.table_octaves, 40); // the table, not Newton, above 1e-13 Pa
}

// The mixture's sound speed at its own density (the vapour's u = (p/p_cav)^(1/γg) read from the table in ρ)
// against the same Wood formula with u = pow(p/p_cav, 1/γg) from the pressure alone (the branch of states on
// the liquid's isentrope; checked against the slope of p(ρ) above), over the mixture range by factors 1.004
// in p, with p the exact pressure of the density: the two differ only by the table's u. Largest relative
// difference measured 9.7e-12, bound 1e-10 (the table's accuracy). Broken on purpose (u read from the p
// column) it fails by 25.
TEST(Cavitation, SoundSpeedFromTheDensityMatchesTheSoundSpeedFromThePressure) {
    const Tait water = cavitating_water();
    double worst = 0;
    int points = 0;
    for (double p = p_cav * (1 - 1e-9); p > 1e-26; p /= 1.004, ++points) {
        const double rho = mixture_density(p);
        const double from_rho = water.cav.mixture_sound_speed(rho, p), from_p = water.cav.mixture_sound_speed(p);
        worst = std::max(worst, std::abs(from_rho / from_p - 1));
        EXPECT_NEAR(from_rho / from_p, 1.0, 1e-10) << "p = " << p << " Pa, rho = " << rho;
        // Tait::sound_speed takes the density's branch inside the mixture's densities.
        EXPECT_EQ(water.sound_speed(rho, p), from_rho);
    }
    EXPECT_GT(points, 16000);
    std::printf("sound speed from rho against from p: largest relative difference %.2e over %d points\n", worst,
                points);
}

// A density the mixture cannot hold (negative, or NaN) gives no finite pressure, so that the solver's
// admissibility checks name the cell: the table is not read outside its range. Broken on purpose (no check
// of t > 0 before the octave is taken from its bits), −1 kg/m³ reads before the table and NaN the last node:
// both give finite pressures.
TEST(Cavitation, InadmissibleDensityGivesNoFinitePressure) {
    const Tait water = cavitating_water();
    for (double rho : {-1.0, -1e-300, std::nan("")}) {
        EXPECT_FALSE(std::isfinite(water.cav.pressure(rho))) << "rho = " << rho;
        EXPECT_FALSE(std::isfinite(water.pressure(rho, 0))) << "rho = " << rho;
    }
}
