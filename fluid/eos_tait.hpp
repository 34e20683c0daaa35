// Barotropic Tait water (physics.md §2, paper eq. 4): p = B[(ρ/ρ0)^γ − 1] + A, a² = γ(p + B − A)/ρ.
// Pressure depends on density only; the energy equation is carried for a uniform data layout and does not
// feed back. With cavitation on, densities below the saturated-mixture density follow the mixture branch
// of cavitation.hpp; between that density and the liquid density at p_cav (a relative width of about α0)
// the pressure stays at p_cav and the mixture sound speed at p_cav is used, so p(ρ) is continuous.
// p(ρ) is evaluated without pow once finalize() has built its table (TaitTable): to within a few units in the
// last place of p + B − A, and exactly A at ρ0.
#pragma once
#include "fluid/cavitation.hpp"
#include "fluid/eos.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace undex::fluid {

// (ρ/ρ0)^γ − 1 for ρ in [ρ0/2, 2ρ0) from nodes ρ_k = ρ0 (1/2 + k/512): with d = (ρ − ρ_k)/ρ_k (the
// difference is exact, |d| ≤ 2e-3), (ρ/ρ0)^γ − 1 = T1_k + T0_k q(d), where T0_k = (ρ_k/ρ0)^γ and
// T1_k = T0_k − 1 are rounded from long double and q(d) = (1 + d)^γ − 1 is its binomial series to d⁵ (the
// next term is below 1e-17 relative). Summing T1_k and T0_k q instead of forming (ρ/ρ0)^γ and then
// subtracting 1 keeps the relative accuracy of p − A near ρ0; at ρ0 itself d = 0 and T1 = 0, so p = A.
class TaitTable {
  public:
    TaitTable(double gamma, double rho0) : lo_(0.5 * rho0), scale_(512.0 / rho0) {
        for (int k = 0; k <= 768; ++k) {
            const double rho = rho0 * (0.5 + k / 512.0);
            const long double r = static_cast<long double>(rho) / rho0;
            const long double t1 = std::expm1(static_cast<long double>(gamma) * std::log(r));
            nodes_.push_back({rho, 1.0 / rho, static_cast<double>(t1 + 1.0L), static_cast<double>(t1)});
        }
        hi_ = nodes_.back().rho;
        long double c = 1.0L;
        for (int j = 1; j <= 5; ++j) {
            c *= (static_cast<long double>(gamma) - (j - 1)) / j;
            c_[j - 1] = static_cast<double>(c);
        }
    }
    bool covers(double rho) const { return rho >= lo_ && rho < hi_; } // false for NaN
    double lowest() const { return lo_; }  // the range it covers, [lowest, highest)
    double highest() const { return hi_; }
    // (ρ/ρ0)^γ − 1 for a ρ it covers.
    double power_minus_one(double rho) const {
        const Node& n = nodes_[static_cast<size_t>((rho - lo_) * scale_ + 0.5)];
        const double d = (rho - n.rho) * n.inv;
        const double q = d * (c_[0] + d * (c_[1] + d * (c_[2] + d * (c_[3] + d * c_[4]))));
        return n.t1 + n.t0 * q;
    }

  private:
    struct Node {
        double rho, inv, t0, t1;
    };
    std::vector<Node> nodes_;
    double lo_, hi_ = 0, scale_;
    double c_[5];
};

struct TaitLiquid;

struct Tait {
    static constexpr bool barotropic = true;
    using Lanes = TaitLiquid; // LaneForm (eos.hpp)
    double gamma = 7.15, B = 3.31e8, A = 1e5, rho0 = 1000.0;
    bool cavitation = false;
    CavitationModel cav;
    std::shared_ptr<const TaitTable> table; // finalize(); without it p(ρ) uses pow

    // Builds the table of p(ρ) for the parameters as set (call again after changing γ or ρ0).
    void finalize() { table = std::make_shared<const TaitTable>(gamma, rho0); }

    // The Tait relation p(ρ) of the liquid, and its inverse ρ(p).
    double liquid_pressure(double rho) const {
        if (table && table->covers(rho)) return B * table->power_minus_one(rho) + A;
        return B * (std::pow(rho / rho0, gamma) - 1.0) + A;
    }
    double density(double p) const { return rho0 * std::pow((p - A) / B + 1.0, 1.0 / gamma); }

