#include "fluid/output.hpp"

#include "base/h5.hpp"

#include <hdf5.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace undex::fluid {

using namespace undex::h5;

Output::Output(const std::string& directory, const std::string& case_text, const FluidSolver& solver,
               const std::vector<GaugePoint>& gauges, int ranks)
    : file_(directory, "fluid.h5", case_text), gauges_(gauges), series_(gauges.size()) {
    describe(solver);
    for (int r = ranks == 1 ? 0 : ranks;; ++r) { // an older run's (on more ranks)
        std::error_code e;
        if (!std::filesystem::remove(std::filesystem::path(directory) / OutputPart::name(r), e)) break;
    }
    if (ranks == 1) {
        std::error_code ignored;
        std::filesystem::remove(std::filesystem::path(directory) / "fluid.parts", ignored); // when empty
    }
    const Mesh& m = solver.mesh();
    write_attr<long>(file_.id(), "dim", m.dim);
    write_attr<long>(file_.id(), "nx", m.nx);
    write_attr<long>(file_.id(), "ny", m.ny);
    write_attr<long>(file_.id(), "degree", solver.degree());
    write_attr<long>(file_.id(), "variables", solver.variables());
    write_attr<long>(file_.id(), "basis_functions", solver.basis_functions());
    write_attr<double>(file_.id(), "x_min", m.x_min);
    write_attr<double>(file_.id(), "x_max", m.x_max);
    write_attr<double>(file_.id(), "y_min", m.y_min);
    write_attr<double>(file_.id(), "y_max", m.y_max);
    for (const char* g : {"fields", "gauges"})
        create_group(file_.id(), g).close();
    std::vector<double> x(m.nx);
    for (int i = 0; i < m.nx; ++i)
        x[i] = m.xc(i);
    write_dataset(file_.id(), "x", {static_cast<hsize_t>(m.nx)}, x.data());
    if (m.dim == 2) {
        std::vector<double> y(m.ny);
        for (int j = 0; j < m.ny; ++j)
            y[j] = m.yc(j);
        write_dataset(file_.id(), "y", {static_cast<hsize_t>(m.ny)}, y.data());
    }
    file_.flush();
}

Output::Output(const std::string& directory, const FluidSolver& solver, const std::vector<GaugePoint>& gauges,
               State& checkpoint)
    : file_(directory, "fluid.h5", OutputFile::Reopen{}), gauges_(gauges), series_(gauges.size()) {
    describe(solver);
    state(checkpoint);
    file_.delete_numbered("fields", count_);
    file_.delete_numbered("frames", frames_);
    write_gauges(); // flushes the file
    write_xdmf();
}

void Output::describe(const FluidSolver& solver) {
    const Mesh& m = solver.mesh();
    dim_ = m.dim, nx_ = m.nx, ny_ = m.ny;
    x_min_ = m.x_min, y_min_ = m.y_min, dx_ = m.dx, dy_ = m.dy;
    cavitation_ = solver.has_cavitation();
    level_set_ = !solver.level_set().empty();
    structure_ = !solver.structure_level_set().empty();
}

void Output::state(State& s) {
    for (size_t k = 0; k < series_.size(); ++k)
        s.io("gauge" + std::to_string(k), series_[k]);
    s.io("count", count_);
    s.io("frames", frames_);
    io_snapshots(s, snapshots_);
}

void Output::write_frame(const FluidSolver& solver, int stride) {
    write_frame(frame_cells(solver, 0, ny_), solver.time(), stride);
}

std::vector<double> frame_cells(const FluidSolver& solver, int j0, int j1) {
    const int nx = solver.mesh().nx;
    const bool cavitation = solver.has_cavitation();
    const std::vector<double> phi = solver.level_set();
    std::vector<double> c;
    c.reserve(4L * (j1 - j0) * nx);
    for (int j = j0; j < j1; ++j)
        for (int i = 0; i < nx; ++i) {
            const Primitive w = solver.cell_average(i, j);
            c.insert(c.end(), {w.p, w.rho, phi.empty() ? 1.0 : phi[static_cast<long>(j) * nx + i],
                               cavitation ? solver.cell_void_fraction(i, j) : 0.0});
        }
    return c;
}

