// Isentropic one-fluid cavitation model (physics.md §2, paper eqs. 5–9, after Liu, Khoo and Xie 2004).
// Below the cavitation pressure a cell holds a homogeneous, barotropic vapour–liquid mixture whose density
// ρ(p) is monotone in p; the pressure is found by inverting it.
#pragma once
#include <algorithm>
#include <cmath>

namespace undex::fluid {

struct CavitationModel {
    double p_cav = 2338.0;     // cavitation (vapour) pressure
    double rho_g_cav = 0.0173; // vapour density at p_cav
    double gamma_g = 1.4;      // vapour isentropic exponent
    double alpha0 = 1e-5;      // void fraction reference
    // Liquid (Tait) constants, copied from the water it belongs to.
    double gamma_w = 7.15, B = 3.31e8, A = 1e5, rho0 = 1000.0;

    // Derived: p̄_cav = p_cav + B − A, liquid density at p_cav, k = α0/(1−α0), mixture density at p_cav.
    double pbar_cav = 0, rho_l_cav = 0, k = 0, rho_sat = 0, a_sat = 0;

    void finalize() {
        pbar_cav = p_cav + B - A;
        rho_l_cav = rho0 * std::pow(pbar_cav / B, 1.0 / gamma_w);
        k = alpha0 / (1.0 - alpha0);
        rho_sat = mixture_density(p_cav);
        a_sat = mixture_sound_speed(p_cav);
    }

    // (p̄/p̄_cav)^e for a mixture pressure 0 < p ≤ p_cav: p̄/p̄_cav = 1 + x with |x| ≤ p_cav/p̄_cav (≈ 7e-6 for
    // water), so (1 + x)^e = exp(e ln(1 + x)) by three terms of each series, exact to rounding (the next
    // terms are below 1e-20), without a pow in the hot loops of cavitating cells.
    double liquid_ratio(double p, double e) const {
        const double x = (p - p_cav) / pbar_cav;
        if (!(std::abs(x) < 1e-4)) return std::pow(1.0 + x, e); // far from p_cav (not a mixture): exact
        const double y = e * x * (1.0 - x * (0.5 - x / 3.0));
        return 1.0 + y * (1.0 + y * (0.5 + y / 6.0));
    }

    // ρ(p) = (k ρg_cav + ρl_cav) / [ (p̄/p̄_cav)^(−1/γw) + k (p/p_cav)^(−1/γg) ]
    double mixture_density(double p) const {
        return (k * rho_g_cav + rho_l_cav) /
               (liquid_ratio(p, -1.0 / gamma_w) + k * std::pow(p / p_cav, -1.0 / gamma_g));
    }

    // Pressure of a mixture of density rho < rho_sat. With q = (p/p_cav)^(−1/γg) ≥ 1, the density relation
    // above reads
    //     g(q) = (p̄/p̄_cav)^(−1/γw) + k q − (k ρg_cav + ρl_cav)/ρ = 0,   p = p_cav q^(−γg),
    // where the liquid term differs from 1 by at most (p_cav/p̄_cav)/γw ≈ 1e-6. Taking it as 1 gives q in
    // closed form, q0 = ((k ρg_cav + ρl_cav)/ρ − 1)/k, at or above the root (within 15 % of it next to p_cav,
    // closer as p falls, where k q outgrows the liquid term's change). g increases with q (dg/dq = k +
    // (γg/γw) L p/(p̄ q) with L the liquid term) and is concave, so Newton from q0 lands at or left of the root
    // and then climbs to it monotonically: three or four steps, one pow each, near p_cav, one or two below.
    // Pressures below e^−60 Pa (ρ about 1e-13 kg/m³) are returned as e^−60.
    double pressure(double rho) const {
        constexpr double p_min = 8.75651076269652e-27; // e^−60
        const double rhs = (k * rho_g_cav + rho_l_cav) / rho;
        double q = (rhs - 1.0) / k;
        double p = p_cav * std::pow(q, -gamma_g);
        for (int it = 0; it < 20 && p > p_min; ++it) {
            const double liquid = liquid_ratio(p, -1.0 / gamma_w); // L = (p̄/p̄_cav)^(−1/γw)
            const double g = liquid + k * q - rhs;
            const double dg_dq = k + (gamma_g / gamma_w) * liquid * p / ((p + B - A) * q);
            const double dq = g / dg_dq;
            q -= dq;
            p = p_cav * std::pow(q, -gamma_g);
            if (std::abs(dq) <= 1e-14 * q) break;
        }
        return std::max(p, p_min);
    }

    // Wood's mixture sound speed: a⁻² = ρm [α/(ρg ag²) + (1−α)/(ρl al²)].
    double mixture_sound_speed(double p) const {
        const double pbar = p + B - A;
        const double liquid = liquid_ratio(p, 1.0 / gamma_w);     // (p̄/p̄_cav)^(1/γw)
        const double vapour = std::pow(p / p_cav, 1.0 / gamma_g); // (p/p_cav)^(1/γg)
        const double ratio = k * liquid / vapour;
        // α and 1 − α each from the ratio: 1 − α by subtraction loses all its digits as α → 1 (p → 0), where
        // (1 − α) ρl is still comparable with α ρg.
        const double alpha = ratio / (1.0 + ratio), liquid_fraction = 1.0 / (1.0 + ratio);
        const double rho_g = rho_g_cav * vapour;
        const double rho_l = rho_l_cav * liquid;
        const double rho_m = alpha * rho_g + liquid_fraction * rho_l;
        const double inv_a2 = rho_m * (alpha / (gamma_g * p) + liquid_fraction / (gamma_w * pbar));
        return 1.0 / std::sqrt(inv_a2);
    }

    double void_fraction(double p) const {
        if (p >= p_cav) return 0.0;
        const double pbar = p + B - A;
        const double ratio =
            k * std::pow(pbar / pbar_cav, 1.0 / gamma_w) * std::pow(p / p_cav, -1.0 / gamma_g);
        return ratio / (1.0 + ratio);
    }
};

} // namespace undex::fluid
