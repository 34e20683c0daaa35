// Checkpoints: the whole state of one side of a run (the fluid, the structure) at the end of a step, enough
// to continue it bit for bit (`undex run CASE --resume DIR`, docs/protocol.md "Checkpoints").
//
// A side writes DIR/SIDE.checkpoint.h5 (SIDE: fluid or solid) every output.checkpoint_seconds of wall time,
// at a step the two sides of a coupled run agree on (the fluid's Grant asks for it), and when a signal stops
// it at the end of a step. The file is written as DIR/SIDE.checkpoint.h5.tmp and renamed; the one it replaces
// becomes DIR/SIDE.checkpoint.prev.h5, so that a stop that leaves the two sides' newest checkpoints at
// different steps still leaves a pair at one step (resume_pair).
//
// Layout: attributes side, step, time; the dataset case (the case text after overrides: a resume must give
// the same); then one dataset per piece of state, named by its owner's path ("solver.side0.minus.u"), raw
// bytes of trivially copyable values. A checkpoint is read back only by the build that wrote it: the
// attribute layout names the build's sizes of long and double, and every piece is checked for presence.
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
    // A new checkpoint of `side` at `step` and `time` in `directory` (written as .tmp until commit()).
    static State create(const std::string& directory, const std::string& side, long step, double time,
                        const std::string& case_text);
    // A checkpoint to read (its path).
    static State open(const std::string& path);

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

    // Writing: closes the file and renames it into place (the older one becomes .prev).
    void commit();

  private:
    struct File;
    State(std::shared_ptr<File> f, std::string prefix) : file_(std::move(f)), prefix_(std::move(prefix)) {}
    std::vector<unsigned char> read_bytes(const std::string& name, size_t unit) const;
    void write_bytes(const std::string& name, const void* data, size_t bytes);
    [[noreturn]] void wrong_size(const std::string& name, size_t got, size_t want) const;
    std::shared_ptr<File> file_;
    std::string prefix_;
};

// DIR/SIDE.checkpoint.h5 and DIR/SIDE.checkpoint.prev.h5.
std::string checkpoint_path(const std::string& directory, const std::string& side, bool previous = false);

// The checkpoints to resume from: for one side, its newest; for a coupled run, the fluid's and the
// structure's of the newest step both hold. Throws std::runtime_error saying what DIR holds when there is
// none (naming each file found and its step).
std::string resume_single(const std::string& directory, const std::string& side);
std::pair<std::string, std::string> resume_pair(const std::string& directory);

} // namespace undex
