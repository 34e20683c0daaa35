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

// Case 4.1 (cases/undex_1d.case) against the exact solution of each water model, 400 and 800 cells.
namespace {

struct Undex1dRun {
    test::Undex1dErrors e;
    double l1_share() const { return e.l1_p / e.p_star; }
    double shock_cells() const { return (e.shock - e.shock_exact) / e.dx; }
    double interface_cells() const { return (e.interface - e.interface_exact) / e.dx; }
};

Undex1dRun run_undex_1d(bool stiffened_gas, int cells, std::vector<std::string> sets) {
    sets.push_back("domain.cells_x=" + std::to_string(cells));
    sets.push_back(std::string("materials[1].tait.as_stiffened_gas=") + (stiffened_gas ? "true" : "false"));
    auto s = fluid::make_solver(CaseFile::load(UNDEX_CASES "/undex_1d.case", sets));
    test::advance(*s, 1e-4);
    Undex1dRun r{test::undex_1d_errors(*s, test::undex_1d_exact(stiffened_gas), 0.5, 1e-4)};
    std::printf(
        "%s water, %d cells%s: L1 rho %.3e u %.3e p %.3e (%.3f %% of p*), shock %+.2f, interface %+.2f, "
        "rarefaction head %+.2f cells\n",
        stiffened_gas ? "stiffened-gas" : "Tait", cells, sets.size() > 2 ? " (paper's setting)" : "",
        r.e.l1_rho, r.e.l1_u, r.e.l1_p, 100 * r.l1_share(), r.shock_cells(), r.interface_cells(),
        (r.e.head - r.e.head_exact) / r.e.dx);
    return r;
}

} // namespace

class Undex1d : public testing::TestWithParam<bool> {};

// The case file as written (modified GFM, minmod limiter on troubled cells, degree 1), against the bar of the
// project for case 4.1: L1(p) ≤ 0.3 % of p* (1.2 cells' worth of the full pressure jump, 1.2 Δx p*/L: the
// shock, the contact and the rarefaction edges each smeared over a fraction of a cell, no wave displaced),
// the shock and the interface within one cell of the exact positions; at 800 cells the L1 error below 0.8 ×
// that at 400 (discontinuous solutions converge in L1 at order 0.6–1, a factor 0.5–0.66 per doubling).
// Measured when written: 0.152 % / 0.174 % (Tait / stiffened gas), shock -0.07 / +0.22 cells.
TEST_P(Undex1d, AsWrittenAgainstExactSolutionOfItsWaterModel) {
    const Undex1dRun coarse = run_undex_1d(GetParam(), 400, {}), fine = run_undex_1d(GetParam(), 800, {});
    EXPECT_LE(coarse.l1_share(), 0.003);
    EXPECT_LE(std::abs(coarse.shock_cells()), 1.0);
    EXPECT_LE(std::abs(coarse.interface_cells()), 1.0);
    EXPECT_LT(fine.e.l1_p, 0.8 * coarse.e.l1_p) << "error must fall under refinement";
}

// The paper's setting, one --set line away (real GFM, WENO limiter, degree 2), 400 cells. Bounds from an
// error budget (said plainly: the measured 0.60 % / 0.83 % were known when the budget was written):
//   L1(p) ≤ 1 % of p*: four cells' worth of the full pressure jump (4 Δx p*/L): the shock, the contact and
//     the two rarefaction edges each smeared or displaced by about one cell;
//   interface within 1 cell of the exact contact (the level set moves with u* itself);
//   shock within 1.5 cells: redefining the real water cell next to the interface with the star state in
//     the first steps, before the shock has crossed it, moves the shock ahead by up to one cell, plus half
//     a cell of capturing (docs/gas_water_interface.md).
// Every cell is solved (numerics.skip_rest off): this setting is ill-conditioned at the shock (changing the
// gas pressure by 1e-13 relative moves the fields there by 9e-2 of their largest value at 1e-4 s, `undex run
// cases/undex_1d.case` with the four settings below), and still water kept exact instead of drifting by
// round-off is such a change: with skipping the shock lies +0.98 / +1.50 cells ahead (+0.70 / +1.42 without).
TEST_P(Undex1d, PaperSettingAgainstExactSolutionOfItsWaterModel) {
    const Undex1dRun r = run_undex_1d(GetParam(), 400,
                                      {"interface.method=real_gfm", "numerics.limiter=weno", "numerics.degree=2",
                                       "numerics.cfl=0.2", "numerics.skip_rest=false"});
    EXPECT_LE(r.l1_share(), 0.01);
    EXPECT_LE(std::abs(r.interface_cells()), 1.0);
    EXPECT_LE(std::abs(r.shock_cells()), 1.5);
}

