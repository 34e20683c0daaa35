// Small HDF5 helpers shared by the fluid and structure outputs: scalar attributes, texts, double datasets,
// reading back. Every HDF5 call is checked: a failure throws h5::Error naming the file, the object (dataset,
// group or attribute) and the cause, the innermost error of HDF5's error stack (for a failed write the
// system's text, e.g. "No space left on device"). HDF5's own printing of errors is turned off.
#pragma once
#include <hdf5.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex::h5 {

// An output that cannot be written or read: "FILE: /OBJECT: cannot ACTION: CAUSE". The last one made is
// remembered for the status of a file left open by it (~OutputFile).
struct Error : std::runtime_error {
    explicit Error(const std::string& what);
};

// Once per process, before any other HDF5 call (every function here calls it): HDF5's own error printing
// and its closing of files at exit turned off.
void init();
// The innermost cause on HDF5's error stack (call it before any other HDF5 call, which clears the stack).
std::string cause();
// Throws Error "FILE: /OBJECT: cannot ACTION: CAUSE" for the object name relative to loc ("" for loc itself).
[[noreturn]] void fail(hid_t loc, const std::string& name, const std::string& action);
// status, or fail() when it is negative.
template <class T> T check(T status, hid_t loc, const std::string& name, const std::string& action) {
    if (status < 0) fail(loc, name, action);
    return status;
}

// An identifier (file, group, dataset, ...) closed on destruction; an error there is ignored (it only happens
// on the way out of an earlier failure, or for dataspaces and types, which live in memory). What writes to
// the file (a dataset, an attribute, a group, the file) is closed with close(), which checks.
class Object {
  public:
    Object() = default;
    // id: what an H5*create/open call returned (checked here); loc and name: where it is, for messages.
    Object(hid_t id, herr_t (*close)(hid_t), hid_t loc, const std::string& name, const std::string& action);
    Object(Object&& o) noexcept : id_(o.id_), close_(o.close_), loc_(o.loc_), name_(std::move(o.name_)) {
        o.id_ = -1;
    }
    Object& operator=(Object&& o) noexcept;
    ~Object();
    hid_t id() const { return id_; }
    // action names what failed in the message ("write the dataset": closing a dataset writes its data).
    void close(const std::string& action = "close");
    // Forgets the identifier without closing it: nothing more is written (OutputFile::fail).
    void abandon();

  private:
    hid_t id_ = -1;
    herr_t (*close_)(hid_t) = nullptr;
    hid_t loc_ = -1;
    std::string name_;
};

Object create_group(hid_t loc, const std::string& name);
Object open_group(hid_t loc, const std::string& name);
void write_attr_string(hid_t obj, const char* name, const std::string& value);
void write_attr_double(hid_t obj, const char* name, double value);
void write_attr_long(hid_t obj, const char* name, long value);
template <class T> void write_attr(hid_t obj, const char* name, T value) {
    if constexpr (std::is_same_v<T, double>)
        write_attr_double(obj, name, value);
    else
        write_attr_long(obj, name, static_cast<long>(value));
}
// A text of any length as a scalar dataset of a fixed-length string (null-padded to at least capacity bytes).
// An existing one is overwritten in place when the text fits: no new space in the file is needed then.
void write_text(hid_t loc, const char* name, const std::string& text, size_t capacity = 0);
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const double* data);
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const float* data);
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const int* data);
// A dataset of doubles of shape dims made of blocks of whole rows (along the first dimension) stored in
// other files: an HDF5 virtual dataset, which every reader (h5py, ParaView, read_dataset) reads as one.
// file: relative to the directory of loc's file (where HDF5 looks for it first); rows not covered, or of a
// file that is missing, read as NaN.
struct RowBlock {
    std::string file, dataset;
    hsize_t first, rows;
};
void write_virtual(hid_t loc, const char* name, const std::vector<hsize_t>& dims,
                   const std::vector<RowBlock>& blocks);
