// Test helpers: build a fluid solver from case text and advance it to its end time without output.
#pragma once
#include "base/case_file.hpp"
#include "fluid/setup.hpp"
#include "fluid/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace undex::test {

inline std::unique_ptr<fluid::FluidSolver> make(const std::string& text) {
    return fluid::make_solver(CaseFile::from_text(text, "<test case>"));
}

// Advances to end_time with the solver's own stable Δt; returns the wall time in seconds.
inline double advance(fluid::FluidSolver& s, double end_time) {
    const auto start = std::chrono::steady_clock::now();
    while (s.time() < end_time * (1 - 1e-14))
        s.step(std::min(s.stable_dt(), end_time - s.time()));
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// L2 norm over the domain of (numerical − exact) for one primitive variable, by 3-point Gauss quadrature
// per direction in every cell; `exact` returns the exact primitive at (x, y).
template <class Exact, class Pick> double l2_error(const fluid::FluidSolver& s, Exact&& exact, Pick&& pick) {
    const auto& m = s.mesh();
    const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5 / 18.0, 8 / 18.0, 5 / 18.0};
    double sum = 0, area = 0;
    for (int j = 0; j < m.ny; ++j)
        for (int i = 0; i < m.nx; ++i)
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < (m.dim == 2 ? 3 : 1); ++b) {
                    const double x = m.xc(i) + 0.5 * m.dx * g[a];
                    const double y = m.dim == 2 ? m.yc(j) + 0.5 * m.dy * g[b] : 0.0;
                    const double wq = (m.dim == 2 ? w[a] * w[b] : w[a]) * m.dx * (m.dim == 2 ? m.dy : 1.0);
                    const double e = pick(s.evaluate(x, y)) - pick(exact(x, y));
                    sum += wq * e * e;
                    area += wq;
                }
    return std::sqrt(sum / area);
}

} // namespace undex::test
