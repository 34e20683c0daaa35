#include "base/run_plan.hpp"

#include "base/case_file.hpp"
#include "base/run_driver.hpp"
#include "proto/case.pb.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

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

void validate_plan(const CaseFile& cf) {
    const cfg::Case& c = cf.get();
    if (!(c.end_time() > 0)) cf.fail("end_time", "must be positive");
    const auto& o = c.output();
    for (int k = 0; k < o.times_size(); ++k)
        if (!(o.times(k) > 0 && o.times(k) <= c.end_time()))
            cf.fail("output.times",
                    "output time " + std::to_string(o.times(k)) + " s lies outside (0, end_time]");
    if (!(o.interval() >= 0)) cf.fail("output.interval", "must be ≥ 0");
    if (!(o.progress_seconds() > 0)) cf.fail("output.progress_seconds", "must be positive");
    if (o.gauge_every() < 1) cf.fail("output.gauge_every", "must be ≥ 1");
    if (c.numerics().max_steps() < 1) cf.fail("numerics.max_steps", "must be ≥ 1");
    const RunPlan rp = plan(cf);
    if (!writable_directory(rp.directory))
        cf.fail("output.directory", "cannot write the output directory '" + rp.directory + "'");
    const auto& k = c.coupling();
    if (!(k.timeout() > 0 && k.timeout() <= 86400))
        cf.fail("coupling.timeout", "must lie in (0, 86400] s (got " + std::to_string(k.timeout()) + ")");
    if (!(k.handshake_timeout() > 0 && k.handshake_timeout() <= 86400))
        cf.fail("coupling.handshake_timeout",
                "must lie in (0, 86400] s (got " + std::to_string(k.handshake_timeout()) + ")");
}

void validate_pressure_history(const CaseFile& cf, const cfg::PressureHistory& h, const std::string& path) {
    if (h.table_t_size() != h.table_p_size())
        cf.fail(path + ".table_p", "table_t and table_p must have the same length");
    for (int k = 1; k < h.table_t_size(); ++k)
        if (!(h.table_t(k) > h.table_t(k - 1)))
            cf.fail(path + ".table_t", "times must increase (entry " + std::to_string(k) + ")");
    if (h.table_t_size() == 0 && !(h.theta() > 0))
        cf.fail(path + ".theta", "decay time theta must be positive");
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