void Output::write_frame(const std::vector<double>& cells, double time, int stride) {
    // The group of frames is made with the first; a resumed run finds it there.
    if (frames_ == 0 &&
        check(H5Lexists(file_.id(), "frames", H5P_DEFAULT), file_.id(), "frames", "look up") <= 0) {
        Object f = create_group(file_.id(), "frames");
        write_attr<long>(f.id(), "stride", stride);
        write_attr<long>(f.id(), "nx", nx_);
        write_attr<long>(f.id(), "ny", ny_);
        write_attr<double>(f.id(), "x_min", x_min_);
        write_attr<double>(f.id(), "x_max", x_min_ + nx_ * dx_);
        write_attr<double>(f.id(), "y_min", y_min_);
        write_attr<double>(f.id(), "y_max", y_min_ + ny_ * dy_);
    }
    char name[32];
    std::snprintf(name, sizeof name, "frames/%06d", frames_++);
    const int bx = (nx_ + stride - 1) / stride, by = (ny_ + stride - 1) / stride;
    const long nb = static_cast<long>(bx) * by;
    std::vector<double> sum(4 * nb, 0.0), count(nb, 0.0);
    for (int j = 0; j < ny_; ++j)
        for (int i = 0; i < nx_; ++i) {
            const long b = static_cast<long>(j / stride) * bx + i / stride;
            const double* c = cells.data() + 4 * (static_cast<long>(j) * nx_ + i);
            for (int v = 0; v < 4; ++v)
                sum[4 * b + v] += c[v];
            count[b] += 1;
        }
    Object group = create_group(file_.id(), name);
    write_attr<double>(group.id(), "time", time);
    std::vector<float> out(nb);
    int v = 0;
    for (const char* field : {"p", "rho", "phi", "void_fraction"}) {
        for (long b = 0; b < nb; ++b)
            out[b] = static_cast<float>(sum[4 * b + v] / count[b]);
        write_dataset(group.id(), field, {hsize_t(by), hsize_t(bx)}, out.data());
        ++v;
    }
    group.close();
    file_.flush();
}

namespace {
// The field datasets of an output: name, and 0 for a cell field or the numbers per cell (coefficients).
struct FieldSet {
    std::string name;
    hsize_t per_cell;
};
std::vector<FieldSet> field_sets(const FluidSolver& solver) {
    std::vector<FieldSet> f = {{"rho", 0}, {"u", 0}};
    if (solver.mesh().dim == 2) f.push_back({"v", 0});
    f.push_back({"p", 0});
    if (solver.has_cavitation()) f.push_back({"void_fraction", 0});
    if (!solver.level_set().empty()) f.push_back({"phi", 0});
    if (!solver.structure_level_set().empty()) f.push_back({"phi_s", 0});
    f.push_back({"coefficients", static_cast<hsize_t>(solver.variables() * solver.basis_functions())});
    return f;
}
// The shape of a field set of `rows` rows of cells.
std::vector<hsize_t> field_dims(const FluidSolver& solver, const FieldSet& f, int rows) {
    const hsize_t nx = solver.mesh().nx;
    if (f.per_cell > 0) return {hsize_t(rows) * nx, f.per_cell};
    if (solver.mesh().dim == 1) return {nx};
    return {hsize_t(rows), nx};
}
// The field sets of rows [j0, j1) into group g (field_sets, field_dims).
void write_field_rows(hid_t g, const FluidSolver& solver, int j0, int j1) {
    const int nx = solver.mesh().nx;
    const long n = static_cast<long>(j1 - j0) * nx, first = static_cast<long>(j0) * nx;
    const bool cavitation = solver.has_cavitation();
    std::vector<double> rho(n), u(n), v(n), p(n), alpha(cavitation ? n : 0);
    for (int j = j0; j < j1; ++j)
        for (int i = 0; i < nx; ++i) {
            const Primitive w = solver.cell_average(i, j);
            const long k = static_cast<long>(j - j0) * nx + i;
            rho[k] = w.rho, u[k] = w.u, v[k] = w.v, p[k] = w.p;
            if (cavitation) alpha[k] = solver.cell_void_fraction(i, j);
        }
    for (const FieldSet& f : field_sets(solver)) {
        const std::vector<hsize_t> dims = field_dims(solver, f, j1 - j0);
        const char* name = f.name.c_str();
        if (f.name == "rho") write_dataset(g, name, dims, rho.data());
        if (f.name == "u") write_dataset(g, name, dims, u.data());
        if (f.name == "v") write_dataset(g, name, dims, v.data());
        if (f.name == "p") write_dataset(g, name, dims, p.data());
        if (f.name == "void_fraction") write_dataset(g, name, dims, alpha.data());
        if (f.name == "phi") write_dataset(g, name, dims, solver.level_set().data() + first);
        if (f.name == "phi_s") write_dataset(g, name, dims, solver.structure_level_set().data() + first);
        if (f.name == "coefficients")
            write_dataset(g, name, dims, solver.coefficients().data() + first * long(f.per_cell));
    }
}
} // namespace

