// Gas–water interfaces (physics.md §4): the solver's interface Riemann solver against the independent exact
// solver of the tests, and case 4.1 (cases/undex_1d.case) against the exact two-material solution of its
// water model. L1 errors are mean absolute errors over [0, 1] (tests/support/undex_1d.hpp).
#include "fluid/interface_riemann.hpp"
#include "tests/support/exact_riemann.hpp"
#include "tests/support/undex_1d.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

using namespace undex;

namespace {

fluid::RiemannMaterial gas() {
    return {1.4, 0.0, false, 0.0, 0.0};
}
fluid::RiemannMaterial tait_water() {
    return {7.15, 3.31e8 - 1e5, true, 3.31e8, 1000.0};
}
fluid::RiemannMaterial sg_water() {
    return {7.15, 3.31e8 - 1e5, false, 0.0, 0.0};
}

struct Pair {
    const char* name;
    fluid::RiemannMaterial ml, mr;
    exact::Material el, er;
    fluid::RiemannSide wl, wr;
};

std::vector<Pair> pairs() {
    const auto eg = exact::stiffened_gas(1.4), et = exact::tait(),
               es = exact::stiffened_gas(7.15, 3.31e8 - 1e5);
    return {
        {"4.1 gas | Tait", gas(), tait_water(), eg, et, {1630, 0, 7.81e9}, {1000, 0, 1e5}},
        {"4.1 gas | stiffened water", gas(), sg_water(), eg, es, {1630, 0, 7.81e9}, {1000, 0, 1e5}},
        {"impact, two shocks", gas(), tait_water(), eg, et, {1.2, 300, 1e5}, {1000, -20, 1e5}},
        {"separation, two rarefactions", tait_water(), gas(), et, eg, {1000, -1, 1e5}, {1.2, 20, 1e5}},
        {"water | compressed gas", sg_water(), gas(), es, eg, {1000, 0, 1e5}, {100, 0, 1e8}},
    };
}

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

} // namespace

// The exact mode solves the same equations as the independent solver to a relative tolerance of 1e-12 on
// p + Π; the star states then agree to round-off amplified by the wave curves: bound 1e-9 relative.
TEST(InterfaceRiemann, ExactModeMatchesTheIndependentExactSolver) {
    for (const auto& c : pairs()) {
        const auto s = fluid::solve_interface(c.ml, c.wl, c.mr, c.wr, fluid::InterfaceRiemann::Exact);
        const exact::Solution ex(c.el, {c.wl.rho, c.wl.u, c.wl.p}, c.er, {c.wr.rho, c.wr.u, c.wr.p});
        const double pscale = std::abs(ex.p_star()) + std::min(c.ml.pi, c.mr.pi) + 1e5;
        EXPECT_NEAR(s.p, ex.p_star(), 1e-9 * pscale) << c.name;
        EXPECT_NEAR(s.u, ex.u_star(), 1e-9 * (std::abs(ex.u_star()) + 1.0)) << c.name;
        EXPECT_NEAR(s.rho_l, ex.rho_star_left(), 1e-9 * ex.rho_star_left()) << c.name;
        EXPECT_NEAR(s.rho_r, ex.rho_star_right(), 1e-9 * ex.rho_star_right()) << c.name;
    }
}

// The double-shock approximation replaces a rarefaction by a shock of the same pressure change. The
// velocity change along the shock and the isentrope agree to second order in Δp/p̄ and differ at third
// order, about (γ+1)/(12γ²)·(Δp/p̄)³ relative; for the gas rarefaction of case 4.1 (Δp/p̄ ≈ 0.47, γ = 1.4)
// that is under 1 % of the velocity change, which moves p* by less than 1 %. Bound: 1 % in p* and u*.
// Where both waves are shocks the approximation is exact (bound: 1e-9).
TEST(InterfaceRiemann, DoubleShockApproximationIsCloseForCase41AndExactForTwoShocks) {
    for (const auto& c : pairs()) {
        const auto d = fluid::solve_interface(c.ml, c.wl, c.mr, c.wr, fluid::InterfaceRiemann::DoubleShock);
        const auto e = fluid::solve_interface(c.ml, c.wl, c.mr, c.wr, fluid::InterfaceRiemann::Exact);
        std::printf("%-30s double shock p* %.6e u* %.3f | exact p* %.6e u* %.3f\n", c.name, d.p, d.u, e.p,
                    e.u);
        const bool two_shocks = e.p > c.wl.p && e.p > c.wr.p;
        const double tol = two_shocks ? 1e-9 : 1e-2;
        if (std::string(c.name).rfind("4.1", 0) == 0 || two_shocks) {
            EXPECT_NEAR(d.p, e.p, tol * e.p) << c.name;
            EXPECT_NEAR(d.u, e.u, tol * std::abs(e.u)) << c.name;
        }
    }
}

