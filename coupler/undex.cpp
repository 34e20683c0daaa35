// undex: the command-line front end.
//   undex check CASE [--set key=value]...      validate a case without running it
//   undex run CASE [--set key=value]...        run a case (starts the solver process the case needs)
//   undex sample DIR --time T --line "x0,y0 x1,y1" --points N [--fields rho,u,v,p]
//   undex gauges DIR [--name NAME]
//   undex options                              list the named choices of a case file
#include "case.pb.h"
#include "case_file.hpp"
#include "h5.hpp"
#include "output.hpp"
#include "setup.hpp"
#include "structure_setup.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

const char* usage = "usage:\n"
                    "  undex check CASE [--set key=value]...\n"
                    "  undex run CASE [--set key=value]...\n"
                    "  undex sample DIR --time T --line \"x0,y0 x1,y1\" --points N [--fields rho,u,v,p]\n"
                    "  undex gauges DIR [--name NAME]\n"
                    "  undex options\n";

struct Args {
    std::vector<std::string> positional;
    std::vector<std::string> overrides;
    std::map<std::string, std::string> options;
};

Args parse(int argc, char** argv, int first) {
    Args a;
    for (int k = first; k < argc; ++k) {
        std::string s = argv[k];
        if (s.rfind("--", 0) == 0) {
            std::string key = s.substr(2), value;
            const auto eq = key.find('=');
            if (eq != std::string::npos)
                value = key.substr(eq + 1), key = key.substr(0, eq);
            else if (k + 1 < argc)
                value = argv[++k];
            else
                throw std::invalid_argument("option --" + key + " needs a value");
            if (key == "set")
                a.overrides.push_back(value);
            else
                a.options[key] = value;
        } else {
            a.positional.push_back(s);
        }
    }
    return a;
}

std::string h5_of(const std::string& dir) {
    const std::filesystem::path p(dir);
    if (!std::filesystem::is_directory(p)) return dir;
    // A structure-only run has solid.h5 and no fluid.h5.
    if (!std::filesystem::exists(p / "fluid.h5") && std::filesystem::exists(p / "solid.h5"))
        return (p / "solid.h5").string();
    return (p / "fluid.h5").string();
}

// Which parts the case holds; each is checked in full. A case with neither is an error.
struct Parts {
    bool fluid, structure;
};
Parts check_parts(const undex::CaseFile& c) {
    const Parts p{undex::solid::has_fluid(c), undex::solid::has_structure(c)};
    if (!p.fluid && !p.structure)
        c.fail("regions", "the case models nothing: give fluid regions or a structure");
    if (p.fluid) undex::fluid::validate(c);
    if (p.structure) undex::solid::make_structure(c);
    return p;
}

int check(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("check needs one CASE");
    const auto c = undex::CaseFile::load(a.positional[0], a.overrides);
    const Parts parts = check_parts(c);
    const auto& m = c.get();
    if (parts.structure) {
        const auto s = undex::solid::make_structure(c);
        std::cout << a.positional[0] << ": ok: structure of " << m.structure().layers_size() << " layer(s), "
                  << (s.plate ? s.plate->element_count() : s.column->element_count()) << " elements"
                  << (s.plate ? (s.plate->plane() == undex::solid::Plane::Axisymmetric ? " (axisymmetric)"
                                                                                       : " (plane strain)")
                              : "")
                  << ", time step " << s.dt << " s";
        if (!parts.fluid) {
            std::cout << ", end time " << m.end_time() << " s\n";
            return 0;
        }
        std::cout << "; ";
    }
    const auto p = undex::fluid::plan(c);
    std::cout << a.positional[0] << ": ok: " << undex::config::Geometry_Name(m.geometry()) << ", "
              << m.domain().cells_x();
    if (m.domain().has_cells_y()) std::cout << " x " << m.domain().cells_y();
    std::cout << " cells, degree " << m.numerics().degree() << ", end time " << m.end_time() << " s, "
              << p.output_times.size() << " output time(s), output to " << p.directory << "\n";
    return 0;
}

