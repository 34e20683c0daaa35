// One end of a coupling connection, internal to the coupler library: a ZeroMQ PAIR socket carrying one
// serialised coupling Envelope (proto/coupling.proto) per frame, with a receive timeout that heartbeats
// renew. Every failure throws CouplingError naming the peer, the step and the cause.
#pragma once
#include "coupling.pb.h"

#include <zmq.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace undex::coupling {

constexpr std::uint32_t protocol_version = 1;

struct CouplingError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

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
    // Waits for the message of the given step and body (or a Stop), skipping heartbeats, each of which
    // renews the timeout. Throws on a timeout, a malformed frame, another protocol version, an Error from the
    // peer, or a message of another step or kind.
    Envelope receive(std::int64_t step, Envelope::BodyCase expected);
    const std::string& peer() const { return peer_; }
    // The endpoint as bound or connected (a tcp://HOST:* binding shows its port here).
    const std::string& endpoint() const { return endpoint_; }

  private:
    zmq::context_t context_;
    zmq::socket_t socket_;
    std::string endpoint_, peer_, ipc_path_;
    int timeout_ms_;
};

// The name of a message body, for errors.
std::string body_name(Envelope::BodyCase b);

} // namespace undex::coupling
