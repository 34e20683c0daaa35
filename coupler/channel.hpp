// One end of a coupling connection, internal to the coupler library: a ZeroMQ PAIR socket carrying one
// serialised coupling Envelope (proto/coupling.proto) per frame, with a receive timeout that heartbeats
// renew (up to heartbeat_limit timeouts), and a monitor of the connection so that a peer whose process ends
// is noticed without waiting for the timeout. Every failure throws CouplingError naming the peer, the step
// and the cause.
#pragma once
#include "coupler/messages.hpp"
#include "coupler/participant.hpp"
#include "proto/coupling.pb.h"

#include <zmq.hpp>

#include <cstdint>
#include <deque>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex::coupling {

// The longest wait for one message, in timeouts: each Heartbeat restarts the timeout, but a wait ends after
// heartbeat_limit timeouts whatever arrives (docs/protocol.md §5: 10 × coupling.timeout, 300 s by default;
// an output of undex-fluid or undex-solid, preceded by one heartbeat, must take less than one timeout).
constexpr int heartbeat_limit = 10;

class Channel {
  public:
    enum class Role { Bind, Connect };
    // Binds or connects to endpoint (ipc://PATH or tcp://HOST:PORT). A bound ipc:// endpoint that another
    // live process holds, or a tcp:// port in use, is an error; tcp://HOST:* binds a free port. peer names
    // the other side in messages.
    Channel(const std::string& endpoint, Role role, std::string peer, int timeout_ms);
    ~Channel();
    Channel(const Channel&) = delete;
    Channel& operator=(const Channel&) = delete;

    // Sends e with this side's protocol version.
    void send(Envelope& e);
    // For the conformance check only: e with another protocol version, and bytes that are no Envelope.
    void send_version(Envelope& e, std::uint32_t version);
    void send_raw(const std::string& bytes);
    // Waits for the message of the given step and body (or a Stop), skipping heartbeats, each of which
    // renews the timeout up to heartbeat_limit timeouts. Throws on a timeout, a malformed frame, another
    // protocol version, an Error from the peer, a message of another step or kind (decode), or a stop
    // request.
    Envelope receive(std::int64_t step, Envelope::BodyCase expected);
    const std::string& peer() const { return peer_; }
    // The endpoint as bound or connected (a tcp://HOST:* binding shows its port here).
    const std::string& endpoint() const { return endpoint_; }
    // The longest wait for a message, and for the peer to take one.
    void set_timeout(int timeout_ms);
    // A wait ends (CouplingError) once stop() is true: a stop signal, even one not arriving during a poll.
    void set_stop(std::function<bool()> stop) { stop_ = std::move(stop); }

  private:
    zmq::context_t context_;
    zmq::socket_t socket_;
    zmq::socket_t monitor_;   // connection events of socket_: a vanished peer ends a wait at once
    std::deque<int> pending_; // connections made, ZeroMQ handshake not yet done
    std::vector<int> peers_;  // connections whose handshake succeeded
    bool peer_lost_ = false;  // one of them closed
    void on_event(int event, int fd);
    bool peer_gone(); // reads the pending connection events first
    Envelope wait(std::int64_t step, Envelope::BodyCase expected); // receive, with ZeroMQ's errors unwrapped
    std::string endpoint_, peer_, ipc_path_;
    int timeout_ms_;
    std::function<bool()> stop_;
};

} // namespace undex::coupling
