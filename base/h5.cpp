#include "base/h5.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>

#include <fcntl.h>

namespace undex::h5 {

namespace {
std::string last_error; // of this process (a solver writes one output file)
} // namespace

Error::Error(const std::string& what) : std::runtime_error(what) {
    last_error = what;
}

// Once per process, before any other HDF5 call: no error printing by HDF5 (our messages say it once), and
// no closing of files by the library at exit. Our files are closed or given up before exit (a file given up
// after a failed write must not be flushed: OutputFile::fail), and a file whose close failed (a full disk)
// stays half closed in HDF5 1.10: closing it again at exit crashed (SIGSEGV in H5F__close_cb).
void init() {
    static const bool done = [] {
        if (H5dont_atexit() < 0 || H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr) < 0)
            throw Error("HDF5: cannot turn off its error printing and its closing of files at exit");
        return true;
    }();
    (void)done;
}

namespace {

struct Walk {
    std::string system;    // the text of errno from a file driver ("No space left on device")
    std::string innermost; // the description of the innermost error
    hid_t minor = -1;
};

herr_t walk(unsigned n, const H5E_error2_t* e, void* data) {
    auto& w = *static_cast<Walk*>(data);
    const std::string desc = e->desc ? e->desc : "";
    if (n == 0) w.innermost = desc, w.minor = e->min_num;
    // The file drivers (sec2, core, ...) report a failed read or write as "... errno = N, error message =
    // 'TEXT', ...".
    const auto k = desc.find("error message = '");
    if (w.system.empty() && k != std::string::npos) {
        const auto start = k + std::strlen("error message = '");
        w.system = desc.substr(start, desc.find('\'', start) - start);
    }
    return 0;
}

// "FILE: /PATH/NAME" of an object name relative to loc ("FILE" for the file itself). For messages only: a
// name HDF5 cannot give is left out.
std::string where(hid_t loc, const std::string& name) {
    if (loc < 0) return name;
    std::string file = "(unknown file)", path;
    if (ssize_t n = H5Fget_name(loc, nullptr, 0); n > 0) {
        file.assign(static_cast<size_t>(n) + 1, '\0');
        H5Fget_name(loc, file.data(), file.size());
        file.resize(static_cast<size_t>(n));
    }
    if (ssize_t n = H5Iget_name(loc, nullptr, 0); n > 0) {
        path.assign(static_cast<size_t>(n) + 1, '\0');
        H5Iget_name(loc, path.data(), path.size());
        path.resize(static_cast<size_t>(n));
    }
    if (path.empty() || path.back() != '/') path += '/';
    path += name;
    return path == "/" ? file : file + ": " + path;
}

} // namespace

std::string cause() {
    Walk w;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &w);
    if (!w.system.empty()) return w.system;
    if (!w.innermost.empty()) return w.innermost;
    char text[256] = "";
    if (w.minor >= 0 && H5Eget_msg(w.minor, nullptr, text, sizeof text) > 0) return text;
    return "HDF5 gives no cause";
}

void fail(hid_t loc, const std::string& name, const std::string& action) {
    const std::string why = cause(); // first: the calls of where() clear the error stack
    throw Error(where(loc, name) + ": cannot " + action + ": " + why);
}

Object::Object(hid_t id, herr_t (*close)(hid_t), hid_t loc, const std::string& name,
               const std::string& action)
    : id_(check(id, loc, name, action)), close_(close), loc_(loc), name_(name) {}

Object& Object::operator=(Object&& o) noexcept {
    std::swap(id_, o.id_);
    std::swap(close_, o.close_);
    std::swap(loc_, o.loc_);
    std::swap(name_, o.name_);
    return *this;
}

void Object::abandon() {
    id_ = -1;
}

Object::~Object() {
    if (id_ >= 0) close_(id_);
}

void Object::close(const std::string& action) {
    const hid_t id = id_;
    id_ = -1; // never closed twice, even when this fails
    if (id >= 0 && close_(id) < 0) fail(loc_, name_, action);
}

