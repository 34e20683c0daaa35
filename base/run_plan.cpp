#include "base/run_plan.hpp"

#include "base/case_file.hpp"
#include "base/run_driver.hpp"
#include "proto/case.pb.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace undex {

namespace cfg = undex::config;

bool has_fluid(const CaseFile& cf) {
    const auto& c = cf.get();
    return c.regions_size() > 0 || c.has_domain() || c.has_boundaries() || c.materials_size() > 0;
}

bool has_structure(const CaseFile& cf) {
    return cf.get().has_structure();
}

RunPlan plan(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    RunPlan p;
    p.end_time = c.end_time();
    for (double t : c.output().times())
        p.output_times.push_back(t);
    if (c.output().interval() > 0)
        for (double t = c.output().interval(); t < c.end_time() * (1 - 1e-12); t += c.output().interval())
            p.output_times.push_back(t);
    p.output_times.push_back(c.end_time());
    std::sort(p.output_times.begin(), p.output_times.end());
    // Output times closer than the Δt floor (base/run_driver.hpp) are one, the later kept (so end_time stays
    // the last): the step between them would be refused.
    const double merge = dt_floor_fraction * c.end_time();
    std::vector<double> kept;
    for (auto t = p.output_times.rbegin(); t != p.output_times.rend(); ++t)
        if (kept.empty() || kept.back() - *t > merge) kept.push_back(*t);
    p.output_times.assign(kept.rbegin(), kept.rend());
    std::string name = c.name();
    if (name.empty()) name = std::filesystem::path(cf.path()).stem().string();
    p.directory = c.output().has_directory() ? c.output().directory() : "out/" + name;
    p.progress_seconds = c.output().progress_seconds();
    p.checkpoint_seconds = c.output().checkpoint_seconds();
    p.gauge_every = c.output().gauge_every();
    p.threads = c.numerics().threads();
    p.max_steps = c.numerics().max_steps();
    p.coupling_timeout_ms = static_cast<int>(1000 * c.coupling().timeout());
    p.handshake_timeout_ms = static_cast<int>(1000 * c.coupling().handshake_timeout());
    for (const auto& g : c.gauges())
        p.gauges.push_back({g.name(), g.x(), g.y()});
    return p;
}

// Whether a directory could be created or written, tested for real (permission bits say nothing to root,
// nor about read-only or pseudo file systems): a probe directory is made in the nearest existing ancestor
// and removed again, so nothing is left behind.
bool writable_directory(const std::string& directory) {
    const std::filesystem::path dir(directory);
    namespace fs = std::filesystem;
    fs::path p = fs::absolute(dir);
    while (!p.empty()) {
        std::error_code ec;
        if (fs::exists(p, ec)) {
            if (!fs::is_directory(p, ec)) return false;
            std::string probe = (p / ".undex-probe-XXXXXX").string();
            if (!mkdtemp(probe.data())) return false;
            rmdir(probe.c_str());
            return true;
        }
        if (p == p.parent_path()) break;
        p = p.parent_path();
    }
    return false;
}

MemoryLimit memory_limit() {
    const double physical =
        static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    MemoryLimit m{physical > 0 ? physical : 0, "the machine's physical memory"};
    rlimit r{};
    if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY &&
        (m.bytes <= 0 || static_cast<double>(r.rlim_cur) < m.bytes))
        m = {static_cast<double>(r.rlim_cur), "the address-space limit (ulimit -v)"};
    // A container's memory limit (cgroup v2, then v1; "max" or a huge number when there is none).
    for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
        std::ifstream in(file);
        double limit = 0;
        if (in >> limit && limit > 0 && (m.bytes <= 0 || limit < m.bytes)) {
            m = {limit, std::string("the memory limit of this process's control group (") + file + ")"};
            break;
        }
    }
    return m;
}

namespace {
std::string gib(double bytes) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g GiB", bytes / (1u << 30));
    return b;
}

std::string number(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", x);
    return b;
}

double output_count(const cfg::Case& c) {
    const auto& o = c.output();
    double n = o.times_size() + 1.0; // end_time
    if (o.interval() > 0) n += std::floor(c.end_time() / o.interval());
    return n;
}
} // namespace

void check_memory(const CaseFile& cf, const std::string& field, const std::string& what, double count,
                  double bytes_each) {
    const MemoryLimit m = memory_limit();
    const double need = count * bytes_each;
    if (!(need <= m.bytes) && m.bytes > 0) {
        char b[64];
        std::snprintf(b, sizeof b, "%.4g", count);
        cf.fail(field, std::string(b) + " " + what + " need about " + gib(need) + " (" +
                           std::to_string(static_cast<long>(bytes_each)) + " bytes each), more than " +
                           m.what + ", " + gib(m.bytes));
    }
}

void validate_plan(const CaseFile& cf) {
    cf.check_ranges();
    const cfg::Case& c = cf.get();
    const auto& o = c.output();
    for (int k = 0; k < o.times_size(); ++k)
        if (!(o.times(k) <= c.end_time()))
            cf.fail("output.times[" + std::to_string(k) + "]",
                    "output time " + std::to_string(o.times(k)) + " s lies after end_time");
    // Counted in double before any list is made: end_time / interval may be any size.
    if (!(output_count(c) <= max_output_times))
        cf.fail(o.interval() > 0 ? "output.interval" : "output.times",
                "the case asks for about " + number(output_count(c)) + " output times; at most " +
                    number(max_output_times));
    if (o.has_directory() && o.directory().find_first_not_of(" \t") == std::string::npos)
        cf.fail("output.directory", "the output directory is empty; give one, or leave the field out for "
                                    "out/<name>");
    const RunPlan rp = plan(cf);
    if (!writable_directory(rp.directory))
        cf.fail("output.directory", "cannot write the output directory '" + rp.directory + "'");
}

void validate_pressure_history(const CaseFile& cf, const cfg::PressureHistory& h, const std::string& path) {
    if (h.table_t_size() != h.table_p_size())
        cf.fail(path + ".table_p", "table_t and table_p must have the same length");
    for (int k = 1; k < h.table_t_size(); ++k)
        if (!(h.table_t(k) > h.table_t(k - 1)))
            cf.fail(path + ".table_t[" + std::to_string(k) + "]",
                    "times must increase (entry " + std::to_string(k) + ")");
}

std::function<double(double)> pressure_history(const cfg::PressureHistory& h) {
    if (h.table_t_size() > 0) {
        std::vector<double> t(h.table_t().begin(), h.table_t().end()),
            p(h.table_p().begin(), h.table_p().end());
        return [t, p](double time) {
            if (time <= t.front()) return p.front();
            if (time >= t.back()) return p.back();
            const auto k = std::upper_bound(t.begin(), t.end(), time) - t.begin();
            const double f = (time - t[k - 1]) / (t[k] - t[k - 1]);
            return (1 - f) * p[k - 1] + f * p[k];
        };
    }
    const double amb = h.p_ambient(), peak = h.p_peak(), theta = h.theta(), t0 = h.t_arrival();
    return [=](double time) { return time < t0 ? amb : amb + peak * std::exp(-(time - t0) / theta); };
}

} // namespace undex
