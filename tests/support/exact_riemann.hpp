// exact_riemann.hpp -- independent exact Riemann solver, used only as a reference in verification tests.
//
// Solves the 1-D Riemann problem for
//   * the Euler equations with the stiffened-gas EOS  p = (gamma - 1) rho e - gamma P_inf  (ideal gas:
//     P_inf = 0),
//   * the barotropic system (mass + momentum only) with the Tait EOS  p = B [(rho/rho0)^gamma - 1] + A,
// and any pairing of the two across the material interface (contact), which moves with u* and carries
// continuous p and u.  The construction follows E. F. Toro, "Riemann Solvers and Numerical Methods for Fluid
// Dynamics", 3rd ed., Springer 2009, ch. 4 (equation numbers below refer to it), generalised as follows:
//
//   * Stiffened gas: every formula of ch. 4 holds with p replaced by p + P_inf (the EOS is the ideal-gas EOS
//     in the variables rho and p + P_inf, and the Euler fluxes only see pressure differences).
//   * Tait: both the Tait isentrope and the Tait EOS itself read  p + B - A = B (rho/rho0)^gamma, i.e. the
//     stiffened-gas isentrope with P_inf -> B - A, so rarefaction curves and fans have the same closed form.
//     Shocks obey mass and momentum conservation only (no energy equation):
//       u* - u_K = -/+ sqrt((p* - p_K)(rho* - rho_K) / (rho* rho_K)),
//       S_K = (rho* u* - rho_K u_K) / (rho* - rho_K),   rho* = rho0 ((p* - A)/B + 1)^(1/gamma).
//
// Notation: Pi is the pressure offset of a material (P_inf, or B - A for Tait) and pbar = p + Pi > 0 is the
// "effective pressure"; pbar -> 0 is vacuum (gas) or cavitation (Tait, p -> A - B).
//
// Usage:
//   const exact::Material air = exact::stiffened_gas(1.4);
//   const exact::Solution sol(air, {1.0, 0.0, 1.0}, air, {0.125, 0.0, 0.1}); // Sod
//   const exact::State w = sol.sample((x - x0) / t);
//
// Header-only, standard library only, C++17.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace exact {

// ------------------------------------------------------------------------------------------------ materials

struct Material {
    enum Kind { StiffenedGas, Tait } kind;
    double gamma;
    double p_inf; // stiffened gas only [Pa]
    double B;     // Tait only [Pa]
    double A;     // Tait only [Pa]
    double rho0;  // Tait only [kg/m^3]
};

// Stiffened gas p = (gamma - 1) rho e - gamma P_inf; ideal gas for p_inf = 0.
inline Material stiffened_gas(double gamma, double p_inf = 0.0) {
    return Material{Material::StiffenedGas, gamma, p_inf, 0.0, 0.0, 0.0};
}

// Barotropic Tait water p = B [(rho/rho0)^gamma - 1] + A.
inline Material tait(double gamma = 7.15, double B = 3.31e8, double A = 1.0e5, double rho0 = 1000.0) {
    return Material{Material::Tait, gamma, 0.0, B, A, rho0};
}

// Primitive state.
struct State {
    double rho, u, p;
};

// Pressure offset Pi of either model: isentropes (p + Pi) / rho^gamma = const, a^2 = gamma (p + Pi) / rho.
inline double pressure_offset(const Material& m) {
    return m.kind == Material::Tait ? m.B - m.A : m.p_inf;
}

inline double sound_speed(const Material& m, double rho, double p) {
    return std::sqrt(m.gamma * (p + pressure_offset(m)) / rho);
}

// Tait EOS and its inverse.
inline double tait_pressure(const Material& m, double rho) {
    return m.B * (std::pow(rho / m.rho0, m.gamma) - 1.0) + m.A;
}
inline double tait_density(const Material& m, double p) {
    return m.rho0 * std::pow((p - m.A) / m.B + 1.0, 1.0 / m.gamma);
}

// Total energy per unit volume of a stiffened gas, E = (p + gamma P_inf) / (gamma - 1) + rho u^2 / 2.
inline double total_energy(const Material& m, const State& w) {
    if (m.kind != Material::StiffenedGas)
        throw std::invalid_argument(
            "exact::total_energy: the Tait model is barotropic and has no energy equation");
    return (w.p + m.gamma * m.p_inf) / (m.gamma - 1.0) + 0.5 * w.rho * w.u * w.u;
}

// A nonlinear wave. For a shock head == tail == shock speed. For a rarefaction, head is the characteristic
// speed on the undisturbed side (u_K -/+ a_K) and tail the one on the star side (u* -/+ a*_K).
struct Wave {
    enum Kind { Shock, Rarefaction } kind;
    double head;
    double tail;
    bool is_shock() const { return kind == Shock; }
};

