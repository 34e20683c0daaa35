// Linear isotropic elasticity (physics.md §6).
#pragma once
#include "solid/material.hpp"

namespace undex::solid {

class Elastic final : public MaterialLaw {
  public:
    Elastic(double rho, double E, double nu) : rho_(rho), el_(E, nu) {
        require(rho > 0, "density rho must be positive");
        require(E > 0, "Young's modulus E must be positive");
        require(nu > -1 && nu < 0.5, "Poisson's ratio nu must lie in (-1, 0.5)");
    }
    std::string name() const override { return "elastic"; }
    double density() const override { return rho_; }
    double wave_modulus() const override { return el_.wave_modulus(); }
    double shear_modulus() const override { return el_.G; }

  protected:
    void advance(const Voigt& de, double, PointState& s) const override {
        el_.add(de, s.stress);
        s.peeq_rate = 0;
    }

  private:
    double rho_;
    Isotropic el_;
};

} // namespace undex::solid
