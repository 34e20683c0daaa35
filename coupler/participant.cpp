#include "coupler/participant.hpp"

#include "coupler/channel.hpp"

#include <cmath>
#include <sstream>

namespace undex::coupling {

namespace {

template <class R> std::vector<double> to_vector(const R& r) {
    return std::vector<double>(r.begin(), r.end());
}
template <class R> void set(R* r, const std::vector<double>& v) {
    r->Assign(v.begin(), v.end());
}

// Checks that a message field holds one finite value per interface node.
template <class R>
void check_values(const R& r, size_t nodes, const std::string& peer, const std::string& what,
                  std::int64_t step) {
    std::ostringstream s;
    if (static_cast<size_t>(r.size()) != nodes) {
        s << peer << " sent " << r.size() << " value(s) of " << what << " at step " << step << " for "
          << nodes << " interface node(s)";
        throw CouplingError(s.str());
    }
    for (int k = 0; k < r.size(); ++k)
        if (!std::isfinite(r.Get(k))) {
            s << peer << " sent a non-finite " << what << " (" << r.Get(k) << ") at interface node " << k
              << " at step " << step;
            throw CouplingError(s.str());
        }
}

void check_step(double dt, const std::string& peer, const std::string& what, std::int64_t step) {
    if (!(dt > 0) || !std::isfinite(dt)) {
        std::ostringstream s;
        s << peer << " sent a time step " << what << " = " << dt << " at step " << step
          << " (must be positive and finite)";
        throw CouplingError(s.str());
    }
}

// An Error to the peer, best effort: a failing side must not fail again while saying why.
void send_error(Channel& c, std::int64_t step, const std::string& message) noexcept {
    try {
        Envelope e;
        e.set_step(step);
        e.mutable_error()->set_message(message);
        c.send(e);
    } catch (...) {
    }
}

void send_heartbeat(Channel& c, std::int64_t step) {
    Envelope e;
    e.set_step(step);
    e.mutable_heartbeat();
    c.send(e);
}

} // namespace

// ---- fluid side ----------------------------------------------------------------------------------------

FluidParticipant::FluidParticipant(const Options& o, const std::string& solver, const std::string& version)
    : channel_(std::make_unique<Channel>(o.endpoint, Channel::Role::Bind, "the structure solver",
                                         o.handshake_timeout_ms)),
      solver_(solver), version_(version), options_(o) {}

FluidParticipant::~FluidParticipant() = default;

const std::string& FluidParticipant::endpoint() const {
    return channel_->endpoint();
}

Interface FluidParticipant::initialize(int dimension, int alpha, double end_time) {
    try {
        return handshake(dimension, alpha, end_time);
    } catch (const CouplingError& e) {
        fail(e.what()); // the structure learns why
        throw;
    }
}

Interface FluidParticipant::handshake(int dimension, int alpha, double end_time) {
    const Envelope e = channel_->receive(0, Envelope::kHello);
    if (e.has_stop())
        throw CouplingError("the structure solver stopped before the handshake: " + e.stop().reason());
    const auto& h = e.hello();
    peer_ = h.solver() + " " + h.version();
    const std::string who = "the structure solver (" + peer_ + ")";
    std::ostringstream s;
    if (h.dimension() != dimension || h.alpha() != alpha) {
        s << who << " models a " << h.dimension() << "D structure with alpha = " << h.alpha()
          << "; the fluid is " << dimension << "D with alpha = " << alpha;
        throw CouplingError(s.str());
    }
    const size_t n = h.x_size();
    if (n == 0) throw CouplingError(who + " has no interface nodes");
    check_values(h.x(), n, who, "x", 0);
    check_values(h.y(), n, who, "y", 0);
    check_values(h.normal_x(), n, who, "normal_x", 0);
    check_values(h.normal_y(), n, who, "normal_y", 0);
    check_values(h.area(), n, who, "area", 0);
    for (size_t k = 0; k < n; ++k) {
        const double len = std::hypot(h.normal_x(k), h.normal_y(k));
        if (std::abs(len - 1) > 1e-9) {
            s << who << ": the normal of interface node " << k << " has length " << len << ", not 1";
            throw CouplingError(s.str());
        }
        if (!(h.area(k) > 0)) {
            s << who << ": interface node " << k << " has wetted area " << h.area(k) << " (must be positive)";
            throw CouplingError(s.str());
        }
    }
    interface_ = {h.dimension(),           h.alpha(),
                  to_vector(h.x()),        to_vector(h.y()),
                  to_vector(h.normal_x()), to_vector(h.normal_y()),
                  to_vector(h.area())};
    Envelope w;
    w.set_step(0);
    w.mutable_welcome()->set_solver(solver_);
    w.mutable_welcome()->set_version(version_);
    w.mutable_welcome()->set_end_time(end_time);
    channel_->send(w);
    channel_->set_timeout(options_.timeout_ms);
    return interface_;
}

bool FluidParticipant::receive_offer(Offer& offer) {
    ++step_;
    const Envelope e = channel_->receive(step_, Envelope::kOffer);
    if (e.has_stop()) {
        stop_reason_ = e.stop().reason();
        return false;
    }
    const auto& o = e.offer();
    const size_t n = interface_.size();
    const std::string& who = channel_->peer();
    check_step(o.dt(), who, "dt_s", step_);
    check_values(o.x(), n, who, "x", step_);
    check_values(o.y(), n, who, "y", step_);
    check_values(o.velocity(), n, who, "velocity", step_);
    dt_s_ = o.dt();
    offer.dt = o.dt();
    offer.x = to_vector(o.x());
    offer.y = to_vector(o.y());
    offer.velocity = to_vector(o.velocity());
    return true;
}

Answer FluidParticipant::exchange(double dt_f, Grant& g) {
    check_step(dt_f, "the fluid solver", "dt_f", step_);
    g.dt = std::min(dt_f, dt_s_);
    Envelope e;
    e.set_step(step_);
    auto* m = e.mutable_grant();
    m->set_dt(g.dt);
    m->set_time(g.time);
    m->set_p_floor(g.p_floor);
    m->set_output(g.output);
    set(m->mutable_p_l(), g.p_L);
    set(m->mutable_u_l(), g.u_L);
    set(m->mutable_z_l(), g.Z_L);
    set(m->mutable_geometric(), g.geometric);
    channel_->send(e);
    const Envelope r = channel_->receive(step_, Envelope::kAnswer);
    if (r.has_stop())
        throw CouplingError("the structure solver stopped at step " + std::to_string(step_) +
                            " instead of answering: " + r.stop().reason());
    const auto& a = r.answer();
    const size_t n = interface_.size();
    const std::string& who = channel_->peer();
    check_values(a.p_i(), n, who, "p_I", step_);
    check_values(a.u_i(), n, who, "u_I", step_);
    check_values(a.x(), n, who, "x", step_);
    check_values(a.y(), n, who, "y", step_);
    for (size_t k = 0; k < n; ++k)
        if (a.p_i(k) < g.p_floor) {
            std::ostringstream s;
            s << who << " answered p_I = " << a.p_i(k) << " Pa at interface node " << k << " at step "
              << step_ << ", below the floor p_floor = " << g.p_floor << " Pa";
            throw CouplingError(s.str());
        }
    return {to_vector(a.p_i()), to_vector(a.u_i()), to_vector(a.x()), to_vector(a.y())};
}

void FluidParticipant::finalize(const std::string& reason) {
    Offer last;
    if (!receive_offer(last)) return; // the structure stopped too
    Envelope e;
    e.set_step(step_);
    e.mutable_stop()->set_reason(reason);
    channel_->send(e);
}

void FluidParticipant::fail(const std::string& message) noexcept {
    send_error(*channel_, step_, message);
}

void FluidParticipant::heartbeat() {
    send_heartbeat(*channel_, step_);
}

// ---- structure side ------------------------------------------------------------------------------------

StructureParticipant::StructureParticipant(const Options& o, const std::string& solver,
                                           const std::string& version)
    : channel_(std::make_unique<Channel>(o.endpoint, Channel::Role::Connect, "the fluid solver",
                                         o.handshake_timeout_ms)),
      solver_(solver), version_(version), options_(o) {}

StructureParticipant::~StructureParticipant() = default;

double StructureParticipant::initialize(const Interface& i) {
    Envelope e;
    e.set_step(0);
    auto* h = e.mutable_hello();
    h->set_solver(solver_);
    h->set_version(version_);
    h->set_dimension(i.dimension);
    h->set_alpha(i.alpha);
    set(h->mutable_x(), i.x);
    set(h->mutable_y(), i.y);
    set(h->mutable_normal_x(), i.normal_x);
    set(h->mutable_normal_y(), i.normal_y);
    set(h->mutable_area(), i.area);
    nodes_ = i.size();
    channel_->send(e);
    const Envelope w = channel_->receive(0, Envelope::kWelcome);
    if (w.has_stop())
        throw CouplingError("the fluid solver stopped during the handshake: " + w.stop().reason());
    peer_ = w.welcome().solver() + " " + w.welcome().version();
    channel_->set_timeout(options_.timeout_ms);
    return w.welcome().end_time();
}

bool StructureParticipant::exchange(const Offer& offer, Grant& grant) {
    ++step_;
    Envelope e;
    e.set_step(step_);
    auto* o = e.mutable_offer();
    o->set_dt(offer.dt);
    set(o->mutable_x(), offer.x);
    set(o->mutable_y(), offer.y);
    set(o->mutable_velocity(), offer.velocity);
    channel_->send(e);
    const Envelope r = channel_->receive(step_, Envelope::kGrant);
    if (r.has_stop()) {
        stop_reason_ = r.stop().reason();
        return false;
    }
    const auto& g = r.grant();
    const std::string& who = channel_->peer();
    check_step(g.dt(), who, "dt", step_);
    if (g.dt() > offer.dt) {
        std::ostringstream s;
        s << who << " granted dt = " << g.dt() << " s at step " << step_
          << ", above the offered dt_s = " << offer.dt << " s";
        throw CouplingError(s.str());
    }
    check_values(g.p_l(), nodes_, who, "p_L", step_);
    check_values(g.u_l(), nodes_, who, "u_L", step_);
    check_values(g.z_l(), nodes_, who, "Z_L", step_);
    check_values(g.geometric(), nodes_, who, "geometric", step_);
    grant.dt = g.dt();
    grant.time = g.time();
    grant.p_floor = g.p_floor();
    grant.output = g.output();
    grant.p_L = to_vector(g.p_l());
    grant.u_L = to_vector(g.u_l());
    grant.Z_L = to_vector(g.z_l());
    grant.geometric = to_vector(g.geometric());
    return true;
}

void StructureParticipant::answer(const Answer& a) {
    Envelope e;
    e.set_step(step_);
    auto* m = e.mutable_answer();
    set(m->mutable_p_i(), a.p_I);
    set(m->mutable_u_i(), a.u_I);
    set(m->mutable_x(), a.x);
    set(m->mutable_y(), a.y);
    channel_->send(e);
}

void StructureParticipant::fail(const std::string& message) noexcept {
    send_error(*channel_, step_, message);
}

void StructureParticipant::heartbeat() {
    send_heartbeat(*channel_, step_);
}

} // namespace undex::coupling
