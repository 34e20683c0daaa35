// undex: the command-line front end.
//   undex check CASE [--set key=value]...      validate a case without running it
//   undex run CASE [--set key=value]... [--tcp | --endpoint E]
//                                              run a case: the solver process a single-field case needs, or
//                                              the fluid and structure processes of a coupled case
//   undex sample DIR --time T --line "x0,y0 x1,y1" --points N [--fields rho,u,v,p]
//   undex gauges DIR [--name NAME]
//   undex options                              list the named choices of a case file
#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "base/run_plan.hpp"
#include "coupler/conform.hpp"
#include "fluid/output.hpp"
#include "fluid/setup.hpp"
#include "proto/case.pb.h"
#include "solid/structure_setup.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

const char* usage =
    "usage:\n"
    "  undex check CASE [--set key=value]...\n"
    "  undex run CASE [--set key=value]... [--tcp | --endpoint ENDPOINT]\n"
    "  undex sample DIR --time T --line \"x0,y0 x1,y1\" --points N [--fields rho,u,v,p]\n"
    "  undex gauges DIR [--name NAME]\n"
    "  undex options\n"
    "  undex conform [--timeout S] -- COMMAND...   check a structure solver against the protocol\n";

struct Args {
    std::vector<std::string> positional;
    std::vector<std::string> overrides;
    std::map<std::string, std::string> options;
};

Args parse(int argc, char** argv, int first) {
    Args a;
    for (int k = first; k < argc; ++k) {
        std::string s = argv[k];
        if (s.rfind("--", 0) == 0) {
            std::string key = s.substr(2), value;
            const auto eq = key.find('=');
            if (eq != std::string::npos)
                value = key.substr(eq + 1), key = key.substr(0, eq);
            else if (key == "tcp") // a flag
                value = "1";
            else if (k + 1 < argc)
                value = argv[++k];
            else
                throw std::invalid_argument("option --" + key + " needs a value");
            if (key == "set")
                a.overrides.push_back(value);
            else
                a.options[key] = value;
        } else {
            a.positional.push_back(s);
        }
    }
    return a;
}

std::string h5_of(const std::string& dir) {
    const std::filesystem::path p(dir);
    if (!std::filesystem::is_directory(p)) return dir;
    // A structure-only run has solid.h5 and no fluid.h5.
    if (!std::filesystem::exists(p / "fluid.h5") && std::filesystem::exists(p / "solid.h5"))
        return (p / "solid.h5").string();
    return (p / "fluid.h5").string();
}

// Which parts the case holds; each is checked in full. A case with neither is an error.
struct Parts {
    bool fluid, structure;
};
Parts check_parts(const undex::CaseFile& c) {
    const Parts p{undex::has_fluid(c), undex::has_structure(c)};
    if (!p.fluid && !p.structure)
        c.fail("regions", "the case models nothing: give fluid regions or a structure");
    if (p.fluid) undex::fluid::validate(c);
    if (p.structure) undex::solid::check_structure(c);
    return p;
}

int check(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("check needs one CASE");
    const auto c = undex::CaseFile::load(a.positional[0], a.overrides);
    const Parts parts = check_parts(c);
    const auto& m = c.get();
    const auto& st = m.structure();
    if (parts.structure && (st.has_rigid_plate() || st.has_command())) {
        std::cout << a.positional[0] << ": ok: structure ";
        if (st.has_rigid_plate())
            std::cout << "rigid plate of " << st.rigid_plate().mass_per_area() << " kg/m² (undex-rigid); ";
        else
            std::cout << "solver '" << st.command() << "'; ";
    } else if (parts.structure) {
        const auto s = undex::solid::make_structure(c);
        std::cout << a.positional[0] << ": ok: structure of " << m.structure().layers_size() << " layer(s), "
                  << s.structure->element_count() << " elements"
                  << (s.structure->dimension() == 1                    ? ""
                      : m.geometry() == undex::config::AXISYMMETRIC_2D ? " (axisymmetric)"
                                                                       : " (plane strain)")
                  << ", time step " << s.dt << " s";
        if (!parts.fluid) {
            std::cout << ", end time " << m.end_time() << " s\n";
            return 0;
        }
        std::cout << "; ";
    }
    const auto p = undex::plan(c);
    std::cout << a.positional[0] << ": ok: " << undex::config::Geometry_Name(m.geometry()) << ", "
              << m.domain().cells_x();
    if (m.domain().has_cells_y()) std::cout << " x " << m.domain().cells_y();
    std::cout << " cells, degree " << m.numerics().degree() << ", end time " << m.end_time() << " s, "
              << p.output_times.size() << " output time(s), output to " << p.directory << "\n";
    return 0;
}

