// undex conform -- COMMAND...: checks a structure solver against the coupling protocol (docs/protocol.md).
// It plays the fluid side: for each check it binds a fresh ipc:// endpoint, starts COMMAND with
// " --couple ENDPOINT" appended (its output goes to a log file), and watches what arrives. Each check prints
// "ok:" or "FAIL:" with what was wrong; the exit status is the number of failed checks (0: conforming).
#include "coupler/conform.hpp"

#include "coupler/channel.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>
#include <vector>

namespace undex::coupling {

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

namespace {

// The solver under test: one process per check.
class Subject {
  public:
    Subject(const std::vector<std::string>& command, const std::string& endpoint, const std::string& log) {
        std::string line = "exec";
        for (const auto& a : command)
            line.append(" ").append(shell_quote(a));
        line.append(" --couple ").append(shell_quote(endpoint));
        pid_ = fork();
        if (pid_ < 0)
            throw std::runtime_error(std::string("cannot start the solver: ") + std::strerror(errno));
        if (pid_ == 0) {
            FILE* f = std::fopen(log.c_str(), "w");
            if (f) {
                dup2(fileno(f), 1);
                dup2(fileno(f), 2);
            }
            execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
    }
    ~Subject() {
        if (pid_ > 0 && !ended_) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
    }
    // The exit status if the process ends within seconds, else -1 (then it is killed).
    int wait(double seconds) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (std::chrono::steady_clock::now() < until) {
            int st = 0;
            if (waitpid(pid_, &st, WNOHANG) == pid_) {
                ended_ = true;
                return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return -1;
    }

  private:
    pid_t pid_ = -1;
    bool ended_ = false;
};

struct Report {
    int failed = 0;
    void check(bool ok, const std::string& what, const std::string& why = "") {
        std::cout << (ok ? "ok: " : "FAIL: ") << what << (ok || why.empty() ? "" : ": " + why) << std::endl;
        failed += !ok;
    }
};

bool finite_all(const google::protobuf::RepeatedField<double>& r) {
    for (double v : r)
        if (!std::isfinite(v)) return false;
    return true;
}

// The Hello's problems, or "".
std::string hello_problems(const Envelope& e) {
    std::ostringstream s;
    if (!e.has_hello()) return "the first message is " + body_name(e.body_case()) + ", not Hello";
    const auto& h = e.hello();
    if (e.step() != 0) s << "Hello has step " << e.step() << " (must be 0); ";
    if (h.solver().empty()) s << "empty solver name; ";
    if (h.dimension() != 1 && h.dimension() != 2) s << "dimension " << h.dimension() << " (1 or 2); ";
    if (h.alpha() < 0 || h.alpha() > 2) s << "alpha " << h.alpha() << " (0, 1 or 2); ";
    const int n = h.x_size();
    if (n == 0) s << "no interface nodes; ";
    if (h.y_size() != n || h.normal_x_size() != n || h.normal_y_size() != n || h.area_size() != n)
        s << "x, y, normal_x, normal_y, area differ in length; ";
    else
        for (int k = 0; k < n; ++k) {
            if (std::abs(std::hypot(h.normal_x(k), h.normal_y(k)) - 1) > 1e-9) {
                s << "normal of node " << k << " is not a unit vector; ";
                break;
            }
            if (!(h.area(k) > 0) || !std::isfinite(h.area(k))) {
                s << "area of node " << k << " is not positive and finite; ";
                break;
            }
        }
    if (!finite_all(h.x()) || !finite_all(h.y())) s << "non-finite positions; ";
    if (h.face_size() != 0 && h.face_size() != n)
        s << "Hello.face has " << h.face_size() << " values for " << n << " nodes; ";
    return s.str();
}

// The faces of a Hello (docs/protocol.md): numbered 0, 1, ... with their nodes consecutive; in 2D at least
// two nodes each, and each node's area and normal those of its area vector a_k = Σ n_s ∫_s N_k r ds over the
// segments joining consecutive nodes of its face (r = x when alpha = 1, else 1), to 1e-9. "" when they are.
std::string face_problems(const wire::Hello& h) {
    const int n = h.x_size();
    std::vector<int> face(n, 0);
    for (int k = 0; k < h.face_size(); ++k)
        face[k] = h.face(k);
    for (int k = 0; k < n; ++k) {
        const int previous = k == 0 ? 0 : face[k - 1];
        if (face[k] != previous && face[k] != previous + 1)
            return "node " + std::to_string(k) + " lies on face " + std::to_string(face[k]) +
                   " after a node of face " + std::to_string(previous) +
                   " (faces 0, 1, ..., their nodes consecutive)";
    }
    if (h.dimension() != 2) return "";
    std::ostringstream s;
    for (int k = 0; k < n;) { // one face: nodes k to e − 1
        int e = k + 1;
        while (e < n && face[e] == face[k])
            ++e;
        if (e - k < 2) return "face " + std::to_string(face[k]) + " has one node (a 2D face needs a segment)";
        std::vector<double> ax(e - k, 0.0),
            ay(e - k, 0.0); // normal to the left of the direction of the nodes
        for (int j = k; j + 1 < e; ++j) {
            const double xa = h.x(j), xb = h.x(j + 1), dx = xb - xa, dy = h.y(j + 1) - h.y(j);
            const double sa = h.alpha() == 1 ? (2 * xa + xb) / 6 : 0.5,
                         sb = h.alpha() == 1 ? (xa + 2 * xb) / 6 : 0.5;
            ax[j - k] += -dy * sa, ay[j - k] += dx * sa;
            ax[j + 1 - k] += -dy * sb, ay[j + 1 - k] += dx * sb;
        }
        // The structure's side: the one the Hello's normals point to.
        double side = 0;
        for (int j = k; j < e; ++j)
            side += h.normal_x(j) * ax[j - k] + h.normal_y(j) * ay[j - k];
        const double sign = side < 0 ? -1.0 : 1.0;
        for (int j = k; j < e; ++j) {
            const double A = std::hypot(ax[j - k], ay[j - k]);
            const double nx = sign * ax[j - k] / A, ny = sign * ay[j - k] / A;
            if (!(std::abs(h.area(j) - A) <= 1e-9 * A) ||
                !(std::hypot(h.normal_x(j) - nx, h.normal_y(j) - ny) <= 1e-9)) {
                s << "node " << j << " of face " << face[k] << ": area " << h.area(j) << ", normal ("
                  << h.normal_x(j) << ", " << h.normal_y(j) << "), but its face's segments give " << A
                  << ", (" << nx << ", " << ny << ")";
                return s.str();
            }
        }
        k = e;
    }
    return "";
}

Envelope welcome() {
    Envelope w;
    w.set_step(0);
    w.mutable_welcome()->set_solver("undex conform");
    w.mutable_welcome()->set_version("1");
    w.mutable_welcome()->set_end_time(1.0);
    return w;
}

// A Grant of step n for a resting fluid with p_L on every one of the nodes.
Envelope grant(std::int64_t n, int nodes, double dt, double time, double p_L) {
    Envelope g;
    g.set_step(n);
    auto* m = g.mutable_grant();
    m->set_dt(dt);
    m->set_time(time);
    m->set_p_floor(2338);
    for (int k = 0; k < nodes; ++k) {
        m->add_p_l(p_L);
        m->add_u_l(0);
        m->add_z_l(1.5e6);
        m->add_geometric(0);
    }
    return g;
}

// The solver processes of one conformance check: each gets a fresh endpoint and a log of its own.
struct Sessions {
    std::vector<std::string> command;
    std::filesystem::path dir;
    double timeout; // seconds
    int n = 0;
    int ms() const { return static_cast<int>(timeout * 1000); }
    std::string next_endpoint() {
        char name[32];
        std::snprintf(name, sizeof name, "s%d.ipc", ++n);
        return "ipc://" + (dir / name).string();
    }
    std::string log() const { return (dir / ("solver-" + std::to_string(n) + ".log")).string(); }
};

// What a solver got wrong during the full run, per kind of message.
struct RunProblems {
    std::string offer, answer, sign, motion;
    int bad_answers = 0; // answers that break the interface condition
};

// The interface of the Hello: areas for the sign check.
struct HelloNodes {
    int n = -1;
    std::vector<double> area;
};

constexpr int full_run_steps = 30;

// The Offer of step from a solver of n interface nodes.
void check_offer(const wire::Offer& of, int step, int n, RunProblems& p) {
    if (!(of.dt() > 0) || !std::isfinite(of.dt()))
        p.offer += "step " + std::to_string(step) + ": dt_s not positive and finite; ";
    if (of.x_size() != n || of.y_size() != n || of.velocity_size() != n)
        p.offer += "step " + std::to_string(step) + ": not one x, y, velocity per node; ";
    else if (!finite_all(of.x()) || !finite_all(of.velocity()))
        p.offer += "step " + std::to_string(step) + ": non-finite values; ";
}

// The Answer of step to a Grant of p_L on each of the n nodes (u_L = geometric = 0, Z_L = 1.5e6); false when
// it does not hold one value per node.
bool check_answer(const wire::Answer& an, int step, int n, double p_L, RunProblems& p) {
    if (an.p_i_size() != n || an.u_i_size() != n || an.x_size() != n || an.y_size() != n) {
        p.answer += "step " + std::to_string(step) + ": not one p_I, u_I, x, y per node; ";
        return false;
    }
    for (int k = 0; k < n; ++k) {
        const double pi = an.p_i(k), u = an.u_i(k);
        if (!std::isfinite(pi) || !std::isfinite(u) || !std::isfinite(an.x(k)) || !std::isfinite(an.y(k))) {
            p.answer += "step " + std::to_string(step) + ": non-finite p_I, u_I, x or y; ";
            return true;
        }
        if (pi < 2338) p.answer += "step " + std::to_string(step) + ": p_I below p_floor; ";
        // The interface condition p_I = p_L − Z (u_I − u_L) − geometric (u_L = geometric = 0).
        const double expect = p_L - 1.5e6 * u;
        if (pi > 2338 * (1 + 1e-9) &&
            std::abs(pi - expect) > 1e-6 * std::max(std::abs(p_L), 1.5e6 * std::abs(u)) + 1e-3) {
            if (p.bad_answers++ == 0) {
                std::ostringstream m;
                m << "step " << step << ", node " << k << ": p_I = " << pi
                  << " Pa but p_L − Z_L (u_I − u_L) = " << expect << " Pa";
                p.answer += m.str();
            }
            return true;
        }
    }
    return true;
}

// The handshake: the interface nodes of a good Hello (n = -1: the failed check reported).
HelloNodes handshake(Channel& c, Report& r) {
    Envelope h;
    try {
        h = c.receive(0, Envelope::kHello);
    } catch (const CouplingError& e) {
        r.check(false, "sends a Hello after connecting", e.what());
        return {};
    }
    const std::string hp = hello_problems(h);
    r.check(hp.empty(), "Hello: dimension, alpha, one position, unit normal and positive area per node", hp);
    if (!hp.empty()) return {};
    const auto& hello = h.hello();
    int faces = 0;
    for (int f : hello.face())
        faces = std::max(faces, f + 1);
    const std::string fp = face_problems(hello);
    r.check(fp.empty(),
            "Hello: faces numbered 0, 1, ..., nodes consecutive" +
                std::string(hello.dimension() == 2 ? "; areas and normals those of the faces' segments (2D)"
                                                   : "") +
                " (dimension " + std::to_string(hello.dimension()) + ", alpha " +
                std::to_string(hello.alpha()) + ", " + std::to_string(hello.x_size()) + " node(s) on " +
                std::to_string(std::max(faces, 1)) + " face(s))",
            fp);
    if (!fp.empty()) return {};
    Envelope w = welcome();
    c.send(w);
    return {hello.x_size(), {hello.area().begin(), hello.area().end()}};
}

// The steps of the full run: 30, the last 20 under a 2 MPa pulse. Each Offer's positions are those the last
// Answer gave (the start of a step is the end of the one before). Throws CouplingError.
RunProblems run_steps(Channel& c, const HelloNodes& hello) {
    const int n = hello.n;
    RunProblems p;
    double time = 0, rise = 0;
    std::vector<double> x_end, y_end; // of the last Answer
    for (int step = 1; step <= full_run_steps; ++step) {
        const Envelope o = c.receive(step, Envelope::kOffer);
        if (o.has_stop()) {
            p.offer = "it sent Stop at step " + std::to_string(step);
            break;
        }
        check_offer(o.offer(), step, n, p);
        const auto& of = o.offer();
        if (p.motion.empty() && !x_end.empty() && of.x_size() == n && of.y_size() == n)
            for (int k = 0; k < n; ++k)
                if (of.x(k) != x_end[k] || of.y(k) != y_end[k]) {
                    std::ostringstream m;
                    m << "step " << step << ", node " << k << ": offered at (" << of.x(k) << ", " << of.y(k)
                      << ") but the Answer of step " << step - 1 << " ended at (" << x_end[k] << ", "
                      << y_end[k] << ")";
                    p.motion = m.str();
                    break;
                }
        const double dt = std::min(o.offer().dt() > 0 ? o.offer().dt() : 1e-7, 1e-7);
        const double p_L = step > 10 ? 2e6 : 1e5; // a 2 MPa pulse from step 11
        Envelope g = grant(step, n, dt, time, p_L);
        c.send(g);
        const Envelope a = c.receive(step, Envelope::kAnswer);
        if (a.has_stop()) {
            p.answer = "it sent Stop instead of the Answer of step " + std::to_string(step);
            break;
        }
        if (!check_answer(a.answer(), step, n, p_L, p)) continue;
        // The push of the pressure: Σ A_k u_I,k on the step it rises (a clamped node does not move; a rigid
        // face moves as one). Later the structure may spring back (a thin plate rings).
        double push = 0;
        for (int k = 0; k < n; ++k)
            push += hello.area[k] * a.answer().u_i(k);
        if (step == 10) rise = push;
        if (step == 11) rise = push - rise;
        x_end.assign(a.answer().x().begin(), a.answer().x().end());
        y_end.assign(a.answer().y().begin(), a.answer().y().end());
        time += dt;
    }
    if (p.offer.empty() && p.answer.find("Stop") == std::string::npos && !(rise > 0))
        p.sign = "when p_L rose from 0.1 to 2 MPa (step 11) Σ A_k u_I,k changed by " + std::to_string(rise) +
                 ": pressure must push the structure along n (from the fluid into it)";
    if (p.bad_answers > 1) p.answer += " (and in " + std::to_string(p.bad_answers - 1) + " more answers)";
    return p;
}

// 1. A full run: handshake, 30 steps (the last 20 under a pressure pulse), Stop. False when the solver did
// not get through the handshake (the other checks would tell nothing more).
bool check_full_run(Sessions& s, Report& r) {
    Channel c(s.next_endpoint(), Channel::Role::Bind, "the solver", s.ms());
    Subject solver(s.command, c.endpoint(), s.log());
    const HelloNodes hello = handshake(c, r);
    if (hello.n < 0) return false;
    try {
        const RunProblems p = run_steps(c, hello);
        r.check(p.offer.empty(), "Offers: steps numbered 1, 2, ...; dt_s > 0; one value per node", p.offer);
        r.check(p.motion.empty(), "Offers: each step starts where the last Answer's positions ended",
                p.motion);
        r.check(p.answer.empty(),
                "Answers: one finite p_I, u_I, x, y per node; p_I ≥ p_floor; p_I = p_L − Z_L (u_I − u_L) "
                "− geometric",
                p.answer);
        r.check(p.sign.empty(), "sign convention: pressure pushes the structure along n", p.sign);
        // After the last step the solver offers the next one and gets Stop.
        c.receive(full_run_steps + 1, Envelope::kOffer);
        Envelope stop;
        stop.set_step(full_run_steps + 1);
        stop.mutable_stop()->set_reason("end of the conformance run");
        c.send(stop);
        const int code = solver.wait(s.timeout);
        r.check(code == 0, "ends with exit status 0 on Stop",
                code < 0 ? "still running " + std::to_string(int(s.timeout)) + " s after Stop"
                         : "exit status " + std::to_string(code));
    } catch (const CouplingError& e) {
        r.check(false, "keeps to the sequence Offer → Grant → Answer for 30 steps and ends on Stop",
                e.what());
    }
    return true;
}

// 2.–4. A bad message from the fluid: the solver must stop with a non-zero status within its timeout.
struct Bad {
    const char* what;
    int kind; // 0 garbage, 1 wrong version, 2 wrong message
};

void send_bad(Channel& c, const Bad& b) {
    c.receive(0, Envelope::kHello);
    if (b.kind == 0) {
        c.send_raw(std::string("\xff\x00 not a coupling envelope", 27));
    } else if (b.kind == 1) {
        Envelope w = welcome();
        c.send_version(w, 99);
    } else {
        Envelope w = welcome();
        c.send(w);
        c.receive(1, Envelope::kOffer);
        Envelope again = welcome();
        again.set_step(1);
        c.send(again);
    }
}

void check_bad_message(Sessions& s, const Bad& b, Report& r) {
    Channel c(s.next_endpoint(), Channel::Role::Bind, "the solver", s.ms());
    Subject solver(s.command, c.endpoint(), s.log());
    try {
        send_bad(c, b);
    } catch (const CouplingError& e) {
        r.check(false, std::string("stops on ") + b.what,
                std::string("the run did not get that far: ") + e.what());
        return;
    }
    const int code = solver.wait(s.timeout + 5);
    r.check(code > 0, std::string("stops with a non-zero status on ") + b.what,
            code == 0 ? "exit status 0" : "still running " + std::to_string(int(s.timeout + 5)) + " s later");
}

} // namespace

int conform(const std::vector<std::string>& command, double timeout) {
    if (command.empty()) throw std::invalid_argument("conform needs a COMMAND after --");
    Sessions s{command,
               std::filesystem::temp_directory_path() / ("undex-conform-" + std::to_string(getpid())),
               timeout};
    std::filesystem::create_directories(s.dir);
    std::cout << "undex conform: checking '";
    for (size_t k = 0; k < command.size(); ++k)
        std::cout << (k ? " " : "") << command[k];
    std::cout << " --couple ENDPOINT'; its output: " << s.dir.string() << "/solver-*.log" << std::endl;
    Report r;
    if (!check_full_run(s, r)) {
        std::cout << "undex conform: " << r.failed << " check(s) failed" << std::endl;
        return r.failed;
    }
    for (const Bad& b :
         {Bad{"garbage bytes instead of the Welcome", 0}, Bad{"a Welcome of protocol version 99", 1},
          Bad{"a Welcome where the Grant of step 1 is due", 2}})
        check_bad_message(s, b, r);
    std::cout << "undex conform: "
              << (r.failed ? std::to_string(r.failed) + " check(s) failed" : "conforming") << std::endl;
    return r.failed;
}

} // namespace undex::coupling
