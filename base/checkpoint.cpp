#include "base/checkpoint.hpp"

#include "base/h5.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace undex {

namespace {
// The build's sizes, so that a checkpoint of another build is refused instead of misread.
std::string layout() {
    return "long " + std::to_string(sizeof(long)) + ", double " + std::to_string(sizeof(double)) +
           ", pointer " + std::to_string(sizeof(void*));
}
} // namespace

struct State::File {
    h5::Object file;
    std::string path, final_path, directory, side, partner;
    bool loading = false, committed = false;
    long step = 0;
    double time = 0;
    // A checkpoint given up on the way (a full disk) leaves nothing: the one before stays in place.
    ~File() {
        if (loading || committed) return;
        file = h5::Object(); // closed, errors ignored
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
    }
};

namespace {

std::string name_of(const std::string& side, long step) {
    char n[64];
    std::snprintf(n, sizeof n, "%s.checkpoint.%09ld.h5", side.c_str(), step);
    return n;
}

} // namespace

std::vector<std::pair<long, std::string>> checkpoints(const std::string& directory, const std::string& side) {
    std::vector<std::pair<long, std::string>> out;
    std::error_code e;
    const std::string head = side + ".checkpoint.";
    for (const auto& entry : std::filesystem::directory_iterator(directory, e)) {
        const std::string n = entry.path().filename().string();
        if (n.size() != head.size() + 12 || n.compare(0, head.size(), head) != 0 ||
            n.substr(n.size() - 3) != ".h5")
            continue;
        char* end = nullptr;
        const long step = std::strtol(n.c_str() + head.size(), &end, 10);
        if (end == n.c_str() + head.size() + 9) out.emplace_back(step, entry.path().string());
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    return out;
}

void remove_checkpoints(const std::string& directory, const std::string& side) {
    for (const auto& c : checkpoints(directory, side)) {
        std::error_code ignored;
        std::filesystem::remove(c.second, ignored);
    }
}

State State::create(const std::string& directory, const std::string& side, const std::string& partner,
                    long step, double time, const std::string& case_text) {
    auto f = std::make_shared<File>();
    f->directory = directory, f->side = side, f->partner = partner;
    f->final_path = (std::filesystem::path(directory) / name_of(side, step)).string();
    f->path = f->final_path + ".tmp";
    f->step = step, f->time = time;
    h5::init();
    const hid_t id = H5Fcreate(f->path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (id < 0) throw h5::Error(f->path + ": cannot create the checkpoint: " + h5::cause());
    f->file = h5::Object(id, H5Fclose, -1, f->path, "");
    h5::write_attr_string(id, "side", side);
    h5::write_attr_string(id, "layout", layout());
    h5::write_attr<long>(id, "step", step);
    h5::write_attr<double>(id, "time", time);
    h5::write_text(id, "case", case_text);
    return State(std::move(f), "");
}

State State::open(const std::string& path, const std::string& side) {
    auto f = std::make_shared<File>();
    f->path = path;
    f->loading = true;
    f->file = h5::open_read(path);
    const hid_t id = f->file.id();
    if (!side.empty() && h5::read_attr_string(id, "side") != side)
        throw std::runtime_error(path + ": a checkpoint of the " + h5::read_attr_string(id, "side") +
                                 " side, not of the " + side);
    if (h5::read_attr_string(id, "layout") != layout())
        throw std::runtime_error(path + ": the checkpoint was written by a build with other sizes (" +
                                 h5::read_attr_string(id, "layout") + "; this build: " + layout() + ")");
    f->step = static_cast<long>(h5::read_attr_double(id, "step"));
    f->time = h5::read_attr_double(id, "time");
    return State(std::move(f), "");
}

bool State::loading() const {
    return file_->loading;
}
long State::step() const {
    return file_->step;
}
double State::time() const {
    return file_->time;
}
const std::string& State::path() const {
    return file_->path;
}
std::string State::case_text() const {
    return h5::read_text(file_->file.id(), "case");
}

State State::scope(const std::string& prefix) const {
    return State(file_, prefix_.empty() ? prefix : prefix_ + "." + prefix);
}

void State::write_bytes(const std::string& name, const void* data, size_t bytes) {
    const std::string full = prefix_.empty() ? name : prefix_ + "." + name;
    const hid_t loc = file_->file.id();
    const hsize_t dims[1] = {bytes};
    h5::Object space(H5Screate_simple(1, dims, nullptr), H5Sclose, loc, full, "make the dataspace of");
    h5::Object set(
        H5Dcreate2(loc, full.c_str(), H5T_NATIVE_UCHAR, space.id(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
        H5Dclose, loc, full, "create the dataset");
    if (bytes > 0)
        h5::check(H5Dwrite(set.id(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), loc, full,
                  "write the dataset");
    set.close("write the dataset");
    h5::after_write(); // a coupled side's heartbeat (fluid/run.cpp, solid/run_structure.cpp)
}

std::vector<unsigned char> State::read_bytes(const std::string& name, size_t unit) const {
    const std::string full = prefix_.empty() ? name : prefix_ + "." + name;
    const hid_t loc = file_->file.id();
    if (h5::check(H5Lexists(loc, full.c_str(), H5P_DEFAULT), loc, full, "look up") <= 0)
        throw std::runtime_error(file_->path + ": the checkpoint holds no " + full +
                                 " (written by another version of the solver?)");
    h5::Object set(H5Dopen2(loc, full.c_str(), H5P_DEFAULT), H5Dclose, loc, full, "open the dataset");
    h5::Object space(H5Dget_space(set.id()), H5Sclose, loc, full, "read the dataspace of");
    const hssize_t n = H5Sget_simple_extent_npoints(space.id());
    if (n < 0) h5::fail(loc, full, "read the size of");
    std::vector<unsigned char> bytes(static_cast<size_t>(n));
    if (bytes.size() % unit != 0) wrong_size(full, bytes.size(), unit);
    if (!bytes.empty())
        h5::check(H5Dread(set.id(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()), loc, full,
                  "read the dataset");
    return bytes;
}

void State::wrong_size(const std::string& name, size_t got, size_t want) const {
    throw std::runtime_error(file_->path + ": " + name + " holds " + std::to_string(got) +
                             " bytes, not a multiple of " + std::to_string(want) + " (another version?)");
}

std::string State::commit() {
    file_->file.close("write the checkpoint");
    std::error_code e;
    std::filesystem::rename(file_->path, file_->final_path, e);
    if (e) throw h5::Error(file_->path + ": cannot rename it to " + file_->final_path + ": " + e.message());
    file_->committed = true;
    // Kept besides this one: the newest step the partner also holds, else (alone, or no such step) the one
    // before.
    const auto own = checkpoints(file_->directory, file_->side);
    const auto theirs =
        file_->partner.empty() ? decltype(own){} : checkpoints(file_->directory, file_->partner);
    long keep = -1;
    for (const auto& a : own)
        if (a.first != file_->step &&
            std::any_of(theirs.begin(), theirs.end(), [&](const auto& b) { return b.first == a.first; })) {
            keep = a.first;
            break;
        }
    if (keep < 0)
        for (const auto& a : own)
            if (a.first != file_->step) {
                keep = a.first;
                break;
            }
    for (const auto& a : own)
        if (a.first != file_->step && a.first != keep) std::filesystem::remove(a.second, e);
    return file_->final_path;
}

namespace {

// What DIR holds, for a message.
std::string listing(const std::string& dir, std::vector<std::pair<long, std::string>> files) {
    std::string found;
    for (const auto& f : files)
        found += "\n  " + f.second + ": step " + std::to_string(f.first);
    return found.empty() ? " (there are none in " + dir + ")" : ":" + found;
}

} // namespace

std::string resume_single(const std::string& directory, const std::string& side) {
    const auto s = checkpoints(directory, side);
    if (s.empty()) throw std::runtime_error(directory + ": no checkpoint of the " + side + " to resume from");
    return s.front().second;
}

std::pair<std::string, std::string> resume_pair(const std::string& directory) {
    const auto f = checkpoints(directory, "fluid"), s = checkpoints(directory, "solid");
    for (const auto& a : f)
        for (const auto& b : s)
            if (a.first == b.first) return {a.second, b.second};
    auto all = f;
    all.insert(all.end(), s.begin(), s.end());
    throw std::runtime_error(directory + ": no checkpoints of the fluid and the structure at the same step" +
                             listing(directory, all));
}

} // namespace undex