INSTANTIATE_TEST_SUITE_P(WaterModels, Undex1d, testing::Values(false, true),
                         [](const auto& info) { return info.param ? "StiffenedGas" : "Tait"; });

namespace {

// Relative L1 difference ∫|a − b| w / ∫|b| w along y = 0, x ∈ [0, 1], by 2000 samples of the DG
// polynomials; weight w = 1, or w = r = x (the cylinder's area element) when r_weighted. With diagonal, a
// (2D) is sampled along x = y at the same distances r from the centre instead.
double relative_l1(const fluid::FluidSolver& a, const fluid::FluidSolver& b, double fluid::Primitive::*field,
                   bool r_weighted = false, bool diagonal = false) {
    double num = 0, den = 0;
    for (int k = 0; k < 2000; ++k) {
        const double x = (k + 0.5) / 2000, w = r_weighted ? x : 1.0, d = x / std::sqrt(2.0);
        const double va = (diagonal ? a.evaluate(d, d) : a.evaluate(x, 0)).*field,
                     vb = b.evaluate(x, 0).*field;
        num += std::abs(va - vb) * w;
        den += std::abs(vb) * w;
    }
    return num / den;
}

} // namespace

// Case 4.4 (cases/free_field_2d.case) against the 1D cylindrical bubble (cases/bubble_1d_cylindrical.case)
// at 1000 cells, whose Δx is 10 times finer than 200² and serves as the reference (the paper uses 5000
// cells; measured, the 1000-cell run differs from the 5000-cell one by 0.055 % in the first norm). The
// reference runs through this code's 1D cylindrical path (its geometric source is checked against an exact
// radial flow in test_convergence, SourceFlowOrder), so this test checks the 2D planar scheme, level set and
// ghost fluid against it. Norms: relative L1 along the positive x axis, ∫|q − q_ref| / ∫|q_ref| over
// 0 ≤ x ≤ 1, for p also weighted by r and along the diagonal x = y (which the x axis alone would not see: a
// level set or ghost band wrong in y only). Bounds about 1.5 times the values measured (written next to
// each), as written (modified GFM, minmod) at 100² and 200², and with the paper's setting (real GFM, WENO,
// degree 2) at 100²; the difference must fall under refinement by at least 1.4 (measured 1.87).
TEST(FreeField2d, AlongTheAxisAgreesWith1DCylindricalBubble) {
    auto ref = fluid::make_solver(CaseFile::load(UNDEX_CASES "/bubble_1d_cylindrical.case",
                                                 {"domain.cells_x=1000", "numerics.threads=1"}));
    test::advance(*ref, 1e-4);
    struct Norms {
        double rho, u, p, p_r, p_diag;
    };
    auto run = [&](int n, std::vector<std::string> sets) {
        sets.push_back("domain.cells_x=" + std::to_string(n));
        sets.push_back("domain.cells_y=" + std::to_string(n));
        sets.push_back("numerics.threads=1"); // CTest runs two tests at once on two cores
        auto s = fluid::make_solver(CaseFile::load(UNDEX_CASES "/free_field_2d.case", sets));
        test::advance(*s, 1e-4);
        const Norms e{
            relative_l1(*s, *ref, &fluid::Primitive::rho), relative_l1(*s, *ref, &fluid::Primitive::u),
            relative_l1(*s, *ref, &fluid::Primitive::p), relative_l1(*s, *ref, &fluid::Primitive::p, true),
            relative_l1(*s, *ref, &fluid::Primitive::p, false, true)};
        std::printf("free field %d^2%s vs 1D cylindrical (1000 cells): relative L1 rho %.4f u %.4f p %.4f "
                    "(weighted by r: %.4f; p along x = y: %.4f)\n",
                    n, sets.size() > 3 ? " (paper's setting)" : "", e.rho, e.u, e.p, e.p_r, e.p_diag);
        return e;
    };
    const Norms coarse = run(100, {});
    EXPECT_LE(coarse.rho, 0.013);    // measured 0.0084
    EXPECT_LE(coarse.u, 0.043);      // measured 0.0287
    EXPECT_LE(coarse.p, 0.021);      // measured 0.0142
    EXPECT_LE(coarse.p_r, 0.035);    // measured 0.0234
    EXPECT_LE(coarse.p_diag, 0.020); // measured 0.0134
    const Norms fine = run(200, {});
    EXPECT_LE(fine.rho, 0.0071);   // measured 0.0047
    EXPECT_LE(fine.u, 0.022);      // measured 0.0144
    EXPECT_LE(fine.p, 0.0114);     // measured 0.0076
    EXPECT_LE(fine.p_r, 0.0195);   // measured 0.0130
    EXPECT_LE(fine.p_diag, 0.010); // measured 0.0067
    // Measured ratio coarse / fine 1.87.
    EXPECT_LE(fine.p, coarse.p / 1.4) << "the difference must fall under refinement";
    const Norms paper = run(
        100, {"interface.method=real_gfm", "numerics.limiter=weno", "numerics.degree=2", "numerics.cfl=0.2"});
    EXPECT_LE(paper.rho, 0.042);    // measured 0.0282
    EXPECT_LE(paper.u, 0.157);      // measured 0.1048
    EXPECT_LE(paper.p, 0.073);      // measured 0.0489
    EXPECT_LE(paper.p_r, 0.117);    // measured 0.0781
    EXPECT_LE(paper.p_diag, 0.061); // measured 0.0406
}