// A scene models no more than it needs: one material, no level set; two materials, a level set.
TEST(TwoFluid, LevelSetOnlyWithTwoMaterials) {
    const std::string text = read(UNDEX_CASES "/undex_1d.case");
    auto two = test::make(text);
    EXPECT_EQ(two->level_set().size(), 400u);
    auto one = test::make(read(UNDEX_CASES "/sod_1d.case"));
    EXPECT_TRUE(one->level_set().empty());
}

// Case 4.1, 400 cells, degree 2, real GFM with the double-shock solver (the case file as written), for both
// water models against the exact solution of each. Bounds from an error budget (said plainly: the
// measured 0.64 % / 0.80 % were known when the budget was written):
//   L1(p) ≤ 1 % of p*: four cells' worth of the full pressure jump (4 Δx p*/L): the shock, the contact and
//     the two rarefaction edges each smeared or displaced by about one cell;
//   interface within 1 cell of the exact contact (the level set moves with u* itself);
//   shock within 1.5 cells: redefining the real water cell next to the interface with the star state in
//     the first steps, before the shock has crossed it, moves the shock ahead by up to one cell, plus half
//     a cell of capturing;
//   refinement: L1(p) at 800 cells below 0.8 × that at 400 (discontinuous solutions converge in L1 at
//     order 0.6–1, i.e. a factor 0.5–0.66 per doubling).
class Undex1d : public testing::TestWithParam<bool> {};

TEST_P(Undex1d, AgainstExactSolutionOfItsWaterModel) {
    const bool sg = GetParam();
    const auto ex = test::undex_1d_exact(sg);
    double prev = 0;
    for (int n : {400, 800}) {
        auto cf =
            CaseFile::load(UNDEX_CASES "/undex_1d.case",
                           {"domain.cells_x=" + std::to_string(n),
                            std::string("materials[1].tait.as_stiffened_gas=") + (sg ? "true" : "false")});
        auto s = fluid::make_solver(cf);
        test::advance(*s, 1e-4);
        const auto e = test::undex_1d_errors(*s, ex, 0.5, 1e-4);
        std::printf(
            "%s water, %d cells: L1 rho %.3e u %.3e p %.3e (%.3f %% of p*), shock %+.2f, interface %+.2f, "
            "rarefaction head %+.2f cells\n",
            sg ? "stiffened-gas" : "Tait", n, e.l1_rho, e.l1_u, e.l1_p, 100 * e.l1_p / e.p_star,
            (e.shock - e.shock_exact) / e.dx, (e.interface - e.interface_exact) / e.dx,
            (e.head - e.head_exact) / e.dx);
        if (n == 400) {
            EXPECT_LE(e.l1_p, 0.01 * e.p_star);
            EXPECT_LE(std::abs(e.interface - e.interface_exact), e.dx);
            EXPECT_LE(std::abs(e.shock - e.shock_exact), 1.5 * e.dx);
        } else {
            EXPECT_LT(e.l1_p, 0.8 * prev) << "error must fall under refinement";
        }
        prev = e.l1_p;
    }
}

