// Material laws of the structure (physics.md §6): one stress update per integration point, small strain,
// rate form. Each law is one unit behind this interface.
// Voigt order: xx, yy, zz, xy, yz, zx; strain increments carry engineering shear (γ = 2ε), stresses the
// tensor components. Plane strain and axisymmetric elements use the same six components.
#pragma once
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace undex::solid {

using Voigt = std::array<double, 6>;

// History of one integration point.
struct PointState {
    Voigt stress{};          // Cauchy stress
    Voigt strain{};          // total strain (engineering shear)
    Voigt plastic_strain{};  // plastic strain (engineering shear)
    double peeq = 0;         // equivalent plastic strain (ε̂_p for the foam laws)
    double peeq_rate = 0;    // its rate over the last increment
    double plastic_work = 0; // plastic work dissipated per unit volume
};

// A constant a law cannot do without, or a value outside its range.
struct MaterialError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// A state the method cannot hold (an inverted element, a non-finite velocity).
struct StructureFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Energies of a structure (per unit area in 1D, per unit depth in plane strain, per radian in axisymmetry),
// accumulated over the run. The internal energy includes the plastic dissipation; the hourglass energy is
// the work of the hourglass forces of one-point quadrilaterals.
//
// A coupled structure's external work is the fluid's, Σ A p_I u_I Δt with u_I the velocity of the half step
// after the load (what the fluid gives up, docs/protocol.md). The central-difference update delivers the
// load's impulse A p_I h at the mean of the half-step velocities around it, A p_I · ½(v⁻ + v⁺) h: the
// difference, `coupling`, is energy the staggered coupling loses (of order Δt, the work of an inelastic
// impulse), kept apart so that the balance measures the integrator.
struct Energies {
    double kinetic = 0, internal = 0, plastic = 0, hourglass = 0, external = 0, coupling = 0;
    double viscous = 0; // the work of the 2D elements' bulk viscosity (solid/plate_2d.hpp), dissipated
    double elastic() const { return internal - plastic; }
    double balance_error() const { return kinetic + internal + viscous + hourglass + coupling - external; }
};

class MaterialLaw {
  public:
    virtual ~MaterialLaw() = default;
    virtual std::string name() const = 0;
    virtual double density() const = 0;
    // Modulus of the fastest dilatational wave, λ̂ + 2μ̂ of physics.md §6 (for uniaxial laws the largest
    // uniaxial modulus), so that the stable time step is L_e / sqrt(wave_modulus / ρ).
    virtual double wave_modulus() const = 0;
    // The modulus of the fastest wave at a point in state s whose axial strain may change by up to
    // strain_step (≥ 0) within the next step: the elastic (unloading) modulus of its present branch, never a
    // plastic tangent (a step from the tangent is unstable on unloading). Laws of one elastic modulus:
    // wave_modulus().
    virtual double wave_modulus_at(const PointState& /*s*/, double /*strain_step*/) const {
        return wave_modulus();
    }
    // Elastic shear modulus G (0 for laws that are uniaxial by construction, which 2D elements refuse).
    virtual double shear_modulus() const = 0;
    // Advances the point by the strain increment de over dt > 0.
    void update(const Voigt& de, double dt, PointState& s) const {
        for (int i = 0; i < 6; ++i)
            s.strain[i] += de[i];
        advance(de, dt, s);
    }

  protected:
    // The law's own update: s.strain already includes de.
    virtual void advance(const Voigt& de, double dt, PointState& s) const = 0;
};

// Isotropic elasticity helpers.
struct Isotropic {
    double E, nu, G, K, lambda;
    Isotropic(double E_, double nu_)
        : E(E_), nu(nu_), G(E_ / (2 * (1 + nu_))), K(E_ / (3 * (1 - 2 * nu_))),
          lambda(E_ * nu_ / ((1 + nu_) * (1 - 2 * nu_))) {}
    // σ += C : de (engineering shear in de).
    void add(const Voigt& de, Voigt& s) const {
        const double tr = de[0] + de[1] + de[2];
        for (int i = 0; i < 3; ++i)
            s[i] += lambda * tr + 2 * G * de[i];
        for (int i = 3; i < 6; ++i)
            s[i] += G * de[i];
    }
    double wave_modulus() const { return lambda + 2 * G; }
};

inline double mean_stress(const Voigt& s) {
    return (s[0] + s[1] + s[2]) / 3;
}
// Von Mises equivalent stress sqrt(3/2 s:s).
inline double von_mises(const Voigt& s) {
    const double m = mean_stress(s);
    const double a = s[0] - m, b = s[1] - m, c = s[2] - m;
    return std::sqrt(1.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

// Root of a function f that falls through zero on [lo, hi] (f(lo) > 0 >= f(hi)), from the guess d: Newton
// with a numerical slope, kept inside the shrinking bracket by bisection. Used by the return mappings, whose
// residual falls monotonically with the plastic increment.
template <class F> double falling_root(F f, double lo, double hi, double d) {
    for (int it = 0; it < 100; ++it) {
        const double v = f(d);
        (v > 0 ? lo : hi) = d;
        const double h = 1e-7 * (d + 1e-12);
        const double slope = (f(d + h) - v) / h;
        double next = slope < 0 ? d - v / slope : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - d) <= 1e-14 * (d + 1e-12) || hi - lo <= 1e-15 * hi) return next;
        d = next;
    }
    return d;
}

inline void require(bool ok, const std::string& what) {
    if (!ok) throw MaterialError(what);
}

} // namespace undex::solid
