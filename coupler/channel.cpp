#include "coupler/channel.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <thread>
#include <utility>

namespace undex::coupling {

namespace {

// A duration in seconds for messages: 2, 0.5, 20.3.
template <class D> std::string seconds(D d) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", std::chrono::duration<double>(d).count());
    return buf;
}

// Whether a process accepts connections on the Unix socket at path.
bool ipc_in_use(const std::string& path) {
    if (!std::filesystem::exists(path)) return false;
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    if (path.size() >= sizeof addr.sun_path) return false;
    std::strcpy(addr.sun_path, path.c_str());
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    if (fd < 0) return false;
    const bool live = ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    return live;
}

// Reads one monitor event: its number (ZMQ_EVENT_*) and value (the file descriptor for connection events).
std::pair<int, int> read_event(zmq::socket_t& monitor) {
    zmq::message_t head, address;
    if (!monitor.recv(head, zmq::recv_flags::none)) return {0, 0};
    if (head.more()) (void)monitor.recv(address, zmq::recv_flags::none);
    std::uint16_t event = 0;
    std::uint32_t value = 0;
    if (head.size() >= sizeof event + sizeof value) {
        std::memcpy(&event, head.data(), sizeof event);
        std::memcpy(&value, static_cast<const char*>(head.data()) + sizeof event, sizeof value);
    }
    return {event, static_cast<int>(value)};
}

} // namespace

Channel::Channel(const std::string& endpoint, Role role, std::string peer, int timeout_ms)
    : socket_(context_, zmq::socket_type::pair), monitor_(context_, zmq::socket_type::pair),
      endpoint_(endpoint), peer_(std::move(peer)), timeout_ms_(timeout_ms) {
    // Messages still queued when the socket closes (the last Stop) get a moment to leave.
    socket_.set(zmq::sockopt::linger, 2000);
    socket_.set(zmq::sockopt::sndtimeo, timeout_ms_);
    const std::string monitor = "inproc://monitor";
    if (zmq_socket_monitor(socket_.handle(), monitor.c_str(),
                           ZMQ_EVENT_CONNECTED | ZMQ_EVENT_ACCEPTED | ZMQ_EVENT_HANDSHAKE_SUCCEEDED |
                               ZMQ_EVENT_DISCONNECTED) != 0)
        throw CouplingError("cannot monitor the coupling socket: " + std::string(zmq_strerror(zmq_errno())));
    monitor_.connect(monitor);
    try {
        if (role == Role::Bind) {
            if (endpoint.rfind("ipc://", 0) == 0) {
                const std::string path = endpoint.substr(6);
                if (ipc_in_use(path))
                    throw CouplingError("endpoint " + endpoint + " is already in use by another process");
                ipc_path_ = path;
            }
            socket_.bind(endpoint);
            endpoint_ = socket_.get(zmq::sockopt::last_endpoint); // the port chosen for tcp://HOST:*
        } else {
            socket_.connect(endpoint);
        }
    } catch (const zmq::error_t& e) {
        throw CouplingError("cannot " + std::string(role == Role::Bind ? "bind" : "connect to") +
                            " endpoint " + endpoint + ": " + e.what());
    }
}

void Channel::set_timeout(int timeout_ms) {
    timeout_ms_ = timeout_ms;
    socket_.set(zmq::sockopt::sndtimeo, timeout_ms_);
}

Channel::~Channel() {
    // What is still queued waits up to the linger time for a peer to take it; with no peer connected (none
    // came, or it is gone) nothing can leave, and the process ends at once.
    try {
        if (peer_gone() || peers_.empty()) socket_.set(zmq::sockopt::linger, 0);
    } catch (const zmq::error_t&) {
    }
    socket_.close();
    std::error_code ignored;
    if (!ipc_path_.empty()) std::filesystem::remove(ipc_path_, ignored);
}

bool Channel::peer_gone() {
    for (zmq::pollitem_t m{monitor_.handle(), 0, ZMQ_POLLIN, 0};
         zmq::poll(&m, 1, std::chrono::milliseconds(0)) > 0 && (m.revents & ZMQ_POLLIN);) {
        const auto [event, fd] = read_event(monitor_);
        on_event(event, fd);
    }
    return peer_lost_ && peers_.empty();
}