// The same case with the modified GFM (no redefinition of real cells, hence no start-up shift of the waves)
// and the minmod limiter on troubled cells, against the bar the project set for case 4.1: L1(p) ≤ 0.3 % of
// p* with the shock and the interface within one cell of the exact positions.
TEST_P(Undex1d, ModifiedGfmWithMinmodLimiterMeetsTheBar) {
    const bool sg = GetParam();
    const auto ex = test::undex_1d_exact(sg);
    auto cf = CaseFile::load(UNDEX_CASES "/undex_1d.case",
                             {"interface.method=modified_gfm", "numerics.limiter=minmod",
                              std::string("materials[1].tait.as_stiffened_gas=") + (sg ? "true" : "false")});
    auto s = fluid::make_solver(cf);
    test::advance(*s, 1e-4);
    const auto e = test::undex_1d_errors(*s, ex, 0.5, 1e-4);
    std::printf("%s water, modified GFM, minmod: L1(p) %.3f %% of p*, shock %+.2f, interface %+.2f cells\n",
                sg ? "stiffened-gas" : "Tait", 100 * e.l1_p / e.p_star, (e.shock - e.shock_exact) / e.dx,
                (e.interface - e.interface_exact) / e.dx);
    EXPECT_LE(e.l1_p, 0.003 * e.p_star);
    EXPECT_LE(std::abs(e.shock - e.shock_exact), e.dx);
    EXPECT_LE(std::abs(e.interface - e.interface_exact), e.dx);
}

INSTANTIATE_TEST_SUITE_P(WaterModels, Undex1d, testing::Values(false, true),
                         [](const auto& info) { return info.param ? "StiffenedGas" : "Tait"; });

namespace {

// Relative L1 difference ∫|a − b| / ∫|b| along y = 0, x ∈ [0, 1], by 2000 samples of the DG polynomials.
double relative_l1(const fluid::FluidSolver& a, const fluid::FluidSolver& b,
                   double fluid::Primitive::*field) {
    double num = 0, den = 0;
    for (int k = 0; k < 2000; ++k) {
        const double x = (k + 0.5) / 2000;
        const double va = a.evaluate(x, 0).*field, vb = b.evaluate(x, 0).*field;
        num += std::abs(va - vb);
        den += std::abs(vb);
    }
    return num / den;
}

} // namespace

// Case 4.4 (cases/free_field_2d.case) at 50² and 100² against the 1D cylindrical bubble
// (cases/bubble_1d_cylindrical.case) at 1000 cells, whose Δx is 20 times finer and serves as the reference
// (the paper uses 5000 cells; 1000 keeps the test short). Norm: relative L1 along the positive x axis.
// Bounds from an error budget (said plainly: the measured 4.8 % was known when it was written): at 100²,
// Δx = 0.02; the rarefaction, the interface and
// the shock each displaced or smeared by about 1.5 cells, with jumps of about p*, give
// 3 × 1.5 Δx × p* / ∫|p| dx ≈ 7 % in p, and with the smaller relative density jumps about 5 % in ρ.
// Refinement from 50² to 100² must reduce the p difference by a factor ≥ 1.5 (L1 order ≥ 0.6).
TEST(FreeField2d, AlongTheAxisAgreesWith1DCylindricalBubble) {
    auto ref = fluid::make_solver(
        CaseFile::load(UNDEX_CASES "/bubble_1d_cylindrical.case", {"domain.cells_x=1000"}));
    test::advance(*ref, 1e-4);
    double prev = 0;
    for (int n : {50, 100}) {
        const std::string cells = std::to_string(n);
        auto s = fluid::make_solver(CaseFile::load(UNDEX_CASES "/free_field_2d.case",
                                                   {"domain.cells_x=" + cells, "domain.cells_y=" + cells}));
        test::advance(*s, 1e-4);
        const double ep = relative_l1(*s, *ref, &fluid::Primitive::p);
        const double er = relative_l1(*s, *ref, &fluid::Primitive::rho);
        const double eu = relative_l1(*s, *ref, &fluid::Primitive::u);
        std::printf("free field %d^2 vs 1D cylindrical (1000 cells): relative L1 rho %.4f u %.4f p %.4f\n", n,
                    er, eu, ep);
        if (n == 100) {
            EXPECT_LE(ep, 0.07);
            EXPECT_LE(er, 0.05);
            EXPECT_LE(ep, prev / 1.5) << "the difference must fall under refinement";
        }
        prev = ep;
    }
}
