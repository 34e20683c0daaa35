// undex gauges (launcher/gauges.hpp): reads HDF5 only.
#include "launcher/gauges.hpp"

#include "base/h5.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace undex::launcher {

namespace {

// The gauge columns of an output: the structure output lists them, the fluid's are fixed.
std::vector<std::string> columns_of(const std::string& h5) {
    if (std::filesystem::path(h5).filename() != "solid.h5") return {"t", "rho", "u", "v", "p"};
    std::vector<std::string> columns;
    const h5::Object f = h5::open_read(h5);
    std::stringstream list(h5::read_attr_string(h5::open_group(f.id(), "gauges").id(), "columns"));
    for (std::string c; std::getline(list, c, ',');)
        columns.push_back(c);
    return columns;
}

} // namespace

int gauges(const std::string& dir, const std::string& name) {
    const std::string h5 = h5::output_file(dir);
    const auto run = h5::read_run(h5);
    std::vector<std::string> names = run.gauge_names;
    if (!name.empty()) {
        names = {name};
        bool found = false;
        for (const auto& g : run.gauge_names)
            found = found || g == names[0];
        if (!found) throw std::runtime_error("no gauge named '" + names[0] + "' in " + h5);
    }
    if (names.empty()) throw std::runtime_error(h5 + ": the case has no gauges");
    const std::vector<std::string> columns = columns_of(h5);
    std::vector<std::vector<std::vector<double>>> cols;
    for (const auto& n : names)
        cols.push_back(h5::read_gauge(h5, n, columns));
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

} // namespace undex::launcher
