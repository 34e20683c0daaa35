// Measured L2 convergence orders on smooth problems (physics.md §3): degree k must reach at least k + 0.8
// between the two finest meshes. The bound k + 0.8 leaves room for pre-asymptotic effects on these small
// meshes; the design order of a degree-k DG scheme is k + 1. The limiter stays on (TVB indicator), so the
// test also checks that it leaves smooth solutions alone.
#include "tests/support/run_case.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

using undex::fluid::Primitive;

namespace {

const double pi = std::acos(-1.0);

// Density wave ρ = 1 + 0.2 sin(2π(x − t)) in uniform flow u = 1, p = 1, periodic on [0, 1].
std::string wave_case(int k, int n) {
    return "geometry: PLANAR_1D domain { x_min: 0 x_max: 1 cells_x: " + std::to_string(n) +
           " } materials { name: 'air' stiffened_gas { gamma: 1.4 } }"
           " regions { material: 'air' rho: 1 u: 1 p: 1 }"
           " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC } }"
           " numerics { degree: " +
           std::to_string(k) + " cfl: " + (k == 0 ? "0.4" : "0.15") +
           " } end_time: 0.5 output { directory: '/tmp' }";
}

double wave_error(int k, int n) {
    auto s = undex::test::make(wave_case(k, n));
    s->project([](double x, double, double* q) {
        const double rho = 1 + 0.2 * std::sin(2 * pi * x);
        q[0] = rho;
        q[1] = rho;
        q[2] = 1.0 / 0.4 + 0.5 * rho;
    });
    undex::test::advance(*s, 0.5);
    return undex::test::l2_error(
        *s,
        [](double x, double) {
            return Primitive{1 + 0.2 * std::sin(2 * pi * (x - 0.5)), 1, 0, 1};
        },
        [](const Primitive& w) { return w.rho; });
}

// Isentropic vortex (Shu 1998) of strength 5 in uniform flow (1, 1) on the periodic square [0, 10]².
// TVB constant: the indicator leaves a smooth extremum alone when M ≥ |ρ''| L² / ρ̄ up to an O(1) factor;
// with the vortex's |ρ''| ≈ 1 on a domain of length L = 10, M = 200 (the 1D wave, L = 1, keeps the default
// M = 10).
Primitive vortex(double x, double y, double t) {
    const double gamma = 1.4, eps = 5.0;
    double xb = x - 5 - t, yb = y - 5 - t;
    xb -= 10 * std::round(xb / 10);
    yb -= 10 * std::round(yb / 10);
    const double r2 = xb * xb + yb * yb;
    const double f = eps / (2 * pi) * std::exp(0.5 * (1 - r2));
    const double T = 1 - (gamma - 1) * eps * eps / (8 * gamma * pi * pi) * std::exp(1 - r2);
    const double rho = std::pow(T, 1 / (gamma - 1));
    return {rho, 1 - f * yb, 1 + f * xb, std::pow(rho, gamma)};
}

double vortex_error(int k, int n, double t_end) {
    auto s = undex::test::make(
        "geometry: PLANAR_2D domain { x_min: 0 x_max: 10 cells_x: " + std::to_string(n) +
        " y_min: 0 y_max: 10 cells_y: " + std::to_string(n) +
        " } materials { name: 'air' stiffened_gas { gamma: 1.4 } } regions { material: 'air' rho: 1 p: 1 }"
        " boundaries { x_min { type: PERIODIC } x_max { type: PERIODIC } y_min { type: PERIODIC }"
        " y_max { type: PERIODIC } } numerics { degree: " +
        std::to_string(k) + " cfl: " + (k == 0 ? "0.4" : "0.15") +
        " tvb_m: 200 } end_time: 1 output { directory: '/tmp' }");
    s->project([](double x, double y, double* q) {
        const Primitive w = vortex(x, y, 0);
        q[0] = w.rho;
        q[1] = w.rho * w.u;
        q[2] = w.rho * w.v;
        q[3] = w.p / 0.4 + 0.5 * w.rho * (w.u * w.u + w.v * w.v);
    });
    undex::test::advance(*s, t_end);
    return undex::test::l2_error(
        *s, [&](double x, double y) { return vortex(x, y, t_end); },
        [](const Primitive& w) { return w.rho; });
}

} // namespace

class WaveOrder : public testing::TestWithParam<int> {};

