#include "solid/run_structure.hpp"

#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "base/run_driver.hpp"
#include "base/run_plan.hpp"
#include "base/signals.hpp"
#include "coupler/participant.hpp"
#include "proto/case.pb.h"
#include "solid/structure_setup.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace undex::solid {

namespace {

std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (size_t k = 0; k < v.size(); ++k)
        s += (k ? "," : "") + v[k];
    return s;
}

// solid.h5 of any structure model (run_structure.hpp describes the layout).
class StructureOutput {
  public:
    StructureOutput(const std::string& dir, const std::string& case_text, const Structure& s,
                    const std::vector<std::string>& layers)
        : s_(s), file_(dir, "solid.h5", case_text) {
        h5::write_attr<long>(file_.id(), "dimension", s.dimension());
        h5::write_attr<long>(file_.id(), "nodes", static_cast<long>(s.nodes()));
        h5::write_attr<long>(file_.id(), "elements", static_cast<long>(s.element_count()));
        h5::write_attr_string(file_.id(), "layers", join(layers));
        for (const Field& f : s.mesh_fields())
            write_field(file_.id(), f);
        h5::create_group(file_.id(), "fields").close();
        h5::create_group(file_.id(), "energies").close();
        h5::Object g = h5::create_group(file_.id(), "gauges");
        h5::write_attr_string(g.id(), "columns", join(gauge_columns()));
        g.close();
        file_.flush();
    }

    // Resuming from a checkpoint: the existing solid.h5 as it was at the checkpoint (the outputs written
    // after it deleted); the gauges are added, then restored by resume().
    StructureOutput(const std::string& dir, const Structure& s)
        : s_(s), file_(dir, "solid.h5", h5::OutputFile::Reopen{}) {}
    void resume(State& st) {
        state(st);
        file_.delete_numbered("fields", count_);
        write_tables(); // flushes the file
        if (s_.dimension() == 2 && !snapshots_.empty()) write_xdmf(s_.state_fields());
    }
    // What a checkpoint holds of the output: the series so far and the outputs written.
    void state(State& st) {
        st.io("count", count_);
        for (size_t k = 0; k < gauges_.size(); ++k)
            st.io("gauge" + std::to_string(k), gauges_[k].series);
        st.io("energies", energies_);
        st.io("layer_energies", layer_energies_);
        st.io("layer_count", layer_count_);
        io_snapshots(st, snapshots_);
    }

    // A gauge at (x, y) of the reference configuration (1D: x is the depth).
    void add_gauge(const std::string& name, double x, double y) {
        gauges_.push_back({name, s_.locate(x, y), {}});
    }
    void record() {
        const Energies& e = s_.energies();
        energies_.insert(energies_.end(), {s_.time(), e.kinetic, e.elastic(), e.plastic, e.viscous,
                                           e.hourglass, e.external, e.coupling, e.balance_error()});
        const auto laws = s_.law_energies();
        if (!laws.empty()) {
            layer_energies_.push_back(s_.time());
            for (const Energies& l : laws)
                layer_energies_.insert(layer_energies_.end(),
                                       {l.kinetic, l.elastic(), l.plastic, l.viscous, l.hourglass});
            layer_count_ = laws.size();
        }
        for (auto& g : gauges_) {
            g.series.push_back(s_.time());
            s_.gauge_values(g.site, g.series);
        }
    }
    void write_fields(bool last_good = false) {
        char name[32];
        std::snprintf(name, sizeof name, "fields/%06d", count_++);
        h5::Object group = h5::create_group(file_.id(), name);
        const hid_t g = group.id();
        h5::write_attr<double>(g, "time", s_.time());
        h5::write_attr<long>(g, "step", s_.steps());
        h5::write_attr<long>(g, "last_good", last_good ? 1 : 0);
        const auto fields = s_.state_fields();
        for (const Field& f : fields)
            write_field(g, f);
        group.close();
        write_tables();                          // flushes the file
        snapshots_.push_back({name, s_.time()}); // solid.xmf shows what the file holds
        if (s_.dimension() == 2) write_xdmf(fields);
    }
    void write_tables() {
        h5::write_table(file_.id(), "energies",
                        {"t", "kinetic", "elastic", "plastic", "viscous", "hourglass", "external", "coupling",
                         "balance_error"},
                        energies_);
        if (layer_count_ > 0) {
            std::vector<std::string> columns{"t"};
            for (size_t l = 0; l < layer_count_; ++l)
                for (const char* c : {"kinetic_", "elastic_", "plastic_", "viscous_", "hourglass_"})
                    columns.push_back(c + std::to_string(l));
            h5::write_table(file_.id(), "energies_by_layer", columns, layer_energies_);
        }
        for (const auto& gauge : gauges_)
            h5::write_table(file_.id(), "gauges/" + gauge.name, gauge_columns(), gauge.series);
        file_.flush();
    }
    h5::OutputFile& file() { return file_; }
    const h5::OutputFile& file() const { return file_; }

