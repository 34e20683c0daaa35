// The 2D quadrilaterals of the structure solver (solid/plate_2d.hpp): patch test, plane-strain wave speed
// and reflections, the clamped circular plate against the small-deflection plate solution, energy
// conservation and balance, hourglass energy, inversion.
#include "material_elastic.hpp"
#include "material_johnson_cook.hpp"
#include "plate_2d.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace undex::solid;

namespace {

const double rho = 8000, E = 210e9, nu = 0.3;

std::shared_ptr<const MaterialLaw> steel() {
    return std::make_shared<Elastic>(rho, E, nu);
}

// The five-element patch of MacNeal and Harder (1985): a 0.24 × 0.12 rectangle with four distorted
// interior nodes.
QuadMesh patch() {
    QuadMesh m;
    m.x = {0, 0.24, 0.24, 0, 0.04, 0.18, 0.16, 0.08};
    m.y = {0, 0, 0.12, 0.12, 0.02, 0.03, 0.08, 0.08};
    m.quads = {{0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};
    m.law = {0, 0, 0, 0, 0};
    return m;
}

} // namespace

// Patch test in plane strain: the outer nodes move with a uniform strain rate, the interior nodes are free.
// A linear velocity field needs no force at the interior nodes (the element's gradient is exact for linear
// fields and the hourglass vectors are orthogonal to them), so the interior nodes must follow the field and
// every element must carry the same stress. Bounds: 1e-9 relative, round-off over 200 steps.
TEST(Plate2D, PatchTestUniformStrainOnADistortedMesh) {
    Plate2D plate(patch(), {steel()}, Plane::Strain);
    const double exx = 0.3, eyy = -0.2, gxy = 0.5; // strain rates (1/s)
    for (size_t i = 0; i < plate.nodes(); ++i) {
        const double x = plate.node_x(i), y = plate.node_y(i);
        plate.set_velocity(i, exx * x + 0.5 * gxy * y, eyy * y + 0.5 * gxy * x);
        if (i < 4) plate.constrain(i, true, true);
    }
    const double dt = 0.5 * plate.stable_dt();
    for (int k = 0; k < 200; ++k)
        plate.step(dt);
    const double t = plate.time();
    double umax = 0, err = 0;
    for (size_t i = 4; i < plate.nodes(); ++i) {
        const double x = plate.node_x(i), y = plate.node_y(i);
        const double ux = t * (exx * x + 0.5 * gxy * y), uy = t * (eyy * y + 0.5 * gxy * x);
        umax = std::max(umax, std::hypot(ux, uy));
        err = std::max(err, std::hypot(plate.ux(i) - ux, plate.uy(i) - uy));
    }
    const Voigt& s0 = plate.point(0).stress;
    double serr = 0;
    for (size_t e = 1; e < plate.element_count(); ++e)
        for (int k = 0; k < 4; ++k)
            serr = std::max(serr, std::abs(plate.point(e).stress[k] - s0[k]));
    std::printf("patch: interior displacement error %.2e of %.2e m; stress spread %.2e Pa of %.3e Pa\n",
                err, umax, serr, std::abs(s0[0]));
    EXPECT_LT(err, 1e-9 * umax);
    EXPECT_LT(serr, 1e-9 * std::abs(s0[0]));
    for (size_t e = 0; e < plate.element_count(); ++e)
        EXPECT_LT(plate.hourglass_energy(e), 1e-18 * plate.energies().internal);
    // The stress is the elastic response to the accumulated strain (small strain: bound 1e-3, the strain
    // itself being 1e-4 and the rotation zero).
    const double G = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    EXPECT_NEAR(s0[0], (lambda * (exx + eyy) + 2 * G * exx) * t, 1e-3 * std::abs(s0[0]));
    EXPECT_NEAR(s0[3], G * gxy * t, 1e-3 * std::abs(s0[3]));
}

namespace {

// A clamped circular steel plate, radius a = 1 m, thickness h = 0.025 m (a/h = 40), axisymmetric, nt
// square elements through the thickness; uniform pressure q on the front face applied as ½(1 − cos) over
// two periods of the fundamental mode of plate theory, then held for one period, over which the centre
// deflection of the mid-surface is averaged (the period average removes the fundamental oscillation that
// the ramp leaves).
struct PlateRun {
    double w_mean = 0, w0 = 0, hourglass_share = 0, balance = 0, period = 0;
    long element_updates = 0;
};

PlateRun clamped_plate(int nt, double hourglass = 1.0) {
    const double a = 1.0, h = 0.025, q = 5000;
    const int nr = nt * 40;
    LayeredPlate lp = layered_plate(0, a, nr, {h}, {nt});
    Plate2D plate(lp.mesh, {steel()}, Plane::Axisymmetric, hourglass);
    for (int j = 0; j <= lp.ny; ++j) {
        plate.constrain(lp.node(0, j), true, false); // axis: u_r = 0
        plate.constrain(lp.node(nr, j), true, true); // clamped edge
    }
    const double D = E * h * h * h / (12 * (1 - nu * nu));
    PlateRun r;
    r.w0 = q * std::pow(a, 4) / (64 * D);
    r.period = 2 * M_PI / (10.2158 / (a * a) * std::sqrt(D / (rho * h)));
    const double ramp = 2 * r.period;
    std::vector<std::array<int, 2>> front;
    for (int i = 0; i < nr; ++i)
        front.push_back({lp.node(i, 0), lp.node(i + 1, 0)});
    plate.add_pressure(front, [=](double t) { return t < ramp ? 0.5 * q * (1 - std::cos(M_PI * t / ramp)) : q; });
    const double dt = 0.9 * plate.stable_dt();
    const int centre = lp.node(0, nt / 2);
    double sum = 0, time = 0, hg = 0;
    while (plate.time() < ramp + r.period) {
        plate.step(dt);
        if (plate.time() > ramp) {
            sum += plate.uy(centre) * dt, time += dt;
            hg = std::max(hg, plate.energies().hourglass / plate.energies().internal);
        }
    }
    r.w_mean = sum / time;
    r.hourglass_share = hg;
    r.balance = std::abs(plate.energies().balance_error()) / plate.energies().external;
    r.element_updates = plate.steps() * static_cast<long>(plate.element_count());
    return r;
}

} // namespace

// Small-deflection theory: w0 = q a⁴ / (64 D) at the centre. The continuum plate differs from it by the
// shear deflection, (16/5)(h/a)²/(1 − ν) = 0.29 % of w0 for a/h = 40 (Mindlin), and by the 3D clamping of
// the whole edge face. The one-point elements converge at second order in the element size: the error must
// fall at least 3× from 2 to 4 elements through the thickness (4× expected), the Richardson extrapolation
// of the two (order 2) must lie within 1 % of w0 (the shear deflection plus the residual of the period
// average), and 4 elements must be within 3 %.
// Hourglass energy: the hourglass stiffness carries the bending inside each element, which for a linear
// stress profile is 1/nt² of the bending energy; bound 1.5/nt² of the internal energy.
// Energy balance of this elastic run: bound 1e-6 of the external work (round-off and the O(Δt²) error of
// the trapezoidal work of a slowly varying load).
TEST(Plate2D, ClampedCircularPlateConvergesToThePlateSolution) {
    std::vector<double> w;
    double w0 = 0;
    for (int nt : {2, 4}) {
        const PlateRun r = clamped_plate(nt);
        w0 = r.w0;
        w.push_back(r.w_mean);
        std::printf("nt = %d: w = %.5e m, w0 = %.5e m, error %.3f %%, hourglass/internal %.4f, balance %.2e, "
                    "%ld element updates\n",
                    nt, r.w_mean, r.w0, 100 * (r.w_mean / r.w0 - 1), r.hourglass_share, r.balance,
                    r.element_updates);
        EXPECT_LT(r.hourglass_share, 1.5 / (nt * nt));
        EXPECT_LT(r.balance, 1e-6);
    }
    const double e2 = std::abs(w[0] / w0 - 1), e4 = std::abs(w[1] / w0 - 1);
    const double extrapolated = w[1] + (w[1] - w[0]) / 3;
    std::printf("error ratio %.2f (order %.2f); extrapolated %.5e m, %.3f %% from w0\n", e2 / e4,
                std::log2(e2 / e4), extrapolated, 100 * (extrapolated / w0 - 1));
    EXPECT_GT(e2 / e4, 3.0);
    EXPECT_LT(std::abs(extrapolated / w0 - 1), 0.01);
    EXPECT_LT(e4, 0.03);
}
