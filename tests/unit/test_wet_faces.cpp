// The fluid's view of the structure's wet faces (fluid/wet_faces.hpp): area vectors and normals against the
// closed forms of docs/protocol.md, signed distances against plane geometry, and the geometric term of the
// impedance relation against its formula.
#include "fluid/wet_faces.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace undex::fluid;

namespace {

// A straight face of n nodes from (x0, y0) to (x1, y1), normal given by (nx, ny).
WetFaces line(int n, double x0, double y0, double x1, double y1, double nx, double ny, int alpha) {
    std::vector<int> face(n, 0);
    std::vector<double> x(n), y(n), vx(n, nx), vy(n, ny);
    for (int k = 0; k < n; ++k)
        x[k] = x0 + (x1 - x0) * k / (n - 1), y[k] = y0 + (y1 - y0) * k / (n - 1);
    return WetFaces(face, x, y, vx, vy, alpha);
}

} // namespace

// Plane strain: each node gets half of each segment it touches (ends L/2, inside L), the normal is the
// face's, whichever way the nodes run.
TEST(WetFaces, PlaneStrainAreasAreHalfSegments) {
    const WetFaces w = line(5, 0, 1, 2, 1, 0, 1, 0); // segments of 0.5, normal +y
    EXPECT_NEAR(w.area(0), 0.25, 1e-15);
    EXPECT_NEAR(w.area(2), 0.5, 1e-15);
    EXPECT_NEAR(w.area(4), 0.25, 1e-15);
    for (int k = 0; k < 5; ++k) {
        EXPECT_NEAR(w.normal(k)[0], 0.0, 1e-15);
        EXPECT_NEAR(w.normal(k)[1], 1.0, 1e-15);
    }
    const WetFaces down = line(5, 0, 1, 2, 1, 0, -1, 0); // the same nodes, the structure below
    EXPECT_NEAR(down.normal(2)[1], -1.0, 1e-15);
}

// Axisymmetric, per radian: ∫ N_k r ds over a segment from r_a to r_b is L (2 r_a + r_b) / 6 for node a;
// a node on the axis still gets L r_b / 6 > 0, and the areas sum to ∫ r ds = (R² − 0) / 2.
TEST(WetFaces, AxisymmetricAreasAreIntegralsOfNr) {
    const double R = 3.0;
    const int n = 7; // segments of 0.5
    const WetFaces w = line(n, 0, 2, R, 2, 0, 1, 1);
    EXPECT_NEAR(w.area(0), 0.5 * 0.5 / 6, 1e-15); // L r_1 / 6
    EXPECT_NEAR(w.area(1), 0.5 * (0 + 2 * 0.5) / 6 + 0.5 * (2 * 0.5 + 1.0) / 6, 1e-15);
    EXPECT_NEAR(w.area(n - 1), 0.5 * (2.5 + 2 * 3.0) / 6, 1e-15);
    double sum = 0;
    for (int k = 0; k < n; ++k)
        sum += w.area(k);
    EXPECT_NEAR(sum, R * R / 2, 1e-13);
}

// A bent face: the area vector of the corner node adds its two half segments as vectors, so its normal is
// the bisector and its area |L/2 n1 + L/2 n2|.
TEST(WetFaces, CornerNodeAddsItsSegmentsAsVectors) {
    const WetFaces w({0, 0, 0}, {-1, 0, 1}, {1, 0, 1}, {0, 0, 0}, {1, 1, 1}, 0); // a V, structure above
    const double L = std::sqrt(2.0);
    const double n1[2] = {1 / L, 1 / L}, n2[2] = {-1 / L, 1 / L}; // segment normals into the structure
    EXPECT_NEAR(w.area(1), std::hypot(L / 2 * (n1[0] + n2[0]), L / 2 * (n1[1] + n2[1])), 1e-15);
    EXPECT_NEAR(w.normal(1)[0], 0.0, 1e-15);
    EXPECT_NEAR(w.normal(1)[1], 1.0, 1e-15);
    EXPECT_NEAR(w.normal(0)[0], n1[0], 1e-15);
    // The corner normal that signs distances to the node: the bisector too.
    EXPECT_NEAR(w.corner_normal(1)[0], 0.0, 1e-15);
    EXPECT_NEAR(w.corner_normal(1)[1], 1.0, 1e-15);
}

