// HLLC numerical flux (Toro, Spruce and Speares 1994) for one equation of state, in direction Dir
// (0: x, 1: y). Wave speeds: Davis estimates with each side's own sound speed (physics.md §3). For
// barotropic water the energy component is carried but plays no part in the pressure.
#pragma once
#include "fluid/eos.hpp"
#include "fluid/euler.hpp"

#include <algorithm>
#include <cmath>

namespace undex::fluid {

// Conserved (ρ, ρu, [ρv,] E) with NV = 3 (1D) or 4 (2D). p is supplied by the caller.
template <int NV, int Dir, EquationOfState Eos>
inline void hllc_flux(const Eos& eos, const double* UL, double pL, const double* UR, double pR, double* F) {
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

    if (!(Ss > SL && Ss < SR)) {
        // Star speed outside the wave fan (near-vacuum or a very soft cavitating mixture, where the
        // estimate above is ill-conditioned): use the positivity-preserving HLL flux instead.
        double FL[NV], FR[NV];
        euler::flux<NV, Dir>(UL, unL, pL, FL);
        euler::flux<NV, Dir>(UR, unR, pR, FR);
        if (SL >= 0.0)
            for (int v = 0; v < NV; ++v)
                F[v] = FL[v];
        else if (SR <= 0.0)
            for (int v = 0; v < NV; ++v)
                F[v] = FR[v];
        else
            for (int v = 0; v < NV; ++v)
                F[v] = (SR * FL[v] - SL * FR[v] + SL * SR * (UR[v] - UL[v])) / (SR - SL);
    } else if (SL >= 0.0) {
        euler::flux<NV, Dir>(UL, unL, pL, F);
    } else if (SR <= 0.0) {
        euler::flux<NV, Dir>(UR, unR, pR, F);
    } else {
        // F*_K = F_K + S_K (U*_K − U_K) of the star state on side K (left: UL, SL, mL).
        auto star = [&](const double* U, double un, double p, double S, double m, double* out) {
            euler::flux<NV, Dir>(U, un, p, out);
            const double r = U[0];
            const double f = m / (S - Ss); // ρ* of this side's star state
            double Us[NV];
            for (int v = 0; v < NV; ++v)
                Us[v] = f * U[v] / r;
            Us[0] = f;
            Us[mn] = f * Ss;
            Us[E] = f * (U[E] / r + (Ss - un) * (Ss + p / m));
            for (int v = 0; v < NV; ++v)
                out[v] += S * (Us[v] - U[v]);
        };
        if (Ss > 0.0) {
            star(UL, unL, pL, SL, mL, F);
        } else if (Ss < 0.0) {
            star(UR, unR, pR, SR, mR, F);
        } else {
            // S* = 0 (a contact at rest, e.g. a fluid at rest): both star fluxes agree but round differently;
            // their mean keeps mirror-image faces exact mirror images.
            double FL[NV], FR[NV];
            star(UL, unL, pL, SL, mL, FL);
            star(UR, unR, pR, SR, mR, FR);
            for (int v = 0; v < NV; ++v)
                F[v] = 0.5 * (FL[v] + FR[v]);
        }
    }
}

} // namespace undex::fluid