// The level set's narrow band (interface.tube_cells, default 20) against the whole mesh (0) on the free
// field at 200² to 1e-4 s, where the bubble (radius 50 cells, growing) is wider than the tube: the cell
// averages agree to 1e-8 of each field's largest value (measured: ρ 1.1e-10, u 3.8e-10, p 1.9e-10). The
// tube changes φ by far less near the interface; what shows in the fields is a cell that changes fluid a
// step earlier or later. With a tube of 12 cells one does (ρ 8e-5, u 6e-4, p 2e-4), so the bound resolves
// the tube's width.
TEST(TwoFluid, NarrowBandAgreesWithTheWholeMeshOnTheFreeField) {
    auto run = [](int tube) {
        auto s = fluid::make_solver(
            CaseFile::load(UNDEX_CASES "/free_field_2d.case",
                           {"domain.cells_x=200", "domain.cells_y=200", "numerics.threads=1",
                            "interface.tube_cells=" + std::to_string(tube)}));
        test::advance(*s, 1e-4);
        return s;
    };
    const auto whole = run(0), band = run(20);
    const auto& m = whole->mesh();
    double diff[4] = {}, scale[4] = {};
    long clamped = 0;
    const std::vector<double> phi = band->level_set();
    for (int j = 0; j < m.ny; ++j)
        for (int i = 0; i < m.nx; ++i) {
            const fluid::Primitive a = whole->cell_average(i, j), b = band->cell_average(i, j);
            const double va[4] = {a.rho, a.u, a.v, a.p}, vb[4] = {b.rho, b.u, b.v, b.p};
            for (int k = 0; k < 4; ++k)
                diff[k] = std::max(diff[k], std::abs(va[k] - vb[k])),
                scale[k] = std::max(scale[k], std::abs(va[k]));
            clamped += std::abs(phi[static_cast<long>(j) * m.nx + i]) == 20 * m.dx;
        }
    std::printf("narrow band against the whole mesh, free field 200^2: rho %.2e u %.2e v %.2e p %.2e of the "
                "largest; %ld of %d cells outside the tube\n",
                diff[0] / scale[0], diff[1] / scale[1], diff[2] / scale[2], diff[3] / scale[3], clamped,
                m.nx * m.ny);
    for (int k = 0; k < 4; ++k)
        EXPECT_LE(diff[k], 1e-8 * scale[k]) << "field " << k;
    EXPECT_GT(clamped, m.nx * m.ny / 2) << "the tube must be narrower than the bubble's surroundings";
}
