// Round-trip latency of the coupling library (coupler/participant.hpp) between two processes over real
// sockets, measured against ZeroMQ's own floor in the same run. Five loops take turns in blocks, so that the
// load of the machine falls on all of them alike:
//   coupling      the structure offers a step with N interface nodes, the fluid grants it with N
//                 characteristic states, the structure answers with N pressures, velocities and positions:
//                 one round trip as a coupled run makes it every step, with no solver work in between;
//   bare loops    a cppzmq PAIR ping-pong on a socket of the same kind carrying the same bytes: the ping as
//                 many as the Grant envelope, the pong as many as the Answer and the next Offer envelopes,
//                 either as the protocol sends them (same frames: two frames, Answer then Offer) or as one
//                 frame (one frame each way, the least ZeroMQ can do with these bytes); each either waiting
//                 in a blocking receive or receiving with zmq::recv_flags::dontwait in a loop (spin).
// The fluid side times each round trip (coupling: from the start of receive_offer to the return of exchange;
// bare: from the send of the ping to the receipt of the whole pong). After a warm-up of S/10 round trips of
// each loop, blocks of B = max(1, S/20) round trips of each loop alternate (the order rotates every cycle)
// until each loop has S timed round trips. Prints one line (medians; ratio = coupling / the faster of the
// blocking and the spinning loop):
//   nodes N endpoint-kind ipc|tcp  bytes Grant G Answer A Offer O  coupling median X us p90 Y us
//   same frames: blocking Z us spin W us ratio R  one frame each way: blocking Z1 us spin W1 us ratio R1
// Usage: coupling_latency --nodes N --steps S --endpoint ipc|tcp
//   ipc: ipc://$TMPDIR/undex-bench-PID.ipc (/tmp without TMPDIR) and the same path with .bare for the bare
//   loops; tcp: tcp://127.0.0.1 on two free ports. The program forks: the child runs the structure side, the
//   parent the fluid side.
// Exits with status 1 and a message on any coupling or socket error or bad argument.
#include "coupler/participant.hpp"
#include "proto/coupling.pb.h"

#include <sys/wait.h>
#include <unistd.h>
#include <zmq.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace undex::coupling;
using Clock = std::chrono::steady_clock;

struct Args {
    long nodes = 0, steps = 0;
    std::string endpoint;
};

Args parse(int argc, char** argv) {
    Args a;
    for (int k = 1; k < argc; ++k) {
        const std::string key = argv[k];
        if (k + 1 >= argc) throw std::invalid_argument(key + " needs a value");
        const std::string value = argv[++k];
        if (key == "--nodes")
            a.nodes = std::stol(value);
        else if (key == "--steps")
            a.steps = std::stol(value);
        else if (key == "--endpoint")
            a.endpoint = value;
        else
            throw std::invalid_argument("unknown option " + key);
    }
    if (a.nodes < 1 || a.steps < 1 || (a.endpoint != "ipc" && a.endpoint != "tcp"))
        throw std::invalid_argument("usage: coupling_latency --nodes N --steps S --endpoint ipc|tcp");
    return a;
}

// The endpoints the fluid binds: the coupling's and the bare loops'.
std::array<std::string, 2> bind_endpoints(const std::string& kind) {
    if (kind == "tcp") return {"tcp://127.0.0.1:*", "tcp://127.0.0.1:*"};
    const char* tmp = std::getenv("TMPDIR");
    const std::string path =
        std::string(tmp && *tmp ? tmp : "/tmp") + "/undex-bench-" + std::to_string(getpid()) + ".ipc";
    return {"ipc://" + path, "ipc://" + path + ".bare"};
}

Options options(const std::string& endpoint) {
    Options o;
    o.endpoint = endpoint;
    o.handshake_timeout_ms = 60000; // the peer is this same program, started at the same moment
    return o;
}

// The loops, in the order of the first cycle.
enum Loop { coupling, same_blocking, same_spin, one_blocking, one_spin, loops };
bool spins(Loop l) {
    return l == same_spin || l == one_spin;
}

// The schedule both sides follow: (loop, round trips) blocks, warm-up first; timed says which count.
struct Block {
    Loop loop;
    long count;
    bool timed;
};
std::vector<Block> schedule(long steps) {
    std::vector<Block> s;
    const long warm_up = std::max(1L, steps / 10), block = std::max(1L, steps / 20);
    for (int l = 0; l < loops; ++l)
        s.push_back({Loop(l), warm_up, false});
    for (long done = 0, cycle = 0; done < steps; done += block, ++cycle)
        for (int l = 0; l < loops; ++l)
            s.push_back({Loop((l + cycle) % loops), std::min(block, steps - done), true});
    return s;
}