Object create_group(hid_t loc, const std::string& name) {
    return {H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, loc, name,
            "create the group"};
}

Object open_group(hid_t loc, const std::string& name) {
    return {H5Gopen2(loc, name.c_str(), H5P_DEFAULT), H5Gclose, loc, name, "open the group"};
}

namespace {

Object scalar_space(hid_t loc, const std::string& name) {
    return {H5Screate(H5S_SCALAR), H5Sclose, loc, name, "make a dataspace for"};
}

// A fixed-length string type of size bytes, null-terminated or padded with nulls.
Object string_type(hid_t loc, const std::string& name, size_t size, H5T_str_t pad = H5T_STR_NULLPAD) {
    Object t(H5Tcopy(H5T_C_S1), H5Tclose, loc, name, "make a string type for");
    check(H5Tset_size(t.id(), size), loc, name, "size the string type of");
    check(H5Tset_strpad(t.id(), pad), loc, name, "pad the string type of");
    return t;
}

void delete_attr(hid_t obj, const char* name) {
    const std::string what = std::string("@") + name;
    if (check(H5Aexists(obj, name), obj, what, "look up the attribute") > 0)
        check(H5Adelete(obj, name), obj, what, "delete the attribute");
}

void delete_link(hid_t loc, const char* name) {
    if (check(H5Lexists(loc, name, H5P_DEFAULT), loc, name, "look up") > 0)
        check(H5Ldelete(loc, name, H5P_DEFAULT), loc, name, "delete");
}

void write_attr(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, const void* value) {
    const std::string what = std::string("@") + name;
    delete_attr(obj, name);
    Object space = scalar_space(obj, what);
    Object attr(H5Acreate2(obj, name, file_type, space.id(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose, obj, what,
                "create the attribute");
    check(H5Awrite(attr.id(), mem_type, value), obj, what, "write the attribute");
    attr.close("write the attribute");
}

} // namespace

void write_attr_string(hid_t obj, const char* name, const std::string& value) {
    Object type = string_type(obj, std::string("@") + name, value.size() + 1, H5T_STR_NULLTERM);
    write_attr(obj, name, type.id(), type.id(), value.c_str());
}

void write_attr_double(hid_t obj, const char* name, double value) {
    write_attr(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}
void write_attr_long(hid_t obj, const char* name, long value) {
    write_attr(obj, name, H5T_STD_I64LE, H5T_NATIVE_LONG, &value);
}

namespace {
void create_text(hid_t loc, const char* name, const std::string& text, size_t capacity) {
    std::string padded = text;
    padded.resize(std::max<size_t>({text.size(), capacity, 1}), '\0');
    Object type = string_type(loc, name, padded.size());
    Object space = scalar_space(loc, name);
    Object set(H5Dcreate2(loc, name, type.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
               loc, name, "create the dataset");
    check(H5Dwrite(set.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()), loc, name,
          "write the dataset");
    set.close("write the dataset");
}
} // namespace

void write_text(hid_t loc, const char* name, const std::string& text, size_t capacity) {
    if (check(H5Lexists(loc, name, H5P_DEFAULT), loc, name, "look up") == 0) {
        create_text(loc, name, text, capacity);
        return;
    }
    Object set(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose, loc, name, "open the dataset");
    Object type(H5Dget_type(set.id()), H5Tclose, loc, name, "read the type of");
    const size_t size = H5Tget_size(type.id());
    if (size == 0) fail(loc, name, "read the size of");
    if (text.size() > size) {
        // A longer text goes into a new dataset that then replaces this one; when the new one cannot be made
        // (a full disk), this one keeps as much of the text's start as it holds.
        const std::string fresh = std::string(name) + ".new";
        try {
            delete_link(loc, fresh.c_str());
            create_text(loc, fresh.c_str(), text, capacity);
            set.close();
            check(H5Ldelete(loc, name, H5P_DEFAULT), loc, name, "delete");
            check(H5Lmove(loc, fresh.c_str(), loc, name, H5P_DEFAULT, H5P_DEFAULT), loc, name,
                  "rename the new");
            return;
        } catch (const Error&) {
            if (set.id() < 0) throw;
        }
    }
    // In place: the space is in the file already (a status written on a full disk).
    std::string padded = text.substr(0, size);
    padded.resize(size, '\0');
    check(H5Dwrite(set.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()), loc, name,
          "write the dataset");
    set.close("write the dataset"); // the text goes to the file here
}

namespace {
// The hook of the WriteHook in scope, and when it last ran.
std::function<void()> write_hook;
double write_hook_seconds = 0;
std::chrono::steady_clock::time_point write_hook_last;

} // namespace

void after_write() {
    if (!write_hook) return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - write_hook_last).count() < write_hook_seconds) return;
    write_hook_last = now;
    write_hook();
}

namespace {
void write_typed(hid_t loc, const char* name, const std::vector<hsize_t>& dims, hid_t file_type,
                 hid_t mem_type, const void* data) {
    delete_link(loc, name);
    Object space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose, loc, name,
                 "make a dataspace for");
    Object set(H5Dcreate2(loc, name, file_type, space.id(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
               loc, name, "create the dataset");
    check(H5Dwrite(set.id(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), loc, name, "write the dataset");
    set.close("write the dataset"); // a small dataset's data goes to the file here
    after_write();
}
} // namespace

WriteHook::WriteHook(std::function<void()> hook, double seconds) {
    write_hook = std::move(hook);
    write_hook_seconds = seconds;
    write_hook_last = std::chrono::steady_clock::now();
}
WriteHook::~WriteHook() {
    write_hook = nullptr;
}

void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const double* data) {
    write_typed(loc, name, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data);
}
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const float* data) {
    write_typed(loc, name, dims, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, data);
}
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const int* data) {
    write_typed(loc, name, dims, H5T_STD_I32LE, H5T_NATIVE_INT, data);
}

void write_virtual(hid_t loc, const char* name, const std::vector<hsize_t>& dims,
                   const std::vector<RowBlock>& blocks) {
    delete_link(loc, name);
    const int rank = static_cast<int>(dims.size());
    Object space(H5Screate_simple(rank, dims.data(), nullptr), H5Sclose, loc, name, "make a dataspace for");
    Object dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, loc, name, "make the creation properties of");
    const double missing = std::numeric_limits<double>::quiet_NaN();
    check(H5Pset_fill_value(dcpl.id(), H5T_NATIVE_DOUBLE, &missing), loc, name, "set the fill value of");
    for (const RowBlock& b : blocks) {
        std::vector<hsize_t> start(rank, 0), count = dims;
        start[0] = b.first, count[0] = b.rows;
        Object source(H5Screate_simple(rank, count.data(), nullptr), H5Sclose, loc, name,
                      "make a dataspace for");
        check(H5Sselect_hyperslab(space.id(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
              loc, name, "select the rows of " + b.file + " in");
        check(H5Pset_virtual(dcpl.id(), space.id(), b.file.c_str(), b.dataset.c_str(), source.id()), loc,
              name, "map " + b.file + " into");
    }
    check(H5Sselect_all(space.id()), loc, name, "select all of");
    Object set(H5Dcreate2(loc, name, H5T_IEEE_F64LE, space.id(), H5P_DEFAULT, dcpl.id(), H5P_DEFAULT),
               H5Dclose, loc, name, "create the dataset");
    set.close("write the dataset");
    after_write();
}

namespace {
// A string of the fixed-length string type of an attribute or dataset, cut at its first null.
std::string read_string(hid_t loc, const std::string& what, hid_t obj, hid_t (*get_type)(hid_t),
                        bool attribute) {
    Object type(get_type(obj), H5Tclose, loc, what, "read the type of");
    const size_t size = H5Tget_size(type.id()); // 0: an error
    if (H5Tget_class(type.id()) != H5T_STRING || H5Tis_variable_str(type.id()) != 0 || size == 0)
        throw Error(where(loc, what) + ": cannot read: not a fixed-length string");
    std::string s(size, '\0');
    Object mem = string_type(loc, what, std::max<size_t>(s.size(), 1));
    check(attribute ? H5Aread(obj, mem.id(), s.data())
                    : H5Dread(obj, mem.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()),
          loc, what, "read");
    s.resize(std::min(s.size(), s.find('\0')));
    return s;
}
} // namespace

std::string read_attr_string(hid_t obj, const char* name) {
    const std::string what = std::string("@") + name;
    Object attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, obj, what, "open the attribute");
    return read_string(obj, what, attr.id(), H5Aget_type, true);
}

double read_attr_double(hid_t obj, const char* name) {
    const std::string what = std::string("@") + name;
    double v = 0;
    Object attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, obj, what, "open the attribute");
    check(H5Aread(attr.id(), H5T_NATIVE_DOUBLE, &v), obj, what, "read the attribute");
    return v;
}

