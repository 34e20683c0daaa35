// Isentropic one-fluid cavitation model (physics.md §2, paper eqs. 5–9, after Liu, Khoo and Xie 2004).
// Below the cavitation pressure a cell holds a homogeneous, barotropic vapour–liquid mixture whose density
// ρ(p) is monotone in p; the pressure is found by inverting it, from a table built once (finalize) with no
// pow per call, so that a cavitating cell costs about what a liquid one does.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace undex::fluid {

struct CavitationModel {
    double p_cav = 2338.0;     // cavitation (vapour) pressure
    double rho_g_cav = 0.0173; // vapour density at p_cav
    double gamma_g = 1.4;      // vapour isentropic exponent
    double alpha0 = 1e-5;      // void fraction reference
    // Liquid (Tait) constants, copied from the water it belongs to.
    double gamma_w = 7.15, B = 3.31e8, A = 1e5, rho0 = 1000.0;

    // Derived: p̄_cav = p_cav + B − A, liquid density at p_cav, k = α0/(1−α0), mixture density at p_cav.
    double pbar_cav = 0, rho_l_cav = 0, k = 0, rho_sum = 0, rho_sat = 0, a_sat = 0;

    void finalize() {
        pbar_cav = p_cav + B - A;
        rho_l_cav = rho0 * std::pow(pbar_cav / B, 1.0 / gamma_w);
        k = alpha0 / (1.0 - alpha0);
        rho_sum = k * rho_g_cav + rho_l_cav;
        rho_sat = mixture_density(p_cav);
        a_sat = mixture_sound_speed(p_cav);
        build_table();
    }

    // (p̄/p̄_cav)^e for a mixture pressure 0 < p ≤ p_cav: p̄/p̄_cav = 1 + x with |x| ≤ p_cav/p̄_cav (≈ 7e-6 for
    // water), so (1 + x)^e = exp(e ln(1 + x)) by three terms of each series, exact to rounding (the next
    // terms are below 1e-20), without a pow in the hot loops of cavitating cells.
    double liquid_ratio(double p, double e) const {
        const double x = (p - p_cav) / pbar_cav;
        if (!(std::abs(x) < 1e-4)) return std::pow(1.0 + x, e); // far from p_cav (not a mixture): exact
        const double y = e * x * (1.0 - x * (0.5 - x / 3.0));
        return 1.0 + y * (1.0 + y * (0.5 + y / 6.0));
    }

    // ρ(p) = (k ρg_cav + ρl_cav) / [ (p̄/p̄_cav)^(−1/γw) + k (p/p_cav)^(−1/γg) ]
    double mixture_density(double p) const {
        return rho_sum /
               (liquid_ratio(p, -1.0 / gamma_w) + k * std::pow(p / p_cav, -1.0 / gamma_g));
    }

    // Pressure of a mixture of density rho < rho_sat: from the table (below) where it holds, by Newton
    // (pressure_newton) in the deep vacuum below it.
    double pressure(double rho) const {
        Lookup at;
        if (!locate(rho, at)) return pressure_newton(rho);
        return interpolate(at, 0);
    }

    // Wood's mixture sound speed at a mixture density rho < rho_sat and its pressure p (of pressure(rho)):
    // the vapour's (p/p_cav)^(1/γg) read from the table, not computed with a pow.
    double mixture_sound_speed(double rho, double p) const {
        Lookup at;
        if (!locate(rho, at)) return mixture_sound_speed(p);
        return wood(p, interpolate(at, 2));
    }

    // Wood's mixture sound speed at a mixture pressure p < p_cav alone (the density need not be the
    // mixture's: a boundary's state on the liquid's isentrope).
    double mixture_sound_speed(double p) const { return wood(p, std::pow(p / p_cav, 1.0 / gamma_g)); }

