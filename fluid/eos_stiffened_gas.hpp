// Stiffened gas (physics.md §2): p = (γ−1)ρe − γP∞, a² = γ(p+P∞)/ρ. An ideal gas has P∞ = 0.
#pragma once
#include "fluid/eos.hpp"

#include <algorithm>
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
    double pressure_floor() const { return -p_inf; }
    // Grüneisen coefficient and pressure shift of the stiffened-gas form used for the characteristic
    // decomposition of the limiter.
    double gruneisen() const { return gamma - 1.0; }
    double isentropic_exponent() const { return gamma; }
    // Isentrope p + P∞ ∝ ρ^γ through (ρ, p).
    double isentrope_density(double rho, double p, double p_new) const {
        return rho * std::pow((p_new + p_inf) / (p + p_inf), 1.0 / gamma);
    }
    double wall_density(double rho, double p, double p_wall) const {
        return isentrope_density(rho, p, p_wall);
    }
    // The entropy function of the original ghost fluid method, s = ρ / (p + P∞)^(1/γ), and its inverse.
    double entropy(double rho, double p) const {
        return rho / std::pow(std::max(p + p_inf, 1e-300), 1.0 / gamma);
    }
    double entropy_density(double s, double pbar) const { return s * std::pow(pbar, 1.0 / gamma); }
    RiemannMaterial riemann_material() const {
        RiemannMaterial m;
        m.gamma = gamma;
        m.pi = p_inf;
        return m;
    }
    bool has_cavitation() const { return false; }
    double void_fraction(double p) const { return 0.0 * p; }
};

static_assert(EquationOfState<StiffenedGas>);

} // namespace undex::fluid
