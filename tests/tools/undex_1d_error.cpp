// Runs a 1D two-material Riemann case (case 4.1, cases/undex_1d.case, or any variant of it given by --set
// overrides) in process and compares it with the exact solution of its own materials and states
// (tests/support/exact_riemann.hpp): the left state is the region at x_min, the right state the region at
// x_max, the initial jump lies at the edge of regions[1] inside the domain. Prints one CSV line:
//   degree,cells,water,wall_s,l1_rho,l1_u,l1_p,l1_p_rel,p_star,shock_err_cells,interface_err_cells,head_err_cells
// (wall_s: the time stepping only; errors as in tests/support/undex_1d.hpp). A run the solver stops prints
//   degree,cells,water,stopped,<message>       and exits with status 2.
// Usage: undex_1d_error CASE [--set key=value ...] [--bins N] [--exact CSV] [--fit-time]
//   --fit-time   ends the run (and its outputs) when the fastest exact wave has covered 80 % of the way to
//                the boundary ahead of it, if that comes before the case's end time (for sweeps of the
//                states);
//   --bins N     also prints, to standard error, the share of L1(p)/p* from each of N equal bins of the
//   domain;
//   --exact CSV  writes the exact solution at the end time (x,rho,u,p, 4000 points) and stops.
#include "proto/case.pb.h"
#include "tests/support/undex_1d.hpp"

#include <cstdio>
#include <iostream>
#include <omp.h>

namespace {

exact::Material material_of(const undex::config::Material& m) {
    if (m.has_stiffened_gas())
        return exact::stiffened_gas(m.stiffened_gas().gamma(), m.stiffened_gas().p_inf());
    const auto& t = m.tait();
    if (t.as_stiffened_gas()) return exact::stiffened_gas(t.gamma(), t.b() - t.a());
    return exact::tait(t.gamma(), t.b(), t.a(), t.rho0());
}

const undex::config::Region& region_at(const undex::config::Case& c, double x) {
    const undex::config::Region* r = &c.regions(0);
    for (const auto& reg : c.regions())
        if (!reg.has_box() || (x >= reg.box().x_min() && x <= reg.box().x_max())) r = &reg;
    return *r;
}

} // namespace

int main(int argc, char** argv) {
    std::string label = "?,?,?";
    try {
        if (argc < 2) {
            std::cerr << "usage: undex_1d_error CASE [--set key=value ...] [--bins N] [--exact CSV]\n";
            return 64;
        }
        std::vector<std::string> sets;
        int bins = 0;
        std::string exact_csv;
        bool fit_time = false;
        for (int k = 2; k < argc; ++k) {
            const std::string a = argv[k];
            if (a == "--set" && k + 1 < argc)
                sets.push_back(argv[++k]);
            else if (a == "--bins" && k + 1 < argc)
                bins = std::stoi(argv[++k]);
            else if (a == "--exact" && k + 1 < argc)
                exact_csv = argv[++k];
            else if (a == "--fit-time")
                fit_time = true;
            else
                throw std::invalid_argument("unknown argument '" + a + "'");
        }
        auto cf = undex::CaseFile::load(argv[1], sets);
        const undex::config::Case c0 = cf.get(); // as given; `cf` may be reloaded with a fitted end time
        const double x_min = c0.domain().x_min(), x_max = c0.domain().x_max();
        if (c0.regions_size() < 2 || !c0.regions(1).has_box())
            throw std::invalid_argument("the case needs a second region with a box (the initial jump)");
        const auto& box = c0.regions(1).box();
        const double x0 = box.x_max() < x_max ? box.x_max() : box.x_min();
        const auto& left = region_at(c0, x_min + 1e-9 * (x_max - x_min));
        const auto& right = region_at(c0, x_max - 1e-9 * (x_max - x_min));
        auto material = [&](const std::string& name) {
            for (const auto& m : c0.materials())
                if (m.name() == name) return m;
            throw std::invalid_argument("unknown material '" + name + "'");
        };
        const auto ml = material(left.material()), mr = material(right.material());
        const bool sg = (mr.has_tait() && mr.tait().as_stiffened_gas()) ||
                        (ml.has_tait() && ml.tait().as_stiffened_gas());
        label = std::to_string(c0.numerics().degree()) + "," + std::to_string(c0.domain().cells_x()) + "," +
                (sg ? "stiffened_gas" : "tait");
        const exact::Solution ex(material_of(ml), {left.rho(), left.u(), left.p()}, material_of(mr),
                                 {right.rho(), right.u(), right.p()});
        double t = c0.end_time();
        if (fit_time) {
            const double reach = std::min((x_max - x0) / std::max(ex.right_wave().head, 1e-300),
                                          (x0 - x_min) / std::max(-ex.left_wave().head, 1e-300));
            if (0.8 * reach < t) {
                t = 0.8 * reach;
                char buf[64];
                std::snprintf(buf, sizeof buf, "%.17g", t);
                sets.push_back(std::string("end_time=") + buf);
                for (int k = 0; k < c0.output().times_size(); ++k)
                    sets.push_back("output.times[" + std::to_string(k) + "]=" + buf);
                cf = undex::CaseFile::load(argv[1], sets);
            }
        }
        const undex::config::Case& c = cf.get();
        if (c.numerics().threads() > 0) omp_set_num_threads(c.numerics().threads());
        if (!exact_csv.empty()) {
            std::FILE* f = std::fopen(exact_csv.c_str(), "w");
            if (!f) throw std::runtime_error(exact_csv + ": cannot write");
            std::fprintf(f, "x,rho,u,p\n");
            for (int k = 0; k < 4000; ++k) {
                const double x = x_min + (k + 0.5) * (x_max - x_min) / 4000;
                const auto w = ex.sample((x - x0) / t);
                std::fprintf(f, "%.9g,%.12g,%.12g,%.12g\n", x, w.rho, w.u, w.p);
            }
            std::fclose(f);
            return 0;
        }
        auto s = undex::fluid::make_solver(cf);
        double wall = 0;
        try {
            wall = undex::test::advance(*s, t);
        } catch (const undex::fluid::SolverFailure& f) {
            std::printf("%s,stopped,\"%s\"\n", label.c_str(), f.what());
            return 2;
        }
        const auto e = undex::test::undex_1d_errors(*s, ex, x0, t);
        if (!std::isfinite(e.l1_p) || !std::isfinite(e.l1_rho) || !std::isfinite(e.l1_u)) {
            std::printf("%s,stopped,\"non-finite values in the final state\"\n", label.c_str());
            return 3;
        }
        std::printf("%s,%.4f,%.4e,%.4e,%.4e,%.4e,%.6e,%.3f,%.3f,%.3f\n", label.c_str(), wall, e.l1_rho,
                    e.l1_u, e.l1_p, e.l1_p / e.p_star, e.p_star, (e.shock - e.shock_exact) / e.dx,
                    (e.interface - e.interface_exact) / e.dx, (e.head - e.head_exact) / e.dx);
        if (bins > 0) {
            const auto& m = s->mesh();
            std::vector<double> share(bins, 0.0);
            const int n = m.nx * 8;
            for (int k = 0; k < n; ++k) {
                const double x = m.x_min + (k + 0.5) * (m.x_max - m.x_min) / n;
                const double err =
                    std::abs(s->evaluate(x, 0).p - ex.sample((x - x0) / t).p) / (n * ex.p_star());
                share[std::min(bins - 1, static_cast<int>((x - m.x_min) / (m.x_max - m.x_min) * bins))] +=
                    err;
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