std::string read_text(hid_t loc, const char* name) {
    Object set(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose, loc, name, "open the dataset");
    return read_string(loc, name, set.id(), H5Dget_type, false);
}

std::vector<double> read_dataset(hid_t loc, const std::string& name) {
    Object set(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose, loc, name, "open the dataset");
    Object space(H5Dget_space(set.id()), H5Sclose, loc, name, "read the shape of");
    const hssize_t n = check(H5Sget_simple_extent_npoints(space.id()), loc, name, "read the shape of");
    std::vector<double> v(static_cast<size_t>(n));
    check(H5Dread(set.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), loc, name,
          "read the dataset");
    return v;
}

namespace {
// Rows per chunk of a table's column: 32 KiB of doubles.
constexpr hsize_t table_chunk = 4096;

// A new column of n rows: chunked, of unlimited length, so that a longer table appends (write_table).
void create_column(hid_t g, const char* name, hsize_t n, const double* data) {
    const hsize_t dims[1] = {n}, max[1] = {H5S_UNLIMITED}, chunk[1] = {table_chunk};
    Object space(H5Screate_simple(1, dims, max), H5Sclose, g, name, "make a dataspace for");
    Object dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, g, name, "make the creation properties of");
    check(H5Pset_chunk(dcpl.id(), 1, chunk), g, name, "set the chunks of");
    Object set(H5Dcreate2(g, name, H5T_IEEE_F64LE, space.id(), H5P_DEFAULT, dcpl.id(), H5P_DEFAULT),
               H5Dclose, g, name, "create the dataset");
    if (n > 0)
        check(H5Dwrite(set.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), g, name,
              "write the dataset");
    set.close("write the dataset");
}