// While one is in scope, hook() runs after a dataset is written (write_dataset, write_table), at most once
// per `seconds`: a coupled solver keeps its partner waiting through a long output with heartbeats between its
// datasets (docs/protocol.md). One at a time per process.
// Runs the hook of the WriteHook in scope (at most once per its seconds): for writers of their own (a
// checkpoint's datasets).
void after_write();
class WriteHook {
  public:
    WriteHook(std::function<void()> hook, double seconds);
    ~WriteHook();
    WriteHook(const WriteHook&) = delete;
    WriteHook& operator=(const WriteHook&) = delete;
};
std::string read_attr_string(hid_t obj, const char* name);
double read_attr_double(hid_t obj, const char* name);
std::string read_text(hid_t loc, const char* name);
std::vector<double> read_dataset(hid_t loc, const std::string& name);
Object open_read(const std::string& path);
// A table of interleaved rows as one dataset per column in group (created when missing). A column already
// in the file whose rows begin the table (its last row bitwise the table's) gets only the rows it lacks
// appended: the rows of the last flush stay in place, and a run killed before the next flush leaves them
// readable. Any other column is written anew.
void write_table(hid_t file, const std::string& group, const std::vector<std::string>& columns,
                 const std::vector<double>& rows);

// The output file of a solver's run, DIRECTORY/NAME: created (replacing an older one, the directory made
// when missing) without HDF5's file lock, so that Python and ParaView can read what was flushed while the
// run goes on. It holds the datasets case (the case text) and status ("running" until complete or fail); a
// file that cannot take them is removed (Error).
// Tables and the status are flushed as they are written. complete() or fail() ends it; one still open at
// destruction (an exception left the run, e.g. an output that could not be created) gets the status
// "failed: " and the last Error, written in place, and stays as its last flush left it.
class OutputFile {
  public:
    OutputFile(const std::string& directory, const std::string& name, const std::string& case_text);
    // Resuming a run: the existing DIRECTORY/NAME, opened for writing, its status "running" again.
    struct Reopen {};
    OutputFile(const std::string& directory, const std::string& name, Reopen);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    hid_t id() const { return file_.id(); }
    const std::string& path() const { return path_; }
    const std::string& directory() const { return directory_; }
    void flush() const;
    // Deletes the members of group named by a number (NNNNNN) of at least first: the outputs a resumed run
    // writes again.
    void delete_numbered(const std::string& group, long first) const;
    void set_status(const std::string& status) const;
    // A table of interleaved rows as one dataset per column in group (write_table).
    void write_table(const std::string& group, const std::vector<std::string>& columns,
                     const std::vector<double>& rows) const;
    // The end of a run: status "complete", the file closed.
    void complete();
    // After a failure: write_state writes the last good state, the status becomes "failed: WHY" and the file
    // is closed. When the state cannot be written (Error), the status is still written in place (it needs no
    // new space in the file) and the file is left unflushed as the last flush left it: every output written
    // before stays readable. Throws that Error.
    void fail(const std::string& why, const std::function<void()>& write_state);

  private:
    std::string directory_, path_;
    Object file_;
    mutable haddr_t reserved_ = 0; // the file's space up to here is allocated on disk (flush)
};

// A file written whole or not at all (e.g. an XDMF sidecar): the text goes to PATH.tmp, renamed to PATH
// once complete; an older PATH stays as it was when that fails (Error naming the file and the cause).
void write_file_atomically(const std::string& path, const std::string& text);

// The output file of a run: DIR/fluid.h5, or DIR/solid.h5 for a structure-only run (no fluid.h5); a path
// that is not a directory as it is.
std::string output_file(const std::string& dir_or_file);
// Reading back an output file of either solver: the case, the output times and groups, the gauge names.
struct StoredRun {
    std::string case_text;
    std::vector<double> times;
    std::vector<std::string> groups;
    std::vector<std::string> gauge_names;
};
StoredRun read_run(const std::string& h5_path);
// The columns of one gauge (fluid: t, rho, u, v, p; structure: t, u, v, a, stress_xx, peeq).
std::vector<std::vector<double>> read_gauge(const std::string& h5_path, const std::string& name,
                                            const std::vector<std::string>& columns = {"t", "rho", "u", "v",
                                                                                       "p"});

} // namespace undex::h5
