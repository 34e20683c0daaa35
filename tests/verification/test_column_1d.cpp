// The 1D layered column of the structure solver (solid/column_1d.hpp): wave speeds and reflections,
// energy conservation and balance, inversion, bad layers.
#include "solid/column_1d.hpp"
#include "solid/material_elastic.hpp"
#include "solid/material_foam_1d.hpp"
#include "solid/material_johnson_cook.hpp"

#include "tests/support/peak.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace undex::solid;

namespace {

const double rho = 8000, E = 210e9, nu = 0.28;

struct Pulse {
    std::vector<double> t, s25, s50;
};

// A sin² pressure pulse of amplitude P and duration tau on the front of a 1 m steel bar of 1000 elements.
Pulse run_pulse(Kinematics1D kin, Face1D back, double t_end, double& c_exact) {
    Column1D col({{std::make_shared<Elastic>(rho, E, nu), 1.0, 1000}}, kin);
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
    c_exact = std::sqrt((kin == Kinematics1D::UniaxialStress ? E : lambda + 2 * G) / rho);
    const double P = 1e8, tau = 40 * 1e-3 / c_exact;
    col.set_pressure(0, [=](double t) { return t < tau ? P * std::pow(std::sin(M_PI * t / tau), 2) : 0.0; });
    col.set_face(1, back);
    Pulse r;
    const double dt = 0.9 * col.stable_dt();
    while (col.time() < t_end) {
        col.step(dt);
        r.t.push_back(col.time());
        r.s25.push_back(col.point(249).stress[0]);
        r.s50.push_back(col.point(499).stress[0]);
    }
    return r;
}

} // namespace

// Wave speed from the arrival of the compressive peak at x = 0.25 and 0.5 m. Bound 0.5 %: with 40
// elements per pulse the phase error of lumped-mass central differences is about (kh)²/24 ≈ 0.1 %, and
// the peak times are interpolated well below a time step. Amplitude of the incident peak: within 2 % of P.
TEST(Column1D, PulseTravelsAtTheBarAndConfinedWaveSpeeds) {
    for (auto kin : {Kinematics1D::UniaxialStress, Kinematics1D::UniaxialStrain}) {
        double c = 0;
        const Pulse r = run_pulse(kin, Face1D::Free, 0.7 / 5000, c);
        const Peak p25 = extreme(r.t, r.s25, false, 0, 0.45 / c),
                   p50 = extreme(r.t, r.s50, false, 0, 0.7 / c);
        const double measured = 0.25 / (p50.time - p25.time);
        std::printf("%s: wave speed %.2f m/s (exact %.2f), peak %.4e Pa\n",
                    kin == Kinematics1D::UniaxialStress ? "uniaxial stress" : "uniaxial strain", measured, c,
                    p50.value);
        EXPECT_NEAR(measured, c, 0.005 * c);
        EXPECT_NEAR(p50.value, -1e8, 0.02e8);
    }
}

// Reflection at the back face (x = 1 m), seen at x = 0.5 m: a free end returns the compressive pulse as
// tension, a fixed end as compression, with the incident amplitude (bound 3 %: dispersion after 1.5 m of
// travel) at t ≈ 1.5 m / c + τ/2.
TEST(Column1D, ReflectionSignAtFreeAndFixedEnds) {
    for (auto back : {Face1D::Free, Face1D::Fixed}) {
        double c = 0;
        const Pulse r = run_pulse(Kinematics1D::UniaxialStress, back, 1.8 / 5100, c);
        const bool free = back == Face1D::Free;
        const Peak p = extreme(r.t, r.s50, free, 1.2 / c, 1.8 / c);
        const double tau = 40 * 1e-3 / c;
        std::printf("%s end: reflected peak %.4e Pa at t = %.4e s (expected %.4e s)\n",
                    free ? "free" : "fixed", p.value, p.time, 1.5 / c + tau / 2);
        EXPECT_NEAR(p.value, free ? 1e8 : -1e8, 0.03e8);
        EXPECT_NEAR(p.time, 1.5 / c + tau / 2, 0.005 * 1.5 / c);
    }
}

