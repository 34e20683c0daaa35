// Cost of one mixture pressure solve, CavitationModel::pressure(ρ) (fluid/cavitation.hpp), over the whole
// mixture range: densities of pressures from p_cav down to 1e-3 Pa, 1 % apart, each solved 200 times.
// Built and run by tests/bench/cavitation_solve.sh, which can also build it against another commit's header.
#include "fluid/cavitation.hpp"
#include <chrono>
#include <cstdio>
#include <vector>

int main() {
    undex::fluid::CavitationModel model;
    model.finalize();
    std::vector<double> rho;
    for (double p = model.p_cav * (1 - 1e-9); p > 1e-3; p /= 1.01) rho.push_back(model.mixture_density(p));
    constexpr int repeats = 200;
    double sum = 0; // printed, so that the solves are not optimised away
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < repeats; ++r)
        for (double x : rho) sum += model.pressure(x * (1 + 1e-15 * r));
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%.1f ns per solve (%zu densities x %d; checksum %.6e)\n", wall / (repeats * rho.size()) * 1e9,
                rho.size(), repeats, sum);
}