// The data of one step, the same on both sides: a plate of N nodes along y = 0 with normals (0, 1).
struct StepData {
    Interface iface;
    Offer offer;
    Grant grant;
    Answer answer;
    explicit StepData(long n) {
        iface.dimension = 2;
        iface.alpha = 0;
        for (long k = 0; k < n; ++k) {
            iface.x.push_back(1e-3 * k);
            iface.y.push_back(0);
            iface.normal_x.push_back(0);
            iface.normal_y.push_back(1);
            iface.area.push_back(1e-3);
        }
        offer.dt = 2e-7;
        offer.x = iface.x;
        offer.y = iface.y;
        offer.velocity.assign(n, 0.5);
        grant.dt = 1e-7;
        grant.time = 0;
        grant.p_floor = 0;
        grant.p_L.assign(n, 1.1e5);
        grant.u_L.assign(n, 0.1);
        grant.Z_L.assign(n, 1.5e6);
        grant.geometric.assign(n, 0); // planar (α = 0)
        answer.p_I.assign(n, 1.2e5);  // above the grant's p_floor = 0
        answer.u_I.assign(n, 0.5);
        answer.x = iface.x;
        answer.y.assign(n, 1e-7);
    }
};

// The bytes of the envelopes the coupling sends each step (protobuf, packed doubles) at a step number of
// 1000: the Grant, the Answer and the Offer.
struct Bytes {
    size_t grant, answer, offer;
};
Bytes envelope_bytes(const StepData& d) {
    using undex::coupling::wire::Envelope;
    auto fill = [](auto* field, const std::vector<double>& v) { field->Assign(v.begin(), v.end()); };
    Envelope g, a, o;
    for (Envelope* e : {&g, &a, &o}) {
        e->set_protocol(protocol_version);
        e->set_step(1000);
    }
    auto* gm = g.mutable_grant();
    gm->set_dt(d.grant.dt);
    gm->set_time(d.grant.time);
    gm->set_p_floor(d.grant.p_floor);
    gm->set_output(false);
    fill(gm->mutable_p_l(), d.grant.p_L);
    fill(gm->mutable_u_l(), d.grant.u_L);
    fill(gm->mutable_z_l(), d.grant.Z_L);
    fill(gm->mutable_geometric(), d.grant.geometric);
    auto* am = a.mutable_answer();
    fill(am->mutable_p_i(), d.answer.p_I);
    fill(am->mutable_u_i(), d.answer.u_I);
    fill(am->mutable_x(), d.answer.x);
    fill(am->mutable_y(), d.answer.y);
    auto* om = o.mutable_offer();
    om->set_dt(d.offer.dt);
    fill(om->mutable_x(), d.offer.x);
    fill(om->mutable_y(), d.offer.y);
    fill(om->mutable_velocity(), d.offer.velocity);
    return {g.ByteSizeLong(), a.ByteSizeLong(), o.ByteSizeLong()};
}

// One side of the bare ping-pong. Each frame is sent from a buffer (cppzmq copies it into a new message,
// as the coupling serialises into a new frame); a receive blocks or spins on dontwait and checks the size.
struct Bare {
    zmq::context_t context;
    zmq::socket_t socket{context, zmq::socket_type::pair};
    std::vector<char> out;
    zmq::message_t in;
    explicit Bare(size_t largest) : out(largest, 1) { socket.set(zmq::sockopt::linger, 0); }
    void send(size_t bytes) { socket.send(zmq::buffer(out.data(), bytes), zmq::send_flags::none); }
    void receive(bool spin, size_t bytes) {
        if (spin)
            while (!socket.recv(in, zmq::recv_flags::dontwait)) {
            }
        else
            (void)socket.recv(in, zmq::recv_flags::none);
        if (in.size() != bytes)
            throw std::runtime_error("bare loop: a frame of " + std::to_string(in.size()) + " bytes, not " +
                                     std::to_string(bytes));
    }
    // The pong: the Answer and the Offer, as two frames or as one.
    std::vector<size_t> pong(Loop l, const Bytes& b) {
        if (l == one_blocking || l == one_spin) return {b.answer + b.offer};
        return {b.answer, b.offer};
    }
};

// The structure side: follows the schedule, then takes the fluid's Stop.
int run_structure(const std::string& endpoint, const std::string& bare_endpoint, const Args& a) {
    try {
        StepData d(a.nodes);
        const Bytes bytes = envelope_bytes(d);
        Bare bare(bytes.answer + bytes.offer);
        bare.socket.connect(bare_endpoint);
        auto link = std::make_unique<StructureParticipant>(options(endpoint), "coupling_latency", "0.1.0");
        link->initialize(d.iface);
        Grant grant;
        for (const Block& b : schedule(a.steps))
            for (long k = 0; k < b.count; ++k) {
                if (b.loop == coupling) {
                    if (!link->exchange(d.offer, grant)) throw CouplingError("the fluid side stopped early");
                    link->answer(d.answer);
                } else {
                    bare.receive(spins(b.loop), bytes.grant);
                    for (const size_t f : bare.pong(b.loop, bytes))
                        bare.send(f);
                }
            }
        if (link->exchange(d.offer, grant)) throw CouplingError("the fluid side did not stop");
        return 0;
    } catch (const std::exception& e) {
        // No fail(): the error is the connection's or the peer's, and a send to a peer that is gone can
        // block.
        std::cerr << "coupling_latency: structure: " << e.what() << std::endl;
        return 1;
    }
}

