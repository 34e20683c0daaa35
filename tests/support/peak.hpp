// The extreme of a sampled time series, located between samples (used by the structure wave tests).
#pragma once
#include <cstddef>
#include <vector>

struct Peak {
    double time, value;
};

// Time and value of the largest (maximum) or smallest sample of s in [t0, t1], refined by the parabola
// through the extreme sample and its neighbours.
inline Peak extreme(const std::vector<double>& t, const std::vector<double>& s, bool maximum, double t0,
                    double t1) {
    std::size_t best = 0;
    bool found = false;
    for (std::size_t k = 1; k + 1 < s.size(); ++k)
        if (t[k] >= t0 && t[k] <= t1 && (!found || (maximum ? s[k] > s[best] : s[k] < s[best])))
            best = k, found = true;
    const double a = s[best - 1], b = s[best], c = s[best + 1], den = a - 2 * b + c;
    const double off = den != 0 ? 0.5 * (a - c) / den : 0.0;
    return {t[best] + off * (t[best + 1] - t[best - 1]) / 2, b - 0.25 * (a - c) * off};
}
