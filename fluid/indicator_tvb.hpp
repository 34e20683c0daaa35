// TVB minmod troubled-cell indicator (Cockburn and Shu 1989; Qiu and Shu 2005). A cell is troubled when
// the deviation of its face values from its average is changed by the TVB-modified minmod of the
// neighbouring average differences. Applied to ρ and E in each direction. The TVB threshold is made
// scale-free: |ũ| ≤ M (Δx/L)² |ū|, with L the domain length in that direction.
#pragma once
#include <cmath>

namespace undex::fluid {

inline double minmod3(double a, double b, double c) {
    if (a > 0 && b > 0 && c > 0) return std::fmin(a, std::fmin(b, c));
    if (a < 0 && b < 0 && c < 0) return std::fmax(a, std::fmax(b, c));
    return 0.0;
}

// True when the face deviation `dev` (u_face − ū, signed outward) is modified by the minmod of the
// forward and backward average differences.
inline bool tvb_modifies(double dev, double forward, double backward, double threshold) {
    if (std::abs(dev) <= threshold) return false;
    const double m = minmod3(dev, forward, backward);
    return std::abs(m - dev) > 1e-12 * (std::abs(dev) + std::abs(m));
}

} // namespace undex::fluid
