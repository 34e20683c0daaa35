// Round-trip latency and throughput of the coupling library (coupler/participant.hpp) between two processes
// over real sockets. The structure side offers a step with N interface nodes, the fluid grants it with N
// characteristic states, the structure answers with N pressures, velocities and positions: one round trip as
// a coupled run makes it every step, with no solver work in between. The fluid side times each round trip
// from the start of receive_offer to the return of exchange (Offer -> Grant -> Answer), after S/10 warm-up
// steps, and prints one line:
//   nodes N endpoint-kind ipc|tcp  round trip median X us  p90 Y us  throughput Z MB/s
// Usage: coupling_latency --nodes N --steps S --endpoint E [--role both|fluid|structure]
//   E: ipc    ipc://$TMPDIR/undex-bench-PID.ipc (/tmp without TMPDIR)
//      tcp    tcp://127.0.0.1 on a free port (the fluid binds port 0 and the system picks one)
//      or a full endpoint ipc://PATH or tcp://HOST:PORT (needed by --role structure).
//   --role both (the default) forks: the child runs the structure side, the parent the fluid side. fluid or
//   structure runs one side only, for two processes started by hand (the fluid prints what it bound).
// Exits with status 1 and a message on any coupling error or bad argument.
#include "coupler/participant.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace undex::coupling;

struct Args {
    long nodes = 0, steps = 0;
    std::string endpoint, role = "both";
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
        else if (key == "--role")
            a.role = value;
        else
            throw std::invalid_argument("unknown option " + key);
    }
    if (a.nodes < 1 || a.steps < 1 || a.endpoint.empty())
        throw std::invalid_argument("usage: coupling_latency --nodes N --steps S --endpoint ipc|tcp|ENDPOINT "
                                    "[--role both|fluid|structure]");
    if (a.role != "both" && a.role != "fluid" && a.role != "structure")
        throw std::invalid_argument("--role is both, fluid or structure, not " + a.role);
    return a;
}

// The endpoint the fluid binds: the short forms ipc and tcp expanded, a full endpoint as given.
std::string bind_endpoint(const std::string& e) {
    if (e == "ipc") {
        const char* tmp = std::getenv("TMPDIR");
        return "ipc://" + std::string(tmp && *tmp ? tmp : "/tmp") + "/undex-bench-" +
               std::to_string(getpid()) + ".ipc";
    }
    if (e == "tcp") return "tcp://127.0.0.1:*";
    return e;
}

std::string kind(const std::string& e) {
    return e.rfind("tcp", 0) == 0 ? "tcp" : "ipc";
}

Options options(const std::string& endpoint) {
    Options o;
    o.endpoint = endpoint;
    o.handshake_timeout_ms = 60000; // the peer is this same program, started at the same moment
    return o;
}

// The structure side: a plate of N nodes along y = 0 with normals (0, 1); it offers, takes the grant and
// answers until the fluid stops the run.
int run_structure(const std::string& endpoint, long n) {
    try {
        auto link = std::make_unique<StructureParticipant>(options(endpoint), "coupling_latency", "0.1.0");
        Interface iface;
        iface.dimension = 2;
        iface.alpha = 0;
        for (long k = 0; k < n; ++k) {
            iface.x.push_back(1e-3 * k);
            iface.y.push_back(0);
            iface.normal_x.push_back(0);
            iface.normal_y.push_back(1);
            iface.area.push_back(1e-3);
        }
        link->initialize(iface);
        Offer offer;
        offer.dt = 2e-7;
        offer.x = iface.x;
        offer.y = iface.y;
        offer.velocity.assign(n, 0.5);
        Answer answer;
        answer.p_I.assign(n, 1.2e5); // above the grant's p_floor = 0
        answer.u_I.assign(n, 0.5);
        answer.x = iface.x;
        answer.y.assign(n, 1e-7);
        Grant grant;
        while (link->exchange(offer, grant))
            link->answer(answer);
        return 0;
    } catch (const CouplingError& e) {
        // No fail(): the error is the connection's or the peer's, and a send to a peer that is gone can
        // block.
        std::cerr << "coupling_latency: structure: " << e.what() << std::endl;
        return 1;
    }
}