// Free vibration of a fixed–fixed bar in its first mode (100 elements) over 20 periods: central
// differences conserve a discrete energy whose difference from KE + IE is O((ω Δt)²) ≈ 1e-4 here; bound 1e-3.
TEST(Column1D, ElasticFreeVibrationConservesEnergy) {
    Column1D col({{std::make_shared<Elastic>(rho, E, nu), 1.0, 100}}, Kinematics1D::UniaxialStress);
    col.set_face(0, Face1D::Fixed);
    col.set_face(1, Face1D::Fixed);
    col.set_velocity([](double x) { return std::sin(M_PI * x); });
    const double e0 = col.energies().kinetic, period = 2.0 / std::sqrt(E / rho), dt = 0.9 * col.stable_dt();
    double worst = 0;
    while (col.time() < 20 * period) {
        col.step(dt);
        const auto& en = col.energies();
        worst = std::max(worst, std::abs(en.kinetic + en.internal - e0) / e0);
    }
    std::printf("free vibration, 20 periods: largest relative energy change %.3e\n", worst);
    EXPECT_LT(worst, 1e-3);
}

// A laterally confined steel plate (uniaxial strain) driven plastic by a 5 GPa pressure pulse (Johnson–Cook,
// A = 950 MPa; the Hugoniot elastic limit is A (1 − ν)/(1 − 2ν) ≈ 1.6 GPa): kinetic + internal (elastic +
// plastic) = external work. The discrete balance closes to O(Δt) of the work rate; bound 0.5 %
// of the external work; the plastic work must be a real share of it (> 1 %).
TEST(Column1D, PlasticRunClosesTheEnergyBalance) {
    JohnsonCook::Constants c;
    c.rho = rho, c.E = E, c.nu = nu, c.A = 950e6, c.B = 560e6, c.n = 0.26, c.C = 0.014;
    Column1D col({{std::make_shared<JohnsonCook>(c), 0.1, 200}}, Kinematics1D::UniaxialStrain);
    const double tau = 5e-6;
    col.set_pressure(0, [=](double t) { return t < tau ? 5e9 * std::sin(M_PI * t / tau) : 0.0; });
    const double dt = 0.9 * col.stable_dt();
    while (col.time() < 4e-5)
        col.step(dt);
    const auto& en = col.energies();
    std::printf("plastic plate: W_ext %.4e, KE %.4e, elastic %.4e, plastic %.4e J/m^2, balance error %.3e\n",
                en.external, en.kinetic, en.elastic(), en.plastic, en.balance_error() / en.external);
    EXPECT_LT(std::abs(en.balance_error()), 0.005 * en.external);
    EXPECT_GT(en.plastic, 0.01 * en.external);
}

// The step follows each element's present modulus (MaterialLaw::wave_modulus_at): a foam core (E_lock = 10 E)
// crushed against a fixed back face by 20 MPa (13 times its plateau) steps at the limit of E, l / sqrt(E/ρ),
// while no element can reach densification within a step, and at that of E_lock wherever one has; stepping
// at 0.9 stable_dt() throughout, it crushes through lock-up with the energy balance closed to 1 % of the
// external work (the bound of the plastic run above, for a shock of lock-up). A step from E alone is 2.8
// times the lock-up limit there: the locked elements ring and invert.
TEST(Column1D, StepFollowsTheFoamThroughLockUp) {
    Foam1D::Constants f;
    f.rho = 236, f.E = 1e9, f.sigma_pl = 1.5e6, f.eta = 1e3, f.eps_d = 0.8, f.E_lock = 1e10;
    const int n = 30;
    const double h = 0.025 / n;
    Column1D col({{std::make_shared<Foam1D>(f), 0.025, n, true}}, Kinematics1D::UniaxialStress);
    col.set_pressure(0, [](double) { return 2e7; });
    col.set_face(1, Face1D::Fixed);
    const double c_E = std::sqrt(f.E / f.rho), c_lock = std::sqrt(f.E_lock / f.rho);
    EXPECT_NEAR(col.stable_dt(), h / c_E, 1e-12 * h / c_E);
    int locked_steps = 0;
    while (col.time() < 2e-4) {
        const double dt = col.stable_dt();
        // Every locked element bounds the step by its present length over the lock-up wave speed.
        double lock_limit = 1e300;
        for (size_t e = 0; e < col.element_count(); ++e)
            if (-col.point(e).strain[0] >= f.eps_d) {
                const double l = col.node_x(e + 1) + col.displacement(e + 1) - col.node_x(e) - col.displacement(e);
                lock_limit = std::min(lock_limit, l / c_lock);
            }
        if (lock_limit < 1e300) {
            ++locked_steps;
            ASSERT_LE(dt, lock_limit * (1 + 1e-12)) << "t = " << col.time();
        }
        col.step(0.9 * dt);
    }
    const auto& en = col.energies();
    std::printf("foam through lock-up: %ld steps (%d with a locked element), W_ext %.4e, balance error %.3e\n",
                col.steps(), locked_steps, en.external, en.balance_error() / en.external);
    EXPECT_GT(locked_steps, 100);
    EXPECT_LT(std::abs(en.balance_error()), 0.01 * en.external);
}

