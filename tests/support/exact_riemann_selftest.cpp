// Self-test of exact_riemann.hpp. Plain main(); returns non-zero on failure.
//
//   g++ -std=c++17 -O2 -Wall -Wextra -o /tmp/ers tests/support/exact_riemann_selftest.cpp && /tmp/ers
//
// References: E. F. Toro, "Riemann Solvers and Numerical Methods for Fluid Dynamics", 3rd ed., Table 4.3
// (exact star states of tests 1-4 of Table 4.1, gamma = 1.4). Everything else is checked through conservation
// laws, symmetries, exact invariances, and limits derived here independently of the header's formulas.
#include "tests/support/exact_riemann.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace {

int n_checks = 0;
int n_failures = 0;

void check(bool ok, const std::string& what, double value = NAN, double expected = NAN) {
    ++n_checks;
    if (ok) return;
    ++n_failures;
    std::printf("  FAIL: %s (value %.12g, expected %.12g)\n", what.c_str(), value, expected);
}

void check_abs(double value, double expected, double tol, const std::string& what) {
    check(std::abs(value - expected) <= tol, what + " [abs tol " + std::to_string(tol) + "]", value,
          expected);
}

void check_rel(double value, double expected, double tol, const std::string& what) {
    check(std::abs(value - expected) <= tol * std::abs(expected), what, value, expected);
}

// Relative residual of a conservation law: |lhs - rhs| / (sum of magnitudes of all terms).
void check_balance(double lhs, double rhs, double scale, double tol, const std::string& what) {
    const double res = std::abs(lhs - rhs) / scale;
    check(res <= tol, what + " relative residual", res, 0.0);
}

using exact::Material;
using exact::Solution;
using exact::State;
using exact::Wave;

// The constructor must throw E for these data.
template <class E>
void check_throws(const Material& ml, const State& L, const Material& mr, const State& R,
                  const std::string& what) {
    bool thrown = false;
    try {
        const Solution sol(ml, L, mr, R);
    } catch (const E& e) {
        thrown = true;
        std::printf("  (expected exception: %s)\n", e.what());
    } catch (...) {
    }
    check(thrown, what + " throws");
}

bool is_sg(const Material& m) {
    return m.kind == Material::StiffenedGas;
}

// Offset such that p + offset is the effective pressure of the EOS, written out here independently.
double offset(const Material& m) {
    return is_sg(m) ? m.p_inf : m.B - m.A;
}

// Rankine-Hugoniot conditions across a shock of speed S between sampled states a (ahead) and b (behind):
// rho (u - S), rho u (u - S) + p and, for stiffened gases, (E + p) u - S E must be equal on both sides.
void check_shock(const Material& m, const State& a, const State& b, double S, const std::string& label) {
    const double tol = 1e-9;
    const double ma = a.rho * (a.u - S), mb = b.rho * (b.u - S);
    check_balance(ma, mb, std::abs(ma) + std::abs(mb), tol, label + ": mass");
    const double ia = a.rho * a.u * (a.u - S), ib = b.rho * b.u * (b.u - S);
    check_balance(ia + a.p, ib + b.p, std::abs(ia) + std::abs(ib) + std::abs(a.p) + std::abs(b.p), tol,
                  label + ": momentum");
    if (is_sg(m)) {
        auto E = [&](const State& w) {
            return (w.p + m.gamma * m.p_inf) / (m.gamma - 1.0) + 0.5 * w.rho * w.u * w.u;
        };
        const double ea = (E(a) + a.p) * a.u - S * E(a), eb = (E(b) + b.p) * b.u - S * E(b);
        const double scale = std::abs((E(a) + a.p) * a.u) + std::abs(S * E(a)) +
                             std::abs((E(b) + b.p) * b.u) + std::abs(S * E(b));
        check_balance(ea, eb, scale, tol, label + ": energy");
    }
    check(b.p > a.p && b.rho > a.rho, label + ": compressive (p and rho increase through the shock)");
}