// The rows of an existing column that the table keeps: all of them when it is chunked, no longer than the
// table and its last row is the table's (bitwise); else none (the column is written anew).
hsize_t kept_rows(hid_t set, hid_t g, const char* name, const std::vector<double>& rows, size_t width,
                  size_t k) {
    const size_t n = rows.size() / width;
    Object dcpl(H5Dget_create_plist(set), H5Pclose, g, name, "read the creation properties of");
    if (H5Pget_layout(dcpl.id()) != H5D_CHUNKED) return 0;
    Object space(H5Dget_space(set), H5Sclose, g, name, "read the dataspace of");
    hsize_t stored = 0;
    if (H5Sget_simple_extent_ndims(space.id()) != 1 ||
        H5Sget_simple_extent_dims(space.id(), &stored, nullptr) < 0 || stored > n)
        return 0;
    if (stored == 0) return 0;
    const hsize_t last[1] = {stored - 1}, one[1] = {1};
    check(H5Sselect_hyperslab(space.id(), H5S_SELECT_SET, last, nullptr, one, nullptr), g, name,
          "select the last row of");
    Object mem(H5Screate_simple(1, one, nullptr), H5Sclose, g, name, "make a dataspace for");
    double v = 0;
    check(H5Dread(set, H5T_NATIVE_DOUBLE, mem.id(), space.id(), H5P_DEFAULT, &v), g, name, "read");
    const double w = rows[(stored - 1) * width + k];
    return std::memcmp(&v, &w, sizeof v) == 0 ? stored : 0;
}
} // namespace