TEST_P(WaveOrder, DensityWave1D) {
    const int k = GetParam();
    const int n0 = k == 0 ? 80 : 10;
    double prev = 0;
    for (int level = 0; level < 4; ++level) {
        const int n = n0 << level;
        const double e = wave_error(k, n);
        if (level > 0) {
            const double order = std::log2(prev / e);
            std::printf("1D wave k=%d N=%4d L2(rho)=%.3e order %.2f\n", k, n, e, order);
            if (level == 3) {
                EXPECT_GE(order, k + 0.8) << "k = " << k;
            }
        } else {
            std::printf("1D wave k=%d N=%4d L2(rho)=%.3e\n", k, n, e);
        }
        prev = e;
    }
}

INSTANTIATE_TEST_SUITE_P(Degrees, WaveOrder, testing::Values(0, 1, 2));

class VortexOrder : public testing::TestWithParam<int> {};

TEST_P(VortexOrder, IsentropicVortex2D) {
    const int k = GetParam();
    const int n0 = k == 0 ? 40 : 20;
    const double t_end = 1.0;
    double prev = 0;
    for (int level = 0; level < 3; ++level) {
        const int n = n0 << level;
        const double e = vortex_error(k, n, t_end);
        if (level > 0) {
            const double order = std::log2(prev / e);
            std::printf("2D vortex k=%d N=%3d L2(rho)=%.3e order %.2f\n", k, n, e, order);
            if (level == 2) {
                EXPECT_GE(order, k + 0.8) << "k = " << k;
            }
        } else {
            std::printf("2D vortex k=%d N=%3d L2(rho)=%.3e\n", k, n, e);
        }
        prev = e;
    }
}

INSTANTIATE_TEST_SUITE_P(Degrees, VortexOrder, testing::Values(0, 1, 2));

namespace {

// Steady isentropic source flow of an ideal gas (γ = 1.4), an exact solution of the Euler equations with the
// geometric source of physics.md §1: constant mass flux ρ u r^α = m, Bernoulli a²/(γ−1) + u²/2 = H and
// p = K ρ^γ. At r = 1: ρ = 1, a = 1 (p = 1/γ), u = 0.3; subsonic (Mach ≤ 0.3) on r ∈ [1, 2]. ρ(r) is the
// subsonic root of the Bernoulli relation, by Newton from above (f is increasing and convex there).
struct SourceFlow {
    int alpha;
    static constexpr double gamma = 1.4, K = 1 / 1.4, u1 = 0.3;
    double m() const { return u1; }
    double H() const { return 1 / (gamma - 1) + 0.5 * u1 * u1; }
    Primitive at(double r) const {
        const double ra = std::pow(r, alpha), flux = m() / ra;
        double rho = 1.5;
        for (int it = 0; it < 60; ++it) {
            const double a2 = gamma * K * std::pow(rho, gamma - 1), u = flux / rho;
            const double f = a2 / (gamma - 1) + 0.5 * u * u - H(), df = (a2 - u * u) / rho;
            rho -= f / df;
        }
        return {rho, flux / rho, 0, K * std::pow(rho, gamma)};
    }
};

// Errors at t = 0.2 after starting from the projected steady state, on r ∈ [1, 2] with n cells
// (AXISYMMETRIC_2D: the same flow, independent of z, on two periodic rows): the L2 errors of ρ and u and the
// mean error of the cell averages of ρ, over the cells inside r ∈ [1.3, 1.7]. The ends are transmissive
// (not exact for this flow); their disturbances travel at most (a + |u|) t ≈ 0.26 in from either end by
// t = 0.2, so the measured cells see only the scheme's interior: the fluxes and the geometric source.
struct SourceFlowErrors {
    double rho, u, average;
};

SourceFlowErrors source_flow_error(const std::string& geometry, int k, int n) {
    const bool two_d = geometry == "AXISYMMETRIC_2D";
    const SourceFlow flow{geometry == "SPHERICAL_1D" ? 2 : 1};
    auto s = undex::test::make(
        "geometry: " + geometry + " domain { x_min: 1 x_max: 2 cells_x: " + std::to_string(n) +
        (two_d ? " y_min: 0 y_max: 1 cells_y: 2" : "") +
        " } materials { name: 'air' stiffened_gas { gamma: 1.4 } } regions { material: 'air' rho: 1 p: 1 }"
        " boundaries { x_min { type: TRANSMISSIVE } x_max { type: TRANSMISSIVE }" +
        (two_d ? " y_min { type: PERIODIC } y_max { type: PERIODIC }" : "") +
        " } numerics { degree: " + std::to_string(k) + " cfl: " + (k == 0 ? "0.4" : "0.15") +
        " } end_time: 0.2 output { directory: '/tmp' }");
    s->project([&](double x, double, double* q) {
        const Primitive w = flow.at(x);
        q[0] = w.rho;
        q[1] = w.rho * w.u;
        if (two_d) q[2] = 0;
        q[two_d ? 3 : 2] = w.p / (SourceFlow::gamma - 1) + 0.5 * w.rho * w.u * w.u;
    });
    undex::test::advance(*s, 0.2);
    // By 3-point Gauss quadrature in each measured cell (exact averages: exact to O(Δx⁶)).
    const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5 / 18.0, 8 / 18.0, 5 / 18.0};
    const auto& mesh = s->mesh();
    const auto coefficients = s->coefficients();
    const int per_cell = s->variables() * s->basis_functions();
    double sum_rho = 0, sum_u = 0, sum_average = 0;
    int cells = 0;
    for (int i = 0; i < mesh.nx; ++i) {
        if (mesh.xc(i) < 1.3 || mesh.xc(i) > 1.7) continue;
        double average = 0;
        for (int a = 0; a < 3; ++a) {
            const double x = mesh.xc(i) + 0.5 * mesh.dx * g[a];
            const Primitive num = s->evaluate(x, mesh.yc(0)), ex = flow.at(x);
            sum_rho += w[a] * (num.rho - ex.rho) * (num.rho - ex.rho);
            sum_u += w[a] * (num.u - ex.u) * (num.u - ex.u);
            average += w[a] * ex.rho;
        }
        sum_average += std::abs(coefficients[static_cast<size_t>(i) * per_cell] - average);
        ++cells;
    }
    return {std::sqrt(sum_rho / cells), std::sqrt(sum_u / cells), sum_average / cells};
}

} // namespace