// Inside a fan sampled states must satisfy the characteristic condition u -/+ a = s, the Riemann invariant
// u +/- 2a/(gamma-1) of the undisturbed state and its isentrope (p + Pi)/rho^gamma (for Tait: the EOS
// itself), and join the undisturbed and star states continuously at head and tail.
void check_fan(const Material& m, double sigma, const State& outer, const State& star, const Wave& w,
               const Solution& sol, const std::string& label) {
    const double g = m.gamma, pi = offset(m);
    auto a_of = [&](const State& s) { return std::sqrt(g * (s.p + pi) / s.rho); };
    const double J = outer.u - sigma * 2.0 * a_of(outer) / (g - 1.0);
    const double K = (outer.p + pi) / std::pow(outer.rho, g);
    const double uscale = std::abs(outer.u) + std::abs(star.u) + a_of(outer);
    for (int i = 1; i < 10; ++i) {
        const double s = w.head + (w.tail - w.head) * i / 10.0;
        const State q = sol.sample(s);
        const std::string at = label + " fan at s=" + std::to_string(s);
        check_abs(q.u + sigma * a_of(q), s, 1e-12 * uscale, at + ": characteristic u -/+ a = s");
        check_abs(q.u - sigma * 2.0 * a_of(q) / (g - 1.0), J, 1e-12 * uscale, at + ": Riemann invariant");
        check_rel((q.p + pi) / std::pow(q.rho, g), K, 1e-11, at + ": isentrope");
        if (!is_sg(m)) check_rel(q.p + pi, m.B * std::pow(q.rho / m.rho0, g), 1e-11, at + ": on Tait EOS");
    }
    const double eps = 1e-9 * (std::abs(w.head) + std::abs(w.tail));
    const State h = sol.sample(w.head - sigma * eps), t = sol.sample(w.tail + sigma * eps);
    check_rel(h.rho, outer.rho, 1e-7, label + ": fan head matches undisturbed rho");
    check_rel(h.p + pi, outer.p + pi, 1e-7, label + ": fan head matches undisturbed p");
    check_rel(t.rho, star.rho, 1e-7, label + ": fan tail matches star rho");
    check_rel(t.p + pi, star.p + pi, 1e-7, label + ": fan tail matches star p");
    check_abs(t.u, star.u, 1e-7 * uscale, label + ": fan tail matches star u");
}

// Generic consistency checks of a solution.
void check_consistency(const Solution& sol, const std::string& label) {
    const Wave& wl = sol.left_wave();
    const Wave& wr = sol.right_wave();
    const double us = sol.u_star(), ps = sol.p_star();
    const State L = sol.left_state(), R = sol.right_state();
    const double span = std::abs(wl.head) + std::abs(wr.head) + 1.0;

    // Wave ordering and far field.
    check(wl.head <= wl.tail && wl.tail <= us && us <= wr.tail && wr.tail <= wr.head,
          label + ": wave ordering");
    const State far_l = sol.sample(wl.head - span), far_r = sol.sample(wr.head + span);
    check(far_l.rho == L.rho && far_l.u == L.u && far_l.p == L.p, label + ": far-left state is L");
    check(far_r.rho == R.rho && far_r.u == R.u && far_r.p == R.p, label + ": far-right state is R");

    // Contact: p and u continuous, densities are the star densities.
    const State sl = sol.sample(0.5 * (wl.tail + us)), sr = sol.sample(0.5 * (us + wr.tail));
    check(sl.p == ps && sr.p == ps && sl.u == us && sr.u == us,
          label + ": p and u continuous across contact");
    check(sl.rho == sol.rho_star_left() && sr.rho == sol.rho_star_right(), label + ": star densities");

    // Star densities lie on the correct curve of each material (independent formulas for Tait).
    const Material& ml = sol.left_material();
    const Material& mr = sol.right_material();
    if (!is_sg(ml))
        check_rel(sol.rho_star_left(), ml.rho0 * std::pow((ps - ml.A) / ml.B + 1.0, 1.0 / ml.gamma), 1e-12,
                  label + ": rho*L on Tait EOS");
    if (!is_sg(mr))
        check_rel(sol.rho_star_right(), mr.rho0 * std::pow((ps - mr.A) / mr.B + 1.0, 1.0 / mr.gamma), 1e-12,
                  label + ": rho*R on Tait EOS");

    if (wl.is_shock()) {
        check(ps > L.p, label + ": left shock has p* > pL");
        check_shock(ml, sol.sample(wl.head - span), sl, wl.head, label + " left shock");
    } else {
        check(ps <= L.p, label + ": left rarefaction has p* <= pL");
        check_fan(ml, -1.0, L, sl, wl, sol, label + " left");
    }
    if (wr.is_shock()) {
        check(ps > R.p, label + ": right shock has p* > pR");
        check_shock(mr, sol.sample(wr.head + span), sr, wr.head, label + " right shock");
    } else {
        check(ps <= R.p, label + ": right rarefaction has p* <= pR");
        check_fan(mr, +1.0, R, sr, wr, sol, label + " right");
    }

    // Mirror symmetry x -> -x: swap sides and negate velocities.
    const Solution mir(mr, State{R.rho, -R.u, R.p}, ml, State{L.rho, -L.u, L.p});
    const double pscale = ps + std::max(offset(ml), offset(mr));
    check_abs(mir.p_star(), ps, 1e-11 * pscale, label + ": mirror p*");
    check_abs(mir.u_star(), -us, 1e-11 * span, label + ": mirror u*");
    check_rel(mir.rho_star_left(), sol.rho_star_right(), 1e-10, label + ": mirror rho*");
    check_abs(mir.right_wave().head, -wl.head, 1e-10 * span, label + ": mirror wave speed");
}