void Channel::send(Envelope& e) {
    e.set_protocol(protocol_version);
    zmq::message_t frame(e.ByteSizeLong()); // serialised straight into the frame: no extra copy
    e.SerializeWithCachedSizesToArray(static_cast<std::uint8_t*>(frame.data()));
    // The usual case first: ZeroMQ queues the frame at once. Reading the connection events before each send
    // cost a few microseconds per message (tests/bench/coupling_latency.sh). A peer that is gone is noticed
    // below when the frame cannot be queued; on the connecting side ZeroMQ keeps queueing after the peer
    // has gone, and the next wait reports it ("closed the connection ... (waiting for ...)").
    try {
        if (socket_.send(frame, zmq::send_flags::dontwait)) return;
    } catch (const zmq::error_t&) {
        // the send below reports it
    }
    // A peer known to be gone takes nothing: say so instead of waiting out the send timeout.
    const std::string gone = peer_ + " closed the connection at step " + std::to_string(e.step()) +
                             " (before " + body_name(e.body_case()) +
                             " could be sent): its process ended or was killed";
    if (peer_gone() && !e.has_error()) throw CouplingError(gone);
    // A peer that is gone leaves nothing to take the message: the send gives up after the timeout.
    if (e.has_error()) socket_.set(zmq::sockopt::sndtimeo, 500); // a last word, not worth a long wait
    bool sent = false;
    try {
        sent = socket_.send(frame, zmq::send_flags::none).has_value();
    } catch (const zmq::error_t& err) {
        throw CouplingError("cannot send " + body_name(e.body_case()) + " to " + peer_ + " at step " +
                            std::to_string(e.step()) + ": " + err.what());
    }
    if (e.has_error()) socket_.set(zmq::sockopt::sndtimeo, timeout_ms_);
    if (!sent && peer_gone()) throw CouplingError(gone);
    if (!sent)
        throw CouplingError("cannot send " + body_name(e.body_case()) + " to " + peer_ + " at step " +
                            std::to_string(e.step()) +
                            ": nobody took it within the timeout (the peer is gone)");
}

// Follows the connections of the socket: a connection counts as the peer's once its ZeroMQ handshake
// succeeded (connections are handshaken in the order they were made), so that a stray connection that opens
// and closes (a port scan, another process probing the ipc:// path) is not taken for the peer going away.
void Channel::on_event(int event, int fd) {
    if (event == ZMQ_EVENT_CONNECTED || event == ZMQ_EVENT_ACCEPTED) {
        pending_.push_back(fd);
    } else if (event == ZMQ_EVENT_HANDSHAKE_SUCCEEDED) {
        if (!pending_.empty()) peers_.push_back(pending_.front()), pending_.pop_front();
    } else if (event == ZMQ_EVENT_DISCONNECTED) {
        pending_.erase(std::remove(pending_.begin(), pending_.end(), fd), pending_.end());
        const auto p = std::find(peers_.begin(), peers_.end(), fd);
        if (p != peers_.end()) peers_.erase(p), peer_lost_ = true;
    }
}

void Channel::send_version(Envelope& e, std::uint32_t version) {
    e.set_protocol(version);
    send_raw(e.SerializeAsString());
}

void Channel::send_raw(const std::string& bytes) {
    if (!socket_.send(zmq::buffer(bytes), zmq::send_flags::none))
        throw CouplingError("cannot send to " + peer_ + ": nobody took the message within the timeout");
}

// Any ZeroMQ call of the wait may be interrupted by a signal (SIGINT, SIGTERM: the run then ends with its
// last good state written) or fail otherwise; either is a coupling failure naming the step.
Envelope Channel::receive(std::int64_t step, Envelope::BodyCase expected) {
    try {
        return wait(step, expected);
    } catch (const zmq::error_t& err) {
        throw CouplingError(
            (err.num() == EINTR ? "stopped by a signal (SIGINT, SIGTERM or SIGHUP)" : "the socket failed") +
            std::string(" at step ") + std::to_string(step) + " while waiting for " + body_name(expected) +
            " from " + peer_ + ": " + err.what());
    }
}

