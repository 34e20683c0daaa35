// Deshpande–Fleck isotropic foam (J. Mech. Phys. Solids 48, 2000; physics.md §6):
//   σ̂² = (σ_e² + α² σ_m²) / (1 + (α/3)²),  yield σ̂ = σ_c(ε̂_p) + η ε̂̇_p  (over-stress viscosity η),
// associated flow, σ_c(ε̂_p) tabulated (linear between points, constant beyond the last). α = 3/√2 gives a
// plastic Poisson ratio of 0: ν_p = (1/2 − (α/3)²) / (1 + (α/3)²).
// Return mapping: with β = 1 + (α/3)² the flow rule gives σ_e = σ_e^tr / (1 + 3GΔ/(σ̂β)) and
// σ_m = σ_m^tr / (1 + Kα²Δ/(σ̂β)) for an increment Δ of ε̂_p; Δ is the root of
// σ̂(σ_e, σ_m) = σ_c(ε̂_p + Δ) + η Δ/dt, unique because the left side falls and the right side rises with Δ.
#pragma once
#include "solid/material.hpp"

#include <algorithm>
#include <vector>

namespace undex::solid {

class DeshpandeFleck final : public MaterialLaw {
  public:
    struct Constants {
        double rho = 0, E = 0, nu = 0, alpha = 2.1213203435596424, eta = 0;
        std::vector<double> eps_p, sigma_c; // σ_c(ε̂_p) table, eps_p increasing from 0
    };
    explicit DeshpandeFleck(const Constants& c) : c_(c), el_(c.E, c.nu), beta_(1 + c.alpha * c.alpha / 9) {
        require(c.rho > 0, "density rho must be positive");
        require(c.E > 0, "Young's modulus E must be positive");
        require(c.nu > -1 && c.nu < 0.5, "elastic Poisson's ratio nu must lie in (-1, 0.5)");
        require(c.alpha > 0 && c.alpha < 4.2426406871192848, "alpha must lie in (0, 3 sqrt(2))");
        require(c.eta >= 0, "over-stress viscosity eta must be >= 0");
        require(!c.eps_p.empty() && c.eps_p.size() == c.sigma_c.size(),
                "the sigma_c table needs eps_p and sigma_c of the same, non-zero length");
        require(c.eps_p.front() == 0, "the sigma_c table must start at eps_p = 0");
        for (size_t k = 0; k < c.eps_p.size(); ++k) {
            require(c.sigma_c[k] > 0, "sigma_c must be positive");
            if (k > 0) require(c.eps_p[k] > c.eps_p[k - 1], "eps_p must increase");
            // A softening foam has no unique return: the crushing stress may stay level, not fall.
            if (k > 0)
                require(c.sigma_c[k] >= c.sigma_c[k - 1], "sigma_c must not decrease (sigma_c[" +
                                                              std::to_string(k) + "] < sigma_c[" +
                                                              std::to_string(k - 1) + "])");
        }
    }
    std::string name() const override { return "deshpande_fleck"; }
    double density() const override { return c_.rho; }
    double wave_modulus() const override { return el_.wave_modulus(); }
    double shear_modulus() const override { return el_.G; }

    double sigma_c(double ep) const {
        const auto& x = c_.eps_p;
        const auto& y = c_.sigma_c;
        if (ep >= x.back()) return y.back();
        const auto k = std::upper_bound(x.begin(), x.end(), ep) - x.begin();
        if (k == 0) return y.front();
        return y[k - 1] + (y[k] - y[k - 1]) * (ep - x[k - 1]) / (x[k] - x[k - 1]);
    }
    // Equivalent stress σ̂ of a stress state.
    double equivalent(double sigma_e, double sigma_m) const {
        return std::sqrt((sigma_e * sigma_e + c_.alpha * c_.alpha * sigma_m * sigma_m) / beta_);
    }

  protected:
    void advance(const Voigt& de, double dt, PointState& s) const override {
        el_.add(de, s.stress);
        const double se = von_mises(s.stress), sm = mean_stress(s.stress);
        if (equivalent(se, sm) <= sigma_c(s.peeq)) {
            s.peeq_rate = 0;
            return;
        }
        const double a2 = c_.alpha * c_.alpha;
        // Returned state for a trial increment d: the target σ̂ and the σ̂ of the returned stresses.
        auto returned = [&](double d, double& target, double& e, double& m) {
            target = sigma_c(s.peeq + d) + c_.eta * d / dt;
            e = se / (1 + 3 * el_.G * d / (target * beta_));
            m = sm / (1 + el_.K * a2 * d / (target * beta_));
            return equivalent(e, m) - target;
        };
        // Bracket from the elastic-perfectly-plastic linearisation at Δ = 0, which overshoots the root when
        // the foam hardens or is viscous; doubled until it brackets.
        const double q = equivalent(se, sm), sc = sigma_c(s.peeq);
        double target, e, m;
        double hi = (q - sc) * q * q * beta_ * beta_ / (3 * el_.G * se * se + el_.K * a2 * a2 * sm * sm);
        while (returned(hi, target, e, m) > 0)
            hi *= 2;
        const double d = falling_root([&](double x) { return returned(x, target, e, m); }, 0, hi, hi);
        returned(d, target, e, m);
        // Flow direction ∂σ̂/∂σ = (3 s + (2/3) α² σ_m I) / (2 σ̂ β) at the returned state.
        const double ratio_e = se > 0 ? e / se : 0.0;
        const double dev = 1.5 * d / (target * beta_), vol = a2 * m * d / (3 * target * beta_);
        for (int i = 0; i < 3; ++i) {
            const double si = ratio_e * (s.stress[i] - sm);
            s.plastic_strain[i] += dev * si + vol;
            s.stress[i] = m + si;
        }
        for (int i = 3; i < 6; ++i) {
            s.stress[i] *= ratio_e;
            s.plastic_strain[i] += 2 * dev * s.stress[i];
        }
        s.peeq += d;
        s.peeq_rate = d / dt;
        s.plastic_work += target * d; // σ : Δε_p = σ̂ Δε̂_p for an associated, homogeneous-degree-one σ̂
    }

  private:
    Constants c_;
    Isotropic el_;
    double beta_;
};

} // namespace undex::solid