double median(std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    const size_t s = v.size();
    return s % 2 ? v[s / 2] : 0.5 * (v[s / 2 - 1] + v[s / 2]);
}

// The fluid side on bound sockets: follows the schedule, ends the run, prints the line.
void run_fluid(FluidParticipant& link, Bare& bare, const Args& a, const std::string& kind) {
    StepData d(a.nodes);
    const Bytes bytes = envelope_bytes(d);
    link.initialize(2, 0, 1.0);
    Grant& grant = d.grant;
    Offer offer;
    std::array<std::vector<double>, loops> us;
    for (auto& v : us)
        v.reserve(a.steps);
    for (const Block& b : schedule(a.steps))
        for (long k = 0; k < b.count; ++k) {
            const auto start = Clock::now();
            if (b.loop == coupling) {
                if (!link.receive_offer(offer))
                    throw CouplingError("the structure side stopped at step " + std::to_string(link.step()));
                (void)link.exchange(1e-7, grant);
                grant.time += grant.dt;
            } else {
                bare.send(bytes.grant);
                for (const size_t f : bare.pong(b.loop, bytes))
                    bare.receive(spins(b.loop), f);
            }
            const auto end = Clock::now();
            if (b.timed) us[b.loop].push_back(std::chrono::duration<double, std::micro>(end - start).count());
        }
    link.finalize("benchmark done");
    std::array<double, loops> m;
    for (int l = 0; l < loops; ++l)
        m[l] = median(us[l]);
    const double p90 = us[coupling][(9 * us[coupling].size() + 9) / 10 - 1]; // nearest rank: ceil(0.9 S)-th
    char line[512];
    std::snprintf(line, sizeof line,
                  "nodes %ld endpoint-kind %s  bytes Grant %zu Answer %zu Offer %zu  coupling median %.1f us "
                  "p90 %.1f us  same frames: blocking %.1f us spin %.1f us ratio %.2f  one frame each way: "
                  "blocking %.1f us spin %.1f us ratio %.2f",
                  a.nodes, kind.c_str(), bytes.grant, bytes.answer, bytes.offer, m[coupling], p90,
                  m[same_blocking], m[same_spin], m[coupling] / std::min(m[same_blocking], m[same_spin]),
                  m[one_blocking], m[one_spin], m[coupling] / std::min(m[one_blocking], m[one_spin]));
    std::cout << line << std::endl;
}

// Binds both sockets, tells the structure process the two endpoints through announce, runs the fluid side.
int fluid_side(const Args& a, int announce, pid_t child) {
    std::unique_ptr<FluidParticipant> link;
    std::string bare_path;
    try {
        const auto endpoints = bind_endpoints(a.endpoint);
        StepData d(a.nodes);
        Bare bare(envelope_bytes(d).grant);
        bare.socket.bind(endpoints[1]);
        if (a.endpoint == "ipc") bare_path = endpoints[1].substr(6);
        link = std::make_unique<FluidParticipant>(options(endpoints[0]), "coupling_latency", "0.1.0");
        const std::string e = link->endpoint() + "\n" + bare.socket.get(zmq::sockopt::last_endpoint) + "\n";
        if (write(announce, e.data(), e.size()) != static_cast<ssize_t>(e.size()))
            throw CouplingError("cannot pass the endpoints to the structure process");
        close(announce);
        announce = -1;
        run_fluid(*link, bare, a, a.endpoint);
        link.reset(); // closes the socket (and removes the ipc file) before the child is waited for
        if (!bare_path.empty()) std::filesystem::remove(bare_path);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "coupling_latency: fluid: " << e.what()
                  << std::endl; // no fail(), as on the structure side
        if (announce >= 0) close(announce);
        if (child > 0) kill(child, SIGTERM);
        std::error_code ignored;
        if (!bare_path.empty()) std::filesystem::remove(bare_path, ignored);
        return 1;
    }
}

} // namespace

int main(int argc, char** argv) {
    Args a;
    try {
        a = parse(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "coupling_latency: " << e.what() << std::endl;
        return 1;
    }
    // The parent binds and passes the bound endpoints (tcp ports the system chose) through a pipe to the
    // child, which connects. The fork comes before any ZeroMQ context exists.
    int fds[2];
    if (pipe(fds) != 0) {
        std::perror("coupling_latency: pipe");
        return 1;
    }
    std::cout.flush();
    const pid_t child = fork();
    if (child < 0) {
        std::perror("coupling_latency: fork");
        return 1;
    }
    if (child == 0) {
        close(fds[1]);
        std::string endpoints[2];
        char c;
        for (auto& e : endpoints)
            while (read(fds[0], &c, 1) == 1 && c != '\n')
                e += c;
        close(fds[0]);
        if (endpoints[1].empty()) return 1; // the parent could not bind; it says why
        return run_structure(endpoints[0], endpoints[1], a);
    }
    close(fds[0]);
    const int code = fluid_side(a, fds[1], child);
    int status = 0;
    waitpid(child, &status, 0);
    if (code == 0 && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        std::cerr << "coupling_latency: the structure process failed (status " << status << ")" << std::endl;
        return 1;
    }
    return code;
}