volatile std::sig_atomic_t interrupted = 0; // 1: SIGINT or SIGTERM arrived, 2: passed on to both sides

// A child process whose stdout and stderr arrive on one pipe.
struct Child {
    std::string name; // the prefix of its lines
    pid_t pid = -1;
    int fd = -1;         // read end of its output
    std::string pending; // an incomplete last line
    std::ofstream log;   // <output>/<name>.log
    int status = -1;     // exit code once ended (128 + signal when killed)
    bool ended = false;
};

void spawn(Child& c, const std::vector<std::string>& args) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) // not inherited by the other side's process
        throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
    std::vector<char*> argv;
    std::vector<std::string> copy = args;
    for (auto& s : copy)
        argv.push_back(s.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        throw std::runtime_error(std::string("cannot start a process: ") + std::strerror(errno));
    }
    if (pid == 0) {
        setpgid(0, 0); // its own process group: stopping it reaches whatever it starts
        dup2(fds[1], 1);
        dup2(fds[1], 2);
        close(fds[0]);
        close(fds[1]);
        execvp(argv[0], argv.data());
        std::fprintf(stderr, "undex: cannot start %s: %s\n", argv[0], std::strerror(errno));
        _exit(127);
    }
    close(fds[1]);
    c.pid = pid;
    c.fd = fds[0];
}

// Passes complete lines of c's output to the terminal (prefixed) and to its log; false at end of output.
bool pump(Child& c) {
    char buf[65536];
    const ssize_t n = read(c.fd, buf, sizeof buf);
    if (n <= 0) {
        if (!c.pending.empty()) c.pending += "\n";
    } else {
        c.pending.append(buf, static_cast<size_t>(n));
    }
    size_t from = 0;
    for (size_t nl; (nl = c.pending.find('\n', from)) != std::string::npos; from = nl + 1) {
        const std::string line = c.pending.substr(from, nl - from);
        c.log << line << '\n';
        std::cout << c.name << " | " << line << '\n';
    }
    c.pending.erase(0, from);
    std::cout.flush();
    c.log.flush();
    return n > 0;
}

bool reap(Child& c, bool block) {
    if (c.ended) return true;
    int st = 0;
    const pid_t r = waitpid(c.pid, &st, block ? 0 : WNOHANG);
    if (r != c.pid) return false;
    c.ended = true;
    c.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    return true;
}

// A free tcp port on this host (bound and released; the fluid binds it right after).
int free_tcp_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;
    socklen_t len = sizeof addr;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
        throw std::runtime_error("cannot find a free tcp port");
    close(fd);
    return ntohs(addr.sin_port);
}