namespace detail {

// One side of the Riemann problem with derived quantities.
struct Side {
    Material mat;
    State w;
    double pi;   // pressure offset Pi
    double pbar; // p + Pi
    double a;    // sound speed
};

inline std::string describe(const State& w) {
    std::ostringstream os;
    os.precision(17);
    os << "(rho=" << w.rho << ", u=" << w.u << ", p=" << w.p << ")";
    return os.str();
}

inline Side make_side(const Material& m, const State& w, const char* name) {
    const std::string where = std::string("exact::Solution: ") + name + " ";
    if (!(std::isfinite(m.gamma) && m.gamma > 1.0))
        throw std::invalid_argument(where + "material needs a finite gamma > 1");
    if (m.kind == Material::StiffenedGas && !std::isfinite(m.p_inf))
        throw std::invalid_argument(where + "material has a non-finite P_inf");
    if (m.kind == Material::Tait &&
        !(std::isfinite(m.B) && m.B > 0.0 && std::isfinite(m.A) && std::isfinite(m.rho0) && m.rho0 > 0.0))
        throw std::invalid_argument(where + "Tait material needs finite B > 0, A and rho0 > 0");
    if (!(std::isfinite(w.rho) && w.rho > 0.0 && std::isfinite(w.u) && std::isfinite(w.p)))
        throw std::invalid_argument(where + "state " + describe(w) + " needs finite values and rho > 0");
    Side k{m, w, pressure_offset(m), w.p + pressure_offset(m), 0.0};
    if (!(k.pbar > 0.0))
        throw std::invalid_argument(where + "state " + describe(w) +
                                    " is at or beyond vacuum/cavitation: p + Pi must be > 0");
    if (m.kind == Material::Tait) {
        // Barotropic: p is a function of rho. Reject states that are not on the EOS (beyond round-off).
        const double p_eos = tait_pressure(m, w.rho);
        if (!(std::abs(w.p - p_eos) <= 1e-8 * k.pbar))
            throw std::invalid_argument(where + "Tait state " + describe(w) +
                                        " is inconsistent with the EOS p(rho) = " + std::to_string(p_eos) +
                                        " (use exact::tait_pressure / exact::tait_density)");
    }
    k.a = std::sqrt(m.gamma * k.pbar / w.rho);
    return k;
}

// rho(p) / rho_K - 1 along the isentrope through K, (pbar / pbar_K)^(1/gamma) - 1, without cancellation.
inline double isentrope_density_ratio_m1(const Side& k, double p) {
    return std::expm1(std::log1p((p - k.w.p) / k.pbar) / k.mat.gamma);
}

// Value and derivative of Toro's pressure function f_K(p): u* = u_L - f_L(p*) = u_R + f_R(p*) (Toro 4.5-4.9).
struct FunctionValue {
    double f, df;
};

inline FunctionValue wave_function(const Side& k, double p) {
    const double g = k.mat.gamma;
    const double dp = p - k.w.p;
    const double pbar = p + k.pi;
    if (dp > 0.0) {
        if (k.mat.kind == Material::StiffenedGas) {
            // Shock, Toro (4.6)-(4.8) and derivative (sec. 4.3.1) with p -> p + P_inf.
            const double Ak = 2.0 / ((g + 1.0) * k.w.rho);
            const double Bk = (g - 1.0) / (g + 1.0) * k.pbar;
            const double q = std::sqrt(Ak / (pbar + Bk));
            return {dp * q, q * (1.0 - 0.5 * dp / (Bk + pbar))};
        }
        // Tait shock (mass + momentum only): f^2 = (p - p_K)(rho - rho_K)/(rho rho_K)
        // = (p - p_K)(1/rho_K - 1/rho), rho = rho0 ((p - A)/B + 1)^(1/gamma) evaluated relative to rho_K;
        // d rho/dp = rho/(gamma pbar).
        const double r = isentrope_density_ratio_m1(k, p); // (rho - rho_K) / rho_K
        const double rho = k.w.rho * (1.0 + r);
        const double dv = r / rho; // 1/rho_K - 1/rho
        const double f = std::sqrt(dp * dv);
        if (!(f > 0.0)) return {0.0, 1.0 / (k.w.rho * k.a)}; // acoustic limit
        const double dg = dv + dp / (g * pbar * rho);
        return {f, 0.5 * dg / f};
    }
    // Rarefaction (both models): integral of dp/(rho a) along the isentrope, Toro (4.6)-(4.7) with
    // p -> p + Pi; for Tait this is the Riemann invariant u +/- 2a/(gamma - 1) with a ~ rho^((gamma - 1)/2).
    const double e = (g - 1.0) / (2.0 * g);
    const double f = 2.0 * k.a / (g - 1.0) * std::expm1(e * std::log1p(dp / k.pbar));
    const double df = std::pow(pbar / k.pbar, -(g + 1.0) / (2.0 * g)) / (k.w.rho * k.a);
    return {f, df};
}

// Star-region density and wave on side K (sigma = -1 left, +1 right) for given p*, u*.
struct StarSide {
    double rho;
    Wave wave;
};

inline StarSide star_side(const Side& k, double sigma, double p_star, double u_star) {
    const double g = k.mat.gamma;
    const double ratio = (p_star + k.pi) / k.pbar;
    if (p_star > k.w.p) {
        if (k.mat.kind == Material::StiffenedGas) {
            // Toro sec. 4.4 (rho*_K, S_K) with p -> p + P_inf;
            // S_K = u_K -/+ Q_K/rho_K with the mass flux Q_K = sqrt((pbar* + B_K)/A_K).
            const double gr = (g - 1.0) / (g + 1.0);
            const double rho = k.w.rho * (ratio + gr) / (gr * ratio + 1.0);
            const double mass_flux = std::sqrt((p_star + k.pi + gr * k.pbar) * (g + 1.0) * k.w.rho / 2.0);
            const double s = k.w.u + sigma * mass_flux / k.w.rho;
            return {rho, Wave{Wave::Shock, s, s}};
        }
        // Tait shock: S = (rho* u* - rho_K u_K)/(rho* - rho_K), evaluated without cancellation as
        // u_K -/+ m/rho_K with the mass flux m^2 = (p* - p_K) rho* rho_K/(rho* - rho_K) (mass + momentum).
        const double r = isentrope_density_ratio_m1(k, p_star);
        const double rho = k.w.rho * (1.0 + r);
        const double mass_flux = r > 0.0 ? std::sqrt((p_star - k.w.p) * rho / r) : k.w.rho * k.a;
        const double s = k.w.u + sigma * mass_flux / k.w.rho;
        return {rho, Wave{Wave::Shock, s, s}};
    }
    // Rarefaction (both models): isentropic, Toro sec. 4.4 (rho*_K, head and tail speeds) with p -> p + Pi.
    const double rho = k.w.rho * std::pow(ratio, 1.0 / g);
    const double a_star = k.a * std::pow(ratio, (g - 1.0) / (2.0 * g));
    return {rho, Wave{Wave::Rarefaction, k.w.u + sigma * k.a, u_star + sigma * a_star}};
}

// Solution at similarity coordinate s on side K (sigma = -1 left of the contact, +1 right of it).
inline State sample_side(const Side& k, double sigma, const Wave& wave, double rho_star, double p_star,
                         double u_star, double s) {
    if (sigma * (s - wave.head) > 0.0) return k.w; // undisturbed
    if (wave.kind == Wave::Shock || sigma * (s - wave.tail) <= 0.0) return State{rho_star, u_star, p_star};
    // Inside the fan (Toro sec. 4.4 fan formulas with p -> p + Pi): on the characteristic u + sigma a = s
    // the Riemann invariant u - sigma 2a/(gamma - 1) = J of the undisturbed state holds; then
    // rho ~ a^(2/(gamma-1)) and pbar ~ rho^gamma on the isentrope (same closed form for SG and Tait).
    const double g = k.mat.gamma;
    const double J = k.w.u - sigma * 2.0 * k.a / (g - 1.0);
    const double a = sigma * (s - J) * (g - 1.0) / (g + 1.0);
    const double ar = a / k.a;
    const double rho = k.w.rho * std::pow(ar, 2.0 / (g - 1.0));
    const double p = k.pbar * std::pow(ar, 2.0 * g / (g - 1.0)) - k.pi;
    return State{rho, s - sigma * a, p};
}

} // namespace detail

