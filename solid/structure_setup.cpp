#include "solid/structure_setup.hpp"

#include "solid/column_1d.hpp"
#include "solid/plate_2d.hpp"

#include "base/case_file.hpp"
#include "base/run_plan.hpp"
#include "proto/case.pb.h"
#include "solid/material_deshpande_fleck.hpp"
#include "solid/material_elastic.hpp"
#include "solid/material_foam_1d.hpp"
#include "solid/material_johnson_cook.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace undex::solid {

namespace cfg = undex::config;

const std::vector<std::pair<const char*, const char*>>& kinematics_names() {
    static const std::vector<std::pair<const char*, const char*>> names = {
        {"uniaxial_stress",
         "through-thickness elements as a bar: lateral stresses zero (σ = Eε when elastic)"},
        {"uniaxial_strain", "a laterally confined plate: lateral strains zero (σ = (λ + 2μ)ε when elastic)"},
    };
    return names;
}

namespace {

std::string gfmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

std::shared_ptr<const MaterialLaw> make_law(const cfg::SolidMaterial& m) {
    if (m.has_elastic())
        return std::make_shared<Elastic>(m.elastic().rho(), m.elastic().e(), m.elastic().nu());
    if (m.has_johnson_cook()) {
        const auto& j = m.johnson_cook();
        JohnsonCook::Constants c;
        c.rho = j.rho(), c.E = j.e(), c.nu = j.nu(), c.A = j.a(), c.B = j.b(), c.n = j.n(), c.C = j.c();
        c.eps_dot0 = j.eps_dot0();
        return std::make_shared<JohnsonCook>(c);
    }
    if (m.has_deshpande_fleck()) {
        const auto& d = m.deshpande_fleck();
        DeshpandeFleck::Constants c;
        c.rho = d.rho(), c.E = d.e(), c.nu = d.nu(), c.alpha = d.alpha(), c.eta = d.eta();
        c.eps_p.assign(d.eps_p().begin(), d.eps_p().end());
        c.sigma_c.assign(d.sigma_c().begin(), d.sigma_c().end());
        return std::make_shared<DeshpandeFleck>(c);
    }
    const auto& f = m.foam_1d();
    Foam1D::Constants c;
    c.rho = f.rho(), c.E = f.e(), c.sigma_pl = f.sigma_pl(), c.eta = f.eta(), c.eps_d = f.eps_d(),
    c.E_lock = f.e_lock();
    return std::make_shared<Foam1D>(c);
}

const char* law_field(const cfg::SolidMaterial& m) {
    return m.has_elastic()           ? "elastic"
           : m.has_johnson_cook()    ? "johnson_cook"
           : m.has_deshpande_fleck() ? "deshpande_fleck"
                                     : "foam_1d";
}

// A face of a 1D column (FLUID on the front only: the fluid's x_max boundary is STRUCTURE) or of a 2D plate
// (FLUID on the front, the back or both: the plate lies inside the fluid's domain).
void check_face(const CaseFile& cf, const cfg::SolidFace& f, const std::string& path, bool two_d = false) {
    if (f.type() == cfg::SolidFace::TYPE_UNSET) cf.fail(path + ".type", "face type is not set");
    const bool front = path == "structure.front";
    if (f.type() == cfg::SolidFace::FLUID && !front && !two_d)
        cf.fail(path + ".type", "only the front face of a 1D column can be wetted by the fluid (FLUID)");
    if (f.type() == cfg::SolidFace::FLUID && !has_fluid(cf))
        cf.fail(path + ".type", "a FLUID face needs a fluid in the case (regions, domain, boundaries)");
    if (front && !two_d && has_fluid(cf) && f.type() != cfg::SolidFace::FLUID)
        cf.fail(path + ".type", "with a fluid in the case the front face is the wet one: FLUID");
    if (f.type() == cfg::SolidFace::PRESSURE) {
        if (!f.has_pressure()) cf.fail(path, "a PRESSURE face needs a 'pressure' history");
        undex::validate_pressure_history(cf, f.pressure(), path + ".pressure");
    } else if (f.has_pressure()) {
        cf.fail(path + ".pressure", "a pressure history is only used by PRESSURE faces");
    }
}

} // namespace