Object Output::begin_fields(const FluidSolver& solver, const std::vector<double>& totals, bool last_good) {
    char name[32];
    std::snprintf(name, sizeof name, "fields/%06d", count_++); // a number per try: a failed one is not reused
    Object group = create_group(file_.id(), name);
    const hid_t g = group.id();
    write_attr<double>(g, "time", solver.time());
    write_attr<long>(g, "step", solver.steps());
    write_attr<long>(g, "last_good", last_good ? 1 : 0);
    // ∫ U dx over the fluid (planar measure): mass, momentum, total energy; the energy balance of a coupled
    // run compares their change with the work on the structure.
    write_attr<double>(g, "mass", totals[0]);
    write_attr<double>(g, "energy", totals.back());
    return group;
}

void Output::finish_fields(Object& group, double time) {
    char name[32];
    std::snprintf(name, sizeof name, "fields/%06d", count_ - 1);
    group.close();
    write_gauges();                      // flushes the file
    snapshots_.push_back({name, time}); // fluid.xmf shows what the file holds
    write_xdmf();
}

void Output::write_fields(const FluidSolver& solver, bool last_good) {
    Object group = begin_fields(solver, solver.totals(), last_good);
    write_field_rows(group.id(), solver, 0, ny_);
    finish_fields(group, solver.time());
}

void Output::write_fields(const FluidSolver& solver, const std::vector<int>& first_row,
                          const std::vector<double>& row_totals, bool last_good) {
    Object group = begin_fields(solver, FluidSolver::sum_rows(row_totals, solver.variables()), last_good);
    char name[32];
    std::snprintf(name, sizeof name, "fields/%06d", count_ - 1); // the ranks' parts count alike
    for (const FieldSet& f : field_sets(solver)) {
        std::vector<h5::RowBlock> blocks;
        const hsize_t per_row = f.per_cell > 0 ? hsize_t(nx_) : 1;
        for (size_t r = 0; r + 1 < first_row.size(); ++r)
            blocks.push_back({OutputPart::name(static_cast<int>(r)), std::string("/") + name + "/" + f.name,
                              hsize_t(first_row[r]) * per_row,
                              hsize_t(first_row[r + 1] - first_row[r]) * per_row});
        write_virtual(group.id(), f.name.c_str(), field_dims(solver, f, ny_), blocks);
    }
    finish_fields(group, solver.time());
}

OutputPart::OutputPart(const std::string& directory, int rank, const std::string& case_text)
    : file_((std::filesystem::path(directory) / name(rank)).parent_path().string(),
            std::filesystem::path(name(rank)).filename().string(), case_text) {}

std::string OutputPart::name(int rank) {
    char name[40];
    std::snprintf(name, sizeof name, "fluid.parts/rank%04d.h5", rank);
    return name;
}

void OutputPart::write_fields(const FluidSolver& solver, int j0, int j1) {
    char name[32];
    std::snprintf(name, sizeof name, "fields/%06d", count_++);
    if (count_ == 1) create_group(file_.id(), "fields").close();
    Object group = create_group(file_.id(), name);
    write_attr<long>(group.id(), "first_row", j0);
    write_attr<long>(group.id(), "rows", j1 - j0);
    write_field_rows(group.id(), solver, j0, j1);
    group.close();
    file_.flush();
}