    // Pressure of a mixture of density rho < rho_sat by Newton. With q = (p/p_cav)^(−1/γg) ≥ 1, the
    // density relation above reads
    //     g(q) = (p̄/p̄_cav)^(−1/γw) + k q − (k ρg_cav + ρl_cav)/ρ = 0,   p = p_cav q^(−γg),
    // where the liquid term differs from 1 by at most (p_cav/p̄_cav)/γw ≈ 1e-6. Taking it as 1 gives q in
    // closed form, q0 = ((k ρg_cav + ρl_cav)/ρ − 1)/k, at or above the root (within 15 % of it next to p_cav,
    // closer as p falls, where k q outgrows the liquid term's change). g increases with q (dg/dq = k +
    // (γg/γw) L p/(p̄ q) with L the liquid term) and is concave, so Newton from q0 lands at or left of the root
    // and then climbs to it monotonically: three or four steps, one pow each, near p_cav, one or two below.
    // Pressures below e^−60 Pa (ρ about 1e-13 kg/m³) are returned as e^−60.
    double pressure_newton(double rho) const {
        constexpr double p_min = 8.75651076269652e-27; // e^−60
        const double rhs = rho_sum / rho;
        double q = (rhs - 1.0) / k;
        double p = p_cav * std::pow(q, -gamma_g);
        for (int it = 0; it < 20 && p > p_min; ++it) {
            const double liquid = liquid_ratio(p, -1.0 / gamma_w); // L = (p̄/p̄_cav)^(−1/γw)
            const double g = liquid + k * q - rhs;
            const double dg_dq = k + (gamma_g / gamma_w) * liquid * p / ((p + B - A) * q);
            const double dq = g / dg_dq;
            q -= dq;
            p = p_cav * std::pow(q, -gamma_g);
            if (std::abs(dq) <= 1e-14 * q) break;
        }
        return std::max(p, p_min);
    }

    // The mixture's p and u = (p/p_cav)^(1/γg) = 1/q as functions of t = 1/q0 = k ρ / (M − ρ), M = k ρg_cav +
    // ρl_cav (q0 the closed-form start above; t = 1 at ρ_sat, t → 0 as ρ → 0). In t the density relation reads
    // 1/u = 1/t − δ(p), δ = (L − 1)/k, so both are smooth in t, p about ∝ t^γg: a cubic Hermite table on
    // octaves of t, [2^−(j+1), 2^−j] for j < octaves, each of n equal intervals, holds p, h dp/dt, u and
    // h du/dt at its nodes (h the octave's interval). finalize() solves each node (solve_node), doubles n
    // (from 128, up to 1024) until p and u at every interval's midpoint (where a cubic Hermite errs most) agree
    // with their own solve to 1e-11 relative, and stops the octaves where p falls below 1e-20 p_cav or at 40;
    // below them, and if no n reaches 1e-11, pressure_newton and the pow.
    int table_n = 0, table_octaves = 0;
    double table_error = 0; // largest relative error of p or u at the midpoints (measured by finalize)
    std::shared_ptr<const std::vector<double>> table;

    struct Lookup {
        const double* node; // the interval's first node
        double s;           // position in the interval, [0, 1]
    };
    bool locate(double rho, Lookup& at) const {
        if (table_octaves == 0) return false;
        const double t = k * rho / (rho_sum - rho);
        if (!(t > 0.0)) return false; // ρ ≤ 0 or NaN: Newton's NaN (or floor), never a read outside the table
        if (!(t < 1.0)) { // ρ at ρ_sat to rounding: the last node
            at.node = table->data() + (table_n - 1) * 4;
            at.s = 1.0;
            return true;
        }
        // t = m 2^e with m in [0.5, 1): octave j = −e, position (2m − 1) n in it (both exact).
        const auto bits = std::bit_cast<std::uint64_t>(t);
        const int j = 1022 - static_cast<int>((bits >> 52) & 0x7ff);
        if (j >= table_octaves) return false;
        const double m = std::bit_cast<double>((bits & 0x800fffffffffffffULL) | 0x3fe0000000000000ULL);
        const double x = (2.0 * m - 1.0) * table_n;
        const int i = std::min(static_cast<int>(x), table_n - 1);
        at.node = table->data() + (static_cast<long>(j) * (table_n + 1) + i) * 4;
        at.s = x - i;
        return true;
    }
    // Column 0 (p) or 2 (u) of the table at a located point.
    static double interpolate(const Lookup& at, int column) {
        const double s = at.s, r = 1.0 - s;
        const double* a = at.node + column;
        const double* b = a + 4;
        return (1.0 + 2.0 * s) * r * r * a[0] + s * r * r * a[1] + s * s * (3.0 - 2.0 * s) * b[0] -
               s * s * r * b[1];
    }