Envelope Channel::wait(std::int64_t step, Envelope::BodyCase expected) {
    using std::chrono::milliseconds;
    using Clock = std::chrono::steady_clock;
    const std::string at = " at step " + std::to_string(step);
    const auto start = Clock::now();
    auto deadline = start + milliseconds(timeout_ms_);
    // Heartbeats renew the wait, but never beyond heartbeat_limit timeouts from its start: a peer that only
    // sends heartbeats is given up on like a silent one (docs/protocol.md §5).
    const auto limit = start + milliseconds(timeout_ms_) * heartbeat_limit;
    bool heartbeats = false;
    auto heartbeats_only = [&] {
        return peer_ + " sent only Heartbeats for " + seconds(Clock::now() - start) + " s" + at +
               " (waiting for " + body_name(expected) + "): heartbeats extend a wait to " +
               std::to_string(heartbeat_limit) + " × the timeout at most";
    };
    for (;;) {
        // Up to 300 µs of trying to receive (yielding the core to any runnable thread) before sleeping: a
        // round trip takes about 70 µs, and waking a sleeping thread on a virtual machine costs tens of
        // microseconds. Measured (tests/bench/coupling_latency.sh, README): 1000-node round trips of
        // 104–132 µs against 145–190 µs without the spin, and the coupling's share of case 4.3 12.5 % against
        // 18.5 %; again after the faster checks and sends, on a 2-core machine under a load of 9: 71–74 µs
        // against 82–920 µs. A receive that does not wait costs two system calls where a poll of the socket
        // and the monitor costs five: the same medians, p90 70–85 µs against 74–119 µs (9 runs each, taken
        // alternately); the monitor is read once the spin is over. A spin without yielding gave the same
        // medians with p90 of 0.4–2 ms under load; 1000 µs gained nothing more.
        zmq::message_t frame;
        const auto spin_until = Clock::now() + std::chrono::microseconds(300);
        bool received = false;
        while (!(received = socket_.recv(frame, zmq::recv_flags::dontwait).has_value()) &&
               Clock::now() < spin_until)
            std::this_thread::yield();
        if (!received) {
            zmq::pollitem_t items[2] = {{socket_.handle(), 0, ZMQ_POLLIN, 0},
                                        {monitor_.handle(), 0, ZMQ_POLLIN, 0}};
            auto poll = [&](milliseconds t) { return zmq::poll(items, 2, t); };
            const auto left = std::chrono::duration_cast<milliseconds>(deadline - Clock::now());
            // The sleep is cut in slices so that a stop request that came outside the poll (no EINTR) is
            // seen. Never negative: a negative timeout makes zmq_poll wait for ever (the deadline may pass
            // during the spin above).
            // A signal interrupts the poll (EINTR): the wait goes on unless stop_ says it ends, so that each
            // side decides where a stop leaves it (fluid/run.cpp, solid/run_structure.cpp: at a step's end).
            try {
                poll(std::max(stop_ ? std::min(left, milliseconds(100)) : left, milliseconds(0)));
            } catch (const zmq::error_t& e) {
                if (e.num() != EINTR) throw;
            }
            if (items[1].revents & ZMQ_POLLIN) {
                const auto [event, fd] = read_event(monitor_);
                on_event(event, fd);
            }
            if (!(items[0].revents & ZMQ_POLLIN)) {
                if (peer_lost_ && peers_.empty()) {
                    // Whatever the peer sent before it went is read first.
                    zmq::poll(items, 1, milliseconds(200));
                    if (!(items[0].revents & ZMQ_POLLIN))
                        throw CouplingError(peer_ + " closed the connection" + at + " (waiting for " +
                                            body_name(expected) + "): its process ended or was killed");
                } else if (stop_ && stop_()) {
                    throw CouplingError("stopped by a signal (SIGINT, SIGTERM or SIGHUP)" + at +
                                        " while waiting for " + body_name(expected) + " from " + peer_);
                } else if ((items[1].revents & ZMQ_POLLIN) || Clock::now() < deadline) {
                    continue;
                } else if (heartbeats && deadline >= limit) {
                    throw CouplingError(heartbeats_only());
                } else {
                    throw CouplingError(peer_ + " did not answer within " +
                                        seconds(milliseconds(timeout_ms_)) + " s" + at + " (waiting for " +
                                        body_name(expected) + ")");
                }
            }
            if (!socket_.recv(frame, zmq::recv_flags::none)) continue;
        }
        Envelope e = decode(frame.data(), frame.size(), peer_, step, expected);
        if (!e.has_heartbeat()) return e;
        if (Clock::now() >= limit) throw CouplingError(heartbeats_only()); // even a flood of them
        heartbeats = true;
        deadline = std::min(Clock::now() + milliseconds(timeout_ms_), limit);
    }
}

} // namespace undex::coupling
