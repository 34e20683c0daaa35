#include "solid/run_structure.hpp"

#include "proto/case.pb.h"
#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "coupler/participant.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "solid/structure_setup.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace undex::solid {

namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a, b, c, d);
    return buf;
}

std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (size_t k = 0; k < v.size(); ++k)
        s += (k ? "," : "") + v[k];
    return s;
}

// solid.h5 of a column or a plate (run_structure.hpp describes the layout).
class StructureOutput {
  public:
    StructureOutput(const std::string& dir, const std::string& case_text, const StructureModel& m)
        : m_(m), dir_(dir) {
        std::filesystem::create_directories(dir);
        path_ = (std::filesystem::path(dir) / "solid.h5").string();
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        file_ = h5::create(path_);
        if (file_ < 0) throw std::runtime_error(path_ + ": cannot create the output file");
        h5::write_attr_string(file_, "case", case_text);
        h5::write_attr<long>(file_, "dimension", m.plate ? 2 : 1);
        h5::write_attr<long>(file_, "nodes", static_cast<long>(nodes()));
        h5::write_attr<long>(file_, "elements", static_cast<long>(elements()));
        h5::write_attr_string(file_, "layers", join(m.layers));
        h5::write_attr_string(file_, "status", "running");
        if (m.plate) {
            const Plate2D& p = *m.plate;
            std::vector<double> xy(2 * p.nodes());
            for (size_t i = 0; i < p.nodes(); ++i)
                xy[2 * i] = p.node_x(i), xy[2 * i + 1] = p.node_y(i);
            std::vector<int> quads(4 * p.element_count()), layer(p.element_count());
            for (size_t e = 0; e < p.element_count(); ++e) {
                for (int k = 0; k < 4; ++k)
                    quads[4 * e + k] = p.quad(e)[k];
                layer[e] = p.law_of(e);
            }
            h5::write_dataset(file_, "nodes", {p.nodes(), 2}, xy.data());
            h5::write_dataset(file_, "quads", {p.element_count(), 4}, quads.data());
            h5::write_dataset(file_, "layer", {p.element_count()}, layer.data());
        } else {
            const Column1D& col = *m.column;
            std::vector<double> x(col.nodes()), xe(col.element_count());
            for (size_t i = 0; i < x.size(); ++i)
                x[i] = col.node_x(i);
            for (size_t e = 0; e < xe.size(); ++e)
                xe[e] = col.element_x(e);
            h5::write_dataset(file_, "x", {x.size()}, x.data());
            h5::write_dataset(file_, "element_x", {xe.size()}, xe.data());
        }
        H5Gclose(H5Gcreate2(file_, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Gclose(H5Gcreate2(file_, "energies", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        hid_t g = H5Gcreate2(file_, "gauges", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        h5::write_attr_string(g, "columns", join(gauge_columns()));
        H5Gclose(g);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    ~StructureOutput() {
        if (file_ >= 0) H5Fclose(file_);
    }
    StructureOutput(const StructureOutput&) = delete;
    StructureOutput& operator=(const StructureOutput&) = delete;

    // A gauge at (x, y) of the reference configuration (1D: x is the depth): the nearest node and the
    // element containing the point.
    void add_gauge(const std::string& name, double x, double y) {
        size_t node = 0, element = 0;
        if (m_.plate) {
            const Plate2D& p = *m_.plate;
            const LayeredPlate& lp = m_.layout;
            double best = 1e300;
            for (size_t i = 0; i < p.nodes(); ++i) {
                const double d = std::hypot(p.node_x(i) - x, p.node_y(i) - y);
                if (d < best) best = d, node = i;
            }
            int i = 0, j = 0;
            while (i + 1 < lp.nx && p.node_x(lp.node(i + 1, 0)) < x)
                ++i;
            while (j + 1 < lp.ny && p.node_y(lp.node(0, j + 1)) < y)
                ++j;
            element = lp.element(i, j);
        } else {
            const Column1D& col = *m_.column;
            for (size_t i = 1; i < col.nodes(); ++i)
                if (std::abs(col.node_x(i) - x) < std::abs(col.node_x(node) - x)) node = i;
            while (element + 1 < col.element_count() && col.node_x(element + 1) < x)
                ++element;
        }
        gauges_.push_back({name, node, element, {}});
    }
    void record(double time, const Energies& e) {
        energies_.insert(energies_.end(), {time, e.kinetic, e.elastic(), e.plastic, e.hourglass, e.external,
                                           e.balance_error()});
        for (auto& g : gauges_) {
            if (m_.plate) {
                const Plate2D& p = *m_.plate;
                const auto& s = p.point(g.element);
                const size_t n = g.node;
                g.series.insert(g.series.end(), {time, p.ux(n), p.uy(n), p.vx(n), p.vy(n), p.ax(n), p.ay(n),
                                                 s.stress[0], s.stress[1], s.stress[2], s.stress[3], s.peeq});
            } else {
                const Column1D& col = *m_.column;
                const auto& s = col.point(g.element);
                g.series.insert(g.series.end(), {time, col.displacement(g.node), col.velocity(g.node),
                                                 col.acceleration(g.node), s.stress[0], s.peeq});
            }
        }
    }
    void write_fields(double time, long step, bool last_good = false) {
        char name[32];
        std::snprintf(name, sizeof name, "fields/%06d", count_++);
        hid_t g = H5Gcreate2(file_, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (g < 0) throw std::runtime_error(path_ + ": cannot create group " + name);
        h5::write_attr<double>(g, "time", time);
        h5::write_attr<long>(g, "step", step);
        h5::write_attr<long>(g, "last_good", last_good ? 1 : 0);
        const size_t n = nodes(), ne = elements();
        std::vector<double> f(std::max(2 * n, ne));
        auto node_field = [&](const char* field, auto pick) {
            for (size_t i = 0; i < n; ++i)
                f[i] = pick(i);
            h5::write_dataset(g, field, {n}, f.data());
        };
        auto element_field = [&](const char* field, auto pick) {
            for (size_t e = 0; e < ne; ++e)
                f[e] = pick(e);
            h5::write_dataset(g, field, {ne}, f.data());
        };
        if (m_.plate) {
            const Plate2D& p = *m_.plate;
            for (size_t i = 0; i < n; ++i)
                f[2 * i] = p.node_x(i) + p.ux(i), f[2 * i + 1] = p.node_y(i) + p.uy(i);
            h5::write_dataset(g, "position", {n, 2}, f.data());
            node_field("u_x", [&](size_t i) { return p.ux(i); });
            node_field("u_y", [&](size_t i) { return p.uy(i); });
            node_field("v_x", [&](size_t i) { return p.vx(i); });
            node_field("v_y", [&](size_t i) { return p.vy(i); });
            node_field("a_x", [&](size_t i) { return p.ax(i); });
            node_field("a_y", [&](size_t i) { return p.ay(i); });
            for (int k = 0; k < 4; ++k)
                element_field(stress_names()[k], [&](size_t e) { return p.point(e).stress[k]; });
            element_field("von_mises", [&](size_t e) { return von_mises(p.point(e).stress); });
            element_field("peeq", [&](size_t e) { return p.point(e).peeq; });
            element_field("peeq_rate", [&](size_t e) { return p.point(e).peeq_rate; });
            element_field("hourglass_energy", [&](size_t e) { return p.hourglass_energy(e); });
        } else {
            const Column1D& col = *m_.column;
            node_field("u", [&](size_t i) { return col.displacement(i); });
            node_field("v", [&](size_t i) { return col.velocity(i); });
            node_field("a", [&](size_t i) { return col.acceleration(i); });
            element_field("stress_xx", [&](size_t e) { return col.point(e).stress[0]; });
            element_field("strain_xx", [&](size_t e) { return col.point(e).strain[0]; });
            element_field("plastic_strain_xx", [&](size_t e) { return col.point(e).plastic_strain[0]; });
            element_field("peeq", [&](size_t e) { return col.point(e).peeq; });
            element_field("peeq_rate", [&](size_t e) { return col.point(e).peeq_rate; });
        }
        H5Gclose(g);
        snapshots_.push_back({name, time});
        write_tables();
        if (m_.plate) write_xdmf();
    }
    void write_tables() {
        h5::write_table(file_, "energies",
                        {"t", "kinetic", "elastic", "plastic", "hourglass", "external", "balance_error"},
                        energies_);
        for (const auto& gauge : gauges_) {
            h5::write_table(file_, "gauges/" + gauge.name, gauge_columns(), gauge.series);
        }
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    // A table of one dataset per column in group.
    void write_group_table(const std::string& group, const std::vector<std::string>& columns,
                           const std::vector<double>& data) {
        h5::write_table(file_, group, columns, data);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    void set_status(const std::string& s) {
        h5::write_attr_string(file_, "status", s);
        H5Fflush(file_, H5F_SCOPE_GLOBAL);
    }
    const std::string& path() const { return path_; }

  private:
    struct Gauge {
        std::string name;
        size_t node, element;
        std::vector<double> series; // rows of gauge_columns()
    };
    struct Snapshot {
        std::string group;
        double time;
    };
    const StructureModel& m_;
    std::string dir_, path_;
    hid_t file_ = -1;
    int count_ = 0;
    std::vector<Gauge> gauges_;
    std::vector<double> energies_;
    std::vector<Snapshot> snapshots_;

    static const char* const* stress_names() {
        static const char* const names[4] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy"};
        return names;
    }
    size_t nodes() const { return m_.plate ? m_.plate->nodes() : m_.column->nodes(); }
    size_t elements() const { return m_.plate ? m_.plate->element_count() : m_.column->element_count(); }
    std::vector<std::string> gauge_columns() const {
        if (m_.plate)
            return {"t",   "u_x",       "u_y",       "v_x",       "v_y",       "a_x",
                    "a_y", "stress_xx", "stress_yy", "stress_zz", "stress_xy", "peeq"};
        return {"t", "u", "v", "a", "stress_xx", "peeq"};
    }
    // solid.xmf: the plate's snapshots as a temporal collection of quadrilateral grids on the current
    // positions, for ParaView.
    void write_xdmf() const {
        const size_t n = nodes(), ne = elements();
        std::ostringstream x;
        x.precision(17);
        x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
          << "<Grid Name=\"solid\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
        auto item = [&](const std::string& path, const std::string& dims, const char* type = "Float",
                        int precision = 8) {
            x << "<DataItem Format=\"HDF\" NumberType=\"" << type << "\" Precision=\"" << precision
              << "\" Dimensions=\"" << dims << "\">solid.h5:" << path << "</DataItem>\n";
        };
        for (const auto& s : snapshots_) {
            x << "<Grid Name=\"" << s.group << "\" GridType=\"Uniform\">\n<Time Value=\"" << s.time
              << "\"/>\n"
              << "<Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << ne << "\">\n";
            item("/quads", std::to_string(ne) + " 4", "Int", 4);
            x << "</Topology>\n<Geometry GeometryType=\"XY\">\n";
            item("/" + s.group + "/position", std::to_string(n) + " 2");
            x << "</Geometry>\n";
            for (const char* f : {"u_x", "u_y", "v_x", "v_y", "a_x", "a_y"}) {
                x << "<Attribute Name=\"" << f << "\" AttributeType=\"Scalar\" Center=\"Node\">\n";
                item("/" + s.group + "/" + f, std::to_string(n));
                x << "</Attribute>\n";
            }
            for (const char* f : {"stress_xx", "stress_yy", "stress_zz", "stress_xy", "von_mises", "peeq",
                                  "peeq_rate", "hourglass_energy"}) {
                x << "<Attribute Name=\"" << f << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
                item("/" + s.group + "/" + f, std::to_string(ne));
                x << "</Attribute>\n";
            }
            x << "<Attribute Name=\"layer\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
            item("/layer", std::to_string(ne), "Int", 4);
            x << "</Attribute>\n</Grid>\n";
        }
        x << "</Grid>\n</Domain>\n</Xdmf>\n";
        const auto path = std::filesystem::path(dir_) / "solid.xmf";
        const auto tmp = std::filesystem::path(dir_) / "solid.xmf.tmp";
        std::ofstream(tmp) << x.str();
        std::filesystem::rename(tmp, path);
    }
};

// The stepping of either model behind one interface.
struct Stepper {
    StructureModel& m;
    double time() const { return m.plate ? m.plate->time() : m.column->time(); }
    long steps() const { return m.plate ? m.plate->steps() : m.column->steps(); }
    const Energies& energies() const { return m.plate ? m.plate->energies() : m.column->energies(); }
    void step(double dt) { m.plate ? m.plate->step(dt) : (void)m.column->step(dt); }
    Column1D& column() { return *m.column; }
};

} // namespace

int run_structure(const CaseFile& c, std::ostream& log, const std::string& couple) {
    StructureModel model = make_structure(c); // checks the whole structure part first
    const auto p = plan(c);
    if (model.wet && couple.empty())
        c.fail("structure.front",
               "the structure is coupled to the case's fluid: run it with `undex run`, or give "
               "undex-solid --couple ENDPOINT with the fluid solver bound there");
    if (!model.wet && !couple.empty())
        c.fail("structure.front", "--couple needs a front face wetted by a fluid (FLUID)");
#ifdef _OPENMP
    if (model.threads > 0) omp_set_num_threads(model.threads);
    const int threads = omp_get_max_threads();
#else
    const int threads = 1;
#endif
    Stepper s{model};
    if (model.plate)
        log << "undex-solid: " << c.path() << ": "
            << (model.plate->plane() == Plane::Axisymmetric ? "axisymmetric" : "plane-strain") << " plate, "
            << model.layout.nx << " x " << model.layout.ny << " elements, " << threads << " thread(s)";
    else
        log << "undex-solid: " << c.path() << ": 1D column, " << model.column->element_count() << " elements";
    log << ", time step " << fmt("%.4g", model.dt) << " s, end time " << p.end_time << " s, output "
        << p.directory << "/solid.h5" << std::endl;

    // The fluid, when the front face is wet: node 0 is the interface node, its normal +x.
    std::unique_ptr<coupling::StructureParticipant> link;
    if (model.wet) {
        coupling::Options o;
        o.endpoint = couple;
        o.timeout_ms = static_cast<int>(1000 * c.get().coupling().timeout());
        o.handshake_timeout_ms = static_cast<int>(1000 * c.get().coupling().handshake_timeout());
        link = std::make_unique<coupling::StructureParticipant>(o, "undex-solid", "0.1.0");
        coupling::Interface i;
        i.x = {0.0}, i.y = {0.0}, i.normal_x = {1.0}, i.normal_y = {0.0}, i.area = {1.0};
        link->initialize(i);
        log << "undex-solid: coupled to " << link->peer_solver() << " on " << couple << std::endl;
    }

    StructureOutput out(p.directory, c.text(), model);
    for (const auto& g : c.get().structure().gauges())
        out.add_gauge(g.name(), g.x(), g.y());
    out.record(s.time(), s.energies());
    out.write_fields(s.time(), s.steps());
    std::vector<double> history; // t, dt, p_I, u_I per coupled step
    const std::vector<std::string> history_columns = {"t", "dt", "p_I", "u_I"};
    auto fail = [&](const std::string& msg, int code) {
        if (link) link->fail(msg); // best effort: the peer learns the cause
        out.write_fields(s.time(), s.steps(), true);
        if (link) out.write_group_table("coupling", history_columns, history);
        out.set_status("failed: " + msg);
        log << "undex-solid: error: " << msg
            << "\nundex-solid: the last good state (t = " << fmt("%.9g", s.time()) << " s, step " << s.steps()
            << ") is in " << out.path() << std::endl;
        return code;
    };
    const auto start = std::chrono::steady_clock::now();
    auto last_progress = start;
    size_t next = 0;
    try {
        for (;;) {
            if (stop_requested()) return fail("stopped by a signal (SIGINT or SIGTERM)", 4);
            double dt = model.dt;
            bool hits = false;
            coupling::Grant g;
            FluidCharacteristic fluid;
            if (link) { // the fluid owns the clock: it grants the step and asks for outputs
                coupling::Offer o;
                o.dt = dt, o.x = {s.column().displacement(0)}, o.y = {0.0},
                o.velocity = {s.column().velocity(0)};
                if (!link->exchange(o, g)) break;
                dt = g.dt, hits = g.output;
                fluid = {g.p_L[0], g.u_L[0], g.Z_L[0], g.geometric[0], g.p_floor};
            } else {
                if (!(s.time() < p.end_time * (1 - 1e-14))) break;
                const double target = p.output_times[next];
                hits = s.time() + dt >= target * (1 - 1e-12);
                if (hits) dt = target - s.time(), ++next;
            }
            InterfaceSolution wet;
            try {
                // On failure the model is left at its last good state.
                if (link)
                    wet = model.column->step(dt, &fluid);
                else
                    s.step(dt);
            } catch (const StructureFailure& f) {
                return fail(f.what(), 2);
            }
            if (link) {
                link->answer({{wet.p_I}, {wet.u_I}, {s.column().displacement(0)}, {0.0}});
                history.insert(history.end(), {s.time() - dt, dt, wet.p_I, wet.u_I});
            }
            if (s.steps() % p.gauge_every == 0 || hits) out.record(s.time(), s.energies());
            if (hits) {
                if (link) link->heartbeat(); // the fluid's wait restarts: an output may take a while
                out.write_fields(s.time(), s.steps());
                if (link) out.write_group_table("coupling", history_columns, history);
            }
            const auto now = std::chrono::steady_clock::now();
            if (std::chrono::duration<double>(now - last_progress).count() >= p.progress_seconds ||
                s.time() >= p.end_time * (1 - 1e-14)) {
                const double wall = std::chrono::duration<double>(now - start).count(),
                             frac = s.time() / p.end_time;
                log << "step " << s.steps()
                    << fmt("  t = %.4e s (%5.1f%%)  wall %.1f s  left ~%.1f s", s.time(), 100 * frac, wall,
                           frac > 0 ? wall * (1 - frac) / frac : 0.0)
                    << "  energy balance error "
                    << fmt("%.2e", s.energies().balance_error() / std::max(s.energies().external, 1e-300))
                    << std::endl;
                last_progress = now;
            }
        }
    } catch (const coupling::CouplingError& e) {
        return fail(std::string("coupling: ") + e.what(), stop_requested() ? 4 : 3);
    }
    out.write_tables();
    if (link) out.write_group_table("coupling", history_columns, history);
    out.set_status("complete");
    log << "undex-solid: done: " << s.steps() << " steps, wall "
        << fmt("%.3f", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
        << " s" << std::endl;
    return 0;
}

} // namespace undex::solid