namespace {

// The most elements of a structure: node and element numbers are int (solid/plate_2d.hpp).
constexpr double max_elements = 1e9;

// The element columns of a 2D plate, in double (checked before it is made an int).
double plate_columns(const cfg::SolidPlate& pl) {
    return std::max(1.0, std::round(pl.span() / pl.element_size()));
}

// The memory of one element in a run, from the arrays of solid/column_1d.hpp and solid/plate_2d.hpp: the
// integration point state (PointState) and per node (about one per element in a large mesh) coordinates,
// displacements, velocities, accelerations, masses, forces and increments; a plate has besides its quad
// connectivity (in the mesh and in the solver), node incidence, hourglass vectors and element forces; an
// output writes a few fields per node and element.
double bytes_per_element(bool two_d) {
    const double point = sizeof(PointState), output = 8.0 * 12;
    if (!two_d) return point + 32 /* Element */ + 6 * 8 /* x, mass, u, v, a, force */ + output;
    const double node = 13 * 8 /* X, Y, u, v, a, mass, w, du */ + 2 +
                        2 * 4 /* cx, cy, incidence start, wet */ + 2 * 8 /* mesh coordinates */;
    const double element = 2 * (16 + 4) /* quads and laws, mesh and solver */ + 32 /* gamma */ +
                           2 * 8 /* kx, ky */ + 8 * 8 /* efx, efy */ + 8 /* ehg */ + 4 * 4 /* incidence */;
    return point + node + element + output;
}

// The wet faces of a 2D plate (front at y_front, back at y_front + thickness, x over the span) inside the
// fluid's domain: x within [x_min, x_max] (a plate may span a channel from wall to wall), y strictly between
// y_min and y_max (there must be fluid in front of a wet face).
void check_wet_faces(const CaseFile& cf, bool front, bool back, double thickness) {
    const auto& c = cf.get();
    if (!(front || back) || !c.has_domain()) return; // a FLUID face without a fluid is refused elsewhere
    const auto& d = c.domain();
    const auto& pl = c.structure().plate();
    const double tol = 1e-12 * std::max({std::abs(d.x_min()), std::abs(d.x_max()), d.x_max() - d.x_min()});
    const std::string box = "the fluid's domain (x " + gfmt(d.x_min()) + " to " + gfmt(d.x_max()) + ", y " +
                            gfmt(d.y_min()) + " to " + gfmt(d.y_max()) + " m)";
    if (pl.x_min() < d.x_min() - tol)
        cf.fail("structure.plate.x_min",
                "the plate's wet face starts at x = " + gfmt(pl.x_min()) + " m, outside " + box);
    if (pl.x_min() + pl.span() > d.x_max() + tol)
        cf.fail("structure.plate.span",
                "the plate's wet face ends at x = " + gfmt(pl.x_min() + pl.span()) + " m, outside " + box);
    for (int side = 0; side < 2; ++side) {
        if (!(side == 0 ? front : back)) continue;
        const double y = pl.y_front() + (side == 0 ? 0.0 : thickness);
        if (!(y > d.y_min() && y < d.y_max()))
            cf.fail("structure.plate.y_front", std::string("the plate's wet ") +
                                                   (side == 0 ? "front" : "back") +
                                                   " face lies at y = " + gfmt(y) + " m, not inside " + box);
    }
    // A clamped edge is held by a support the fluid must see: the domain's side (a plate that ends inside
    // the fluid continues there as a rigid wall along its faces, which is a clamp only at the side).
    const struct {
        const cfg::SolidEdge& edge;
        double x, side;
        const char* path;
    } edges[] = {{pl.left(), pl.x_min(), d.x_min(), "structure.plate.left"},
                 {pl.right(), pl.x_min() + pl.span(), d.x_max(), "structure.plate.right"}};
    for (const auto& e : edges)
        if (e.edge.type() == cfg::SolidEdge::CLAMPED && std::abs(e.x - e.side) > tol)
            cf.fail(std::string(e.path) + ".type",
                    "a clamped edge of a wet plate must lie on the fluid's side x = " + gfmt(e.side) +
                        " m; this one is at x = " + gfmt(e.x) + " m");
    // The second fluid (a gas bubble) may touch the plate, not overlap it: a cell inside the structure holds
    // no fluid.
    const double px0 = pl.x_min(), px1 = pl.x_min() + pl.span(), py0 = pl.y_front(), py1 = py0 + thickness;
    for (int r = 1; r < c.regions_size(); ++r) {
        const auto& reg = c.regions(r);
        if (reg.material() == c.regions(0).material()) continue;
        const std::string path = "regions[" + std::to_string(r) + "]";
        bool overlaps = false;
        if (reg.has_ball()) {
            const auto& b = reg.ball();
            const double ox = std::max({px0 - b.x(), b.x() - px1, 0.0}),
                         oy = std::max({py0 - b.y(), b.y() - py1, 0.0});
            overlaps = std::hypot(ox, oy) < b.radius() * (1 - 1e-12);
        } else if (reg.has_box()) {
            const auto& b = reg.box();
            overlaps = std::max(b.x_min(), px0) < std::min(b.x_max(), px1) &&
                       std::max(b.y_min(), py0) < std::min(b.y_max(), py1);
        }
        if (overlaps)
            cf.fail(path + (reg.has_ball() ? ".ball" : ".box"),
                    "the " + reg.material() + " region overlaps the plate (x " + gfmt(px0) + " to " +
                        gfmt(px1) + ", y " + gfmt(py0) + " to " + gfmt(py1) +
                        " m): it may touch the plate, not reach into it");
    }
}

void check_edge(const CaseFile& cf, const cfg::SolidEdge& e, const std::string& path) {
    if (e.type() == cfg::SolidEdge::TYPE_UNSET) cf.fail(path + ".type", "edge type is not set");
}

// Face and edge conditions and loads of a 2D plate. A FLUID face is wet: its nodes in order of increasing
// x, the front first (docs/protocol.md).
void apply_plate_conditions(const cfg::Structure& st, const LayeredPlate& lp, Plate2D& plate) {
    for (int side = 0; side < 2; ++side) {
        const auto& f = side == 0 ? st.front() : st.back();
        const int j = side == 0 ? 0 : lp.ny;
        if (f.type() == cfg::SolidFace::FIXED)
            for (int i = 0; i <= lp.nx; ++i)
                plate.constrain(lp.node(i, j), true, true);
        if (f.type() == cfg::SolidFace::FLUID) {
            std::vector<int> nodes;
            for (int i = 0; i <= lp.nx; ++i)
                nodes.push_back(lp.node(i, j));
            plate.add_wet_face(nodes, side == 0); // the plate lies above the front (+y), below the back
        }
        if (f.type() == cfg::SolidFace::PRESSURE) {
            // Edges in their element's counter-clockwise order: left to right on the front, right to left on
            // the back.
            std::vector<std::array<int, 2>> edges;
            for (int i = 0; i < lp.nx; ++i)
                edges.push_back(side == 0 ? std::array<int, 2>{lp.node(i, j), lp.node(i + 1, j)}
                                          : std::array<int, 2>{lp.node(i + 1, j), lp.node(i, j)});
            plate.add_pressure(edges, undex::pressure_history(f.pressure()));
        }
    }
    for (int side = 0; side < 2; ++side) {
        const auto type = (side == 0 ? st.plate().left() : st.plate().right()).type();
        const int i = side == 0 ? 0 : lp.nx;
        for (int j = 0; j <= lp.ny; ++j) {
            if (type == cfg::SolidEdge::CLAMPED) plate.constrain(lp.node(i, j), true, true);
            if (type == cfg::SolidEdge::SYMMETRY) plate.constrain(lp.node(i, j), true, false);
        }
    }
}

} // namespace