// Runs the fluid and the structure process of a coupled case side by side (docs/protocol.md).
int run_coupled(const Args& a, const undex::CaseFile& c, const std::filesystem::path& bin) {
    std::string endpoint;
    if (a.options.count("endpoint"))
        endpoint = a.options.at("endpoint");
    else if (a.options.count("tcp"))
        endpoint = "tcp://127.0.0.1:" + std::to_string(free_tcp_port());
    else
        endpoint = "ipc://" +
                   (std::filesystem::temp_directory_path() / ("undex-" + std::to_string(getpid()) + ".ipc"))
                       .string();
    const auto plan = undex::plan(c);
    std::filesystem::create_directories(plan.directory);
    const auto& st = c.get().structure();
    std::vector<std::string> fluid = {(bin / "undex-fluid").string(), a.positional[0]}, solid;
    if (st.has_command()) {
        solid = {"/bin/sh", "-c",
                 "exec " + st.command() + " --couple " + undex::coupling::shell_quote(endpoint)};
    } else {
        solid = {(bin / (st.has_rigid_plate() ? "undex-rigid" : "undex-solid")).string(), a.positional[0]};
    }
    for (const auto& o : a.overrides) {
        fluid.insert(fluid.end(), {"--set", o});
        if (!st.has_command()) solid.insert(solid.end(), {"--set", o});
    }
    fluid.insert(fluid.end(), {"--couple", endpoint});
    if (!st.has_command()) solid.insert(solid.end(), {"--couple", endpoint});
    Child children[2];
    children[0].name = "fluid";
    children[1].name = "solid";
    std::cout << "undex: " << a.positional[0] << ": coupled run over " << endpoint << "; logs "
              << plan.directory << "/fluid.log, " << plan.directory << "/solid.log" << std::endl;
    try {
        for (int k = 0; k < 2; ++k)
            spawn(children[k], k == 0 ? fluid : solid);
    } catch (...) {
        if (children[0].pid > 0) kill(-children[0].pid, SIGKILL), reap(children[0], true);
        throw;
    }
    for (auto& ch : children) // opened after both started, so that neither inherits the other's log
        ch.log.open(std::filesystem::path(plan.directory) / (ch.name + ".log"));
    // SIGINT or SIGTERM to undex stops both sides (each runs in its own process group).
    struct sigaction sa {};
    sa.sa_handler = [](int) { interrupted = 1; };
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    // Interleave the output until both sides ended; when one side fails, the other gets a grace period to
    // notice (it writes its last output), then is stopped.
    bool open[2] = {true, true};
    std::chrono::steady_clock::time_point failed_at{};
    bool any_failed = false;
    int stopped = 0; // 1: SIGTERM sent, 2: SIGKILL sent
    auto signal_all = [&](int sig) {
        for (auto& ch : children)
            if (!ch.ended) kill(-ch.pid, sig), kill(-ch.pid, SIGCONT);
    };
    while (!children[0].ended || !children[1].ended) {
        pollfd fds[2];
        int n = 0, which[2];
        for (int k = 0; k < 2; ++k)
            if (open[k]) fds[n] = {children[k].fd, POLLIN, 0}, which[n++] = k;
        if (n > 0)
            poll(fds, n, 200);
        else
            usleep(50000);
        for (int i = 0; i < n; ++i)
            if (fds[i].revents & (POLLIN | POLLHUP | POLLERR))
                if (!pump(children[which[i]])) open[which[i]] = false, close(children[which[i]].fd);
        for (auto& ch : children)
            if (reap(ch, false) && ch.status != 0 && !any_failed)
                any_failed = true, failed_at = std::chrono::steady_clock::now();
        if (interrupted == 1) {
            std::cout << "undex: interrupted: stopping both sides" << std::endl;
            signal_all(SIGTERM);
            interrupted = 2;
            if (!any_failed) any_failed = true, failed_at = std::chrono::steady_clock::now(), stopped = 1;
        }
        // A side that is still running 5 s after the other failed is stopped (SIGTERM, and SIGKILL 3 s later
        // for one that does not react, e.g. a stopped process).
        const auto since = std::chrono::steady_clock::now() - failed_at;
        if (any_failed && stopped < 2 && since > std::chrono::seconds(stopped == 0 ? 5 : 8)) {
            for (auto& ch : children)
                if (!ch.ended && stopped == 0)
                    std::cout << "undex: stopping " << ch.name << " (the other side failed)" << std::endl;
            signal_all(stopped == 0 ? SIGTERM : SIGKILL);
            ++stopped;
        }
    }
    // What is left in the pipes (a process the solver started may still hold one: not waited for).
    for (int k = 0; k < 2; ++k) {
        if (!open[k]) continue;
        pollfd f{children[k].fd, POLLIN, 0};
        while (poll(&f, 1, 100) > 0 && pump(children[k])) {
        }
        close(children[k].fd);
    }
    int code = 0;
    for (const auto& ch : children)
        if (ch.status != 0) {
            std::cout << "undex: " << ch.name << " ended with exit code " << ch.status << std::endl;
            if (code == 0) code = ch.status;
        }
    if (code == 0) std::cout << "undex: done: output in " << plan.directory << std::endl;
    return code;
}