// The fluid side on a bound participant: warm-up, S timed round trips, the end of the run; prints the line.
int run_fluid(FluidParticipant& link, const Args& a) {
    const long n = a.nodes, warm_up = std::max(1L, a.steps / 10);
    link.initialize(2, 0, 1.0);
    Grant grant;
    grant.time = 0;
    grant.p_floor = 0;
    grant.p_L.assign(n, 1.1e5);
    grant.u_L.assign(n, 0.1);
    grant.Z_L.assign(n, 1.5e6);
    grant.geometric.assign(n, 0); // planar (α = 0)
    Offer offer;
    std::vector<double> us;
    us.reserve(a.steps);
    for (long step = 0; step < warm_up + a.steps; ++step) {
        const auto start = std::chrono::steady_clock::now();
        if (!link.receive_offer(offer))
            throw CouplingError("the structure side stopped at step " + std::to_string(step + 1));
        const Answer answer = link.exchange(1e-7, grant);
        const auto end = std::chrono::steady_clock::now();
        if (step >= warm_up) us.push_back(std::chrono::duration<double, std::micro>(end - start).count());
        grant.time += grant.dt;
        (void)answer;
    }
    link.finalize("benchmark done");
    std::sort(us.begin(), us.end());
    const size_t s = us.size();
    const double median = s % 2 ? us[s / 2] : 0.5 * (us[s / 2 - 1] + us[s / 2]);
    const double p90 = us[(9 * s + 9) / 10 - 1]; // nearest rank: the ceil(0.9 s)-th smallest
    // Payload per round trip, in doubles: Offer dt + x, y, velocity (3N + 1) and Answer p_I, u_I, x, y (4N)
    // from the structure; Grant dt, time, p_floor + p_L, u_L, Z_L, geometric (4N + 3) from the fluid:
    // 11N + 4 doubles of 8 bytes. Protobuf tags, lengths, the step and the output flag are not counted.
    // MB = 10^6 bytes.
    const double bytes = 8.0 * (11.0 * n + 4);
    const double mb_per_s = bytes / (median * 1e-6) / 1e6;
    char line[256];
    std::snprintf(line, sizeof line,
                  "nodes %ld endpoint-kind %s  round trip median %.1f us  p90 %.1f us  "
                  "throughput %.1f MB/s",
                  n, kind(link.endpoint()).c_str(), median, p90, mb_per_s);
    std::cout << line << std::endl;
    return 0;
}

// Binds the fluid side and runs it; announce (when given) is told the bound endpoint, then closed.
int fluid_side(const Args& a, int announce, pid_t child) {
    std::unique_ptr<FluidParticipant> link;
    try {
        link = std::make_unique<FluidParticipant>(options(bind_endpoint(a.endpoint)), "coupling_latency",
                                                  "0.1.0");
        if (announce >= 0) {
            const std::string e = link->endpoint() + "\n";
            if (write(announce, e.data(), e.size()) != static_cast<ssize_t>(e.size()))
                throw CouplingError("cannot pass the endpoint to the structure process");
            close(announce);
            announce = -1;
        } else {
            std::cerr << "coupling_latency: fluid bound " << link->endpoint() << std::endl;
        }
        const int code = run_fluid(*link, a);
        link.reset(); // closes the socket (and removes the ipc file) before the child is waited for
        return code;
    } catch (const CouplingError& e) {
        std::cerr << "coupling_latency: fluid: " << e.what()
                  << std::endl; // no fail(), as on the structure side
        if (announce >= 0) close(announce);
        if (child > 0) kill(child, SIGTERM);
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
    if (a.role == "structure") {
        if (a.endpoint == "ipc" || a.endpoint == "tcp") {
            std::cerr << "coupling_latency: --role structure needs the fluid's full endpoint" << std::endl;
            return 1;
        }
        return run_structure(a.endpoint, a.nodes);
    }
    if (a.role == "fluid") return fluid_side(a, -1, 0);

    // Both sides: the parent binds and passes the bound endpoint (a tcp port the system chose) through a pipe
    // to the child, which connects. The fork comes before any ZeroMQ context exists.
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
        std::string endpoint;
        char c;
        while (read(fds[0], &c, 1) == 1 && c != '\n')
            endpoint += c;
        close(fds[0]);
        if (endpoint.empty()) return 1; // the parent could not bind; it says why
        return run_structure(endpoint, a.nodes);
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