// Signed distances of points around a tilted face against plane geometry; beyond an end, the distance to
// the end node.
TEST(WetFaces, SignedDistanceToATiltedFace) {
    const double c = std::cos(0.5), s = std::sin(0.5);
    const WetFaces w = line(11, 0, 0, 2 * c, 2 * s, -s, c, 0); // normal (−sin, cos): structure on the left
    auto phi = [&](double px, double py) {
        ClosestPoint best;
        for (int a = 0; a + 1 < w.nodes(); ++a) {
            const ClosestPoint cp = w.to_segment(a, px, py);
            if (cp.distance < best.distance) best = cp;
        }
        return w.signed_distance(best, px, py);
    };
    // A point at arc length 0.77 along the face, 0.3 off it on either side.
    const double bx = 0.77 * c, by = 0.77 * s;
    EXPECT_NEAR(phi(bx - 0.3 * s, by + 0.3 * c), 0.3, 1e-14);
    EXPECT_NEAR(phi(bx + 0.3 * s, by - 0.3 * c), -0.3, 1e-14);
    // Beyond the far end, on the structure's side: the distance to the end node.
    const double ex = 2 * c + 0.4 * c - 0.1 * s, ey = 2 * s + 0.4 * s + 0.1 * c;
    EXPECT_NEAR(phi(ex, ey), std::hypot(0.4, 0.1), 1e-14);
    // With rays (the fluid's use), the face continues along its end segments: the distance to the line.
    ClosestPoint ray;
    for (int a = 0; a + 1 < w.nodes(); ++a) {
        const ClosestPoint cp = w.to_segment(a, ex, ey, true);
        if (cp.distance < ray.distance) ray = cp;
    }
    EXPECT_NEAR(w.signed_distance(ray, ex, ey), 0.1, 1e-14);
    EXPECT_GT(ray.t, 1.0);
    const double bx2 = -0.3 * c + 0.2 * s, by2 = -0.3 * s - 0.2 * c; // before the first node, fluid side
    ClosestPoint back;
    for (int a = 0; a + 1 < w.nodes(); ++a) {
        const ClosestPoint cp = w.to_segment(a, bx2, by2, true);
        if (cp.distance < back.distance) back = cp;
    }
    EXPECT_NEAR(w.signed_distance(back, bx2, by2), -0.2, 1e-14);
}

TEST(WetFaces, NodesThatCoincideAreRefused) {
    EXPECT_THROW(WetFaces({0, 0, 0}, {0, 1, 1}, {0, 0, 0}, {0, 0, 0}, {1, 1, 1}, 0), std::invalid_argument);
    EXPECT_THROW(WetFaces({0, 0, 1}, {0, 1, 2}, {0, 0, 0}, {0, 0, 0}, {1, 1, 1}, 0), std::invalid_argument);
}

// The geometric term α Δt ρ a² u_r / r (physics.md §5), dropped within axis_band of the axis.
TEST(WetFaces, GeometricTermFollowsItsFormula) {
    const double dt = 1e-7, rho = 1020, a = 1450, u = -3.5, r = 0.4;
    EXPECT_DOUBLE_EQ(geometric_term(1, dt, rho, a, u, r), 1 * dt * rho * a * a * u / r);
    EXPECT_DOUBLE_EQ(geometric_term(2, dt, rho, a, u, r), 2 * dt * rho * a * a * u / r);
    EXPECT_EQ(geometric_term(0, dt, rho, a, u, r), 0.0);
    EXPECT_EQ(geometric_term(1, dt, rho, a, u, 0.004, 0.005), 0.0);
    EXPECT_DOUBLE_EQ(geometric_term(1, dt, rho, a, u, 0.006, 0.005), dt * rho * a * a * u / 0.006);
}