    double pressure(double rho, double /*rho_e*/) const {
        if (cavitation && rho < cav.rho_l_cav) return rho < cav.rho_sat ? cav.pressure(rho) : cav.p_cav;
        return liquid_pressure(rho);
    }
    double sound_speed(double rho, double p) const {
        if (cavitation && p <= cav.p_cav) {
            if (p == cav.p_cav) return cav.a_sat;
            // The mixture is barotropic: at its own density the vapour's share comes from the table; a state
            // with the liquid's density (a boundary's, on the liquid's isentrope) from p alone.
            return rho < cav.rho_sat ? cav.mixture_sound_speed(rho, p) : cav.mixture_sound_speed(p);
        }
        return liquid_sound_speed(rho, p);
    }
    double liquid_sound_speed(double rho, double p) const { return std::sqrt(gamma * (p + B - A) / rho); }
    // Energy of the equivalent stiffened gas (P∞ = B − A), so that E is well defined for output and for
    // the characteristic decomposition; it never feeds back into p.
    double internal_energy(double /*rho*/, double p) const { return (p + gamma * (B - A)) / (gamma - 1.0); }
    // Any positive density is admissible: p + B − A > 0 for ρ > 0, and p > 0 with cavitation.
    double pressure_margin(double /*p*/) const { return 1.0; }
    double pressure_floor() const { return cavitation ? cav.p_cav : A - B; }
    double gruneisen() const { return gamma - 1.0; }
    double isentropic_exponent() const { return gamma; }
    // Barotropic: every state lies on the one isentrope ρ(p).
    double isentrope_density(double /*rho*/, double /*p*/, double p_new) const { return density(p_new); }
    // A wall held at the cavitation pressure keeps the mixture's density.
    double wall_density(double rho, double /*p*/, double p_wall) const {
        return cavitation && p_wall <= cav.p_cav ? std::min(rho, cav.rho_l_cav) : density(p_wall);
    }
    // The entropy function of the original ghost fluid method, s = ρ / (p + B − A)^(1/γ) (constant for Tait
    // water, which is isentropic).
    double entropy(double rho, double p) const {
        return rho / std::pow(std::max(p + (B - A), 1e-300), 1.0 / gamma);
    }
    // ρ(p̄) with p̄ = p + B − A; the entropy s plays no part.
    double entropy_density(double /*s*/, double pbar) const { return rho0 * std::pow(pbar / B, 1.0 / gamma); }
    RiemannMaterial riemann_material() const {
        RiemannMaterial m;
        m.gamma = gamma;
        m.pi = B - A;
        m.tait = true;
        m.B = B;
        m.rho0 = rho0;
        return m;
    }
    bool has_cavitation() const { return cavitation; }
    double void_fraction(double p) const { return cavitation ? cav.void_fraction(p) : 0.0; }
};

static_assert(EquationOfState<Tait>);

// Tait water of the SIMD lanes (LaneForm, eos.hpp): for a density the table covers and above the cavitation
// branch, p(ρ) is the table's B [(ρ/ρ0)^γ − 1] + A and a² = γ (p + B − A)/ρ, the very operations of Tait's
// own, without their tests. Above the branch means ρ ≥ ρl_cav (1 + 1e-9): there p exceeds p_cav by about
// 1e-9 ρ a² (2 Pa), far above the table's rounding, so Tait's sound speed takes its liquid branch too.
struct TaitLiquid : Tait {
    TaitLiquid() = default;
    explicit TaitLiquid(const Tait& t) : Tait(t) {
        if (!table) return; // nothing holds: every block goes one cell at a time
        lo_ = std::max(table->lowest(), cavitation ? cav.rho_l_cav * (1.0 + 1e-9) : 0.0);
        hi_ = table->highest();
    }
    bool holds(double rho) const { return (rho >= lo_) & (rho < hi_); } // false for NaN
    double pressure(double rho, double /*rho_e*/) const { return B * table->power_minus_one(rho) + A; }
    double sound_speed(double rho, double p) const { return liquid_sound_speed(rho, p); }

  private:
    double lo_ = 1.0, hi_ = 0.0;
};

static_assert(EquationOfState<TaitLiquid>);

} // namespace undex::fluid
