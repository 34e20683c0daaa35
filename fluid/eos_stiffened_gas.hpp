// Stiffened gas (physics.md §2): p = (γ−1)ρe − γP∞, a² = γ(p+P∞)/ρ. An ideal gas has P∞ = 0.
#pragma once
#include <cmath>

namespace undex::fluid {

struct StiffenedGas {
    static constexpr bool barotropic = false;
    double gamma = 1.4;
    double p_inf = 0.0;

    // rho_e: internal energy per unit volume, ρe = E − ½ρ|u|².
    double pressure(double /*rho*/, double rho_e) const { return (gamma - 1.0) * rho_e - gamma * p_inf; }
    double sound_speed(double rho, double p) const { return std::sqrt(gamma * (p + p_inf) / rho); }
    double internal_energy(double /*rho*/, double p) const { return (p + gamma * p_inf) / (gamma - 1.0); }
    // The state is admissible while ρ > 0 and this margin is positive (Zhang–Shu positivity).
    double pressure_margin(double p) const { return p + p_inf; }
    // Grüneisen coefficient and pressure shift of the stiffened-gas form used for the characteristic
    // decomposition of the limiter.
    double gruneisen() const { return gamma - 1.0; }
};

} // namespace undex::fluid