int run(const Args& a, char** argv) {
    if (a.positional.size() != 1) throw std::invalid_argument("run needs one CASE");
    // Check the case here so that a bad case is reported before any process starts.
    const auto c = undex::CaseFile::load(a.positional[0], a.overrides);
    const Parts parts = check_parts(c);
    if (parts.structure && parts.fluid)
        throw std::runtime_error(a.positional[0] + ": a fluid with a structure needs the coupler, which this "
                                                   "version does not have yet; each part alone runs");
    // A single-field case needs only its own process.
    const auto self = std::filesystem::read_symlink("/proc/self/exe");
    const std::string fluid = (self.parent_path() / (parts.fluid ? "undex-fluid" : "undex-solid")).string();
    std::vector<std::string> args = {fluid, a.positional[0]};
    for (const auto& o : a.overrides)
        args.insert(args.end(), {"--set", o});
    std::vector<char*> cargs;
    for (auto& s : args)
        cargs.push_back(s.data());
    cargs.push_back(nullptr);
    std::cout.flush();
    execv(fluid.c_str(), cargs.data());
    std::cerr << "undex: error: cannot start " << fluid << ": " << std::strerror(errno) << "\n";
    (void)argv;
    return 1;
}

std::vector<double> parse_point(const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string part;
    while (std::getline(ss, part, ','))
        v.push_back(std::stod(part));
    if (v.size() == 1) v.push_back(0.0);
    if (v.size() != 2) throw std::invalid_argument("a point is x,y (got '" + s + "')");
    return v;
}

int sample(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("sample needs one output DIR");
    for (const char* k : {"time", "line", "points"})
        if (!a.options.count(k)) throw std::invalid_argument(std::string("sample needs --") + k);
    const std::string h5 = h5_of(a.positional[0]);
    if (std::filesystem::path(h5).filename() == "solid.h5")
        throw std::runtime_error(h5 + ": sample evaluates fluid fields; a structure's fields are datasets of "
                                      "solid.h5 (fields/NNNNNN) and its gauges print with `undex gauges`");
    const auto run = undex::fluid::read_run(h5);
    if (run.times.empty()) throw std::runtime_error(h5 + ": holds no output");
    const double t = std::stod(a.options.at("time"));
    size_t best = 0;
    for (size_t k = 1; k < run.times.size(); ++k)
        if (std::abs(run.times[k] - t) < std::abs(run.times[best] - t)) best = k;
    const auto c = undex::CaseFile::from_text(run.case_text, h5);
    auto solver = undex::fluid::make_solver(c);
    solver->set_coefficients(undex::fluid::read_coefficients(h5, run.groups[best]), run.times[best]);
    const auto phi = undex::fluid::read_level_set(h5, run.groups[best]);
    if (!phi.empty()) solver->set_level_set(phi);
    std::stringstream line(a.options.at("line"));
    std::string p0s, p1s;
    line >> p0s >> p1s;
    const auto p0 = parse_point(p0s), p1 = parse_point(p1s);
    const int n = std::stoi(a.options.at("points"));
    if (n < 1) throw std::invalid_argument("--points must be ≥ 1");
    std::vector<std::string> fields = {"rho", "u", "v", "p"};
    if (a.options.count("fields")) {
        fields.clear();
        std::stringstream fs(a.options.at("fields"));
        std::string f;
        while (std::getline(fs, f, ','))
            if (f == "rho" || f == "u" || f == "v" || f == "p")
                fields.push_back(f);
            else
                throw std::invalid_argument("unknown field '" + f + "' (fields: rho, u, v, p)");
    }
    std::printf("# time = %.9g s\nx,y", run.times[best]);
    for (const auto& f : fields)
        std::printf(",%s", f.c_str());
    std::printf("\n");
    for (int k = 0; k < n; ++k) {
        const double s = n == 1 ? 0.0 : double(k) / (n - 1);
        const double x = p0[0] + s * (p1[0] - p0[0]), y = p0[1] + s * (p1[1] - p0[1]);
        const auto w = solver->evaluate(x, y);
        std::printf("%.9g,%.9g", x, y);
        for (const auto& f : fields)
            std::printf(",%.12g", f == "rho" ? w.rho : f == "u" ? w.u : f == "v" ? w.v : w.p);
        std::printf("\n");
    }
    return 0;
}