// Each column grows by appending the rows it lacks: the rows of the last flush are never moved or their
// space freed, so the file's last flushed state stays readable when the process is killed before the next
// flush. (Deleting and writing a column anew would free that space for the next dataset written, while the
// flushed state still points at it.) A column that does not begin the table is written anew.
void write_table(hid_t file, const std::string& group, const std::vector<std::string>& columns,
                 const std::vector<double>& rows) {
    if (check(H5Lexists(file, group.c_str(), H5P_DEFAULT), file, group, "look up") <= 0)
        create_group(file, group).close();
    Object g = open_group(file, group);
    const size_t width = columns.size(), n = rows.size() / width;
    std::vector<double> column;
    for (size_t k = 0; k < width; ++k) {
        const char* name = columns[k].c_str();
        hsize_t start = 0;
        Object set;
        if (check(H5Lexists(g.id(), name, H5P_DEFAULT), g.id(), name, "look up") > 0) {
            set = Object(H5Dopen2(g.id(), name, H5P_DEFAULT), H5Dclose, g.id(), name, "open the dataset");
            start = kept_rows(set.id(), g.id(), name, rows, width, k);
            if (start == 0) {
                set.close();
                check(H5Ldelete(g.id(), name, H5P_DEFAULT), g.id(), name, "delete");
            }
        }
        column.resize(n - start);
        for (size_t r = start; r < n; ++r)
            column[r - start] = rows[r * width + k];
        if (set.id() < 0) {
            create_column(g.id(), name, n, column.data());
        } else if (start < n) {
            const hsize_t dims[1] = {n}, first[1] = {start}, count[1] = {n - start};
            check(H5Dset_extent(set.id(), dims), g.id(), name, "extend the dataset");
            Object space(H5Dget_space(set.id()), H5Sclose, g.id(), name, "read the dataspace of");
            check(H5Sselect_hyperslab(space.id(), H5S_SELECT_SET, first, nullptr, count, nullptr), g.id(), name,
                  "select the new rows of");
            Object mem(H5Screate_simple(1, count, nullptr), H5Sclose, g.id(), name, "make a dataspace for");
            check(H5Dwrite(set.id(), H5T_NATIVE_DOUBLE, mem.id(), space.id(), H5P_DEFAULT, column.data()),
                  g.id(), name, "write the dataset");
        }
        if (set.id() >= 0) set.close("write the dataset");
        after_write();
    }
    g.close();
}

namespace {
// Room for the status texts of a run ("running", "complete", "failed: " and a message naming a file, an
// object and a cause): a later status that fits is written in place, so that even a full disk takes it.
constexpr size_t status_capacity = 4096;

Object create_file(const std::string& path) {
    init();
    Object fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, -1, path, "make the file access properties of");
    if (H5Pset_file_locking(fapl.id(), false, true) < 0 ||
        H5Pset_fclose_degree(fapl.id(), H5F_CLOSE_STRONG) < 0) // closing the file closes what is open in it
        throw Error(path + ": cannot set the file access properties: " + cause());
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id());
    if (f < 0) {
        const std::string why = cause();
        std::error_code ignored;
        std::filesystem::remove(path, ignored); // made, perhaps, without its superblock
        throw Error(path + ": cannot create the output file: " + why);
    }
    Object file(f, H5Fclose, -1, path, "");
    fapl.close("close the file access properties of");
    return file;
}
} // namespace