// ------------------------------------------------------------------------------------------------ solution

// Exact solution of the Riemann problem with left state L (material `left`) for x < x0 and right state R
// (material `right`) for x > x0 at t = 0. Throws std::runtime_error if the data generate vacuum/cavitation
// and std::invalid_argument for invalid input.
class Solution {
  public:
    static constexpr double tolerance = 1e-12; // relative tolerance on p* + Pi

    Solution(const Material& left, const State& L, const Material& right, const State& R)
        : L_(detail::make_side(left, L, "left")), R_(detail::make_side(right, R, "right")) {
        p_star_ = solve_pressure();
        // Toro (4.9).
        const double fl = detail::wave_function(L_, p_star_).f;
        const double fr = detail::wave_function(R_, p_star_).f;
        u_star_ = 0.5 * (L_.w.u + R_.w.u) + 0.5 * (fr - fl);
        const detail::StarSide sl = detail::star_side(L_, -1.0, p_star_, u_star_);
        const detail::StarSide sr = detail::star_side(R_, +1.0, p_star_, u_star_);
        rho_star_left_ = sl.rho;
        rho_star_right_ = sr.rho;
        left_wave_ = sl.wave;
        right_wave_ = sr.wave;
    }

    double p_star() const { return p_star_; }
    double u_star() const { return u_star_; }
    double rho_star_left() const { return rho_star_left_; }
    double rho_star_right() const { return rho_star_right_; }
    double contact_speed() const { return u_star_; }
    const Wave& left_wave() const { return left_wave_; }
    const Wave& right_wave() const { return right_wave_; }
    const Material& left_material() const { return L_.mat; }
    const Material& right_material() const { return R_.mat; }
    const State& left_state() const { return L_.w; }
    const State& right_state() const { return R_.w; }
    int iterations() const { return iterations_; }

