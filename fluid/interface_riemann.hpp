// Two-material Riemann problem along the interface normal (physics.md §4): given the states on the two
// sides of a gas–water (or gas–gas) interface, the interface pressure p*, velocity u* and the densities
// next to the interface on each side. Each side is a stiffened gas or barotropic Tait water; both share the
// form p + Π = const·ρ^γ on their isentropes (Π = P∞, or B − A for Tait).
//   exact:        each wave is a shock (p* > p_K) or a rarefaction (p* ≤ p_K);
//   double shock: both waves are taken as shocks (Liu, Khoo and Yeo 2003), the paper's approximation.
#pragma once
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace undex::fluid {

enum class InterfaceRiemann { DoubleShock, Exact };

// One side's material: stiffened gas (γ, P∞) or Tait (γ, B, A, ρ0; shocks conserve mass and momentum only).
struct RiemannMaterial {
    double gamma = 1.4;
    double pi = 0.0; // pressure offset Π: P∞ or B − A
    bool tait = false;
    double B = 0, rho0 = 0; // Tait only
};

struct RiemannSide {
    double rho, u, p; // u: velocity along the normal, from left to right
};

struct InterfaceState {
    double p, u, rho_l, rho_r;
};

namespace detail {

// Velocity jump f_K(p*) across the wave of side K, its derivative, and the density behind the wave.
struct WaveCurve {
    double f, df, rho;
};

inline WaveCurve wave_curve(const RiemannMaterial& m, const RiemannSide& w, double p, bool shock) {
    const double g = m.gamma, pbar_k = w.p + m.pi, pbar = p + m.pi;
    const double a = std::sqrt(g * pbar_k / w.rho);
    if (!shock) { // isentrope p + Π ∝ ρ^γ
        const double r = pbar / pbar_k;
        return {2.0 * a / (g - 1.0) * (std::pow(r, (g - 1.0) / (2.0 * g)) - 1.0),
                std::pow(r, -(g + 1.0) / (2.0 * g)) / (w.rho * a), w.rho * std::pow(r, 1.0 / g)};
    }
    if (!m.tait) { // Rankine–Hugoniot of the stiffened gas
        const double A = 2.0 / ((g + 1.0) * w.rho), Bk = (g - 1.0) / (g + 1.0) * pbar_k;
        const double q = std::sqrt(A / (pbar + Bk));
        const double mu = (g - 1.0) / (g + 1.0), r = pbar / pbar_k;
        return {(p - w.p) * q, q * (1.0 - 0.5 * (p - w.p) / (pbar + Bk)), w.rho * (r + mu) / (mu * r + 1.0)};
    }
    // Tait: density from the equation of state, velocity jump from mass and momentum conservation.
    const double rho = m.rho0 * std::pow(pbar / m.B, 1.0 / g);
    const double dp = p - w.p, drho = rho - w.rho;
    const double x = dp * drho / (rho * w.rho);
    if (!(x > 1e-300)) return {0.0, 1.0 / (w.rho * a), rho};
    const double f = std::copysign(std::sqrt(x), dp);
    const double drho_dp = rho / (g * pbar);
    const double dx = (drho + dp * drho_dp) / (rho * w.rho) - x * drho_dp / rho;
    return {f, 0.5 * dx / std::abs(f), rho};
}

} // namespace detail

// Solves for p* with a safeguarded Newton iteration on f_L(p) + f_R(p) + u_R − u_L = 0 (monotone in p).
// Throws std::runtime_error when the sides separate into vacuum (no p* with p + Π > 0 on both sides).
inline InterfaceState solve_interface(const RiemannMaterial& ml, const RiemannSide& wl,
                                      const RiemannMaterial& mr, const RiemannSide& wr,
                                      InterfaceRiemann method) {
    const bool exact = method == InterfaceRiemann::Exact;
    auto F = [&](double p, detail::WaveCurve& l, detail::WaveCurve& r) {
        l = detail::wave_curve(ml, wl, p, !exact || p > wl.p);
        r = detail::wave_curve(mr, wr, p, !exact || p > wr.p);
        return l.f + r.f + wr.u - wl.u;
    };
    // Bracket: p + Π > 0 on both sides.
    const double p_floor = -std::min(ml.pi, mr.pi);
    const double scale = std::max({wl.p + ml.pi, wr.p + mr.pi, 1e-300});
    double lo = p_floor + 1e-12 * scale, hi = std::max(wl.p, wr.p);
    detail::WaveCurve l{}, r{};
    if (F(lo, l, r) > 0)
        throw std::runtime_error(
            "interface Riemann problem: the two sides separate (vacuum at the interface)");
    for (int k = 0; F(hi, l, r) < 0; ++k) {
        hi = p_floor + 2.0 * (hi - p_floor) + scale;
        if (k > 200) throw std::runtime_error("interface Riemann problem: no interface pressure found");
    }
    // Acoustic first guess.
    const double zl = wl.rho * std::sqrt(ml.gamma * (wl.p + ml.pi) / wl.rho);
    const double zr = wr.rho * std::sqrt(mr.gamma * (wr.p + mr.pi) / wr.rho);
    double p = (zr * wl.p + zl * wr.p + zl * zr * (wl.u - wr.u)) / (zl + zr);
    if (!(p > lo && p < hi)) p = 0.5 * (lo + hi);
    for (int it = 0; it < 100; ++it) {
        const double f = F(p, l, r);
        if (f > 0)
            hi = p;
        else
            lo = p;
        double next = p - f / (l.df + r.df);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const double change = std::abs(next - p);
        p = next;
        if (change <= 1e-12 * (p - p_floor)) break; // relative to p + Π of the softer side
    }
    F(p, l, r);
    return {p, 0.5 * (wl.u + wr.u) + 0.5 * (r.f - l.f), l.rho, r.rho};
}

} // namespace undex::fluid
