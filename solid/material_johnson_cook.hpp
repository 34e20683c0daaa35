// J2 plasticity with Johnson–Cook hardening and rate term, radial return (physics.md §6):
//   σ_y = (A + B ε_p^n)(1 + C ln ε̇*),  ε̇* = max(ε̇_p / ε̇0, 1),
// isothermal (T* = 0, a [choice] of physics.md). Below the reference rate the rate term is 1, so that the
// flow stress never falls under the quasi-static curve.
#pragma once
#include "solid/material.hpp"

#include <algorithm>

namespace undex::solid {

class JohnsonCook final : public MaterialLaw {
  public:
    struct Constants {
        double rho = 0, E = 0, nu = 0, A = 0, B = 0, n = 1, C = 0, eps_dot0 = 1;
    };
    explicit JohnsonCook(const Constants& c) : c_(c), el_(c.E, c.nu) {
        require(c.rho > 0, "density rho must be positive");
        require(c.E > 0, "Young's modulus E must be positive");
        require(c.nu > -1 && c.nu < 0.5, "Poisson's ratio nu must lie in (-1, 0.5)");
        require(c.A > 0, "yield stress A must be positive");
        require(c.B >= 0, "hardening modulus B must be >= 0");
        require(c.n > 0, "hardening exponent n must be positive");
        require(c.C >= 0, "rate constant C must be >= 0");
        require(c.eps_dot0 > 0, "reference strain rate eps_dot0 must be positive");
    }
    std::string name() const override { return "johnson_cook"; }
    double density() const override { return c_.rho; }
    double wave_modulus() const override { return el_.wave_modulus(); }
    double shear_modulus() const override { return el_.G; }

    // Flow stress at plastic strain ep and plastic strain rate rate.
    double flow_stress(double ep, double rate) const {
        const double r = std::max(rate / c_.eps_dot0, 1.0);
        return (c_.A + c_.B * std::pow(std::max(ep, 0.0), c_.n)) * (1 + c_.C * std::log(r));
    }

  protected:
    void advance(const Voigt& de, double dt, PointState& s) const override {
        el_.add(de, s.stress);
        const double q = von_mises(s.stress);
        if (q <= flow_stress(s.peeq, 0.0)) {
            s.peeq_rate = 0;
            return;
        }
        // q − 3G Δ = σ_y(ε_p + Δ, Δ/dt): the left side falls and the right side rises with Δ, so the root in
        // [0, q/3G] is unique.
        auto f = [&](double d) { return q - 3 * el_.G * d - flow_stress(s.peeq + d, d / dt); };
        const double d =
            falling_root(f, 0, q / (3 * el_.G), 0.5 * (q - flow_stress(s.peeq, 0.0)) / (3 * el_.G));
        // Radial return of the deviator; Δε_p = (3/2) Δ s / q along the trial deviator s.
        const double m = mean_stress(s.stress), scale = 1 - 3 * el_.G * d / q;
        for (int i = 0; i < 3; ++i) {
            s.plastic_strain[i] += 1.5 * d * (s.stress[i] - m) / q;
            s.stress[i] = m + scale * (s.stress[i] - m);
        }
        for (int i = 3; i < 6; ++i) {
            s.plastic_strain[i] += 3 * d * s.stress[i] / q;
            s.stress[i] *= scale;
        }
        s.peeq += d;
        s.peeq_rate = d / dt;
        s.plastic_work += von_mises(s.stress) * d;
    }

  private:
    Constants c_;
    Isotropic el_;
};

} // namespace undex::solid