// An element that inverts stops the run with a message naming it; bad layers are refused by name.
TEST(Column1D, InversionAndBadLayers) {
    Foam1D::Constants f;
    f.rho = 236, f.E = 1e9, f.sigma_pl = 1.5e6, f.eta = 0, f.eps_d = 0.99, f.E_lock = 1e9;
    Column1D col({{std::make_shared<Foam1D>(f), 0.025, 30}}, Kinematics1D::UniaxialStress);
    col.set_pressure(0, [](double) { return 1e9; });
    col.set_face(1, Face1D::Fixed);
    try {
        const double dt = 0.5 * col.stable_dt();
        for (int k = 0; k < 1000000; ++k)
            col.step(dt);
        FAIL() << "no inversion";
    } catch (const StructureFailure& e) {
        EXPECT_NE(std::string(e.what()).find("element 0"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
    }
    auto steel = std::make_shared<Elastic>(rho, E, nu);
    EXPECT_THROW(Column1D({{steel, 0.0, 10}}, Kinematics1D::UniaxialStress), MaterialError);
    EXPECT_THROW(Column1D({{steel, 0.01, 0}}, Kinematics1D::UniaxialStress), MaterialError);
}

// A fluid on the back face is the mirror image of a fluid on the front: a uniform column wetted at its back
// by a fluid state must move as the same column wetted at its front, mirrored (velocities and displacements
// change sign, pressures do not). Through the Structure interface, as the run loop drives it. Tolerance: the
// two runs sum the same forces in opposite node order, so they agree to round-off (1e-9 relative).
TEST(Column1D, BackFaceFluidMirrorsTheFrontFace) {
    auto steel = std::make_shared<Elastic>(rho, E, nu);
    Column1D front({{steel, 0.01, 20}}, Kinematics1D::UniaxialStrain);
    Column1D back({{steel, 0.01, 20}}, Kinematics1D::UniaxialStrain);
    front.set_wet(0);
    back.set_wet(1);
    Structure& f = front;
    Structure& b = back;
    ASSERT_EQ(f.wet_nodes().size(), 1u);
    ASSERT_EQ(b.wet_nodes().size(), 1u);
    EXPECT_EQ(f.wet_nodes()[0].normal_x, 1.0);
    EXPECT_EQ(b.wet_nodes()[0].normal_x, -1.0);
    EXPECT_NEAR(b.wet_nodes()[0].x, 0.01, 1e-15); // the back face, at the column's thickness
    const double Z = 1000 * 1500, dt = 0.5 * front.stable_dt();
    const size_t last = back.nodes() - 1;
    for (int n = 0; n < 400; ++n) {
        // An incoming compression wave in the fluid: the normal velocity u_L points into the structure.
        const FluidCharacteristic fc{1e7, 2.0, Z, 0.0, -1e5};
        const auto wf = f.step(dt, std::span(&fc, 1));
        const auto wb = b.step(dt, std::span(&fc, 1));
        ASSERT_EQ(wf.size(), 1u);
        ASSERT_NEAR(wb[0].p_I, wf[0].p_I, 1e-9 * std::abs(wf[0].p_I));
        ASSERT_NEAR(wb[0].u_I, wf[0].u_I, 1e-9 * std::abs(wf[0].u_I) + 1e-15);
        ASSERT_NEAR(back.velocity(last), -front.velocity(0), 1e-9 * std::abs(front.velocity(0)) + 1e-15);
        ASSERT_NEAR(back.displacement(last), -front.displacement(0),
                    1e-9 * std::abs(front.displacement(0)) + 1e-18);
        ASSERT_NEAR(b.wet_nodes()[0].velocity, f.wet_nodes()[0].velocity,
                    1e-9 * std::abs(f.wet_nodes()[0].velocity) + 1e-15);
    }
    EXPECT_GT(front.velocity(0), 0.1); // the front face was pushed into the column
    // The external work of the fluid is the same on both faces and closes the energy balance.
    EXPECT_NEAR(back.energies().external, front.energies().external, 1e-9 * front.energies().external);
    EXPECT_LT(std::abs(back.energies().balance_error()), 1e-3 * back.energies().external);
    // The number of fluid states must match the wet nodes.
    EXPECT_THROW(f.step(dt, {}), std::invalid_argument);
}

// A uniform column wetted on both faces, by fluid A in front and fluid B behind, is the mirror image of the
// same column with B in front and A behind: wet nodes, interface pressures and velocities swap faces, the
// velocities change sign. With A = B it is loaded symmetrically and its middle node stays at rest.
// Tolerance: round-off of sums taken in opposite node order (1e-9 relative).
TEST(Column1D, BothFacesWetMirrorWhenTheirFluidsSwap) {
    const FluidCharacteristic A{1e7, 2.0, 1.5e6, 0.0, -1e5}, B{4e6, 0.5, 1.2e6, 0.0, -1e5};
    for (const bool same : {false, true}) {
        const FluidCharacteristic ab[2] = {A, same ? A : B}, ba[2] = {same ? A : B, A};
        Column1D c1({{std::make_shared<Elastic>(rho, E, nu), 0.01, 20}}, Kinematics1D::UniaxialStrain);
        Column1D c2({{std::make_shared<Elastic>(rho, E, nu), 0.01, 20}}, Kinematics1D::UniaxialStrain);
        for (Column1D* c : {&c1, &c2})
            c->set_wet(0), c->set_wet(1);
        Structure &s1 = c1, &s2 = c2;
        ASSERT_EQ(s1.wet_nodes().size(), 2u);
        const double dt = 0.5 * c1.stable_dt();
        const size_t last = c1.nodes() - 1, middle = last / 2;
        double most_work = 0;
        for (int n = 0; n < 300; ++n) {
            const auto w1 = s1.step(dt, ab);
            const auto w2 = s2.step(dt, ba);
            ASSERT_EQ(w1.size(), 2u);
            // Front first, then back; u_I along each face's normal is the node's velocity at the half step.
            ASSERT_EQ(w1[0].u_I, c1.velocity(0));
            ASSERT_EQ(w1[1].u_I, -c1.velocity(last));
            for (int k = 0; k < 2; ++k) {
                ASSERT_NEAR(w2[1 - k].p_I, w1[k].p_I, 1e-9 * std::abs(w1[k].p_I));
                ASSERT_NEAR(w2[1 - k].u_I, w1[k].u_I, 1e-9 * std::abs(w1[k].u_I) + 1e-15);
            }
            ASSERT_NEAR(c2.velocity(last), -c1.velocity(0), 1e-9 * std::abs(c1.velocity(0)) + 1e-15);
            ASSERT_NEAR(c2.velocity(0), -c1.velocity(last), 1e-9 * std::abs(c1.velocity(last)) + 1e-15);
            if (same) {
                ASSERT_NEAR(c1.velocity(middle), 0.0, 1e-9 * std::abs(c1.velocity(0)) + 1e-15);
            }
            if (n == 5) {
                EXPECT_GT(c1.velocity(0), 0.1); // both faces pushed in
                EXPECT_LT(c1.velocity(last), -0.01);
            }
            most_work = std::max(most_work, c1.energies().external);
        }
        // The squeezed column gives work back to the fluids, so the balance is measured against the most
        // work done: the O(Δt²) error of central differences under a sudden load, below 1 % of it.
        EXPECT_LT(std::abs(c1.energies().balance_error()), 1e-2 * most_work);
    }
}
