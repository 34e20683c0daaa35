#include "coupler/participant.hpp"

#include "coupler/channel.hpp"
#include "coupler/messages.hpp"

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
      solver_(solver), version_(version), options_(o) {
    channel_->set_stop(o.stop_requested);
}

FluidParticipant::~FluidParticipant() = default;

const std::string& FluidParticipant::endpoint() const {
    return channel_->endpoint();
}

Interface FluidParticipant::initialize(int dimension, int alpha, double end_time, const Start& start) {
    try {
        return handshake(dimension, alpha, end_time, start);
    } catch (const CouplingError& e) {
        fail(e.what()); // the structure learns why
        throw;
    }
}

Interface FluidParticipant::handshake(int dimension, int alpha, double end_time, const Start& start) {
    const Envelope e = channel_->receive(0, Envelope::kHello);
    if (e.has_stop())
        throw CouplingError("the structure solver stopped before the handshake: " + check_stop(e.stop()));
    interface_ = check_hello(e.hello(), dimension, alpha, peer_);
    const double t = e.hello().start_time();
    if (e.hello().start_step() != start.step ||
        !(std::abs(t - start.time) <= limits::time_tolerance * std::max(end_time, 1e-300))) {
        std::ostringstream s;
        s.precision(12);
        s << "the structure solver (" << peer_ << ") starts from step " << e.hello().start_step()
          << " (t = " << t << " s), the fluid from step " << start.step << " (t = " << start.time
          << " s): a resumed run needs both sides' checkpoints of one step";
        throw CouplingError(s.str());
    }
    step_ = start.step;
    end_time_ = end_time;
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
        stop_reason_ = check_stop(e.stop());
        return false;
    }
    offer = check_offer(e.offer(), interface_.size(), end_time_, channel_->peer(), step_);
    dt_s_ = offer.dt;
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
    m->set_checkpoint(g.checkpoint);
    set(m->mutable_p_l(), g.p_L);
    set(m->mutable_u_l(), g.u_L);
    set(m->mutable_z_l(), g.Z_L);
    set(m->mutable_geometric(), g.geometric);
    channel_->send(e);
    const Envelope r = channel_->receive(step_, Envelope::kAnswer);
    if (r.has_stop())
        throw CouplingError("the structure solver stopped at step " + std::to_string(step_) +
                            " instead of answering: " + check_stop(r.stop()));
    return check_answer(r.answer(), interface_.size(), g.p_floor, channel_->peer(), step_);
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
      solver_(solver), version_(version), options_(o) {
    channel_->set_stop(o.stop_requested);
}

StructureParticipant::~StructureParticipant() = default;

double StructureParticipant::initialize(const Interface& i, const Start& start) {
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
    for (const int f : i.face)
        h->add_face(f);
    h->set_start_step(start.step);
    h->set_start_time(start.time);
    step_ = start.step, time_ = start.time, short_ = start.after_short;
    nodes_ = i.size();
    channel_->send(e);
    const Envelope w = channel_->receive(0, Envelope::kWelcome);
    if (w.has_stop())
        throw CouplingError("the fluid solver stopped during the handshake: " + check_stop(w.stop()));
    end_time_ = check_welcome(w.welcome(), peer_);
    channel_->set_timeout(options_.timeout_ms);
    return end_time_;
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
        stop_reason_ = check_stop(r.stop());
        return false;
    }
    grant = check_grant(r.grant(), nodes_, offer.dt, time_, end_time_, short_, channel_->peer(), step_);
    time_ += grant.dt;
    short_ = grant.dt < limits::dt_floor_fraction * end_time_;
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