class SourceFlowOrder : public testing::TestWithParam<std::tuple<std::string, int>> {};

// The geometric source against an exact steady radial flow: between the two finest meshes, order ≥ k + 0.8
// in ρ and u, and for k ≥ 1 order ≥ k + 1.8 in the cell averages of ρ (DG cell averages superconverge:
// measured 4.2 (k = 1) and 5.1 (k = 2) cylindrical and axisymmetric, 4.1 and 5.3 spherical; L2 orders 2.0–2.2
// (k = 1), 3.0–3.4 (k = 2), 1.0–1.7 (k = 0)). Evaluating the source at the cell centre instead of at the
// quadrature points is an O(Δx) error in the slope modes and O(Δx²) in the averages: it drops the L2 order
// of k = 2 to 1.8–2.0 and the average order of k = 1 and 2 to 1.9–2.4 (k = 0 has one point, the centre).
TEST_P(SourceFlowOrder, SteadyRadialFlow) {
    const auto& [geometry, k] = GetParam();
    const int n0 = k == 0 ? 40 : 10;
    SourceFlowErrors prev{};
    for (int level = 0; level < 3; ++level) {
        const int n = n0 << level;
        const SourceFlowErrors e = source_flow_error(geometry, k, n);
        std::printf("%s k=%d N=%4d L2(rho)=%.3e L2(u)=%.3e mean|avg rho err|=%.3e", geometry.c_str(), k, n,
                    e.rho, e.u, e.average);
        if (level > 0) {
            const double o_rho = std::log2(prev.rho / e.rho), o_u = std::log2(prev.u / e.u),
                         o_avg = std::log2(prev.average / e.average);
            std::printf(" orders %.2f %.2f %.2f", o_rho, o_u, o_avg);
            if (level == 2) {
                EXPECT_GE(o_rho, k + 0.8) << geometry << " k = " << k;
                EXPECT_GE(o_u, k + 0.8) << geometry << " k = " << k;
                if (k > 0) {
                    EXPECT_GE(o_avg, k + 1.8) << geometry << " k = " << k;
                }
            }
        }
        std::printf("\n");
        prev = e;
    }
}

INSTANTIATE_TEST_SUITE_P(GeometriesAndDegrees, SourceFlowOrder,
                         testing::Combine(testing::Values("CYLINDRICAL_1D", "SPHERICAL_1D",
                                                          "AXISYMMETRIC_2D"),
                                          testing::Values(0, 1, 2)),
                         [](const auto& info) {
                             std::string g = std::get<0>(info.param);
                             return g.substr(0, g.find('_')) + "_k" + std::to_string(std::get<1>(info.param));
                         });