int gauges(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("gauges needs one output DIR");
    const std::string h5 = h5_of(a.positional[0]);
    const auto run = undex::fluid::read_run(h5);
    std::vector<std::string> names = run.gauge_names;
    if (a.options.count("name")) {
        names = {a.options.at("name")};
        bool found = false;
        for (const auto& g : run.gauge_names)
            found = found || g == names[0];
        if (!found) throw std::runtime_error("no gauge named '" + names[0] + "' in " + h5);
    }
    if (names.empty()) throw std::runtime_error(h5 + ": the case has no gauges");
    const bool solid = std::filesystem::path(h5).filename() == "solid.h5";
    std::vector<std::string> columns = {"t", "rho", "u", "v", "p"};
    if (solid) { // the structure output lists its gauge columns
        columns.clear();
        hid_t f = undex::h5::open_read(h5);
        hid_t g = H5Gopen2(f, "gauges", H5P_DEFAULT);
        std::stringstream list(undex::h5::read_attr_string(g, "columns"));
        H5Gclose(g);
        H5Fclose(f);
        for (std::string c; std::getline(list, c, ',');)
            columns.push_back(c);
    }
    std::vector<std::vector<std::vector<double>>> cols;
    for (const auto& n : names)
        cols.push_back(undex::fluid::read_gauge(h5, n, columns));
    std::printf("t");
    const bool many = names.size() > 1;
    for (const auto& n : names)
        for (size_t f = 1; f < columns.size(); ++f)
            std::printf(many ? ",%s.%s" : ",%s", many ? n.c_str() : columns[f].c_str(), columns[f].c_str());
    std::printf("\n");
    const size_t rows = cols[0][0].size();
    for (size_t r = 0; r < rows; ++r) {
        std::printf("%.12g", cols[0][0][r]);
        for (const auto& g : cols)
            for (size_t f = 1; f < columns.size(); ++f)
                std::printf(",%.12g", r < g[f].size() ? g[f][r] : NAN);
        std::printf("\n");
    }
    return 0;
}

int options() {
    std::cout << "numerics.indicator:\n";
    for (const auto& n : undex::fluid::indicator_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "numerics.limiter:\n";
    for (const auto& n : undex::fluid::limiter_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "interface.method:\n";
    for (const auto& n : undex::fluid::ghost_method_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "interface.riemann:\n";
    for (const auto& n : undex::fluid::interface_riemann_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "structure.kinematics:\n";
    for (const auto& n : undex::solid::kinematics_names())
        std::cout << "  " << n.first << "  " << n.second << "\n";
    std::cout << "geometry: PLANAR_1D CYLINDRICAL_1D SPHERICAL_1D PLANAR_2D AXISYMMETRIC_2D\n"
              << "boundary type: TRANSMISSIVE WALL SYMMETRY PRESSURE PERIODIC\n"
              << "material models: stiffened_gas { gamma p_inf }, tait { gamma B A rho0 as_stiffened_gas }\n"
              << "the schema with every field and its default: proto/case.proto\n";
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << usage;
        return 64;
    }
    const std::string cmd = argv[1];
    try {
        const Args a = parse(argc, argv, 2);
        if (cmd == "check") return check(a);
        if (cmd == "run") return run(a, argv);
        if (cmd == "sample") return sample(a);
        if (cmd == "gauges") return gauges(a);
        if (cmd == "options") return options();
        if (cmd == "help" || cmd == "--help" || cmd == "-h") {
            std::cout << usage;
            return 0;
        }
        std::cerr << "undex: unknown command '" << cmd << "'\n" << usage;
        return 64;
    } catch (const undex::CaseError& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return 1;
    } catch (const std::invalid_argument& e) {
        std::cerr << "undex: error: " << e.what() << "\n" << usage;
        return 64;
    } catch (const std::exception& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return 1;
    }
}