void Output::record_gauges(const FluidSolver& solver) {
    std::vector<Primitive> w(gauges_.size());
    for (size_t k = 0; k < gauges_.size(); ++k)
        w[k] = solver.evaluate(gauges_[k].x, gauges_[k].y);
    record_gauges(solver.time(), w);
}

void Output::record_gauges(double t, const std::vector<Primitive>& w) {
    for (size_t k = 0; k < gauges_.size(); ++k)
        series_[k].insert(series_[k].end(), {t, w[k].rho, w[k].u, w[k].v, w[k].p});
}

void Output::write_gauges() {
    for (size_t k = 0; k < gauges_.size(); ++k) {
        const std::string group = "gauges/" + gauges_[k].name;
        if (check(H5Lexists(file_.id(), group.c_str(), H5P_DEFAULT), file_.id(), group, "look up") <= 0)
            create_group(file_.id(), group).close();
        Object gauge = open_group(file_.id(), group);
        const hid_t g = gauge.id();
        write_attr<double>(g, "x", gauges_[k].x);
        write_attr<double>(g, "y", gauges_[k].y);
        const auto& s = series_[k];
        const size_t rows = s.size() / 5;
        const char* names[5] = {"t", "rho", "u", "v", "p"};
        for (int col = 0; col < 5; ++col) {
            std::vector<double> column(rows);
            for (size_t r = 0; r < rows; ++r)
                column[r] = s[r * 5 + col];
            write_dataset(g, names[col], {hsize_t(rows)}, column.data());
        }
        gauge.close();
    }
    file_.flush();
}

void Output::write_table(const std::string& group, const std::vector<std::string>& columns,
                         const std::vector<double>& data) {
    file_.write_table(group, columns, data);
}

void Output::complete() {
    file_.complete();
}

void Output::fail(const std::string& why, const std::function<void()>& write_state) {
    file_.fail(why, write_state);
}

void Output::write_xdmf() const {
    // A 1D run is shown as a strip one cell high.
    const int ny_nodes = ny_ + 1;
    const double dy = dim_ == 2 ? dy_ : dx_;
    const double y0 = dim_ == 2 ? y_min_ : -0.5 * dx_;
    std::ostringstream x;
    x.precision(17);
    x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      << "<Grid Name=\"fluid\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    std::vector<std::string> fields = {"rho", "u", "p"};
    if (dim_ == 2) fields.insert(fields.begin() + 2, "v");
    if (cavitation_) fields.push_back("void_fraction");
    if (level_set_) fields.push_back("phi");
    if (structure_) fields.push_back("phi_s");
    const std::string dims = std::to_string(ny_) + " " + std::to_string(nx_);
    for (const auto& s : snapshots_) {
        x << "<Grid Name=\"" << s.group << "\" GridType=\"Uniform\">\n<Time Value=\"" << s.time << "\"/>\n"
          << "<Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"" << ny_nodes << " " << nx_ + 1 << "\"/>\n"
          << "<Geometry GeometryType=\"ORIGIN_DXDY\">\n"
          << "<DataItem Format=\"XML\" Dimensions=\"2\">" << y0 << " " << x_min_ << "</DataItem>\n"
          << "<DataItem Format=\"XML\" Dimensions=\"2\">" << dy << " " << dx_ << "</DataItem>\n</Geometry>\n";
        for (const auto& f : fields)
            x << "<Attribute Name=\"" << f << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
              << "<DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"" << dims
              << "\">fluid.h5:/" << s.group << "/" << f << "</DataItem>\n</Attribute>\n";
        x << "</Grid>\n";
    }
    x << "</Grid>\n</Domain>\n</Xdmf>\n";
    write_file_atomically((std::filesystem::path(file_.directory()) / "fluid.xmf").string(), x.str());
}

std::vector<double> read_coefficients(const std::string& h5_path, const std::string& group) {
    return read_dataset(open_read(h5_path).id(), group + "/coefficients");
}

std::vector<double> read_level_set(const std::string& h5_path, const std::string& group) {
    const Object f = open_read(h5_path);
    const std::string name = group + "/phi";
    if (check(H5Lexists(f.id(), name.c_str(), H5P_DEFAULT), f.id(), name, "look up") <= 0) return {};
    return read_dataset(f.id(), name);
}

} // namespace undex::fluid