void print_waves(const Solution& sol, const char* label) {
    auto wave = [](const char* side, const Wave& w) {
        if (w.is_shock())
            std::printf("    %s wave: shock, S = %.10g\n", side, w.head);
        else
            std::printf("    %s wave: rarefaction, head = %.10g, tail = %.10g\n", side, w.head, w.tail);
    };
    std::printf("  %s: p* = %.10g, u* = %.10g, rho*L = %.10g, rho*R = %.10g (%d iterations)\n", label,
                sol.p_star(), sol.u_star(), sol.rho_star_left(), sol.rho_star_right(), sol.iterations());
    wave("left ", sol.left_wave());
    std::printf("    contact: %.10g\n", sol.contact_speed());
    wave("right", sol.right_wave());
}

// Toro, Table 4.3 (gamma = 1.4): values printed with 5-6 significant digits; tolerance = half a unit in the
// last printed digit.
void toro_test(const char* name, State L, State R, double p, double dp, double u, double du, double rl,
               double drl, double rr, double drr) {
    std::printf("%s\n", name);
    const Material g = exact::stiffened_gas(1.4);
    const Solution sol(g, L, g, R);
    print_waves(sol, name);
    check_abs(sol.p_star(), p, dp, std::string(name) + ": p* vs Toro Table 4.3");
    check_abs(sol.u_star(), u, du, std::string(name) + ": u* vs Toro Table 4.3");
    check_abs(sol.rho_star_left(), rl, drl, std::string(name) + ": rho*L vs Toro Table 4.3");
    check_abs(sol.rho_star_right(), rr, drr, std::string(name) + ": rho*R vs Toro Table 4.3");
    check_consistency(sol, name);
}

} // namespace

