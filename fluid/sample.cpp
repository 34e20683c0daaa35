// undex-fluid --sample (fluid/sample.hpp).
#include "fluid/sample.hpp"

#include "base/case_file.hpp"
#include "base/h5.hpp"
#include "fluid/output.hpp"
#include "fluid/setup.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace undex::fluid {

namespace {

// "x,y" or "x" (y = 0): finite numbers, each read whole (no "1x" read as 1).
std::vector<double> parse_point(const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string part;
    while (std::getline(ss, part, ',')) {
        char* end = nullptr;
        const double x = std::strtod(part.c_str(), &end);
        if (part.empty() || *end != '\0' || !std::isfinite(x))
            throw UsageError("a point is x,y of two finite numbers (got '" + s + "')");
        v.push_back(x);
    }
    if (v.size() == 1) v.push_back(0.0);
    if (v.size() != 2 || (!s.empty() && s.back() == ','))
        throw UsageError("a point is x,y of two finite numbers (got '" + s + "')");
    return v;
}

std::vector<std::string> checked_fields(const std::vector<std::string>& asked) {
    if (asked.empty()) return {"rho", "u", "v", "p"};
    for (const auto& f : asked)
        if (f != "rho" && f != "u" && f != "v" && f != "p")
            throw UsageError("unknown field '" + f + "' (fields: rho, u, v, p)");
    return asked;
}

} // namespace

int sample(const SampleRequest& r, std::FILE* out) {
    std::stringstream line(r.line);
    std::string p0s, p1s, more;
    line >> p0s >> p1s;
    if (p1s.empty() || line >> more)
        throw UsageError("--line is two points \"x0,y0 x1,y1\" (got '" + r.line + "')");
    const auto p0 = parse_point(p0s), p1 = parse_point(p1s);
    if (!std::isfinite(r.time)) throw UsageError("--time must be a finite number");
    const int n = r.points;
    if (n < 1) throw UsageError("--points must be ≥ 1");
    const auto fields = checked_fields(r.fields);
    const std::string h5 = h5::output_file(r.directory);
    if (std::filesystem::path(h5).filename() == "solid.h5")
        throw std::runtime_error(h5 + ": sample evaluates fluid fields; a structure's fields are datasets of "
                                      "solid.h5 (fields/NNNNNN) and its gauges print with `undex gauges`");
    const auto run = h5::read_run(h5);
    if (run.times.empty()) throw std::runtime_error(h5 + ": holds no output");
    size_t best = 0;
    for (size_t k = 1; k < run.times.size(); ++k)
        if (std::abs(run.times[k] - r.time) < std::abs(run.times[best] - r.time)) best = k;
    const auto c = CaseFile::from_text(run.case_text, h5);
    auto solver = make_solver(c);
    solver->set_coefficients(read_coefficients(h5, run.groups[best]), run.times[best]);
    const auto phi = read_level_set(h5, run.groups[best]);
    if (!phi.empty()) solver->set_level_set(phi);
    std::fprintf(out, "# time = %.9g s\nx,y", run.times[best]);
    for (const auto& f : fields)
        std::fprintf(out, ",%s", f.c_str());
    std::fprintf(out, "\n");
    for (int k = 0; k < n; ++k) {
        const double s = n == 1 ? 0.0 : double(k) / (n - 1);
        const double x = p0[0] + s * (p1[0] - p0[0]), y = p0[1] + s * (p1[1] - p0[1]);
        const auto w = solver->evaluate(x, y);
        std::fprintf(out, "%.9g,%.9g", x, y);
        for (const auto& f : fields)
            std::fprintf(out, ",%.12g", f == "rho" ? w.rho : f == "u" ? w.u : f == "v" ? w.v : w.p);
        std::fprintf(out, "\n");
    }
    return 0;
}

} // namespace undex::fluid