  private:
    struct Gauge {
        std::string name;
        GaugeSite site;
        std::vector<double> series; // rows of gauge_columns()
    };
    struct Snapshot {
        std::string group;
        double time;
    };
    const Structure& s_;
    h5::OutputFile file_;
    int count_ = 0;
    std::vector<Gauge> gauges_;
    std::vector<double> energies_;
    std::vector<double> layer_energies_; // rows: t, then kinetic, elastic, plastic, hourglass of each layer
    size_t layer_count_ = 0;
    std::vector<Snapshot> snapshots_;

    std::vector<std::string> gauge_columns() const {
        std::vector<std::string> c = {"t"};
        for (const auto& n : s_.gauge_columns())
            c.push_back(n);
        return c;
    }
    static void write_field(hid_t loc, const Field& f) {
        const hsize_t rows = (f.integers.empty() ? f.values.size() : f.integers.size()) / f.columns;
        std::vector<hsize_t> dims = {rows};
        if (f.columns > 1) dims.push_back(f.columns);
        if (f.integers.empty())
            h5::write_dataset(loc, f.name.c_str(), dims, f.values.data());
        else
            h5::write_dataset(loc, f.name.c_str(), dims, f.integers.data());
    }
    // solid.xmf: the snapshots of a 2D model as a temporal collection of quadrilateral grids on the current
    // positions, for ParaView; every node and element field is an attribute (fields of three columns as
    // vectors).
    void write_xdmf(const std::vector<Field>& fields) const {
        const size_t n = s_.nodes(), ne = s_.element_count();
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
            for (const Field& f : fields) {
                if (f.columns != 1 && f.columns != 3) continue; // the position is the geometry
                const bool node = f.centre == Field::Centre::Node, vector = f.columns == 3;
                x << "<Attribute Name=\"" << f.name << "\" AttributeType=\"" << (vector ? "Vector" : "Scalar")
                  << "\" Center=\"" << (node ? "Node" : "Cell") << "\">\n";
                item("/" + s.group + "/" + f.name, std::to_string(node ? n : ne) + (vector ? " 3" : ""));
                x << "</Attribute>\n";
            }
            x << "<Attribute Name=\"layer\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
            item("/layer", std::to_string(ne), "Int", 4);
            x << "</Attribute>\n</Grid>\n";
        }
        x << "</Grid>\n</Domain>\n</Xdmf>\n";
        h5::write_file_atomically((std::filesystem::path(file_.directory()) / "solid.xmf").string(), x.str());
    }
};

// The fluid, when a face is wet, through the coupling library: the Hello carries every wet node with its
// face (docs/protocol.md).
// A stop request (SIGINT, SIGTERM, SIGHUP) ends a wait of the coupling 1.5 s after it came: a Grant the fluid
// sent meanwhile (it may be moving its wet faces when the signal comes) is taken and its step finished, so
// that both sides stop at the end of one step and can be resumed from there.
bool stop_wait() {
    static std::optional<std::chrono::steady_clock::time_point> since;
    if (!stop_requested()) return false;
    const auto now = std::chrono::steady_clock::now();
    if (!since) since = now;
    return now - *since >= std::chrono::milliseconds(1500);
}

std::unique_ptr<coupling::StructureParticipant> connect(const CaseFile& c, const RunPlan& p,
                                                        const std::string& endpoint, const Structure& s,
                                                        std::ostream& log, const coupling::Start& start) {
    const coupling::Options o{endpoint, p.coupling_timeout_ms, p.handshake_timeout_ms, stop_wait};
    auto link = std::make_unique<coupling::StructureParticipant>(o, "undex-solid", "0.1.0");
    coupling::Interface i;
    i.dimension = s.dimension();
    i.alpha = c.get().geometry() == config::AXISYMMETRIC_2D ? 1 : 0;
    for (const WetNode& n : s.wet_nodes()) {
        i.x.push_back(n.x), i.y.push_back(n.y), i.normal_x.push_back(n.normal_x);
        i.normal_y.push_back(n.normal_y), i.area.push_back(n.area), i.face.push_back(n.face);
    }
    link->initialize(i, start);
    log << "undex-solid: coupled to " << link->peer_solver() << " on " << endpoint << std::endl;
    return link;
}

