#include "run_column.hpp"

#include "case.pb.h"
#include "case_file.hpp"
#include "h5.hpp"
#include "setup.hpp"
#include "structure_setup.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace undex::solid {

namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a, b, c, d);
    return buf;
}

class ColumnOutput {
  public:
    ColumnOutput(const std::string& dir, const std::string& case_text, const Column1D& col) {
        std::filesystem::create_directories(dir);
        path_ = (std::filesystem::path(dir) / "solid.h5").string();
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        file_ = H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
        if (file_ < 0) throw std::runtime_error(path_ + ": cannot create the output file");
        h5::write_attr_string(file_, "case", case_text);
        h5::write_attr<long>(file_, "nodes", static_cast<long>(col.nodes()));
        h5::write_attr<long>(file_, "elements", static_cast<long>(col.element_count()));
        h5::write_attr_string(file_, "status", "running");
        std::vector<double> x(col.nodes()), xe(col.element_count());
        for (size_t i = 0; i < x.size(); ++i)
            x[i] = col.node_x(i);
        for (size_t e = 0; e < xe.size(); ++e)
            xe[e] = col.element_x(e);
        h5::write_dataset(file_, "x", {x.size()}, x.data());
        h5::write_dataset(file_, "element_x", {xe.size()}, xe.data());
        H5Gclose(H5Gcreate2(file_, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Gclose(H5Gcreate2(file_, "energies", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Gclose(H5Gcreate2(file_, "gauges", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    ~ColumnOutput() {
        if (file_ >= 0) H5Fclose(file_);
    }
    ColumnOutput(const ColumnOutput&) = delete;
    ColumnOutput& operator=(const ColumnOutput&) = delete;

    struct Gauge {
        std::string name;
        size_t node, element;
        std::vector<double> series; // t, u, v, a, stress_xx, peeq interleaved
    };
    void add_gauge(const std::string& name, double x, const Column1D& col) {
        size_t node = 0, element = 0;
        for (size_t i = 1; i < col.nodes(); ++i)
            if (std::abs(col.node_x(i) - x) < std::abs(col.node_x(node) - x)) node = i;
        while (element + 1 < col.element_count() && col.node_x(element + 1) < x)
            ++element;
        gauges_.push_back({name, node, element, {}});
    }
    void record_gauges(const Column1D& col) {
        for (auto& g : gauges_) {
            const auto& p = col.point(g.element);
            g.series.insert(g.series.end(), {col.time(), col.displacement(g.node), col.velocity(g.node),
                                             col.acceleration(g.node), p.stress[0], p.peeq});
        }
    }
    void record_energies(const Column1D& col) {
        const auto& e = col.energies();
        energies_.insert(energies_.end(),
                         {col.time(), e.kinetic, e.elastic(), e.plastic, e.external, e.balance_error()});
    }
    void write_fields(const Column1D& col, bool last_good = false) {
        char name[32];
        std::snprintf(name, sizeof name, "fields/%06d", count_++);
        hid_t g = H5Gcreate2(file_, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (g < 0) throw std::runtime_error(path_ + ": cannot create group " + name);
        h5::write_attr<double>(g, "time", col.time());
        h5::write_attr<long>(g, "step", col.steps());
        h5::write_attr<long>(g, "last_good", last_good ? 1 : 0);
        const size_t n = col.nodes(), ne = col.element_count();
        std::vector<double> u(n), v(n), a(n);
        for (size_t i = 0; i < n; ++i)
            u[i] = col.displacement(i), v[i] = col.velocity(i), a[i] = col.acceleration(i);
        h5::write_dataset(g, "u", {n}, u.data());
        h5::write_dataset(g, "v", {n}, v.data());
        h5::write_dataset(g, "a", {n}, a.data());
        std::vector<double> f(ne);
        auto element_field = [&](const char* field, auto pick) {
            for (size_t e = 0; e < ne; ++e)
                f[e] = pick(col.point(e));
            h5::write_dataset(g, field, {ne}, f.data());
        };
        element_field("stress_xx", [](const PointState& p) { return p.stress[0]; });
        element_field("strain_xx", [](const PointState& p) { return p.strain[0]; });
        element_field("plastic_strain_xx", [](const PointState& p) { return p.plastic_strain[0]; });
        element_field("peeq", [](const PointState& p) { return p.peeq; });
        element_field("peeq_rate", [](const PointState& p) { return p.peeq_rate; });
        H5Gclose(g);
        write_energies();
    }
    void write_energies() {
        const char* names[6] = {"t", "kinetic", "elastic", "plastic", "external", "balance_error"};
        write_table(file_, "energies", names, energies_);
        const char* columns[6] = {"t", "u", "v", "a", "stress_xx", "peeq"};
        for (const auto& gauge : gauges_) {
            const std::string group = "gauges/" + gauge.name;
            if (H5Lexists(file_, group.c_str(), H5P_DEFAULT) <= 0)
                H5Gclose(H5Gcreate2(file_, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
            write_table(file_, group.c_str(), columns, gauge.series);
        }
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    void set_status(const std::string& s) {
        h5::write_attr_string(file_, "status", s);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    const std::string& path() const { return path_; }

  private:
    // Six interleaved columns into datasets of one group.
    static void write_table(hid_t file, const char* group, const char* const* names,
                            const std::vector<double>& data) {
        const size_t rows = data.size() / 6;
        hid_t g = H5Gopen2(file, group, H5P_DEFAULT);
        std::vector<double> col(rows);
        for (int k = 0; k < 6; ++k) {
            for (size_t r = 0; r < rows; ++r)
                col[r] = data[r * 6 + k];
            h5::write_dataset(g, names[k], {rows}, col.data());
        }
        H5Gclose(g);
    }
    std::vector<Gauge> gauges_;
    std::string path_;
    hid_t file_ = -1;
    int count_ = 0;
    std::vector<double> energies_;
};

} // namespace

int run_column(const CaseFile& c, std::ostream& log) {
    StructureModel model = make_structure(c); // checks the whole structure part first
    const auto p = fluid::plan(c);
    Column1D& col = *model.column;
    log << "undex-solid: " << c.path() << ": 1D column, " << col.element_count() << " elements, time step "
        << fmt("%.4g", model.dt) << " s, end time " << p.end_time << " s, output " << p.directory
        << "/solid.h5" << std::endl;
    ColumnOutput out(p.directory, c.text(), col);
    for (const auto& g : c.get().structure().gauges())
        out.add_gauge(g.name(), g.x(), col);
    out.record_energies(col);
    out.record_gauges(col);
    out.write_fields(col);
    const auto start = std::chrono::steady_clock::now();
    auto last_progress = start;
    size_t next = 0;
    Column1D last_good = col;
    while (col.time() < p.end_time * (1 - 1e-14)) {
        const double target = p.output_times[next];
        double dt = model.dt;
        const bool hits = col.time() + dt >= target * (1 - 1e-12);
        if (hits) dt = target - col.time();
        last_good = col;
        try {
            col.step(dt);
        } catch (const StructureFailure& f) {
            out.write_fields(last_good, true);
            out.set_status(std::string("failed: ") + f.what());
            log << "undex-solid: error: " << f.what()
                << "\nundex-solid: the last good state (t = " << fmt("%.9g", last_good.time()) << " s, step "
                << last_good.steps() << ") is in " << out.path() << std::endl;
            return 2;
        }
        if (col.steps() % p.gauge_every == 0 || hits) {
            out.record_energies(col);
            out.record_gauges(col);
        }
        if (hits) {
            out.write_fields(col);
            ++next;
        }
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_progress).count() >= p.progress_seconds ||
            col.time() >= p.end_time * (1 - 1e-14)) {
            const double wall = std::chrono::duration<double>(now - start).count(),
                         frac = col.time() / p.end_time;
            log << "step " << col.steps()
                << fmt("  t = %.4e s (%5.1f%%)  wall %.1f s  left ~%.1f s", col.time(), 100 * frac, wall,
                       frac > 0 ? wall * (1 - frac) / frac : 0.0)
                << "  energy balance error "
                << fmt("%.2e", col.energies().balance_error() / std::max(col.energies().external, 1e-300))
                << std::endl;
            last_progress = now;
        }
    }
    out.write_energies();
    out.set_status("complete");
    log << "undex-solid: done: " << col.steps() << " steps, wall "
        << fmt("%.3f", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
        << " s" << std::endl;
    return 0;
}

} // namespace undex::solid
