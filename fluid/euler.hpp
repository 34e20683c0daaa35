// The compressible Euler equations for any equation of state (eos.hpp): the physical flux and the
// conversions between conserved (ρ, ρu, [ρv,] E) and primitive (ρ, u, v, p) variables, written once and
// used by the scheme, the HLLC flux, the boundary ghosts and the set-up (physics.md §1).
//
// States are read and written through x[v], so that the same code serves a contiguous array (double*),
// a cell's modal coefficients (Strided: variable v at p[v * stride]) and the point-major arrays of the
// scheme's vectorised loops (AtPoint: variable v at a[v][k]; AtLane: a[v][k][w], lane w).
#pragma once
#include "fluid/eos.hpp"
#include "fluid/solver.hpp"

namespace undex::fluid::euler {

// Variable v at p[v * stride].
template <class T> struct Strided {
    T* p;
    int stride;
    T& operator[](int v) const { return p[v * stride]; }
};

// Variable v at a[v][k] of a point-major array a[NV][N].
template <class A> struct AtPoint {
    A& a;
    int k;
    auto& operator[](int v) const { return a[v][k]; }
};
template <class A> AtPoint(A&, int) -> AtPoint<A>;

// Variable v at a[v][k][w] of a point-major array a[NV][N][W] of W cells, one per SIMD lane.
template <class A> struct AtLane {
    A& a;
    int k, w;
    auto& operator[](int v) const { return a[v][k][w]; }
};
template <class A> AtLane(A&, int, int) -> AtLane<A>;

// Physical flux in direction Dir (0: x, 1: y) of the conserved state U with normal velocity un and
// pressure p; NV = 3 (1D) or 4 (2D).
template <int NV, int Dir, class In, class Out> inline void flux(const In& U, double un, double p, Out&& F) {
    constexpr int mn = 1 + Dir; // normal momentum component
    constexpr int E = NV - 1;
    for (int v = 0; v < NV; ++v)
        F[v] = U[v] * un;
    F[mn] += p;
    F[E] += p * un;
}

// Primitive state of a conserved state q in D dimensions (v = 0 in 1D).
template <int D, EquationOfState Eos, class In> inline Primitive to_primitive(const Eos& eos, const In& q) {
    Primitive w;
    w.rho = q[0];
    w.u = q[1] / q[0];
    w.v = D == 2 ? q[2] / q[0] : 0.0;
    w.p = eos.pressure(w.rho, q[D + 1] - 0.5 * w.rho * (w.u * w.u + w.v * w.v));
    return w;
}

// Pressure of a conserved state q alone, from the momenta without forming the velocities (the face and
// positivity loops).
template <int D, EquationOfState Eos, class In> inline double pressure(const Eos& eos, const In& q) {
    double ke = 0;
    for (int d = 0; d < D; ++d)
        ke += q[1 + d] * q[1 + d];
    return eos.pressure(q[0], q[D + 1] - 0.5 * ke / q[0]);
}

// Conserved state q of a primitive state w in D dimensions.
template <int D, EquationOfState Eos, class Out>
inline void to_conserved(const Eos& eos, const Primitive& w, Out&& q) {
    q[0] = w.rho;
    q[1] = w.rho * w.u;
    if constexpr (D == 2) q[2] = w.rho * w.v;
    q[D + 1] = eos.internal_energy(w.rho, w.p) + 0.5 * w.rho * (w.u * w.u + w.v * w.v);
}

} // namespace undex::fluid::euler
