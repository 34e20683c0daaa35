// HLLC numerical flux (Toro, Spruce and Speares 1994) for one equation of state, in direction Dir
// (0: x, 1: y). Wave speeds: Davis estimates with each side's own sound speed (physics.md §3). For
// barotropic water the energy component is carried but plays no part in the pressure.
#pragma once
#include "fluid/eos.hpp"
#include "fluid/euler.hpp"

#include <algorithm>
#include <cmath>

namespace undex::fluid {

// Conserved (ρ, ρu, [ρv,] E) with NV = 3 (1D) or 4 (2D), read and written through [v] (double* or
// euler::Strided). p is supplied by the caller. Select = true computes every candidate flux and picks one
// without branching, so that a loop over faces vectorises; the flux is the same to the last bit.
template <int NV, int Dir, bool Select = false, EquationOfState Eos, class In, class Out>
inline void hllc_flux(const Eos& eos, const In& UL, double pL, const In& UR, double pR, Out&& F) {
    constexpr int mn = 1 + Dir; // normal momentum component
    constexpr int E = NV - 1;
    const double rL = UL[0], rR = UR[0];
    const double unL = UL[mn] / rL, unR = UR[mn] / rR;
    const double aL = eos.sound_speed(rL, pL), aR = eos.sound_speed(rR, pR);
    const double SL = std::min(unL - aL, unR - aR);
    const double SR = std::max(unL + aL, unR + aR);
    const double mL = rL * (SL - unL), mR = rR * (SR - unR);
    // Grouped so that the mirror image (left and right swapped, normal velocities negated) gives exactly −S*.
    const double Ss = ((pR - pL) + (unL * mL - unR * mR)) / (mL - mR);
    // Star speed outside the wave fan (near-vacuum or a very soft cavitating mixture, where the estimate
    // above is ill-conditioned): the positivity-preserving HLL flux instead.
    // (Both comparisons are evaluated, without a branch between them.)
    const bool hll = !((Ss > SL) & (Ss < SR));

    // The HLL flux from the two physical fluxes.
    auto hll_flux = [&](const double* FL, const double* FR, double* out) {
        for (int v = 0; v < NV; ++v)
            out[v] = (SR * FL[v] - SL * FR[v] + SL * SR * (UR[v] - UL[v])) / (SR - SL);
    };
    // F*_K = F_K + S_K (U*_K − U_K) of the star state on side K (left: UL, SL, mL) from its flux FK.
    auto star = [&](const In& U, double un, double p, double S, double m, const double* FK, double* out) {
        const double r = U[0];
        const double f = m / (S - Ss); // ρ* of this side's star state
        double Us[NV];
        for (int v = 0; v < NV; ++v)
            Us[v] = f * U[v] / r;
        Us[0] = f;
        Us[mn] = f * Ss;
        Us[E] = f * (U[E] / r + (Ss - un) * (Ss + p / m));
        for (int v = 0; v < NV; ++v)
            out[v] = FK[v] + S * (Us[v] - U[v]);
    };
    // S* = 0 (a contact at rest, e.g. a fluid at rest): both star fluxes agree but round differently; their
    // mean keeps mirror-image faces exact mirror images.
    auto mean = [](const double* a, const double* b, double* out) {
        for (int v = 0; v < NV; ++v)
            out[v] = 0.5 * (a[v] + b[v]);
    };
    double FL[NV], FR[NV];
    euler::flux<NV, Dir>(UL, unL, pL, FL);
    euler::flux<NV, Dir>(UR, unR, pR, FR);
    if constexpr (Select) {
        double H[NV], SsL[NV], SsR[NV], M[NV];
        hll_flux(FL, FR, H);
        star(UL, unL, pL, SL, mL, FL, SsL);
        star(UR, unR, pR, SR, mR, FR, SsR);
        mean(SsL, SsR, M);
        // The choices of the branches below, the first that holds winning (two-way selects, which the
        // compiler turns into blends).
        for (int v = 0; v < NV; ++v) {
            double r = M[v];
            r = Ss < 0.0 ? SsR[v] : r;
            r = Ss > 0.0 ? SsL[v] : r;
            r = hll ? H[v] : r;
            r = SR <= 0.0 ? FR[v] : r;
            r = SL >= 0.0 ? FL[v] : r;
            F[v] = r;
        }
    } else {
        double out[NV];
        if (SL >= 0.0)
            std::copy_n(FL, NV, out);
        else if (SR <= 0.0)
            std::copy_n(FR, NV, out);
        else if (hll)
            hll_flux(FL, FR, out);
        else if (Ss > 0.0)
            star(UL, unL, pL, SL, mL, FL, out);
        else if (Ss < 0.0)
            star(UR, unR, pR, SR, mR, FR, out);
        else {
            double a[NV], b[NV];
            star(UL, unL, pL, SL, mL, FL, a);
            star(UR, unR, pR, SR, mR, FR, b);
            mean(a, b, out);
        }
        for (int v = 0; v < NV; ++v)
            F[v] = out[v];
    }
}

} // namespace undex::fluid
