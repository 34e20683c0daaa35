// Eigenvectors of the Euler flux Jacobian in direction Dir, for the characteristic decomposition of the
// WENO limiter (physics.md §3). Written for a stiffened-gas form with Grüneisen coefficient Γ = γ − 1
// (Tait water uses its equivalent stiffened gas); H is taken as a²/Γ + ½|u|² so that L = R⁻¹ exactly.
#pragma once

namespace undex::fluid {

template <int NV> struct Eigenvectors {
    double L[NV][NV]; // rows: left eigenvectors
    double R[NV][NV]; // columns: right eigenvectors
};

// Conserved variables (ρ, ρu, [ρv,] E); waves ordered (un − a, [shear,] entropy, un + a).
template <int NV, int Dir>
inline Eigenvectors<NV> euler_eigenvectors(double rho, const double* vel, double a, double gruneisen) {
    static_assert(NV == 3 || NV == 4);
    constexpr int n = 1 + Dir; // normal momentum component
    constexpr int E = NV - 1;
    Eigenvectors<NV> e{};
    double q2 = 0;
    for (int d = 0; d < NV - 2; ++d)
        q2 += vel[d] * vel[d];
    (void)rho;
    const double un = vel[Dir];
    const double H = a * a / gruneisen + 0.5 * q2;
    const double b1 = gruneisen / (a * a), b2 = 0.5 * q2 * b1;
    const int last = NV - 1, ent = NV - 2;
    // Right eigenvectors (columns).
    for (int k : {0, ent, last}) {
        e.R[0][k] = 1.0;
        for (int d = 0; d < NV - 2; ++d)
            e.R[1 + d][k] = vel[d];
    }
    e.R[n][0] = un - a;
    e.R[E][0] = H - un * a;
    e.R[E][ent] = 0.5 * q2;
    e.R[n][last] = un + a;
    e.R[E][last] = H + un * a;
    // Left eigenvectors (rows).
    e.L[0][0] = 0.5 * (b2 + un / a);
    e.L[ent][0] = 1.0 - b2;
    e.L[last][0] = 0.5 * (b2 - un / a);
    for (int d = 0; d < NV - 2; ++d) {
        e.L[0][1 + d] = -0.5 * b1 * vel[d];
        e.L[ent][1 + d] = b1 * vel[d];
        e.L[last][1 + d] = -0.5 * b1 * vel[d];
    }
    e.L[0][n] -= 0.5 / a;
    e.L[last][n] += 0.5 / a;
    e.L[0][E] = 0.5 * b1;
    e.L[ent][E] = -b1;
    e.L[last][E] = 0.5 * b1;
    if constexpr (NV == 4) {
        constexpr int t = 2 - Dir; // tangential momentum component
        const double ut = vel[1 - Dir];
        e.R[t][1] = 1.0;
        e.R[E][1] = ut;
        e.L[1][0] = -ut;
        e.L[1][t] = 1.0;
    }
    return e;
}

// Barotropic flow (Tait water): p = p(ρ), so the waves un ± a involve (ρ, ρu, ρv) only and E is passive.
// The energy row and column are the identity; this avoids the a⁻² factors of the form above, which make
// the decomposition ill-conditioned where the mixture sound speed of a cavitating cell is tiny.
template <int NV, int Dir> inline Eigenvectors<NV> barotropic_eigenvectors(const double* vel, double a) {
    static_assert(NV == 3 || NV == 4);
    constexpr int n = 1 + Dir, E = NV - 1;
    // Wave order: (un − a, [shear,] passive E, un + a); E sits in slot NV − 2.
    constexpr int pas = NV - 2;
    Eigenvectors<NV> e{};
    const double un = vel[Dir];
    const int lastw = NV - 1;
    for (int k : {0, lastw}) {
        e.R[0][k] = 1.0;
        for (int d = 0; d < NV - 2; ++d)
            e.R[1 + d][k] = vel[d];
    }
    e.R[n][0] = un - a;
    e.R[n][lastw] = un + a;
    e.R[E][pas] = 1.0;
    e.L[pas][E] = 1.0;
    e.L[0][0] = (un + a) / (2 * a);
    e.L[0][n] = -1.0 / (2 * a);
    e.L[lastw][0] = -(un - a) / (2 * a);
    e.L[lastw][n] = 1.0 / (2 * a);
    if constexpr (NV == 4) {
        constexpr int t = 2 - Dir;
        e.R[t][1] = 1.0;
        e.L[1][0] = -vel[1 - Dir];
        e.L[1][t] = 1.0;
    }
    return e;
}

} // namespace undex::fluid