RigidPlateModel make_rigid_plate(const CaseFile& cf) {
    const auto& c = cf.get();
    undex::validate_plan(cf);
    const auto& st = c.structure();
    if (!st.has_rigid_plate()) cf.fail("structure.rigid_plate", "the structure is not a rigid plate");
    const bool two_d = c.geometry() == cfg::PLANAR_2D || c.geometry() == cfg::AXISYMMETRIC_2D;
    if (c.geometry() != cfg::PLANAR_1D && !two_d)
        cf.fail("geometry", "a rigid plate is PLANAR_1D, PLANAR_2D or AXISYMMETRIC_2D");
    if (st.materials_size()) cf.fail("structure.materials", "a rigid plate has no materials");
    if (st.layers_size()) cf.fail("structure.layers", "a rigid plate has no layers");
    if (!two_d && st.has_plate()) cf.fail("structure.plate", "a 1D rigid plate has no 'plate' mesh");
    if (two_d && !st.has_plate())
        cf.fail("structure.plate", "a 2D rigid plate needs 'plate' (x_min, span, element_size, y_front): the "
                                   "nodes of its wet face");
    if (st.gauges_size())
        cf.fail("structure.gauges", "a rigid plate has no gauges (its history is solid.h5 /gauges/plate)");
    check_face(cf, st.front(), "structure.front");
    if (st.front().type() != cfg::SolidFace::FLUID)
        cf.fail("structure.front.type", "a rigid plate is driven by the fluid: its front face is FLUID");
    if (st.back().type() != cfg::SolidFace::FREE)
        cf.fail("structure.back.type", "a rigid plate's back face is FREE (its back_pressure acts there)");
    const auto& r = st.rigid_plate(); // its numbers are within their ranges (validate_plan)
    RigidPlateModel m;
    m.mass_per_area = r.mass_per_area(), m.stiffness = r.stiffness(), m.damping = r.damping();
    m.back_pressure = r.back_pressure();
    if (two_d) {
        const auto& pl = st.plate();
        const bool axi = c.geometry() == cfg::AXISYMMETRIC_2D;
        if (pl.span() < pl.element_size() * (1 - 1e-12))
            cf.fail("structure.plate.span", "the span (" + gfmt(pl.span()) +
                                                " m) is shorter than one element (" +
                                                gfmt(pl.element_size()) + " m)");
        for (const auto* e : {&pl.left(), &pl.right()})
            if (e->type() != cfg::SolidEdge::FREE)
                cf.fail(std::string("structure.plate.") + (e == &pl.left() ? "left" : "right") + ".type",
                        "a rigid plate moves as one body: its edges are FREE");
        if (axi && !(pl.x_min() >= 0))
            cf.fail("structure.plate.x_min", "an axisymmetric plate needs x_min = r >= 0");
        const double nx = plate_columns(pl);
        if (!(nx <= 1e6))
            cf.fail("structure.plate.element_size", gfmt(nx) + " nodes; at most 1e6 in a rigid plate");
        m.dimension = 2, m.alpha = axi ? 1 : 0, m.y_front = pl.y_front();
        const int n = static_cast<int>(nx);
        for (int i = 0; i <= n; ++i) // as the mesh of a plate (layered_plate)
            m.x.push_back(i == n ? pl.x_min() + pl.span() : pl.x_min() + pl.span() * i / n);
        check_wet_faces(cf, true, false, 0);
    }
    // A spring–mass oscillator of period 2π sqrt(m/k) needs steps well below it; without a spring any step.
    m.dt = m.stiffness > 0 ? st.safety() * 0.1 * std::sqrt(m.mass_per_area / m.stiffness) : 1e300;
    if (st.has_dt()) m.dt = st.dt();
    return m;
}