OutputFile::OutputFile(const std::string& directory, const std::string& name, const std::string& case_text)
    : directory_(directory), path_((std::filesystem::path(directory) / name).string()) {
    std::error_code e;
    std::filesystem::create_directories(directory, e);
    if (e) throw Error(directory + ": cannot create the output directory: " + e.message());
    file_ = create_file(path_);
    try {
        write_text(file_.id(), "case", case_text);
        write_text(file_.id(), "status", "running", status_capacity);
        flush();
    } catch (const Error&) {
        file_.abandon(); // a close would try again what failed
        std::error_code ignored;
        std::filesystem::remove(path_, ignored); // it holds no status, perhaps not even its superblock
        throw;
    }
}

OutputFile::OutputFile(const std::string& directory, const std::string& name, Reopen)
    : directory_(directory), path_((std::filesystem::path(directory) / name).string()) {
    init();
    Object fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, -1, path_, "make the file access properties of");
    if (H5Pset_file_locking(fapl.id(), false, true) < 0 ||
        H5Pset_fclose_degree(fapl.id(), H5F_CLOSE_STRONG) < 0)
        throw Error(path_ + ": cannot set the file access properties: " + cause());
    const hid_t f = H5Fopen(path_.c_str(), H5F_ACC_RDWR, fapl.id());
    if (f < 0) throw Error(path_ + ": cannot open the output to resume it: " + cause());
    file_ = Object(f, H5Fclose, -1, path_, "");
    fapl.close("close the file access properties of");
    write_text(file_.id(), "status", "running", status_capacity);
    flush();
}

void OutputFile::delete_numbered(const std::string& group, long first) const {
    if (check(H5Lexists(file_.id(), group.c_str(), H5P_DEFAULT), file_.id(), group, "look up") <= 0) return;
    Object g = open_group(file_.id(), group);
    H5G_info_t info{};
    check(H5Gget_info(g.id(), &info), g.id(), "", "read the members of");
    std::vector<std::string> doomed;
    for (hsize_t k = 0; k < info.nlinks; ++k) {
        char name[64] = {};
        if (H5Lget_name_by_idx(g.id(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT) <
            0)
            h5::fail(g.id(), "", "read the member names of");
        char* end = nullptr;
        const long n = std::strtol(name, &end, 10);
        if (end != name && *end == '\0' && n >= first) doomed.push_back(name);
    }
    for (const auto& name : doomed)
        check(H5Ldelete(g.id(), name.c_str(), H5P_DEFAULT), g.id(), name, "delete");
    g.close();
}

OutputFile::~OutputFile() {
    if (file_.id() < 0) return; // completed, failed or given up
    try {
        write_text(file_.id(), "status",
                   "failed: " + (last_error.empty()
                                     ? std::string("the run stopped before its output was complete (the "
                                                   "solver's log has the cause)")
                                     : last_error),
                   status_capacity);
    } catch (const Error&) { // the message of the first error is out already
    }
    file_.abandon();
}

void OutputFile::flush() const {
    // A flush writes groups and attributes, some in place (the links of a group) and some into new space
    // below the file's end of allocation (EOA). That space is reserved first: a full disk fails here, before
    // the flush, instead of in its middle with the links written and what they point at not (an unreadable
    // file).
    const std::string what = "flush the file (the groups and attributes written since the last flush)";
    haddr_t eoa = 0;
    void* handle = nullptr;
    check(H5Fget_eoa(file_.id(), &eoa), file_.id(), "", what);
    check(H5Fget_vfd_handle(file_.id(), H5P_DEFAULT, &handle), file_.id(), "", what);
    if (eoa > reserved_) {
        const int e = posix_fallocate(*static_cast<int*>(handle), static_cast<off_t>(reserved_),
                                      static_cast<off_t>(eoa - reserved_));
        if (e != 0 && e != EOPNOTSUPP && e != ENOSYS) // (a file system that cannot reserve flushes anyway)
            throw Error(path_ + ": cannot " + what + ": " + std::strerror(e));
        reserved_ = eoa;
    }
    check(H5Fflush(file_.id(), H5F_SCOPE_GLOBAL), file_.id(), "", what);
}

void OutputFile::set_status(const std::string& status) const {
    write_text(file_.id(), "status", status, status_capacity);
    flush();
}

void OutputFile::write_table(const std::string& group, const std::vector<std::string>& columns,
                             const std::vector<double>& rows) const {
    h5::write_table(file_.id(), group, columns, rows);
    flush();
}

void OutputFile::complete() {
    set_status("complete");
    file_.close("close the file");
}

void OutputFile::fail(const std::string& why, const std::function<void()>& write_state) {
    try {
        write_state();
    } catch (const Error& e) {
        // The file holds what HDF5 could not write (e.g. a full disk): a flush or a close would write the
        // groups and links that point at it over the last good state. So only the status is written, in place
        // (its space is in the file already), and the file is given up unflushed: it stays as the last flush
        // left it.
        std::string also;
        try {
            write_text(file_.id(), "status", "failed: " + why, status_capacity);
        } catch (const Error& s) {
            also = "; nor the status: " + std::string(s.what());
        }
        file_.abandon();
        throw Error(e.what() + also);
    }
    set_status("failed: " + why);
    file_.close("close the file");
}

void write_file_atomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    const auto failed = [] { return errno != 0 ? errno : EIO; };
    std::FILE* f = std::fopen(tmp.c_str(), "w");
    int error = f ? 0 : failed();
    if (f && (std::fwrite(text.data(), 1, text.size(), f) != text.size() || std::fflush(f) != 0))
        error = failed();
    if (f && std::fclose(f) != 0 && !error) error = failed();
    if (!error && std::rename(tmp.c_str(), path.c_str()) != 0) error = failed();
    if (error) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write: " + std::strerror(error));
    }
}