int run(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("run needs one CASE");
    // Check the case here so that a bad case is reported before any process starts.
    const auto c = undex::CaseFile::load(a.positional[0], a.overrides);
    const Parts parts = check_parts(c);
    const auto bin = std::filesystem::read_symlink("/proc/self/exe").parent_path();
    if (parts.structure && parts.fluid) return run_coupled(a, c, bin);
    // A single-field case needs only its own process.
    const std::string exe = (bin / (parts.fluid ? "undex-fluid" : "undex-solid")).string();
    std::vector<std::string> args = {exe, a.positional[0]};
    for (const auto& o : a.overrides)
        args.insert(args.end(), {"--set", o});
    std::vector<char*> cargs;
    for (auto& s : args)
        cargs.push_back(s.data());
    cargs.push_back(nullptr);
    std::cout.flush();
    execv(exe.c_str(), cargs.data());
    std::cerr << "undex: error: cannot start " << exe << ": " << std::strerror(errno) << "\n";
    return 1;
}

std::vector<double> parse_point(const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string part;
    while (std::getline(ss, part, ','))
        v.push_back(std::stod(part));
    if (v.size() == 1) v.push_back(0.0);
    if (v.size() != 2) throw std::invalid_argument("a point is x,y (got '" + s + "')");
    return v;
}

int sample(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("sample needs one output DIR");
    for (const char* k : {"time", "line", "points"})
        if (!a.options.count(k)) throw std::invalid_argument(std::string("sample needs --") + k);
    const std::string h5 = h5_of(a.positional[0]);
    if (std::filesystem::path(h5).filename() == "solid.h5")
        throw std::runtime_error(h5 + ": sample evaluates fluid fields; a structure's fields are datasets of "
                                      "solid.h5 (fields/NNNNNN) and its gauges print with `undex gauges`");
    const auto run = undex::h5::read_run(h5);
    if (run.times.empty()) throw std::runtime_error(h5 + ": holds no output");
    const double t = std::stod(a.options.at("time"));
    size_t best = 0;
    for (size_t k = 1; k < run.times.size(); ++k)
        if (std::abs(run.times[k] - t) < std::abs(run.times[best] - t)) best = k;
    const auto c = undex::CaseFile::from_text(run.case_text, h5);
    auto solver = undex::fluid::make_solver(c);
    solver->set_coefficients(undex::fluid::read_coefficients(h5, run.groups[best]), run.times[best]);
    const auto phi = undex::fluid::read_level_set(h5, run.groups[best]);
    if (!phi.empty()) solver->set_level_set(phi);
    std::stringstream line(a.options.at("line"));
    std::string p0s, p1s;
    line >> p0s >> p1s;
    const auto p0 = parse_point(p0s), p1 = parse_point(p1s);
    const int n = std::stoi(a.options.at("points"));
    if (n < 1) throw std::invalid_argument("--points must be ≥ 1");
    std::vector<std::string> fields = {"rho", "u", "v", "p"};
    if (a.options.count("fields")) {
        fields.clear();
        std::stringstream fs(a.options.at("fields"));
        std::string f;
        while (std::getline(fs, f, ','))
            if (f == "rho" || f == "u" || f == "v" || f == "p")
                fields.push_back(f);
            else
                throw std::invalid_argument("unknown field '" + f + "' (fields: rho, u, v, p)");
    }
    std::printf("# time = %.9g s\nx,y", run.times[best]);
    for (const auto& f : fields)
        std::printf(",%s", f.c_str());
    std::printf("\n");
    for (int k = 0; k < n; ++k) {
        const double s = n == 1 ? 0.0 : double(k) / (n - 1);
        const double x = p0[0] + s * (p1[0] - p0[0]), y = p0[1] + s * (p1[1] - p0[1]);
        const auto w = solver->evaluate(x, y);
        std::printf("%.9g,%.9g", x, y);
        for (const auto& f : fields)
            std::printf(",%.12g", f == "rho" ? w.rho : f == "u" ? w.u : f == "v" ? w.v : w.p);
        std::printf("\n");
    }
    return 0;
}

