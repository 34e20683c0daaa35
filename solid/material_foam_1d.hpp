// Uniaxial rate-dependent elastic–plastic foam with densification lock-up, for the cores of 1D sandwich
// columns (physics.md §6, case 4.3). Only the xx components are used (through-thickness elements):
//   σ = E (ε − ε_p);  |σ| ≤ σ_pl + η |ε̇_p|  (plateau stress σ_pl, over-stress viscosity η);
//   while the compressive strain −ε exceeds the densification strain ε_D the foam is locked: no plastic
//   flow, and σ = E(−ε_D − ε_p) + E_lock (ε + ε_D), continuous with the unlocked branch at ε = −ε_D.
#pragma once
#include "solid/material.hpp"

namespace undex::solid {

class Foam1D final : public MaterialLaw {
  public:
    struct Constants {
        double rho = 0, E = 0, sigma_pl = 0, eta = 0, eps_d = 0, E_lock = 0;
    };
    explicit Foam1D(const Constants& c) : c_(c) {
        require(c.rho > 0, "density rho must be positive");
        require(c.E > 0, "Young's modulus E must be positive");
        require(c.sigma_pl > 0, "plateau stress sigma_pl must be positive");
        require(c.eta >= 0, "over-stress viscosity eta must be >= 0");
        require(c.eps_d > 0 && c.eps_d < 1, "densification strain eps_d must lie in (0, 1)");
        require(c.E_lock >= c.E, "lock-up modulus E_lock must be >= E");
    }
    std::string name() const override { return "foam_1d"; }
    double density() const override { return c_.rho; }
    double wave_modulus() const override { return c_.E_lock; }
    // E while the step cannot carry the compression to ε_D, E_lock from there on.
    double wave_modulus_at(const PointState& s, double strain_step) const override {
        return -s.strain[0] + strain_step >= c_.eps_d ? c_.E_lock : c_.E;
    }
    double shear_modulus() const override { return 0; }

  protected:
    void advance(const Voigt&, double dt, PointState& s) const override {
        const double eps = s.strain[0];
        double& ep = s.plastic_strain[0];
        s.peeq_rate = 0;
        if (-eps >= c_.eps_d) {
            s.stress[0] = c_.E * (-c_.eps_d - ep) + c_.E_lock * (eps + c_.eps_d);
            return;
        }
        double sig = c_.E * (eps - ep);
        if (std::abs(sig) > c_.sigma_pl) {
            // σ = trial ∓ E Δ and |σ| = σ_pl + η Δ/dt: Δ = (|trial| − σ_pl) / (E + η/dt).
            const double d = (std::abs(sig) - c_.sigma_pl) / (c_.E + c_.eta / dt);
            const double sign = sig > 0 ? 1.0 : -1.0;
            sig -= sign * c_.E * d;
            ep += sign * d;
            s.peeq += d;
            s.peeq_rate = d / dt;
            s.plastic_work += std::abs(sig) * d;
        }
        s.stress[0] = sig;
    }

  private:
    Constants c_;
};

} // namespace undex::solid