    // Material found at s = (x - x0)/t; the contact itself (s == u*) is attributed to the left material.
    const Material& material_at(double s) const { return s <= u_star_ ? L_.mat : R_.mat; }

    // Exact (rho, u, p) at s = (x - x0)/t. At s == u* the left star state is returned.
    State sample(double s) const {
        if (s <= u_star_)
            return detail::sample_side(L_, -1.0, left_wave_, rho_star_left_, p_star_, u_star_, s);
        return detail::sample_side(R_, +1.0, right_wave_, rho_star_right_, p_star_, u_star_, s);
    }

  private:
    // Root of f(p) = f_L(p) + f_R(p) + (u_R - u_L) (Toro 4.5), which is monotonically increasing in p.
    // Safeguarded Newton: each iterate narrows a bracket [lo, hi]; steps leaving it become bisections.
    double solve_pressure() {
        const double du = R_.w.u - L_.w.u;
        auto f = [&](double p) {
            const detail::FunctionValue l = detail::wave_function(L_, p);
            const detail::FunctionValue r = detail::wave_function(R_, p);
            return detail::FunctionValue{l.f + r.f + du, l.df + r.df};
        };
        // Lowest admissible pressure: vacuum (gas) or cavitation (Tait) on one of the two sides.
        const double p_floor = std::max(-L_.pi, -R_.pi) + 0.0; // + 0.0: no "-0" in messages
        const double f_floor = f(p_floor).f;
        if (!(f_floor < 0.0)) {
            std::ostringstream os;
            os.precision(10);
            os << "exact::Solution: the initial data generate vacuum/cavitation: p* would not exceed the "
               << "minimum admissible pressure p_min = " << p_floor << " (max of -P_inf / A - B of the two "
               << "materials; f(p_min) = " << f_floor << " >= 0). Only vacuum-free problems are supported.";
            throw std::runtime_error(os.str());
        }
        double lo = p_floor;
        double hi = std::max(L_.w.p, R_.w.p);
        detail::FunctionValue fh = f(hi);
        for (int n = 0; fh.f < 0.0; ++n) {
            lo = hi;
            hi = p_floor + 2.0 * (hi - p_floor);
            if (n > 2000 || !std::isfinite(hi))
                throw std::runtime_error("exact::Solution: could not bracket p*");
            fh = f(hi);
        }
        if (fh.f == 0.0) return hi;
        // Initial guess: linearised acoustic (impedance-weighted) estimate, if inside the bracket.
        const double zl = L_.w.rho * L_.a, zr = R_.w.rho * R_.a;
        double p = (zr * L_.w.p + zl * R_.w.p - zl * zr * du) / (zl + zr);
        if (!(p > lo && p < hi)) p = 0.5 * (lo + hi);
        for (iterations_ = 1; iterations_ <= 500; ++iterations_) {
            const detail::FunctionValue fv = f(p);
            if (fv.f == 0.0) return p;
            (fv.f < 0.0 ? lo : hi) = p;
            const double step = fv.f / fv.df;
            // Converged once the Newton correction is below the tolerance (the error is then ~ step^2).
            if (std::isfinite(step) && std::abs(step) <= tolerance * (p - p_floor))
                return std::clamp(p - step, lo, hi);
            p -= step;
            if (!(p > lo && p < hi)) p = 0.5 * (lo + hi); // Newton left the bracket (or failed): bisect
            if (hi - lo <= tolerance * (lo - p_floor)) return 0.5 * (lo + hi);
        }
        throw std::runtime_error("exact::Solution: pressure iteration did not converge");
    }

    detail::Side L_, R_;
    double p_star_ = 0.0, u_star_ = 0.0, rho_star_left_ = 0.0, rho_star_right_ = 0.0;
    Wave left_wave_{Wave::Rarefaction, 0.0, 0.0}, right_wave_{Wave::Rarefaction, 0.0, 0.0};
    int iterations_ = 0;
};

} // namespace exact