int gauges(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("gauges needs one output DIR");
    const std::string h5 = h5_of(a.positional[0]);
    const auto run = undex::h5::read_run(h5);
    std::vector<std::string> names = run.gauge_names;
    if (a.options.count("name")) {
        names = {a.options.at("name")};
        bool found = false;
        for (const auto& g : run.gauge_names)
            found = found || g == names[0];
        if (!found) throw std::runtime_error("no gauge named '" + names[0] + "' in " + h5);
    }
    if (names.empty()) throw std::runtime_error(h5 + ": the case has no gauges");
    const bool solid = std::filesystem::path(h5).filename() == "solid.h5";
    std::vector<std::string> columns = {"t", "rho", "u", "v", "p"};
    if (solid) { // the structure output lists its gauge columns
        columns.clear();
        hid_t f = undex::h5::open_read(h5);
        hid_t g = H5Gopen2(f, "gauges", H5P_DEFAULT);
        std::stringstream list(undex::h5::read_attr_string(g, "columns"));
        H5Gclose(g);
        H5Fclose(f);
        for (std::string c; std::getline(list, c, ',');)
            columns.push_back(c);
    }
    std::vector<std::vector<std::vector<double>>> cols;
    for (const auto& n : names)
        cols.push_back(undex::h5::read_gauge(h5, n, columns));
    std::printf("t");
    const bool many = names.size() > 1;
    for (const auto& n : names)
        for (size_t f = 1; f < columns.size(); ++f)
            std::printf(many ? ",%s.%s" : ",%s", many ? n.c_str() : columns[f].c_str(), columns[f].c_str());
    std::printf("\n");
    const size_t rows = cols[0][0].size();
    for (size_t r = 0; r < rows; ++r) {
        std::printf("%.12g", cols[0][0][r]);
        for (const auto& g : cols)
            for (size_t f = 1; f < columns.size(); ++f)
                std::printf(",%.12g", r < g[f].size() ? g[f][r] : NAN);
        std::printf("\n");
    }
    return 0;
}

int options() {
    std::cout << "numerics.indicator:\n";
    for (const auto& n : undex::fluid::indicator_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "numerics.limiter:\n";
    for (const auto& n : undex::fluid::limiter_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "interface.method:\n";
    for (const auto& n : undex::fluid::ghost_method_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "interface.riemann:\n";
    for (const auto& n : undex::fluid::interface_riemann_names())
        std::cout << "  " << n.name << "  " << n.doc << "\n";
    std::cout << "structure.kinematics:\n";
    for (const auto& n : undex::solid::kinematics_names())
        std::cout << "  " << n.first << "  " << n.second << "\n";
    std::cout << "geometry: PLANAR_1D CYLINDRICAL_1D SPHERICAL_1D PLANAR_2D AXISYMMETRIC_2D\n"
              << "boundary type: TRANSMISSIVE WALL SYMMETRY PRESSURE PERIODIC STRUCTURE (x_max: the "
                 "structure's wet face)\n"
              << "structure face type: FREE FIXED PRESSURE FLUID (front: wetted by the fluid)\n"
              << "material models: stiffened_gas { gamma p_inf }, tait { gamma B A rho0 as_stiffened_gas }\n"
              << "the schema with every field and its default: proto/case.proto\n";
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << usage;
        return 64;
    }
    const std::string cmd = argv[1];
    try {
        if (cmd == "conform") { // undex conform [--timeout S] -- COMMAND...
            double timeout = 10;
            int k = 2;
            for (; k < argc && std::strcmp(argv[k], "--") != 0; ++k)
                if (std::strcmp(argv[k], "--timeout") == 0 && k + 1 < argc)
                    timeout = std::stod(argv[++k]);
                else
                    throw std::invalid_argument(std::string("conform: unexpected '") + argv[k] + "'");
            std::vector<std::string> command(argv + std::min(k + 1, argc), argv + argc);
            return std::min(undex::coupling::conform(command, timeout), 100);
        }
        const Args a = parse(argc, argv, 2);
        if (cmd == "check") return check(a);
        if (cmd == "run") return run(a);
        if (cmd == "sample") return sample(a);
        if (cmd == "gauges") return gauges(a);
        if (cmd == "options") return options();
        if (cmd == "help" || cmd == "--help" || cmd == "-h") {
            std::cout << usage;
            return 0;
        }
        std::cerr << "undex: unknown command '" << cmd << "'\n" << usage;
        return 64;
    } catch (const undex::CaseError& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return 1;
    } catch (const std::invalid_argument& e) {
        std::cerr << "undex: error: " << e.what() << "\n" << usage;
        return 64;
    } catch (const std::exception& e) {
        std::cerr << "undex: error: " << e.what() << "\n";
        return 1;
    }
}
