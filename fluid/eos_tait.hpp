// Barotropic Tait water (physics.md §2, paper eq. 4): p = B[(ρ/ρ0)^γ − 1] + A, a² = γ(p + B − A)/ρ.
// Pressure depends on density only; the energy equation is carried for a uniform data layout and does not
// feed back. With cavitation on, densities below the saturated-mixture density follow the mixture branch
// of cavitation.hpp; between that density and the liquid density at p_cav (a relative width of about α0)
// the pressure stays at p_cav and the mixture sound speed at p_cav is used, so p(ρ) is continuous.
#pragma once
#include "fluid/cavitation.hpp"

#include <cmath>

namespace undex::fluid {

struct Tait {
    static constexpr bool barotropic = true;
    double gamma = 7.15, B = 3.31e8, A = 1e5, rho0 = 1000.0;
    bool cavitation = false;
    CavitationModel cav;

    double pressure(double rho, double /*rho_e*/) const {
        if (cavitation && rho < cav.rho_l_cav) return rho < cav.rho_sat ? cav.pressure(rho) : cav.p_cav;
        return B * (std::pow(rho / rho0, gamma) - 1.0) + A;
    }
    double sound_speed(double rho, double p) const {
        if (cavitation && p <= cav.p_cav) return p < cav.p_cav ? cav.mixture_sound_speed(p) : cav.a_sat;
        return std::sqrt(gamma * (p + B - A) / rho);
    }
    // Energy of the equivalent stiffened gas (P∞ = B − A), so that E is well defined for output and for
    // the characteristic decomposition; it never feeds back into p.
    double internal_energy(double /*rho*/, double p) const { return (p + gamma * (B - A)) / (gamma - 1.0); }
    // Any positive density is admissible: p + B − A > 0 for ρ > 0, and p > 0 with cavitation.
    double pressure_margin(double /*p*/) const { return 1.0; }
    double gruneisen() const { return gamma - 1.0; }
    double density(double p) const { return rho0 * std::pow((p - A) / B + 1.0, 1.0 / gamma); }
};

} // namespace undex::fluid
