// Case 4.1 (1D underwater explosion, cases/undex_1d.case) against the exact two-material Riemann solution
// of its water model (tests/support/exact_riemann.hpp, written independently of the solver).
//   L1 errors: mean absolute error over [0, 1], integrated with 8 equally spaced samples per cell of the DG
//     polynomials (a midpoint rule that resolves the jumps inside cells);
//   positions: the same level crossing is located in the numerical and in the exact profile, so both carry
//     the same bias: the shock at half the water pressure jump, the rarefaction head at 1 % of the gas
//     pressure drop; the interface is the zero of the level set (linear between cell centres) against the
//     exact contact x0 + u* t.
#pragma once
#include "base/case_file.hpp"
#include "tests/support/exact_riemann.hpp"
#include "tests/support/run_case.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace undex::test {

struct Undex1dErrors {
    double l1_rho = 0, l1_u = 0, l1_p = 0; // absolute
    double p_star = 0;                     // exact interface pressure
    double shock = 0, shock_exact = 0, interface = 0, interface_exact = 0, head = 0, head_exact = 0;
    double dx = 0;
};

// The exact solution of case 4.1 with either water model.
inline exact::Solution undex_1d_exact(bool water_as_stiffened_gas) {
    const exact::Material gas = exact::stiffened_gas(1.4);
    const exact::Material water =
        water_as_stiffened_gas ? exact::stiffened_gas(7.15, 3.31e8 - 1e5) : exact::tait();
    return exact::Solution(gas, {1630.0, 0.0, 7.81e9}, water, {1000.0, 0.0, 1e5});
}

// The first x where f crosses `level`, scanning [a, b] from the right (rightmost crossing) or from the left
// (leftmost), on `samples` intervals and then by bisection; NaN if there is none.
template <class F> double crossing(F&& f, double a, double b, int samples, double level, bool from_right) {
    auto at = [&](int k) { return from_right ? b - (b - a) * k / samples : a + (b - a) * k / samples; };
    double prev_x = at(0), prev = f(prev_x) - level;
    for (int k = 1; k <= samples; ++k) {
        const double x = at(k), v = f(x) - level;
        if ((v > 0) != (prev > 0)) {
            double lo = x, hi = prev_x; // f(lo) − level has the sign of v
            for (int it = 0; it < 60; ++it) {
                const double mid = 0.5 * (lo + hi);
                if (((f(mid) - level) > 0) == (v > 0))
                    lo = mid;
                else
                    hi = mid;
            }
            return 0.5 * (lo + hi);
        }
        prev_x = x, prev = v;
    }
    return NAN;
}

inline Undex1dErrors undex_1d_errors(const fluid::FluidSolver& s, const exact::Solution& ex, double x0,
                                     double t) {
    const auto& m = s.mesh();
    Undex1dErrors e;
    e.dx = m.dx;
    e.p_star = ex.p_star();
    constexpr int per_cell = 8;
    const int n = m.nx * per_cell;
    for (int k = 0; k < n; ++k) {
        const double x = m.x_min + (k + 0.5) * (m.x_max - m.x_min) / n;
        const auto w = s.evaluate(x, 0);
        const auto r = ex.sample((x - x0) / t);
        e.l1_rho += std::abs(w.rho - r.rho) / n;
        e.l1_u += std::abs(w.u - r.u) / n;
        e.l1_p += std::abs(w.p - r.p) / n;
    }
    const double p_water = ex.right_state().p, p_gas = ex.left_state().p;
    const double shock_level = 0.5 * (ex.p_star() + p_water),
                 head_level = p_gas - 0.01 * (p_gas - ex.p_star());
    auto p_num = [&](double x) { return s.evaluate(x, 0).p; };
    auto p_ex = [&](double x) { return ex.sample((x - x0) / t).p; };
    const int fine = m.nx * per_cell;
    e.shock = crossing(p_num, m.x_min, m.x_max, fine, shock_level, true);
    e.shock_exact = crossing(p_ex, m.x_min, m.x_max, fine, shock_level, true);
    e.head = crossing(p_num, m.x_min, m.x_max, fine, head_level, false);
    e.head_exact = crossing(p_ex, m.x_min, m.x_max, fine, head_level, false);
    e.interface_exact = x0 + ex.u_star() * t;
    const auto phi = s.level_set();
    e.interface = NAN;
    for (int i = 0; i + 1 < m.nx && !phi.empty(); ++i)
        if (phi[i] < 0 && phi[i + 1] >= 0) e.interface = m.xc(i) + m.dx * phi[i] / (phi[i] - phi[i + 1]);
    return e;
}

} // namespace undex::test
