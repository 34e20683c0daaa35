// Small HDF5 helpers shared by the fluid and structure outputs: scalar attributes, double datasets, reading
// back. Every call throws std::runtime_error naming what failed.
#pragma once
#include <hdf5.h>

#include <string>
#include <vector>

namespace undex::h5 {

void check(herr_t status, const std::string& what);
void write_attr_string(hid_t obj, const char* name, const std::string& value);
void write_attr_double(hid_t obj, const char* name, double value);
void write_attr_long(hid_t obj, const char* name, long value);
template <class T> void write_attr(hid_t obj, const char* name, T value) {
    if constexpr (std::is_same_v<T, double>)
        write_attr_double(obj, name, value);
    else
        write_attr_long(obj, name, static_cast<long>(value));
}
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const double* data);
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const int* data);
std::string read_attr_string(hid_t obj, const char* name);
double read_attr_double(hid_t obj, const char* name);
std::vector<double> read_dataset(hid_t loc, const std::string& name);
hid_t open_read(const std::string& path);
// A table of interleaved rows as one dataset per column in group (created when missing).
void write_table(hid_t file, const std::string& group, const std::vector<std::string>& columns,
                 const std::vector<double>& rows);
// The output file of a solver's run, DIRECTORY/NAME: created (replacing an older one, the directory made
// when missing) without HDF5's file lock, so that Python and ParaView can read what was flushed while the
// run goes on; it holds the case text and the status ("running" until set_status). Tables and the status
// are flushed as they are written. Closed on destruction.
class OutputFile {
  public:
    OutputFile(const std::string& directory, const std::string& name, const std::string& case_text);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    hid_t id() const { return file_; }
    const std::string& path() const { return path_; }
    const std::string& directory() const { return directory_; }
    void flush() const;
    void set_status(const std::string& status) const;
    // A table of interleaved rows as one dataset per column in group (write_table).
    void write_table(const std::string& group, const std::vector<std::string>& columns,
                     const std::vector<double>& rows) const;

  private:
    std::string directory_, path_;
    hid_t file_ = -1;
};

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