// A structure run for the driver (base/run_driver.hpp): alone on the plan's clock, or coupled on the fluid's.
class StructureRun : public Run {
  public:
    // A new run (resume: nothing), or one continued from a checkpoint (the model restored here).
    StructureRun(const CaseFile& c, const RunPlan& p, StructureModel& m,
                 std::unique_ptr<coupling::StructureParticipant> link, State* resume)
        : m_(m), s_(*m.structure), link_(std::move(link)), case_text_(c.text()), directory_(p.directory) {
        out_ = resume ? std::make_unique<StructureOutput>(p.directory, s_)
                      : std::make_unique<StructureOutput>(p.directory, c.text(), s_, m.layers);
        // A 2D gauge's y is its depth from the front face, which lies at plate.y_front.
        const auto& st = c.get().structure();
        for (const auto& g : st.gauges())
            out_->add_gauge(g.name(), g.x(), st.plate().y_front() + g.y());
        if (resume) {
            State model = resume->scope("model"), run = resume->scope("run"), out = resume->scope("output");
            s_.state(model);
            run.io("history", history_);
            out_->resume(out);
            write_history(); // the table as it was at the checkpoint
            return;
        }
        remove_checkpoints(p.directory, "solid"); // of an older run in the directory
        out_->record();
        out_->write_fields();
    }

    double time() const override { return s_.time(); }
    long steps() const override { return s_.steps(); }
    bool owns_clock() const override { return !link_; } // the fluid owns the clock of a coupled run

    std::optional<Step> next_step(const OutputClock& clock, bool checkpoint_due) override {
        if (!link_) {
            Step s = clock.clip(time(), m_.dt);
            s.checkpoint = checkpoint_due;
            return s;
        }
        // The fluid grants the step and asks for outputs; a Stop ends the run.
        coupling::Offer o;
        o.dt = m_.dt;
        for (const WetNode& n : s_.wet_nodes()) {
            o.x.push_back(n.x), o.y.push_back(n.y);
            o.velocity.push_back(n.velocity);
        }
        if (!link_->exchange(o, grant_)) return std::nullopt;
        fluid_.resize(grant_.p_L.size());
        for (size_t k = 0; k < fluid_.size(); ++k)
            fluid_[k] = {grant_.p_L[k], grant_.u_L[k], grant_.Z_L[k], grant_.geometric[k], grant_.p_floor};
        return Step{grant_.dt, grant_.output, grant_.checkpoint};
    }