    // Wood's mixture sound speed a⁻² = ρm [α/(ρg ag²) + (1−α)/(ρl al²)] at pressure p < p_cav, with the
    // vapour's u = (p/p_cav)^(1/γg). With r = α/(1 − α) = k (ρl/ρl_cav)/u, ρg ag² = γg p and ρl al² = γw p̄,
    // it reads a² = (1 + r)² γg p γw p̄ / [(r ρg + ρl)(r γw p̄ + γg p)]: no 1 − α by subtraction (which
    // loses all its digits as α → 1, p → 0, where (1 − α) ρl is still comparable with α ρg), two divisions.
    double wood(double p, double vapour) const {
        const double pbar = p + B - A;
        const double liquid = liquid_ratio(p, 1.0 / gamma_w); // (p̄/p̄_cav)^(1/γw)
        const double r = k * liquid / vapour;
        const double rho_g = rho_g_cav * vapour, rho_l = rho_l_cav * liquid;
        const double vapour_stiffness = gamma_g * p, liquid_stiffness = gamma_w * pbar;
        const double one_r = 1.0 + r;
        return std::sqrt(one_r * one_r * vapour_stiffness * liquid_stiffness /
                         ((r * rho_g + rho_l) * (r * liquid_stiffness + vapour_stiffness)));
    }

    // The table's node at t: u from F(u) = 1/u − 1/t + δ(p_cav u^γg) = 0 by Newton kept inside the bracket
    // [t, t/(1 − t δ(0))] (F decreases in u, as δ does in p, and δ ≤ δ(0)), to rounding; the slopes by
    // implicit differentiation. δ = (L − 1)/k from expm1 and log1p, so that L − 1 (at most 1e-6) keeps its
    // digits.
    struct Node {
        double p, dp_dt, u, du_dt;
    };
    Node solve_node(double t) const {
        const double e = -1.0 / gamma_w;
        auto at = [&](double u, double& F, double& dF_du, double& p) {
            p = p_cav * std::pow(u, gamma_g);
            const double x = (p - p_cav) / pbar_cav, l = e * std::log1p(x);
            const double ddelta_dp = e * std::exp(l) / (pbar_cav * (1 + x)) / k;
            F = 1 / u - 1 / t + std::expm1(l) / k;
            dF_du = -1 / (u * u) + ddelta_dp * gamma_g * p / u;
        };
        const double delta0 = std::expm1(e * std::log1p(-p_cav / pbar_cav)) / k;
        double lo = t, hi = std::min(1.0, t / std::max(1 - t * delta0, 1e-300)), u = 0.5 * (lo + hi), F, dF, p;
        for (int it = 0; it < 100; ++it) {
            at(u, F, dF, p);
            (F > 0 ? lo : hi) = u;
            double next = u - F / dF;
            if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);
            const bool converged = F == 0 || std::abs(next - u) <= 1e-16 * u || hi - lo <= 1e-16 * u;
            u = next;
            if (converged) break;
        }
        at(u, F, dF, p);
        const double du_dt = (1 / (t * t)) / -dF;
        return {p, gamma_g * p / u * du_dt, u, du_dt};
    }

    void build_table() {
        table.reset();
        table_n = table_octaves = 0;
        table_error = 0;
        int octaves = 0;
        while (octaves < 40 && solve_node(std::ldexp(1.0, -octaves - 1)).p >= 1e-20 * p_cav) ++octaves;
        for (int n = 128; n <= 1024 && octaves > 0; n *= 2) {
            auto nodes = std::make_shared<std::vector<double>>(static_cast<std::size_t>(octaves) * (n + 1) * 4);
            for (int j = 0; j < octaves; ++j) {
                const double a = std::ldexp(1.0, -j - 1), h = a / n;
                for (int i = 0; i <= n; ++i) {
                    const Node v = solve_node(a + i * h);
                    double* d = nodes->data() + (static_cast<long>(j) * (n + 1) + i) * 4;
                    d[0] = v.p, d[1] = h * v.dp_dt, d[2] = v.u, d[3] = h * v.du_dt;
                }
            }
            double worst = 0;
            for (int j = 0; j < octaves; ++j) {
                const double a = std::ldexp(1.0, -j - 1), h = a / n;
                for (int i = 0; i < n; ++i) {
                    const Node v = solve_node(a + (i + 0.5) * h);
                    const Lookup at{nodes->data() + (static_cast<long>(j) * (n + 1) + i) * 4, 0.5};
                    worst = std::max({worst, std::abs(interpolate(at, 0) / v.p - 1),
                                      std::abs(interpolate(at, 2) / v.u - 1)});
                }
            }
            table_error = worst;
            if (worst <= 1e-11) {
                table = nodes, table_n = n, table_octaves = octaves;
                return;
            }
        }
        // No n reached 1e-11: Newton everywhere (table_error keeps the last n's error).
    }

    double void_fraction(double p) const {
        if (p >= p_cav) return 0.0;
        const double pbar = p + B - A;
        const double ratio =
            k * std::pow(pbar / pbar_cav, 1.0 / gamma_w) * std::pow(p / p_cav, -1.0 / gamma_g);
        return ratio / (1.0 + ratio);
    }
};

} // namespace undex::fluid