void check_structure(const CaseFile& cf) {
    const auto& st = cf.get().structure();
    undex::validate_plan(cf);
    if (st.has_command()) {
        if (st.command().find_first_not_of(" \t") == std::string::npos)
            cf.fail("structure.command", "the command is empty");
        if (!has_fluid(cf))
            cf.fail("structure.command", "another structure solver needs a fluid to couple with");
        check_face(cf, st.front(), "structure.front");
        return;
    }
    if (st.has_rigid_plate()) {
        make_rigid_plate(cf);
        return;
    }
    make_structure(cf, Build::IfSmall);
}

namespace {

// The material laws by name.
std::map<std::string, std::shared_ptr<const MaterialLaw>> make_laws(const CaseFile& cf) {
    const auto& st = cf.get().structure();
    std::map<std::string, std::shared_ptr<const MaterialLaw>> laws;
    for (int m = 0; m < st.materials_size(); ++m) {
        const auto& mat = st.materials(m);
        const std::string path = "structure.materials[" + std::to_string(m) + "]";
        if (laws.count(mat.name())) cf.fail(path + ".name", "material '" + mat.name() + "' is defined twice");
        if (mat.law_case() == cfg::SolidMaterial::LAW_NOT_SET)
            cf.fail(path, "material '" + mat.name() +
                              "' needs a law: elastic, johnson_cook, deshpande_fleck or foam_1d");
        if (mat.has_deshpande_fleck()) { // the table's own entry is named, not only the law
            const auto& d = mat.deshpande_fleck();
            for (int k = 1; k < std::min(d.eps_p_size(), d.sigma_c_size()); ++k) {
                const std::string at = path + ".deshpande_fleck.", ks = std::to_string(k);
                if (!(d.eps_p(k) > d.eps_p(k - 1)))
                    cf.fail(at + "eps_p[" + ks + "]", "eps_p must increase: the crushing curve's strains");
                if (!(d.sigma_c(k) >= d.sigma_c(k - 1)))
                    cf.fail(at + "sigma_c[" + ks + "]",
                            "sigma_c must not decrease along the crushing curve (" + gfmt(d.sigma_c(k)) +
                                " Pa after " + gfmt(d.sigma_c(k - 1)) +
                                " Pa): a softening foam has no unique return");
            }
        }
        try {
            laws[mat.name()] = make_law(mat);
        } catch (const MaterialError& e) {
            cf.fail(path + "." + law_field(mat), e.what());
        }
    }
    return laws;
}

// The layers, front to back, each with its law and element count.
std::vector<Layer1D> make_layers(const CaseFile& cf,
                                 const std::map<std::string, std::shared_ptr<const MaterialLaw>>& laws,
                                 bool two_d) {
    const auto& st = cf.get().structure();
    if (st.layers_size() == 0) cf.fail("structure.layers", "a structure needs at least one layer");
    if (!two_d && (st.bulk_viscosity_quadratic() > 0 || st.bulk_viscosity_linear() > 0))
        cf.fail(st.bulk_viscosity_quadratic() > 0 ? "structure.bulk_viscosity_quadratic"
                                                  : "structure.bulk_viscosity_linear",
                "bulk viscosity is a property of the 2D plates; a 1D column has none");
    std::vector<Layer1D> layers;
    for (int l = 0; l < st.layers_size(); ++l) {
        const auto& L = st.layers(l);
        const std::string path = "structure.layers[" + std::to_string(l) + "]";
        const auto law = laws.find(L.material());
        if (law == laws.end())
            cf.fail(path + ".material", "unknown structure material '" + L.material() + "'");
        if (L.thickness() < L.element_size() * (1 - 1e-12))
            cf.fail(path + ".thickness", "the layer (" + gfmt(L.thickness()) +
                                             " m) is thinner than one element (" + gfmt(L.element_size()) +
                                             " m)");
        Layer1D layer;
        layer.law = law->second;
        layer.thickness = L.thickness();
        // Counted in double: an element size of 1e-12 m must not wrap around an int.
        const double n = std::max(1.0, std::round(L.thickness() / L.element_size()));
        if (!(n <= max_elements))
            cf.fail(path + ".element_size", gfmt(n) + " elements through the layer; at most " +
                                                gfmt(max_elements) + " in a structure");
        layer.elements = static_cast<int>(n);
        layer.uniaxial_law = law->second->name() == "foam_1d";
        if (two_d && layer.uniaxial_law)
            cf.fail(path + ".material",
                    "material '" + L.material() +
                        "' is a uniaxial foam_1d law, for 1D columns only; 2D plates need "
                        "elastic, johnson_cook or deshpande_fleck");
        layers.push_back(layer);
    }
    return layers;
}

// Faces, kinematics, safety factor, end time, output directory, hourglass factor, threads.
void check_conditions(const CaseFile& cf, bool two_d) {
    const auto& c = cf.get();
    const auto& st = c.structure();
    check_face(cf, st.front(), "structure.front", two_d);
    check_face(cf, st.back(), "structure.back", two_d);
    if (two_d && has_fluid(cf) && st.front().type() != cfg::SolidFace::FLUID &&
        st.back().type() != cfg::SolidFace::FLUID)
        cf.fail("structure.front.type", "with a fluid in the case the plate is coupled to it: its front, its "
                                        "back or both faces are FLUID");
    bool known = false;
    for (const auto& k : kinematics_names())
        known |= st.kinematics() == k.first;
    if (!known)
        cf.fail("structure.kinematics",
                "unknown kinematics '" + st.kinematics() + "'; choose uniaxial_stress or uniaxial_strain");
}

// The plate's span, element size, edges and axis.
void check_plate(const CaseFile& cf, bool axi) {
    const auto& pl = cf.get().structure().plate();
    if (pl.span() < pl.element_size() * (1 - 1e-12))
        cf.fail("structure.plate.span", "the span (" + gfmt(pl.span()) + " m) is shorter than one element (" +
                                            gfmt(pl.element_size()) + " m)");
    check_edge(cf, pl.left(), "structure.plate.left");
    check_edge(cf, pl.right(), "structure.plate.right");
    if (axi && !(pl.x_min() >= 0))
        cf.fail("structure.plate.x_min", "an axisymmetric plate needs x_min = r >= 0");
    if (axi && pl.x_min() == 0 && pl.left().type() != cfg::SolidEdge::SYMMETRY)
        cf.fail("structure.plate.left.type",
                "an axisymmetric plate from r = 0 needs SYMMETRY (the axis) there");
    const auto& st = cf.get().structure();
    double total = 0;
    for (const auto& L : st.layers())
        total += L.thickness();
    check_wet_faces(cf, st.front().type() == cfg::SolidFace::FLUID, st.back().type() == cfg::SolidFace::FLUID,
                    total);
}

// Gauges: unique names, inside the structure.
void check_gauges(const CaseFile& cf, bool two_d) {
    const auto& st = cf.get().structure();
    double total = 0;
    for (const auto& L : st.layers())
        total += L.thickness();
    const double x_min = two_d ? st.plate().x_min() : 0, span = two_d ? st.plate().span() : 0;
    std::set<std::string> names;
    for (int k = 0; k < st.gauges_size(); ++k) {
        const auto& g = st.gauges(k);
        const std::string path = "structure.gauges[" + std::to_string(k) + "]";
        if (!names.insert(g.name()).second)
            cf.fail(path + ".name", "gauge '" + g.name() + "' is defined twice");
        const double depth = two_d ? g.y() : g.x();
        if (!(depth >= 0 && depth <= total))
            cf.fail(path + (two_d ? ".y" : ".x"),
                    "gauge lies outside the structure (depth 0 to " + gfmt(total) + " m)");
        if (two_d && !(g.x() >= x_min && g.x() <= x_min + span))
            cf.fail(path + ".x", "gauge lies outside the plate (x from " + gfmt(x_min) + " to " +
                                     gfmt(x_min + span) + " m)");
        if (!two_d && g.has_y()) cf.fail(path + ".y", "a gauge of a 1D column has only the depth x");
    }
}

// A layered plate on its structured mesh, with its face and edge conditions.
std::unique_ptr<Plate2D> make_plate(const CaseFile& cf, const std::vector<Layer1D>& layers, bool axi) {
    const auto& st = cf.get().structure();
    std::vector<double> thickness;
    std::vector<int> rows;
    std::vector<std::shared_ptr<const MaterialLaw>> per_layer;
    for (const auto& L : layers) {
        thickness.push_back(L.thickness);
        rows.push_back(L.elements);
        per_layer.push_back(L.law);
    }
    const auto& pl = st.plate();
    const int nx = static_cast<int>(plate_columns(pl)); // bounded by make_structure's size check
    const LayeredPlate layout = layered_plate(pl.x_min(), pl.span(), nx, thickness, rows, pl.y_front());
    auto plate = std::make_unique<Plate2D>(layout.mesh, per_layer, axi ? Plane::Axisymmetric : Plane::Strain,
                                           st.hourglass(),
                                           BulkViscosity{st.bulk_viscosity_quadratic(), st.bulk_viscosity_linear()});
    apply_plate_conditions(st, layout, *plate);
    return plate;
}

// A layered column with its face conditions; a FLUID front face is wet.
std::unique_ptr<Column1D> make_column(const CaseFile& cf, const std::vector<Layer1D>& layers) {
    const auto& st = cf.get().structure();
    auto column = std::make_unique<Column1D>(layers, st.kinematics() == "uniaxial_strain"
                                                         ? Kinematics1D::UniaxialStrain
                                                         : Kinematics1D::UniaxialStress);
    for (int side = 0; side < 2; ++side) {
        const auto& f = side == 0 ? st.front() : st.back();
        if (f.type() == cfg::SolidFace::FIXED) column->set_face(side, Face1D::Fixed);
        if (f.type() == cfg::SolidFace::PRESSURE)
            column->set_pressure(side, undex::pressure_history(f.pressure()));
    }
    if (st.front().type() == cfg::SolidFace::FLUID) column->set_wet(0);
    return column;
}

} // namespace

