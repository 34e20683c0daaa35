// Runs case 4.1 (or any variant of it given by --set overrides) in process and prints its errors against
// the exact solution of its water model, and the wall time of the time stepping, as one CSV line:
//   degree,cells,water,wall_s,l1_rho,l1_u,l1_p,l1_p_rel,p_star,shock_err_cells,interface_err_cells,head_err_cells
// Usage: undex_1d_error CASE [--set key=value ...] [--bins N] [--exact CSV]
// --exact CSV writes the exact solution of the case's water model at its end time (x,rho,u,p, 4000 points)
// and stops without running the case.
// --bins N also prints, to standard error, the share of L1(p)/p* from each of N equal bins of [0, 1].
#include "case.pb.h"
#include "undex_1d.hpp"

#include <cstdio>
#include <iostream>
#include <omp.h>

static double e_pstar(const exact::Solution& ex) {
    return ex.p_star();
}

int main(int argc, char** argv) {
    try {
        if (argc < 2) {
            std::cerr << "usage: undex_1d_error CASE [--set key=value ...]\n";
            return 64;
        }
        std::vector<std::string> sets;
        int bins = 0;
        std::string exact_csv;
        for (int k = 2; k < argc; ++k) {
            const std::string a = argv[k];
            if (a == "--set" && k + 1 < argc)
                sets.push_back(argv[++k]);
            else if (a == "--bins" && k + 1 < argc)
                bins = std::stoi(argv[++k]);
            else if (a == "--exact" && k + 1 < argc)
                exact_csv = argv[++k];
            else
                throw std::invalid_argument("unknown argument '" + a + "'");
        }
        auto cf = undex::CaseFile::load(argv[1], sets);
        const auto& c = cf.get();
        if (c.numerics().threads() > 0) omp_set_num_threads(c.numerics().threads());
        auto s = undex::fluid::make_solver(cf);
        bool sg = false;
        for (const auto& m : c.materials())
            sg |= m.has_tait() && m.tait().as_stiffened_gas();
        const double t = c.end_time();
        if (!exact_csv.empty()) {
            const auto ex = undex::test::undex_1d_exact(sg);
            std::FILE* f = std::fopen(exact_csv.c_str(), "w");
            if (!f) throw std::runtime_error(exact_csv + ": cannot write");
            std::fprintf(f, "x,rho,u,p\n");
            for (int k = 0; k < 4000; ++k) {
                const double x = (k + 0.5) / 4000;
                const auto w = ex.sample((x - 0.5) / t);
                std::fprintf(f, "%.9g,%.12g,%.12g,%.12g\n", x, w.rho, w.u, w.p);
            }
            std::fclose(f);
            return 0;
        }
        const double wall = undex::test::advance(*s, t);
        const auto ex = undex::test::undex_1d_exact(sg);
        const auto e = undex::test::undex_1d_errors(*s, ex, 0.5, t);
        std::printf("%d,%d,%s,%.4f,%.4e,%.4e,%.4e,%.4e,%.6e,%.3f,%.3f,%.3f\n", s->degree(), s->mesh().nx,
                    sg ? "stiffened_gas" : "tait", wall, e.l1_rho, e.l1_u, e.l1_p, e.l1_p / e.p_star,
                    e.p_star, (e.shock - e.shock_exact) / e.dx, (e.interface - e.interface_exact) / e.dx,
                    (e.head - e.head_exact) / e.dx);
        if (bins > 0) {
            const auto& m = s->mesh();
            std::vector<double> share(bins, 0.0);
            const int n = m.nx * 8;
            for (int k = 0; k < n; ++k) {
                const double x = m.x_min + (k + 0.5) * (m.x_max - m.x_min) / n;
                const double e =
                    std::abs(s->evaluate(x, 0).p - ex.sample((x - 0.5) / t).p) / (n * e_pstar(ex));
                share[std::min(bins - 1, static_cast<int>((x - m.x_min) / (m.x_max - m.x_min) * bins))] += e;
            }
            for (int b = 0; b < bins; ++b)
                std::fprintf(stderr, "x in [%.3f, %.3f): L1(p)/p* %.3e\n",
                             m.x_min + (m.x_max - m.x_min) * b / bins,
                             m.x_min + (m.x_max - m.x_min) * (b + 1) / bins, share[b]);
        }
        return 0;
    } catch (const std::exception& ex) {
        std::cerr << "undex_1d_error: " << ex.what() << "\n";
        return 1;
    }
}