    void advance(const Step& s) override {
        at_step_end_ = false; // until the answer is sent
        std::vector<InterfaceSolution> wet;
        const double t = s_.time(); // recorded as it was, bit for bit the Grant's time
        const auto start = std::chrono::steady_clock::now();
        try {
            wet = s_.step(s.dt, fluid_); // on failure the model is left at its last good state
        } catch (const StructureFailure& f) {
            throw RunFailure(exit_method_failed, f.what());
        }
        step_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        at_step_end_ = !link_;
        if (!link_) return;
        coupling::Answer a;
        for (size_t k = 0; k < wet.size(); ++k) {
            a.p_I.push_back(wet[k].p_I), a.u_I.push_back(wet[k].u_I);
            history_.insert(history_.end(), {t, s.dt, wet[k].p_I, wet[k].u_I, m_.dt});
        }
        for (const WetNode& n : s_.wet_nodes())
            a.x.push_back(n.x), a.y.push_back(n.y);
        link_->answer(a);
        at_step_end_ = true;
    }
    bool at_step_end() const override { return at_step_end_; }
    std::string write_checkpoint() override {
        std::optional<h5::WriteHook> keep_waiting; // heartbeats, as for an output
        if (link_) keep_waiting.emplace([this] { beat(); }, 1.0);
        beat();
        State st = State::create(directory_, "solid", link_ ? "fluid" : "", steps(), time(), case_text_);
        State model = st.scope("model"), run = st.scope("run"), out = st.scope("output");
        s_.state(model);
        run.io("history", history_);
        if (link_) {
            // The link's step once the step is taken (it counts the next one while waiting for its Grant).
            coupling::Start at = link_->position();
            at.step = steps();
            run.io("link_step", at.step), run.io("link_time", at.time),
                run.io("link_after_short", at.after_short);
        }
        out_->state(out);
        return st.commit();
    }
    void beat() noexcept {
        try {
            if (link_) link_->heartbeat();
        } catch (const std::exception&) {
        }
    }
    void record() override { out_->record(); }
    void write_output() override {
        // The fluid's wait restarts: an output may take a while (a heartbeat before it and between its
        // datasets, at most once a second).
        std::optional<h5::WriteHook> keep_waiting;
        if (link_) {
            link_->heartbeat();
            keep_waiting.emplace([this] { link_->heartbeat(); }, 1.0);
        }
        out_->write_fields();
        write_history();
    }
    void complete() override {
        out_->write_tables();
        write_history();
        out_->file().complete();
        remove_checkpoints(directory_, "solid"); // a complete run needs none
    }
    void fail(const std::string& why) override {
        if (link_) link_->fail(why); // best effort: the peer learns the cause
        out_->file().fail(why, [&] {
            out_->write_fields(true);
            write_history();
        });
    }
    std::string output_path() const override { return out_->file().path(); }
    std::string progress() const override {
        const Energies& e = s_.energies();
        return "  energy balance error " + format("%.2e", e.balance_error() / std::max(e.external, 1e-300));
    }
    bool coupling_error(const std::exception& e) const override {
        return dynamic_cast<const coupling::CouplingError*>(&e) != nullptr;
    }
    // The structure's own steps: the fluid's time in the coupling library less this is the coupling's cost.
    std::string summary(double wall) const override {
        return format(" (structure steps %.3f s, %.1f %%)", step_wall_, 100 * step_wall_ / wall);
    }

  private:
    double step_wall_ = 0; // in Structure::step
    StructureModel& m_;
    Structure& s_;
    std::unique_ptr<coupling::StructureParticipant> link_;
    std::string case_text_, directory_;
    std::unique_ptr<StructureOutput> out_;
    bool at_step_end_ = true; // false while a step is being taken
    coupling::Grant grant_;
    std::vector<FluidCharacteristic> fluid_; // at each wet node, for the step granted
    std::vector<double> history_;            // t, dt, p_I, u_I, dt_s per coupled step and wet node
    void write_history() {
        if (link_) out_->file().write_table("coupling", {"t", "dt", "p_I", "u_I", "dt_s"}, history_);
    }
};

} // namespace

int run_structure(const CaseFile& c, std::ostream& log, const std::string& couple,
                  const std::string& resume) {
    StructureModel model = make_structure(c); // checks the whole structure part first
    const auto p = plan(c);
    if (model.wet && couple.empty())
        c.fail("structure.front",
               "the structure is coupled to the case's fluid: run it with `undex run`, or give "
               "undex-solid --couple ENDPOINT with the fluid solver bound there");
    if (!model.wet && !couple.empty())
        c.fail("structure.front", "--couple needs a face wetted by a fluid (FLUID)");
#ifdef _OPENMP
    if (model.threads > 0) omp_set_num_threads(model.threads);
    const int threads = omp_get_max_threads();
#else
    const int threads = 1;
#endif
    log << "undex-solid: " << c.path() << ": " << model.structure->description() << ", " << threads
        << " thread(s), time step " << format("%.4g", model.dt) << " s, end time " << p.end_time
        << " s, output " << p.directory << "/solid.h5" << std::endl;
    std::optional<State> from;
    coupling::Start start;
    if (!resume.empty()) {
        from.emplace(State::open(resume, "solid"));
        log << "undex-solid: resuming from " << resume << " (step " << from->step()
            << ", t = " << format("%.9g", from->time()) << " s)" << std::endl;
        if (model.wet) {
            State run = from->scope("run");
            run.io("link_step", start.step), run.io("link_time", start.time);
            run.io("link_after_short", start.after_short);
        }
    }
    auto link = model.wet ? connect(c, p, couple, *model.structure, log, start) : nullptr;
    StructureRun r(c, p, model, std::move(link), from ? &*from : nullptr);
    return drive(r, p, "undex-solid", log);
}

} // namespace undex::solid