int main() {
    // ---------------------------------------------------------------- published references (Toro Table 4.3)
    toro_test("Toro test 1 (Sod)", {1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 0.30313, 5e-6, 0.92745, 5e-6, 0.42632,
              5e-6, 0.26557, 5e-6);
    toro_test("Toro test 2 (123 problem)", {1.0, -2.0, 0.4}, {1.0, 2.0, 0.4}, 0.00189, 5e-6, 0.0, 1e-14,
              0.02185, 5e-6, 0.02185, 5e-6);
    toro_test("Toro test 3", {1.0, 0.0, 1000.0}, {1.0, 0.0, 0.01}, 460.894, 5e-4, 19.5975, 5e-5, 0.57506,
              5e-6, 5.99924, 5e-6);
    toro_test("Toro test 4", {1.0, 0.0, 0.01}, {1.0, 0.0, 100.0}, 46.0950, 5e-5, -6.19633, 5e-6, 5.99242,
              5e-6, 0.57511, 5e-6);

    // ---------------------------------------------------------------- stiffened gas = ideal gas on p + P_inf
    std::printf("Stiffened gas vs shifted ideal gas\n");
    {
        const double pinf = 3.31e8 - 1e5;
        const State L{1100.0, 20.0, 6.0e8}, R{1000.0, -5.0, 1.0e5};
        const Solution sg(exact::stiffened_gas(7.15, pinf), L, exact::stiffened_gas(4.4, pinf), R);
        const Solution ig(exact::stiffened_gas(7.15), {L.rho, L.u, L.p + pinf}, exact::stiffened_gas(4.4),
                          {R.rho, R.u, R.p + pinf});
        print_waves(sg, "SG (7.15, 4.4; P_inf)");
        print_waves(ig, "ideal gas on p + P_inf");
        check_rel(sg.p_star() + pinf, ig.p_star(), 1e-11, "SG p* + P_inf == ideal-gas p*");
        check_rel(sg.u_star(), ig.u_star(), 1e-10, "SG u* == ideal-gas u*");
        check_rel(sg.rho_star_left(), ig.rho_star_left(), 1e-11, "SG rho*L == ideal-gas rho*L");
        check_rel(sg.rho_star_right(), ig.rho_star_right(), 1e-11, "SG rho*R == ideal-gas rho*R");
        check_rel(sg.left_wave().head, ig.left_wave().head, 1e-11, "SG left wave speed");
        check_rel(sg.right_wave().head, ig.right_wave().head, 1e-11, "SG right wave speed");
        for (int i = 0; i <= 40; ++i) {
            const double s = -3000.0 + 150.0 * i;
            const State a = sg.sample(s), b = ig.sample(s);
            check(std::abs(a.rho - b.rho) <= 1e-10 * b.rho && std::abs(a.u - b.u) <= 1e-10 * 3000.0 &&
                      std::abs(a.p + pinf - b.p) <= 1e-10 * b.p,
                  "SG sampled state == shifted ideal-gas state at s=" + std::to_string(s));
        }
        check_consistency(sg, "SG shifted");
    }

    // ---------------------------------------------------------------- Tait water
    const Material water = exact::tait();
    std::printf("Tait symmetric collision\n");
    {
        const Solution sol(water, {1000.0, 100.0, 1e5}, water, {1000.0, -100.0, 1e5});
        print_waves(sol, "Tait (1000,+100,1e5)/(1000,-100,1e5)");
        check_abs(sol.u_star(), 0.0, 1e-12, "symmetric collision u* = 0");
        check_rel(sol.rho_star_left(), sol.rho_star_right(), 1e-14, "symmetric collision rho*L == rho*R");
        check_rel(-sol.left_wave().head, sol.right_wave().head, 1e-12, "symmetric shock speeds");
        check(sol.left_wave().is_shock() && sol.right_wave().is_shock(), "symmetric collision: two shocks");
        // Independent restatement of the barotropic jump condition: (p* - p)(1/rho - 1/rho*) = (u - u*)^2.
        const double rs = 1000.0 * std::pow((sol.p_star() - 1e5) / 3.31e8 + 1.0, 1.0 / 7.15);
        check_rel((sol.p_star() - 1e5) * (1.0 / 1000.0 - 1.0 / rs), 100.0 * 100.0, 1e-10,
                  "barotropic jump (p*-p)(1/rho-1/rho*) = du^2");
        check_consistency(sol, "Tait symmetric");
    }
    std::printf("Tait identical states\n");
    for (double rho : {1000.0, 1050.0, 990.0}) {
        const double p = exact::tait_pressure(water, rho);
        const Solution sol(water, {rho, 5.0, p}, water, {rho, 5.0, p});
        const std::string lab = "Tait identical states rho=" + std::to_string(rho);
        check_rel(sol.p_star(), p, 1e-12, lab + ": p* = p");
        check_rel(sol.u_star(), 5.0, 1e-12, lab + ": u* = u");
        check_rel(sol.rho_star_left(), rho, 1e-12, lab + ": rho* = rho");
        const State w = sol.sample(0.0);
        check(w.rho == sol.rho_star_left() && w.p == sol.p_star(), lab + ": sample");
    }
    std::printf("Tait-Tait, different materials, shock + rarefaction\n");
    {
        const Material w2 = exact::tait(7.0, 3.0e8, 0.0, 1020.0);
        const double rl = 1080.0;
        const Solution sol(water, {rl, -30.0, exact::tait_pressure(water, rl)}, w2,
                           {1020.0, -60.0, exact::tait_pressure(w2, 1020.0)});
        print_waves(sol, "Tait/Tait'");
        check_consistency(sol, "Tait/Tait'");
    }

    // Weak-wave limit (water hammer): for |du| << a both water models approach linear acoustics,
    // p* - p = rho a u (Joukowsky), and the barotropic Tait shock and the stiffened-gas Hugoniot (same
    // isentrope, P_inf = B - A) agree up to O((dp / (p + B - A))^2).
    std::printf("Weak water hammer (u = +/-0.1 m/s)\n");
    {
        const Material sgw = exact::stiffened_gas(7.15, 3.31e8 - 1e5);
        const double u = 0.1, rho = 1000.0, p = 1e5;
        const double a = std::sqrt(7.15 * (p + 3.31e8 - 1e5) / rho);
        const Solution t(water, {rho, u, p}, water, {rho, -u, p});
        const Solution s(sgw, {rho, u, p}, sgw, {rho, -u, p});
        const double joukowsky = rho * a * u;
        std::printf("  Joukowsky rho a u = %.10g; Tait p*-p = %.10g; SG p*-p = %.10g\n", joukowsky,
                    t.p_star() - p, s.p_star() - p);
        check_rel(t.p_star() - p, joukowsky, 1e-3, "Tait water hammer ~ Joukowsky");
        check_rel(s.p_star() - p, joukowsky, 1e-3, "SG water hammer ~ Joukowsky");
        check_rel(t.p_star() - p, s.p_star() - p, 1e-5, "Tait and SG water agree for a weak shock");
        check_consistency(t, "weak hammer Tait");
        check_consistency(s, "weak hammer SG");
    }

    // ---------------------------------------------------------------- gas-water (no independent reference)
    std::printf("Gas-water shock tube: gas (1630, 0, 7.81e9, gamma 1.4) | water (1000, 0, 1e5)\n");
    {
        const Material gas = exact::stiffened_gas(1.4);
        const State G{1630.0, 0.0, 7.81e9}, W{1000.0, 0.0, 1e5};
        const Solution t(gas, G, water, W);
        const Solution s(gas, G, exact::stiffened_gas(7.15, 3.31e8 - 1e5), W);
        print_waves(t, "gas | Tait water");
        print_waves(s, "gas | SG water (7.15, 3.31e8 - 1e5)");
        std::printf("  relative difference of p*: %.3e\n", (s.p_star() - t.p_star()) / t.p_star());
        for (const Solution* sol : {&t, &s}) {
            const std::string lab = sol == &t ? "gas|Tait" : "gas|SG water";
            check(sol->p_star() > W.p && sol->p_star() < G.p, lab + ": pR < p* < pL", sol->p_star());
            check(sol->u_star() > 0.0, lab + ": u* > 0", sol->u_star());
            check(!sol->left_wave().is_shock() && sol->right_wave().is_shock(),
                  lab + ": rarefaction + shock");
            check_consistency(*sol, lab);
        }
        // Same problem with water on the left (gas on the right) must be the mirror image.
        const Solution m(water, {W.rho, -W.u, W.p}, gas, {G.rho, -G.u, G.p});
        check_rel(m.p_star(), t.p_star(), 1e-12, "water|gas mirror p*");
        check_rel(m.u_star(), -t.u_star(), 1e-10, "water|gas mirror u*");
        check_consistency(m, "Tait|gas");
    }

    // ---------------------------------------------------------------- vacuum / cavitation and invalid input
    std::printf("Error handling\n");
    {
        const Material g = exact::stiffened_gas(1.4);
        check_throws<std::runtime_error>(g, {1.0, -20.0, 0.4}, g, {1.0, 20.0, 0.4}, "ideal-gas vacuum");
        check_throws<std::runtime_error>(water, {1000.0, -600.0, 1e5}, water, {1000.0, 600.0, 1e5},
                                         "Tait cavitation (p* < A - B)");
        check_throws<std::runtime_error>(g, {1.0, -2000.0, 1e5}, water, {1000.0, 10.0, 1e5},
                                         "gas-water separation");
        check_throws<std::invalid_argument>(water, {1000.0, 0.0, 2e5}, water, {1000.0, 0.0, 1e5},
                                            "Tait state off the EOS");
        check_throws<std::invalid_argument>(g, {-1.0, 0.0, 1.0}, g, {1.0, 0.0, 1.0}, "negative density");
    }

    std::printf("%d checks, %d failures\n", n_checks, n_failures);
    return n_failures == 0 ? 0 : 1;
}
