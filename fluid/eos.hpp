// What an equation of state must provide (docs/adding_an_eos.md). Generic code — the scheme, the Euler
// flux and conversions (euler.hpp), the boundary ghosts, the two-fluid coupling — calls these members
// only, never an EOS's parameters. Units: ρ kg/m³, p Pa, ρe J/m³ (internal energy per unit volume), a m/s.
#pragma once
#include "fluid/interface_riemann.hpp"

#include <concepts>

namespace undex::fluid {

template <class E>
concept EquationOfState = std::copyable<E> && requires(const E& eos, double rho, double rho_e, double p) {
    // true: p = p(ρ) only (the energy equation is carried but does not feed back); selects the barotropic
    // characteristic decomposition and skips the pressure part of the positivity scaling.
    { E::barotropic } -> std::convertible_to<bool>;
    // p(ρ, ρe).
    { eos.pressure(rho, rho_e) } -> std::same_as<double>;
    // ρe(ρ, p): the inverse of pressure in its second argument.
    { eos.internal_energy(rho, p) } -> std::same_as<double>;
    // a(ρ, p).
    { eos.sound_speed(rho, p) } -> std::same_as<double>;
    // A state is admissible while ρ > 0 and pressure_margin(p) > 0 (e.g. p + P∞); Pa, or 1 if always.
    { eos.pressure_margin(p) } -> std::same_as<double>;
    // The lowest pressure a state can reach (e.g. −P∞, A − B, or the cavitation pressure); Pa.
    { eos.pressure_floor() } -> std::same_as<double>;
    // Grüneisen coefficient Γ of the stiffened-gas form used for the characteristic decomposition.
    { eos.gruneisen() } -> std::same_as<double>;
    // γ of the isentropes p + Π ∝ ρ^γ: the Riemann invariants u ± 2a/(γ − 1) of pressure boundaries.
    { eos.isentropic_exponent() } -> std::same_as<double>;
    // Density reached from (ρ, p) along its isentrope at pressure p_new (pressure boundary ghost).
    { eos.isentrope_density(rho, p, p) } -> std::same_as<double>;
    // Density of a wall ghost held at p_wall next to a cell (ρ, p) (structure boundary ghost).
    { eos.wall_density(rho, p, p) } -> std::same_as<double>;
    // Original ghost fluid method: the entropy function s = ρ/(p + Π)^(1/γ) of a state, and the density of
    // entropy function s at p̄ = p + Π.
    { eos.entropy(rho, p) } -> std::same_as<double>;
    { eos.entropy_density(rho, p) } -> std::same_as<double>;
    // The material seen by the two-material interface Riemann solver (γ, Π, Tait shock data).
    { eos.riemann_material() } -> std::same_as<RiemannMaterial>;
    // Cavitation: whether the model is on, and the void fraction α(p) (0 without cavitation).
    { eos.has_cavitation() } -> std::same_as<bool>;
    { eos.void_fraction(p) } -> std::same_as<double>;
};

// The form of an equation of state E that the SIMD lane loops of the scheme use (Scheme::faces_flux and
// Scheme::cells_rhs over W > 1 cells): E::Lanes, constructed from E, whose p(ρ, ρe) and a(ρ, p) have no
// branches and are E's to the last bit for every density its holds(ρ) accepts (a block with any other
// density goes one cell at a time, with E); or E itself, when E's own have no branches to remove.
template <class E> struct LaneForm {
    using type = E;
    static constexpr bool always = true; // every state
};
template <class E>
    requires requires { typename E::Lanes; }
struct LaneForm<E> {
    using type = typename E::Lanes;
    static constexpr bool always = false;
};

} // namespace undex::fluid