Object open_read(const std::string& path) {
    init();
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) throw Error(path + ": cannot open (not an HDF5 output of undex?): " + cause());
    return {f, H5Fclose, -1, path, ""};
}

std::string output_file(const std::string& dir) {
    const std::filesystem::path p(dir);
    if (!std::filesystem::is_directory(p)) return dir;
    if (!std::filesystem::exists(p / "fluid.h5") && std::filesystem::exists(p / "solid.h5"))
        return (p / "solid.h5").string();
    return (p / "fluid.h5").string();
}

namespace {
// The names of the links of a group, in name order.
std::vector<std::string> links(hid_t file, const std::string& group) {
    Object g = open_group(file, group);
    H5G_info_t info;
    check(H5Gget_info(g.id(), &info), file, group, "read the group");
    std::vector<std::string> names;
    for (hsize_t k = 0; k < info.nlinks; ++k) {
        const ssize_t n =
            check(H5Lget_name_by_idx(g.id(), ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT),
                  file, group, "read the names in");
        std::string name(static_cast<size_t>(n) + 1, '\0');
        check(H5Lget_name_by_idx(g.id(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size(),
                                 H5P_DEFAULT),
              file, group, "read the names in");
        name.resize(static_cast<size_t>(n));
        names.push_back(name);
    }
    return names;
}
} // namespace

StoredRun read_run(const std::string& h5_path) {
    Object f = open_read(h5_path);
    StoredRun r;
    // Files written before the case text was a dataset hold it as an attribute.
    r.case_text = check(H5Lexists(f.id(), "case", H5P_DEFAULT), f.id(), "case", "look up") > 0
                      ? read_text(f.id(), "case")
                      : read_attr_string(f.id(), "case");
    for (const auto& name : links(f.id(), "fields")) {
        r.groups.push_back("fields/" + name);
        Object g = open_group(f.id(), r.groups.back());
        r.times.push_back(read_attr_double(g.id(), "time"));
    }
    r.gauge_names = links(f.id(), "gauges");
    return r;
}

std::vector<std::vector<double>> read_gauge(const std::string& h5_path, const std::string& name,
                                            const std::vector<std::string>& columns) {
    Object f = open_read(h5_path);
    std::vector<std::vector<double>> cols;
    for (const auto& c : columns)
        cols.push_back(read_dataset(f.id(), "gauges/" + name + "/" + c));
    return cols;
}

} // namespace undex::h5
