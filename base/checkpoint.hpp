// Checkpoints: the whole state of one side of a run (the fluid, the structure) at the end of a step, enough
// to continue it bit for bit (`undex run CASE --resume DIR`, docs/protocol.md "Checkpoints").
//
// A side writes DIR/SIDE.checkpoint.STEP.h5 (SIDE: fluid or solid, STEP its step, 9 digits) every
// output.checkpoint_seconds of wall time, at a step the two sides of a coupled run agree on (the fluid's
// Grant asks for it), and when a signal stops it at the end of a step. A file is written as .tmp and renamed
// once complete. Of its older ones a side keeps the newest step its partner also holds (or, alone, its one
// before): however the two sides' writes fall (one killed while it writes, one whose disk is full), a pair at
// one step stays for resume_pair, and at most two files per side.
//
// Layout: attributes side, layout, step, time; the dataset case (the case text after overrides: a resume
// must give the same); then one dataset per piece of state, named by its owner's path
// ("solver.side0.minus.u"), raw bytes of trivially copyable values. A checkpoint is read back by the build
// that wrote it: the attribute layout names the build's sizes, and every piece is checked for presence and
// size.
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace undex {

// Throws std::runtime_error naming the file, the piece and the cause.
class State {
  public:
    // A new checkpoint of `side` at `step` and `time` in `directory` (written as .tmp until commit());
    // partner: the other side of a coupled run ("fluid" or "solid"; "" alone), whose files set which of this
    // side's older ones are kept.
    static State create(const std::string& directory, const std::string& side, const std::string& partner,
                        long step, double time, const std::string& case_text);
    // A checkpoint to read (its path); side: the side it must be of ("" any).
    static State open(const std::string& path, const std::string& side = "");

    bool loading() const;
    long step() const;
    double time() const;
    std::string case_text() const;
    const std::string& path() const;

    // The same file, its names prefixed by prefix + ".".
    State scope(const std::string& prefix) const;

    // Writes or reads (resized to what was written) one piece.
    template <class T> void io(const std::string& name, std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (loading()) {
            const std::vector<unsigned char> bytes = read_bytes(name, sizeof(T));
            v.resize(bytes.size() / sizeof(T));
            if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
        } else {
            write_bytes(name, v.data(), v.size() * sizeof(T));
        }
    }
    template <class T> void io(const std::string& name, T& x) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (loading()) {
            const std::vector<unsigned char> bytes = read_bytes(name, sizeof(T));
            if (bytes.size() != sizeof(T)) wrong_size(name, bytes.size(), sizeof(T));
            std::memcpy(&x, bytes.data(), sizeof(T));
        } else {
            write_bytes(name, &x, sizeof(T));
        }
    }

    // Writing: closes the file, renames it into place and removes what is no longer kept; returns its path.
    std::string commit();

  private:
    struct File;
    State(std::shared_ptr<File> f, std::string prefix) : file_(std::move(f)), prefix_(std::move(prefix)) {}
    std::vector<unsigned char> read_bytes(const std::string& name, size_t unit) const;
    void write_bytes(const std::string& name, const void* data, size_t bytes);
    [[noreturn]] void wrong_size(const std::string& name, size_t got, size_t want) const;
    std::shared_ptr<File> file_;
    std::string prefix_;
};

// A list of outputs written, each a group name and a time (fluid.h5 and solid.h5 keep one for their XDMF), as
// a checkpoint holds it.
template <class Snapshot> void io_snapshots(State& s, std::vector<Snapshot>& v) {
    std::string names;
    std::vector<double> times;
    for (const auto& x : v)
        names += x.group + '\n', times.push_back(x.time);
    std::vector<char> text(names.begin(), names.end());
    s.io("snapshot_groups", text);
    s.io("snapshot_time", times);
    if (!s.loading()) return;
    const std::string all(text.begin(), text.end());
    v.clear();
    size_t begin = 0;
    for (const double t : times) {
        const size_t end = all.find('\n', begin);
        v.push_back({all.substr(begin, end - begin), t});
        begin = end + 1;
    }
}

// The checkpoints of side in directory, newest first: (step, path).
std::vector<std::pair<long, std::string>> checkpoints(const std::string& directory, const std::string& side);
// Removes them (a new run in the directory; a run that completed).
void remove_checkpoints(const std::string& directory, const std::string& side);

// The checkpoints to resume from: for one side, its newest; for a coupled run, the fluid's and the
// structure's of the newest step both hold. Throws std::runtime_error saying what DIR holds when there is
// none (naming each file found and its step).
std::string resume_single(const std::string& directory, const std::string& side);
std::pair<std::string, std::string> resume_pair(const std::string& directory);

} // namespace undex
