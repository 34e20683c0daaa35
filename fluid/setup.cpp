#include "fluid/setup.hpp"

#include "base/case_file.hpp"
#include "base/run_plan.hpp"
#include "fluid/eos_stiffened_gas.hpp"
#include "fluid/eos_tait.hpp"
#include "fluid/euler.hpp"
#include "fluid/scheme.hpp"
#include "fluid/two_fluid.hpp"
#include "fluid/wet_fluid.hpp"
#include "proto/case.pb.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <unistd.h>
#include <variant>

namespace undex::fluid {

namespace cfg = undex::config;

const std::vector<NamedOption>& indicator_names() {
    static const std::vector<NamedOption> names = {
        {"tvb", "TVB minmod indicator on density and energy (threshold numerics.tvb_m)"},
        {"all", "every cell is troubled (limiter everywhere)"},
        {"none", "no cell is troubled (no limiting)"},
    };
    return names;
}

const std::vector<NamedOption>& limiter_names() {
    static const std::vector<NamedOption> names = {
        {"weno", "simple WENO limiter of Zhong and Shu (2013) in characteristic variables"},
        {"minmod", "troubled cells become linear, slope limited by minmod in characteristic variables "
                   "(Cockburn and Shu 1989)"},
        {"none", "no limiting of troubled cells"},
    };
    return names;
}

const std::vector<NamedOption>& ghost_method_names() {
    static const std::vector<NamedOption> names = {
        {"real_gfm",
         "real ghost fluid method: interface Riemann states redefine the real cell and fill the ghost band"},
        {"modified_gfm", "modified ghost fluid method: the same interface states fill the ghost band only"},
        {"original_gfm",
         "original ghost fluid method: ghost pressure and velocity from the real fluid, own entropy"},
    };
    return names;
}

const std::vector<NamedOption>& interface_riemann_names() {
    static const std::vector<NamedOption> names = {
        {"double_shock", "both waves taken as shocks (Liu, Khoo and Yeo 2003), as in the paper"},
        {"exact", "exact two-material solution: shock or rarefaction on each side"},
    };
    return names;
}

namespace {

bool is_2d(cfg::Geometry g) {
    return g == cfg::PLANAR_2D || g == cfg::AXISYMMETRIC_2D;
}
int alpha_of(cfg::Geometry g) {
    switch (g) {
    case cfg::CYLINDRICAL_1D:
    case cfg::AXISYMMETRIC_2D:
        return 1;
    case cfg::SPHERICAL_1D:
        return 2;
    default:
        return 0;
    }
}

std::string choices(const std::vector<NamedOption>& names) {
    std::string s;
    for (const auto& n : names)
        s += (s.empty() ? "" : ", ") + std::string(n.name);
    return s;
}
bool known(const std::vector<NamedOption>& names, const std::string& v) {
    return std::any_of(names.begin(), names.end(), [&](const NamedOption& n) { return v == n.name; });
}

// The index of each material name (its first definition): one pass, so that checks stay linear in the size
// of the case.
std::map<std::string, int> material_indices(const cfg::Case& c) {
    std::map<std::string, int> index;
    for (int m = 0; m < c.materials_size(); ++m)
        index.emplace(c.materials(m).name(), m);
    return index;
}

int material_index(const cfg::Case& c, const std::string& name) {
    for (int m = 0; m < c.materials_size(); ++m)
        if (c.materials(m).name() == name) return m;
    return -1;
}

// ---- The equations of state a material can name: one row each (docs/adding_an_eos.md). ----

using AnyEos = std::variant<StiffenedGas, Tait>;

struct EosRow {
    const char* model;                    // the field of cfg::Material's `model` oneof
    bool (*chosen)(const cfg::Material&); // the material names this model
    // Checks the model's parameters beyond their ranges (proto/case.proto, checked before); path is the
    // material's, e.g. "materials[0]".
    void (*check)(const CaseFile&, const cfg::Material&, const std::string& path);
    // The EOS of the material; cavitation null: the cavitation model is off.
    AnyEos (*make)(const cfg::Material&, const cfg::Cavitation* cavitation);
};

const EosRow eos_table[] = {
    {"stiffened_gas", [](const cfg::Material& m) { return m.has_stiffened_gas(); },
     [](const CaseFile&, const cfg::Material&, const std::string&) {}, // ranges only (proto/case.proto)
     [](const cfg::Material& m, const cfg::Cavitation*) -> AnyEos {
         return StiffenedGas{m.stiffened_gas().gamma(), m.stiffened_gas().p_inf()};
     }},
    {"tait", [](const cfg::Material& m) { return m.has_tait(); },
     [](const CaseFile& cf, const cfg::Material& m, const std::string& p) {
         const auto& t = m.tait();
         if (!(t.b() > t.a())) cf.fail(p + ".tait.A", "A must be smaller than B");
     },
     [](const cfg::Material& m, const cfg::Cavitation* cv) -> AnyEos {
         const auto& t = m.tait();
         if (t.as_stiffened_gas()) return StiffenedGas{t.gamma(), t.b() - t.a()};
         Tait eos;
         eos.gamma = t.gamma();
         eos.B = t.b();
         eos.A = t.a();
         eos.rho0 = t.rho0();
         eos.finalize();
         eos.cavitation = cv != nullptr;
         if (eos.cavitation) {
             eos.cav.p_cav = cv->p_cav();
             eos.cav.rho_g_cav = cv->rho_g_cav();
             eos.cav.gamma_g = cv->gamma_g();
             eos.cav.alpha0 = cv->alpha0();
             eos.cav.gamma_w = eos.gamma;
             eos.cav.B = eos.B;
             eos.cav.A = eos.A;
             eos.cav.rho0 = eos.rho0;
             eos.cav.finalize();
         }
         return eos;
     }},
};

// The row of a material's model, or null if it names none.
const EosRow* eos_row(const cfg::Material& m) {
    for (const auto& row : eos_table)
        if (row.chosen(m)) return &row;
    return nullptr;
}

// The EOS of a checked material, with the case's cavitation model when it is enabled; without c, with
// cavitation off (for checking initial states).
AnyEos eos_of(const cfg::Material& m, const cfg::Case* c = nullptr) {
    const bool cav = c && c->cavitation().enabled();
    return eos_row(m)->make(m, cav ? &c->cavitation() : nullptr);
}

bool is_barotropic(const AnyEos& eos) {
    return std::visit([](const auto& e) { return std::decay_t<decltype(e)>::barotropic; }, eos);
}

bool inside(const cfg::Region& r, double x, double y) {
    if (r.has_box())
        return x >= r.box().x_min() && x <= r.box().x_max() && y >= r.box().y_min() && y <= r.box().y_max();
    if (r.has_ball()) {
        const double dx = x - r.ball().x(), dy = y - r.ball().y();
        return dx * dx + dy * dy <= r.ball().radius() * r.ball().radius();
    }
    return true;
}

void validate_boundary(const CaseFile& cf, const cfg::Boundary& b, const std::string& path) {
    if (b.type() == cfg::Boundary::TYPE_UNSET) cf.fail(path + ".type", "boundary type is not set");
    if (b.type() == cfg::Boundary::PRESSURE || b.type() == cfg::Boundary::INCIDENT) {
        const char* name = b.type() == cfg::Boundary::PRESSURE ? "a PRESSURE" : "an INCIDENT";
        if (!b.has_pressure()) cf.fail(path, std::string(name) + " boundary needs a 'pressure' history");
        validate_pressure_history(cf, b.pressure(), path + ".pressure");
    } else if (b.has_pressure()) {
        cf.fail(path + ".pressure", "a pressure history is only used by PRESSURE and INCIDENT boundaries");
    }
    if (b.type() == cfg::Boundary::ABSORBING) {
        const auto& d = cf.get().domain();
        const bool x = path.find(".x_") != std::string::npos;
        const double cell = x ? (d.x_max() - d.x_min()) / d.cells_x() : (d.y_max() - d.y_min()) / d.cells_y();
        if (!b.has_layer()) cf.fail(path, "an ABSORBING boundary needs 'layer', its thickness (m)");
        if (!(b.layer() >= 2 * cell * (1 - 1e-9))) {
            std::ostringstream m;
            m << "the layer (" << b.layer() << " m) must be at least 2 cells (" << 2 * cell << " m)";
            cf.fail(path + ".layer", m.str());
        }
    } else if (b.has_layer() || b.has_strength()) {
        cf.fail(path + (b.has_layer() ? ".layer" : ".strength"), "only an ABSORBING boundary has a layer");
    }
    if (b.type() == cfg::Boundary::INCIDENT) {
        // The incident wave's sound speeds are read on the isentrope of the water it enters (regions[0]'s
        // material): every pressure of the history must be one that material can hold.
        const cfg::Case& c = cf.get();
        const auto& h = b.pressure();
        const std::string& water = c.regions(0).material();
        const double floor = std::visit([](const auto& e) { return e.pressure_floor(); },
                                        eos_of(c.materials(material_index(c, water))));
        const auto refuse_below = [&](double p, const std::string& field, const std::string& what) {
            std::ostringstream m;
            m << what << " = " << p << " Pa must exceed " << floor + 0.0 << " Pa, the lowest pressure of '"
              << water << "' (regions[0])";
            if (!(p > floor)) cf.fail(path + ".pressure." + field, m.str());
        };
        if (h.table_t_size() > 0) {
            for (int k = 0; k < h.table_p_size(); ++k) {
                const std::string field = "table_p[" + std::to_string(k) + "]";
                refuse_below(h.table_p(k), field, field);
            }
        } else {
            refuse_below(h.p_ambient(), "p_ambient", "p_ambient");
            refuse_below(h.p_ambient() + h.p_peak(), "p_peak", "p_ambient + p_peak");
        }
    }
}

} // namespace

namespace {

// The memory of one fluid cell in a run, from the arrays of fluid/scheme.hpp, fluid/two_fluid.hpp and
// fluid/level_set.hpp: per solver the state u, u0, stage and rhs (NC = NV × NB doubles each), the face fluxes
// (D × NQF × NV doubles) and the troubled flag; an output copies the coefficients (NC doubles per solver) and
// writes a few fields per cell; two fluids have two solvers, the level set φ with its padded copy, Runge–
// Kutta and extension-velocity arrays, the masks and the primitive fields of each fluid (about 24 doubles).
// Measured against /usr/bin/time's maximum resident size (tests/cli/bad_input.sh notes the numbers).
double bytes_per_cell(int dim, int degree, bool two_fluids) {
    const int nb = dim == 1 ? degree + 1 : (degree + 1) * (degree + 2) / 2, nv = dim + 2, nc = nv * nb;
    const int nqf = dim == 1 ? 1 : degree + 1;
    const double solver = 8.0 * (4 * nc + dim * nqf * nv) + 1, output = 8.0 * (nc + 8);
    return two_fluids ? 2 * (solver + output) + 8.0 * 24 : solver + output;
}

void validate_domain(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    if (c.geometry() == cfg::GEOMETRY_UNSET) cf.fail("geometry", "geometry is not set");
    const bool two_d = is_2d(c.geometry());
    if (!c.has_domain()) cf.fail("domain", "a fluid needs a domain (x_min, x_max, cells_x)");
    if (!c.has_boundaries()) cf.fail("boundaries", "a fluid needs boundaries (x_min, x_max)");
    const auto& d = c.domain();
    if (!(d.x_max() > d.x_min())) cf.fail("domain.x_max", "x_max must be greater than x_min");
    if (alpha_of(c.geometry()) > 0 && d.x_min() < 0)
        cf.fail("domain.x_min",
                "the radius x must be non-negative in a cylindrical, spherical or axisymmetric case");
    if (two_d) {
        if (!d.has_y_min() || !d.has_y_max()) cf.fail("domain", "a 2D case needs y_min and y_max");
        if (!(d.y_max() > d.y_min())) cf.fail("domain.y_max", "y_max must be greater than y_min");
        if (!d.has_cells_y()) cf.fail("domain", "a 2D case needs cells_y");
    } else if (d.has_y_min() || d.has_y_max() || d.has_cells_y()) {
        cf.fail(d.has_cells_y() ? "domain.cells_y" : "domain.y_min", "a 1D case has no y extent");
    }
    // The cells, counted in double, against the solver's memory before anything is made; cell indices are
    // int (fluid/mesh.hpp), so the padded mesh stays below 2^31 cells as well.
    const double cells = static_cast<double>(d.cells_x()) * (two_d ? d.cells_y() : 1);
    const std::string cells_field = two_d && d.cells_y() > d.cells_x() ? "domain.cells_y" : "domain.cells_x";
    if (!((d.cells_x() + 2.0) * (two_d ? d.cells_y() + 2.0 : 1.0) < 2147483647.0))
        cf.fail(cells_field, "the mesh of " + std::to_string(static_cast<long long>(cells)) +
                                 " cells is beyond the solver's cell numbers (int, 2^31)");
    bool two_materials = false;
    for (const auto& reg : c.regions())
        two_materials |= reg.material() != c.regions(0).material(); // no regions: no loop
    undex::check_memory(cf, cells_field, "fluid cells", cells,
                        bytes_per_cell(two_d ? 2 : 1, c.numerics().degree(), two_materials));
}

void validate_materials(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    if (c.materials_size() == 0) cf.fail("materials", "no material is defined");
    const auto index = material_indices(c);
    for (int m = 0; m < c.materials_size(); ++m) {
        const auto& mat = c.materials(m);
        const std::string p = "materials[" + std::to_string(m) + "]";
        if (index.at(mat.name()) != m) cf.fail(p + ".name", "material '" + mat.name() + "' is defined twice");
        if (const EosRow* row = eos_row(mat)) {
            row->check(cf, mat, p);
        } else {
            std::string models;
            for (const auto& r : eos_table)
                models += (models.empty() ? "" : " or ") + std::string(r.model);
            cf.fail(p, "material '" + mat.name() + "' needs a model: " + models);
        }
    }
}

void validate_regions(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    const bool two_d = is_2d(c.geometry());
    if (c.regions_size() == 0) cf.fail("regions", "no initial region is defined");
    if (c.regions(0).shape_case() != cfg::Region::SHAPE_NOT_SET)
        cf.fail("regions[0]", "the first region must cover the whole domain (no box or ball)");
    const auto index = material_indices(c);
    const std::string& first = c.regions(0).material();
    const std::string* second = nullptr; // the other material, from the first region that names it
    for (int r = 0; r < c.regions_size(); ++r) {
        const auto& reg = c.regions(r);
        const std::string p = "regions[" + std::to_string(r) + "]";
        const auto found = index.find(reg.material());
        if (found == index.end()) cf.fail(p + ".material", "unknown material '" + reg.material() + "'");
        const int m = found->second;
        if (reg.material() != first) {
            if (!second) second = &reg.material();
            if (reg.material() != *second)
                cf.fail(p + ".material", "a third material '" + reg.material() +
                                             "': a case holds at most two (" + first + " and " + *second +
                                             ")");
        }
        // Without cavitation: the lowest admissible pressure, −P∞ (stiffened gas) or A − B (Tait, ρ > 0).
        const AnyEos eos = eos_of(c.materials(m));
        const double pmin = std::visit([](const auto& e) { return e.pressure_floor(); }, eos);
        if (!(reg.p() > pmin))
            cf.fail(p + ".p", "pressure " + std::to_string(reg.p()) + " Pa must exceed " +
                                  std::to_string(pmin) + " Pa (−P∞ of '" + reg.material() + "')");
        // A shape must hold part of the domain: a box not inverted and overlapping it, a ball reaching it.
        const auto& d = c.domain();
        if (reg.has_box()) {
            const auto& b = reg.box();
            if (!(b.x_min() < b.x_max())) cf.fail(p + ".box.x_max", "the box's x_max must exceed its x_min");
            if (two_d && !(b.y_min() < b.y_max()))
                cf.fail(p + ".box.y_max", "the box's y_max must exceed its y_min");
            if (!(b.x_min() < d.x_max() && b.x_max() > d.x_min()) ||
                (two_d && !(b.y_min() < d.y_max() && b.y_max() > d.y_min())))
                cf.fail(p + ".box", "the box lies outside the domain");
        }
        if (reg.has_ball()) {
            const auto& b = reg.ball();
            const double dx = std::max({d.x_min() - b.x(), b.x() - d.x_max(), 0.0});
            const double dy = two_d ? std::max({d.y_min() - b.y(), b.y() - d.y_max(), 0.0}) : 0.0;
            if (!(std::hypot(dx, dy) < b.radius())) cf.fail(p + ".ball", "the ball lies outside the domain");
            if (!two_d && b.has_y() && b.y() != 0) cf.fail(p + ".ball.y", "a 1D case has no y");
        }
        if (!two_d && reg.has_v() && reg.v() != 0) cf.fail(p + ".v", "a 1D case has no v velocity");
        if (is_barotropic(eos)) {
            // Barotropic (Tait water): the pressure follows from the density. Tolerance relative to
            // |p(ρ)| − p_min (for Tait: |p(ρ)| + B − A).
            const double p_rho = std::visit([&](const auto& e) { return e.pressure(reg.rho(), 0.0); }, eos);
            if (!std::isfinite(p_rho))
                cf.fail(p + ".rho", "material '" + reg.material() + "' gives no finite pressure at rho = " +
                                        std::to_string(reg.rho()) + " kg/m^3");
            if (std::abs(reg.p() - p_rho) > 1e-6 * (std::abs(p_rho) - pmin))
                cf.fail(p + ".p", "material '" + reg.material() +
                                      "' is barotropic, p = p(rho): rho = " + std::to_string(reg.rho()) +
                                      " kg/m^3 gives p = " + std::to_string(p_rho) + " Pa, not " +
                                      std::to_string(reg.p()) + " Pa");
        }
    }
}

// Two materials: a level set from the region shapes and the ghost fluid method.
void validate_interface(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    bool two_materials = false;
    for (const auto& reg : c.regions())
        two_materials |= reg.material() != c.regions(0).material();
    if (two_materials) {
        for (int r = 1; r < c.regions_size(); ++r)
            if (c.regions(r).shape_case() == cfg::Region::SHAPE_NOT_SET)
                cf.fail("regions[" + std::to_string(r) + "]",
                        "with two materials every region after the first needs a box or ball (it shapes the "
                        "interface)");
        const auto& in = c.interface();
        if (!known(ghost_method_names(), in.method()))
            cf.fail("interface.method",
                    "unknown method '" + in.method() + "'; choose one of " + choices(ghost_method_names()));
        if (!known(interface_riemann_names(), in.riemann()))
            cf.fail("interface.riemann", "unknown interface Riemann solver '" + in.riemann() +
                                             "'; choose one of " + choices(interface_riemann_names()));
        if (in.tube_cells() > 0 && in.tube_cells() < in.band_cells() + 4)
            cf.fail("interface.tube_cells",
                    "the narrow band of " + std::to_string(in.tube_cells()) +
                        " cells must reach 4 cells beyond the ghost band (band_cells + 4 = " +
                        std::to_string(in.band_cells() + 4) + "), or be 0 (the whole mesh)");
    }
}

// Boundaries.
void validate_boundaries(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    const bool two_d = is_2d(c.geometry());
    const auto& d = c.domain();
    const auto& b = c.boundaries();
    validate_boundary(cf, b.x_min(), "boundaries.x_min");
    validate_boundary(cf, b.x_max(), "boundaries.x_max");
    for (const auto* side : {&b.x_min(), &b.y_min(), &b.y_max()})
        if (side->type() == cfg::Boundary::STRUCTURE)
            cf.fail(side == &b.x_min()   ? "boundaries.x_min"
                    : side == &b.y_min() ? "boundaries.y_min"
                                         : "boundaries.y_max",
                    "the structure's wet face is the x_max side (STRUCTURE there)");
    if (b.x_max().type() == cfg::Boundary::STRUCTURE) {
        if (two_d)
            cf.fail("boundaries.x_max",
                    "in 2D the structure lies inside the fluid domain (its wet faces come from "
                    "the structure solver): no STRUCTURE boundary");
        if (!c.has_structure())
            cf.fail("boundaries.x_max", "a STRUCTURE boundary needs a structure in the case");
        if (c.geometry() != cfg::PLANAR_1D)
            cf.fail("boundaries.x_max", "coupling to a structure is available in PLANAR_1D cases for now");
    } else if (c.has_structure() && !two_d) {
        cf.fail("boundaries.x_max", "with a structure in the case, the fluid's x_max side is its wet face: "
                                    "STRUCTURE");
    }
    if (two_d) {
        if (!b.has_y_min() || !b.has_y_max())
            cf.fail("boundaries", "a 2D case needs y_min and y_max boundaries");
        validate_boundary(cf, b.y_min(), "boundaries.y_min");
        validate_boundary(cf, b.y_max(), "boundaries.y_max");
        if ((b.y_min().type() == cfg::Boundary::PERIODIC) != (b.y_max().type() == cfg::Boundary::PERIODIC))
            cf.fail("boundaries.y_max", "periodic boundaries come in pairs: y_min and y_max");
    } else if (b.has_y_min() || b.has_y_max()) {
        cf.fail("boundaries.y_min", "a 1D case has no y boundaries");
    }
    if ((b.x_min().type() == cfg::Boundary::PERIODIC) != (b.x_max().type() == cfg::Boundary::PERIODIC))
        cf.fail("boundaries.x_max", "periodic boundaries come in pairs: x_min and x_max");
    if (alpha_of(c.geometry()) > 0 && d.x_min() == 0 && b.x_min().type() != cfg::Boundary::SYMMETRY)
        cf.fail("boundaries.x_min", "the axis or centre x = 0 needs a SYMMETRY boundary");
    if (alpha_of(c.geometry()) > 0 && b.x_min().type() == cfg::Boundary::PERIODIC)
        cf.fail("boundaries.x_min", "a radial direction cannot be periodic");
}

// Numerics.
void validate_numerics(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    const auto& n = c.numerics();
    if (!known(indicator_names(), n.indicator()))
        cf.fail("numerics.indicator",
                "unknown indicator '" + n.indicator() + "'; choose one of " + choices(indicator_names()));
    if (!known(limiter_names(), n.limiter()))
        cf.fail("numerics.limiter",
                "unknown limiter '" + n.limiter() + "'; choose one of " + choices(limiter_names()));
    // Degree 2 next to a structure's ghost band in 2D: a mode along the wet face, seeded by round-off, grows
    // at CFL 0.2 (still water under a plate: the wet nodes' pressures 50 kPa apart within 0.1 ms) and not at
    // 0.15 (README, 2D coupling).
    if (is_2d(c.geometry()) && c.has_structure() && n.degree() == 2 && n.cfl() > 0.15)
        cf.fail("numerics.cfl", "degree 2 next to a structure in 2D is unstable above CFL 0.15 (it is " +
                                    std::to_string(n.cfl()) +
                                    "): set numerics.cfl at most 0.15, or degree 1");
}

// Cavitation.
void validate_cavitation(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    if (c.cavitation().enabled()) {
        bool barotropic = false;
        const auto index = material_indices(c);
        for (const auto& reg : c.regions())
            barotropic |= is_barotropic(eos_of(c.materials(index.at(reg.material()))));
        if (!barotropic)
            cf.fail("cavitation.enabled",
                    "the cavitation model needs barotropic Tait water, and no region holds it");
    }
}

// Gauges (base/run_plan.hpp checks times and output).
void validate_frames(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    const auto& o = c.output();
    if (o.frame_interval() == 0) return;
    if (!is_2d(c.geometry())) cf.fail("output.frame_interval", "frames are pictures of a 2D fluid");
    if (c.end_time() / o.frame_interval() > 1e5)
        cf.fail("output.frame_interval", "more than 100000 frames: choose a longer interval");
}

void validate_gauges(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    const bool two_d = is_2d(c.geometry());
    const auto& d = c.domain();
    std::set<std::string> names;
    for (int g = 0; g < c.gauges_size(); ++g) {
        const auto& ga = c.gauges(g);
        const std::string p = "gauges[" + std::to_string(g) + "]";
        if (!names.insert(ga.name()).second)
            cf.fail(p + ".name", "gauge '" + ga.name() + "' is defined twice");
        if (ga.x() < d.x_min() || ga.x() > d.x_max()) cf.fail(p + ".x", "gauge lies outside the domain");
        if (two_d && (ga.y() < d.y_min() || ga.y() > d.y_max()))
            cf.fail(p + ".y", "gauge lies outside the domain");
    }
}

} // namespace

void validate(const CaseFile& cf) {
    undex::validate_plan(cf);
    validate_domain(cf);
    validate_materials(cf);
    validate_regions(cf);
    validate_interface(cf);
    validate_boundaries(cf);
    validate_numerics(cf);
    validate_cavitation(cf);
    validate_gauges(cf);
    validate_frames(cf);
}

namespace {

Boundary boundary(const cfg::Boundary& b) {
    Boundary out;
    switch (b.type()) {
    case cfg::Boundary::WALL:
        out.type = BoundaryType::Wall;
        break;
    case cfg::Boundary::SYMMETRY:
        out.type = BoundaryType::Symmetry;
        break;
    case cfg::Boundary::PRESSURE:
        out.type = BoundaryType::Pressure;
        out.pressure = pressure_history(b.pressure());
        break;
    case cfg::Boundary::PERIODIC:
        out.type = BoundaryType::Periodic;
        break;
    case cfg::Boundary::STRUCTURE:
        out.type = BoundaryType::Structure;
        break;
    case cfg::Boundary::INCIDENT:
        // The still water outside: the history's pressure before the wave arrives.
        out.type = BoundaryType::Incident;
        out.pressure = pressure_history(b.pressure());
        out.p_ambient = b.pressure().table_p_size() > 0 ? b.pressure().table_p(0) : b.pressure().p_ambient();
        break;
    case cfg::Boundary::ABSORBING:
        out.type = BoundaryType::Absorbing;
        out.strength = b.strength();
        break;
    default:
        out.type = BoundaryType::Transmissive;
    }
    return out;
}

// Cells of a side's absorbing layer of `cell` metres per cell (0 for other boundaries).
int layer_cells(const cfg::Boundary& b, double cell) {
    return b.type() == cfg::Boundary::ABSORBING ? static_cast<int>(std::lround(b.layer() / cell)) : 0;
}

template <int D, int K, class Eos>
std::unique_ptr<Scheme<D, K, Eos>> build(const cfg::Case& c, const Mesh& mesh, const Eos& eos,
                                         const Settings& s, const std::array<Boundary, 4>& bc) {
    auto solver = std::make_unique<Scheme<D, K, Eos>>(mesh, eos, s, bc);
    solver->project([&](double x, double y, double* q) {
        const cfg::Region* reg = &c.regions(0);
        for (const auto& r : c.regions())
            if (inside(r, x, y)) reg = &r;
        euler::to_conserved<D>(eos, Primitive{reg->rho(), reg->u(), reg->v(), reg->p()}, q);
    });
    return solver;
}

template <int D, class Eos>
std::unique_ptr<FluidSolver> build_degree(const cfg::Case& c, const Mesh& m, const Eos& eos,
                                          const Settings& s, const std::array<Boundary, 4>& bc) {
    switch (s.degree) {
    case 0:
        return build<D, 0>(c, m, eos, s, bc);
    case 1:
        return build<D, 1>(c, m, eos, s, bc);
    default:
        return build<D, 2>(c, m, eos, s, bc);
    }
}

template <class Eos>
std::unique_ptr<FluidSolver> build_dim(const cfg::Case& c, const Mesh& m, const Eos& eos, const Settings& s,
                                       const std::array<Boundary, 4>& bc) {
    return m.dim == 1 ? build_degree<1>(c, m, eos, s, bc) : build_degree<2>(c, m, eos, s, bc);
}

// Signed distance to a region's shape (negative inside).
double signed_distance(const cfg::Region& r, double x, double y, int dim) {
    if (r.has_ball()) {
        const double dx = x - r.ball().x(), dy = dim == 2 ? y - r.ball().y() : 0.0;
        return std::hypot(dx, dy) - r.ball().radius();
    }
    const auto& b = r.box();
    const double ox = std::max(b.x_min() - x, x - b.x_max());
    const double oy = dim == 2 ? std::max(b.y_min() - y, y - b.y_max()) : -1e300;
    if (ox <= 0 && oy <= 0) return std::max(ox, oy);
    return std::hypot(std::max(ox, 0.0), std::max(oy, 0.0));
}

// Conserved state of material `name` at (x, y): the last region of that material containing the point, or
// else its first region (each fluid's data continued over the whole domain; the ghost fluid method
// overwrites what lies beyond the interface).
template <int D, class Eos>
void state_of(const cfg::Case& c, const std::string& name, const Eos& eos, double x, double y, double* q) {
    const cfg::Region* reg = nullptr;
    for (const auto& r : c.regions())
        if (r.material() == name && (inside(r, x, y) || !reg)) reg = &r;
    euler::to_conserved<D>(eos, Primitive{reg->rho(), reg->u(), reg->v(), reg->p()}, q);
}

template <int D, int K, class EosM, class EosP>
std::unique_ptr<TwoFluid<D, K, EosM, EosP>>
build_two(const cfg::Case& c, const Mesh& mesh, const EosM& em, const EosP& ep, const Settings& s,
          const std::array<Boundary, 4>& bc, const InterfaceSettings& is) {
    const std::string plus = c.regions(0).material();
    std::string minus;
    for (const auto& r : c.regions())
        if (r.material() != plus && minus.empty()) minus = r.material();
    auto solver = std::make_unique<TwoFluid<D, K, EosM, EosP>>(mesh, em, ep, s, bc, is, minus, plus);
    solver->initialise(
        [&](double x, double y) {
            double phi = 1e300;
            for (int r = 1; r < c.regions_size(); ++r) {
                const double sd = signed_distance(c.regions(r), x, y, D);
                phi = c.regions(r).material() == minus ? std::min(phi, sd) : std::max(phi, -sd);
            }
            return phi;
        },
        [&](double x, double y, double* q) { state_of<D>(c, minus, em, x, y, q); },
        [&](double x, double y, double* q) { state_of<D>(c, plus, ep, x, y, q); });
    return solver;
}

template <class EosM, class EosP>
std::unique_ptr<FluidSolver> build_two_dim(const cfg::Case& c, const Mesh& m, const EosM& em, const EosP& ep,
                                           const Settings& s, const std::array<Boundary, 4>& bc,
                                           const InterfaceSettings& is) {
    const bool one = m.dim == 1;
    switch (s.degree) {
    case 0:
        if (one) return build_two<1, 0>(c, m, em, ep, s, bc, is);
        return build_two<2, 0>(c, m, em, ep, s, bc, is);
    case 1:
        if (one) return build_two<1, 1>(c, m, em, ep, s, bc, is);
        return build_two<2, 1>(c, m, em, ep, s, bc, is);
    default:
        if (one) return build_two<1, 2>(c, m, em, ep, s, bc, is);
        return build_two<2, 2>(c, m, em, ep, s, bc, is);
    }
}

// A 2D fluid around a structure (fluid/wet_fluid.hpp): one fluid, or two (a gas bubble in water). Each wet
// face gets its own fluid, built from the case when the structure attaches; the case is copied so that the
// builder outlives the caller's.
template <int K, class Eos>
std::unique_ptr<FluidSolver> build_wet(const cfg::Case& c, const Mesh& m, const Eos& eos, const Settings& s,
                                       const std::array<Boundary, 4>& bc) {
    using F = Scheme<2, K, Eos>;
    return std::make_unique<WetFluid<K, F>>(
        m, std::function<std::unique_ptr<F>()>(
               [c = cfg::Case(c), m, eos, s, bc] { return build<2, K>(c, m, eos, s, bc); }));
}
template <int K, class EosM, class EosP>
std::unique_ptr<FluidSolver> build_wet_two(const cfg::Case& c, const Mesh& m, const EosM& em, const EosP& ep,
                                           const Settings& s, const std::array<Boundary, 4>& bc,
                                           const InterfaceSettings& is) {
    using F = TwoFluid<2, K, EosM, EosP>;
    return std::make_unique<WetFluid<K, F>>(
        m, std::function<std::unique_ptr<F>()>([c = cfg::Case(c), m, em, ep, s, bc, is] {
            return build_two<2, K>(c, m, em, ep, s, bc, is);
        }));
}
template <class Eos>
std::unique_ptr<FluidSolver> build_wet_degree(const cfg::Case& c, const Mesh& m, const Eos& eos,
                                              const Settings& s, const std::array<Boundary, 4>& bc) {
    switch (s.degree) {
    case 0:
        return build_wet<0>(c, m, eos, s, bc);
    case 1:
        return build_wet<1>(c, m, eos, s, bc);
    default:
        return build_wet<2>(c, m, eos, s, bc);
    }
}
template <class EosM, class EosP>
std::unique_ptr<FluidSolver>
build_wet_two_degree(const cfg::Case& c, const Mesh& m, const EosM& em, const EosP& ep, const Settings& s,
                     const std::array<Boundary, 4>& bc, const InterfaceSettings& is) {
    switch (s.degree) {
    case 0:
        return build_wet_two<0>(c, m, em, ep, s, bc, is);
    case 1:
        return build_wet_two<1>(c, m, em, ep, s, bc, is);
    default:
        return build_wet_two<2>(c, m, em, ep, s, bc, is);
    }
}

} // namespace

std::unique_ptr<FluidSolver> make_solver(const CaseFile& cf) {
    validate(cf);
    const cfg::Case& c = cf.get();
    Mesh mesh;
    mesh.dim = is_2d(c.geometry()) ? 2 : 1;
    mesh.alpha = alpha_of(c.geometry());
    mesh.nx = c.domain().cells_x();
    mesh.x_min = c.domain().x_min();
    mesh.x_max = c.domain().x_max();
    mesh.dx = (mesh.x_max - mesh.x_min) / mesh.nx;
    if (mesh.dim == 2) {
        mesh.ny = c.domain().cells_y();
        mesh.y_min = c.domain().y_min();
        mesh.y_max = c.domain().y_max();
        mesh.dy = (mesh.y_max - mesh.y_min) / mesh.ny;
    }
    Settings s;
    const auto& n = c.numerics();
    s.degree = n.degree();
    s.cfl = n.cfl();
    s.indicator = n.indicator() == "tvb"   ? Indicator::Tvb
                  : n.indicator() == "all" ? Indicator::All
                                           : Indicator::None;
    s.tvb_m = n.tvb_m();
    s.limiter = n.limiter() == "weno"     ? Limiter::Weno
                : n.limiter() == "minmod" ? Limiter::Minmod
                                          : Limiter::None;
    s.weno_neighbour_weight = n.weno_neighbour_weight();
    s.weno_epsilon = n.weno_epsilon();
    s.positivity = n.positivity();
    s.positivity_epsilon = n.positivity_epsilon();
    const auto& still = c.regions(0);
    s.skip_rest = n.skip_rest() && still.u() == 0 && still.v() == 0;
    s.rest = {still.rho(), 0.0, 0.0, still.p()};
    std::array<Boundary, 4> bc;
    bc[0] = boundary(c.boundaries().x_min());
    bc[1] = boundary(c.boundaries().x_max());
    if (mesh.dim == 2) {
        bc[2] = boundary(c.boundaries().y_min());
        bc[3] = boundary(c.boundaries().y_max());
    }
    // Absorbing layers: the mesh grows beyond the domain by whole cells.
    const auto& cb = c.boundaries();
    bc[0].layer_cells = layer_cells(cb.x_min(), mesh.dx);
    bc[1].layer_cells = layer_cells(cb.x_max(), mesh.dx);
    mesh.nx += bc[0].layer_cells + bc[1].layer_cells;
    mesh.x_min -= bc[0].layer_cells * mesh.dx;
    mesh.x_max += bc[1].layer_cells * mesh.dx;
    if (mesh.dim == 2) {
        bc[2].layer_cells = layer_cells(cb.y_min(), mesh.dy);
        bc[3].layer_cells = layer_cells(cb.y_max(), mesh.dy);
        mesh.ny += bc[2].layer_cells + bc[3].layer_cells;
        mesh.y_min -= bc[2].layer_cells * mesh.dy;
        mesh.y_max += bc[3].layer_cells * mesh.dy;
    }
    const auto eos_plus = eos_of(c.materials(material_index(c, c.regions(0).material())), &c);
    const cfg::Region* other = nullptr;
    for (const auto& r : c.regions())
        if (r.material() != c.regions(0).material() && !other) other = &r;
    const bool wet = mesh.dim == 2 && c.has_structure();
    if (!other && wet)
        return std::visit([&](const auto& eos) { return build_wet_degree(c, mesh, eos, s, bc); }, eos_plus);
    if (!other) return std::visit([&](const auto& eos) { return build_dim(c, mesh, eos, s, bc); }, eos_plus);
    InterfaceSettings is;
    const auto& in = c.interface();
    is.method = in.method() == "original_gfm"   ? GhostMethod::Original
                : in.method() == "modified_gfm" ? GhostMethod::Modified
                                                : GhostMethod::Real;
    is.riemann = in.riemann() == "exact" ? InterfaceRiemann::Exact : InterfaceRiemann::DoubleShock;
    is.band_cells = in.band_cells();
    is.reinit_every = in.reinit_every();
    is.reinit_iterations = in.reinit_iterations();
    is.tube_cells = in.tube_cells();
    const auto eos_minus = eos_of(c.materials(material_index(c, other->material())), &c);
    if (wet)
        return std::visit(
            [&](const auto& em, const auto& ep) { return build_wet_two_degree(c, mesh, em, ep, s, bc, is); },
            eos_minus, eos_plus);
    return std::visit(
        [&](const auto& em, const auto& ep) { return build_two_dim(c, mesh, em, ep, s, bc, is); }, eos_minus,
        eos_plus);
}

} // namespace undex::fluid