StructureModel make_structure(const CaseFile& cf, Build build) {
    const auto& c = cf.get();
    if (!c.has_structure()) cf.fail("structure", "the case has no structure");
    undex::validate_plan(cf);
    const auto& st = c.structure();
    if (st.has_rigid_plate())
        cf.fail("structure.rigid_plate", "a rigid plate is solved by undex-rigid, not undex-solid");
    if (st.has_command())
        cf.fail("structure.command", "the structure is solved by '" + st.command() + "', not undex-solid");
    const bool two_d = c.geometry() == cfg::PLANAR_2D || c.geometry() == cfg::AXISYMMETRIC_2D;
    const bool axi = c.geometry() == cfg::AXISYMMETRIC_2D;
    if (!two_d && c.geometry() != cfg::PLANAR_1D)
        cf.fail("geometry",
                "a structure is a 1D column (PLANAR_1D) or a 2D plate (PLANAR_2D, AXISYMMETRIC_2D)");
    if (two_d && !st.has_plate())
        cf.fail("structure.plate", "a 2D structure needs 'plate' (x_min, span, element_size, left, right)");
    if (!two_d && st.has_plate()) cf.fail("structure.plate", "a 1D column (PLANAR_1D) has no plate");
    if (two_d && st.has_kinematics())
        cf.fail("structure.kinematics", "kinematics applies to 1D columns only; 2D plates are "
                                        "plane strain (PLANAR_2D) or axisymmetric (AXISYMMETRIC_2D)");
    const auto layers = make_layers(cf, make_laws(cf), two_d);
    check_conditions(cf, two_d);
    if (two_d) check_plate(cf, axi);
    check_gauges(cf, two_d);

    StructureModel model;
    model.threads = st.threads();
    for (const auto& L : st.layers())
        model.layers.push_back(L.material());
    // The size, in double, before anything is made.
    double rows = 0;
    for (const auto& L : layers)
        rows += L.elements;
    model.elements = two_d ? rows * plate_columns(st.plate()) : rows;
    const std::string size_field = two_d ? "structure.plate.element_size" : "structure.layers";
    if (!(model.elements <= max_elements))
        cf.fail(size_field,
                gfmt(model.elements) + " elements; at most " + gfmt(max_elements) + " in a structure");
    undex::check_memory(cf, size_field, "structure elements", model.elements, bytes_per_element(two_d));
    if (build == Build::IfSmall && model.elements * bytes_per_element(two_d) > check_build_bytes)
        return model; // checked but for the forced time step against the stable one: at run time
    if (two_d)
        model.structure = make_plate(cf, layers, axi);
    else
        model.structure = make_column(cf, layers);
    model.wet = !model.structure->wet_nodes().empty();
    const double stable = model.structure->stable_dt();
    model.dt = st.safety() * stable;
    if (st.has_dt()) {
        if (st.dt() > stable)
            cf.fail("structure.dt", "time step " + gfmt(st.dt()) + " s exceeds the stable one, " +
                                        gfmt(stable) + " s (min L_e / c_e)");
        model.dt = st.dt();
    }
    return model;
}

} // namespace undex::solid
