// The coupling library: one object per side of a coupled fluid–structure run (docs/protocol.md). The fluid
// side binds the endpoint and owns the clock; the structure side connects. Each step the structure offers
// its stable step and interface motion, the fluid grants Δt = min(Δt_f, Δt_s) with its characteristic state
// at the interface (physics.md §5), and the structure answers with p_I, u_I and its new positions.
// Every failure (a peer that dies, hangs past the timeout, or sends a malformed, out-of-order or
// wrong-version message) throws CouplingError naming the peer, the step and the cause.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex::coupling {

constexpr std::uint32_t protocol_version = 1;

struct CouplingError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::string endpoint;   // ipc://PATH or tcp://HOST:PORT (tcp://HOST:* on the fluid side: any port)
    int timeout_ms = 30000; // longest wait for the peer's next message during the run
    int handshake_timeout_ms = 300000;    // longest wait for the handshake (the peer may still be setting up)
    std::function<bool()> stop_requested; // when given and true, a wait ends at once (SIGINT, SIGTERM)
};

// The interface nodes, sent once by the structure: reference positions, unit normals pointing from the fluid
// into the structure, wetted areas, and the wet face of each node (the nodes of a face consecutive and in
// order along it; empty: all on face 0).
struct Interface {
    int dimension = 1;
    int alpha = 0; // 0 planar, 1 cylindrical or axisymmetric, 2 spherical
    std::vector<double> x, y, normal_x, normal_y, area;
    std::vector<int> face;
    size_t size() const { return x.size(); }
};

// The structure's offer of a step: its stable Δt_s, interface positions and normal velocities.
struct Offer {
    double dt = 0;
    std::vector<double> x, y, velocity;
};

// The fluid's grant: the step Δt both sides take, the time it starts from, and per node the characteristic
// state (p_L, u_L, Z_L) and geometric term of physics.md §5; p_floor bounds p_I from below; output asks for
// an output at the end of the step.
struct Grant {
    double dt = 0, time = 0, p_floor = 0;
    bool output = false;
    bool checkpoint = false; // both sides write a checkpoint at the end of the step
    std::vector<double> p_L, u_L, Z_L, geometric;
};

// The structure's answer: the interface pressure and velocity of the step, the positions at its end.
struct Answer {
    std::vector<double> p_I, u_I, x, y;
};

class Channel;

// Where a run starts: the step it continues after and its time (0, 0 for a new run; a checkpoint's for a
// resumed one), and on the structure side whether the last step granted was below the Δt floor.
struct Start {
    std::int64_t step = 0;
    double time = 0;
    bool after_short = false;
};

// The fluid side.
class FluidParticipant {
  public:
    FluidParticipant(const Options& o, const std::string& solver, const std::string& version);
    ~FluidParticipant();
    // Waits for the structure's Hello, checks it (dimension and α must match, one value per node, unit
    // normals, positive areas, every value in its range: docs/protocol.md §5) and answers with this side's
    // name and the end time. A structure that starts from another step than `start` is refused.
    Interface initialize(int dimension, int alpha, double end_time, const Start& start = {});
    // The structure's offer for the next step (Δt_s not below the Δt floor, every value in range); false
    // when the structure ended the run (Stop).
    bool receive_offer(Offer& offer);
    // Grants Δt = min(dt_f, Δt_s of the last offer) with the fluid state g (g.dt is set here) and returns the
    // structure's answer.
    Answer exchange(double dt_f, Grant& g);
    // Ends the run normally: tells the structure to stop.
    void finalize(const std::string& reason);
    // Tells the structure that this side fails (best effort; never throws).
    void fail(const std::string& message) noexcept;
    // Keeps the structure waiting during long work (an output): call at least once per timeout.
    void heartbeat();
    std::int64_t step() const { return step_; }
    const std::string& endpoint() const;
    const std::string& peer_solver() const { return peer_; }
    // The reason the structure gave when it ended the run with Stop.
    const std::string& stop_reason() const { return stop_reason_; }

  private:
    Interface handshake(int dimension, int alpha, double end_time, const Start& start);
    std::unique_ptr<Channel> channel_;
    std::string solver_, version_, peer_, stop_reason_;
    Options options_;
    Interface interface_;
    std::int64_t step_ = 0;
    double dt_s_ = 0, end_time_ = 0;
};

// The structure side.
class StructureParticipant {
  public:
    StructureParticipant(const Options& o, const std::string& solver, const std::string& version);
    ~StructureParticipant();
    // Sends Hello with the interface and where this side starts, and waits for the fluid's Welcome; returns
    // the end time of the run.
    double initialize(const Interface& i, const Start& start = {});
    // Where this side stands after its last step (for a checkpoint).
    Start position() const { return {step_, time_, short_}; }
    // Offers the next step and waits for the grant (checked: Δt, time against this side's, every value in
    // range); false when the fluid ended the run (Stop).
    bool exchange(const Offer& offer, Grant& grant);
    // Answers the last grant.
    void answer(const Answer& a);
    void fail(const std::string& message) noexcept;
    void heartbeat();
    std::int64_t step() const { return step_; }
    const std::string& peer_solver() const { return peer_; }
    const std::string& stop_reason() const { return stop_reason_; }

  private:
    std::unique_ptr<Channel> channel_;
    std::string solver_, version_, peer_, stop_reason_;
    Options options_;
    size_t nodes_ = 0;
    std::int64_t step_ = 0;
    double end_time_ = 0, time_ = 0; // from the Welcome; the sum of the Δt granted
    bool short_ = false;             // the last Δt granted was below the Δt floor (on an output time)
};

} // namespace undex::coupling
