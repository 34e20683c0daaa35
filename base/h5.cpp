#include "base/h5.hpp"

#include <filesystem>
#include <stdexcept>

namespace undex::h5 {

void check(herr_t status, const std::string& what) {
    if (status < 0) throw std::runtime_error("HDF5: cannot " + what);
}

void write_attr_string(hid_t obj, const char* name, const std::string& value) {
    if (H5Aexists(obj, name) > 0) H5Adelete(obj, name);
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, value.size() + 1);
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    check(H5Awrite(attr, type, value.c_str()), std::string("write attribute ") + name);
    H5Aclose(attr);
    H5Sclose(space);
    H5Tclose(type);
}

namespace {
template <class T> void write_scalar(hid_t obj, const char* name, T value, hid_t mem, hid_t file) {
    if (H5Aexists(obj, name) > 0) H5Adelete(obj, name);
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = H5Acreate2(obj, name, file, space, H5P_DEFAULT, H5P_DEFAULT);
    check(H5Awrite(attr, mem, &value), std::string("write attribute ") + name);
    H5Aclose(attr);
    H5Sclose(space);
}
} // namespace

void write_attr_double(hid_t obj, const char* name, double value) {
    write_scalar(obj, name, value, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
}
void write_attr_long(hid_t obj, const char* name, long value) {
    write_scalar(obj, name, value, H5T_NATIVE_LONG, H5T_STD_I64LE);
}

namespace {
void write_typed(hid_t loc, const char* name, const std::vector<hsize_t>& dims, hid_t file_type,
                 hid_t mem_type, const void* data) {
    if (H5Lexists(loc, name, H5P_DEFAULT) > 0) H5Ldelete(loc, name, H5P_DEFAULT);
    hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    hid_t set = H5Dcreate2(loc, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (set < 0) throw std::runtime_error(std::string("HDF5: cannot create dataset ") + name);
    check(H5Dwrite(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), std::string("write ") + name);
    H5Dclose(set);
    H5Sclose(space);
}
} // namespace

void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const double* data) {
    write_typed(loc, name, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data);
}
void write_dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const int* data) {
    write_typed(loc, name, dims, H5T_STD_I32LE, H5T_NATIVE_INT, data);
}

std::string read_attr_string(hid_t obj, const char* name) {
    hid_t attr = H5Aopen(obj, name, H5P_DEFAULT);
    if (attr < 0) throw std::runtime_error(std::string("missing attribute ") + name);
    hid_t type = H5Aget_type(attr);
    std::string s(H5Tget_size(type), '\0');
    hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, s.size());
    H5Aread(attr, mem, s.data());
    H5Tclose(mem);
    H5Tclose(type);
    H5Aclose(attr);
    s.resize(s.find('\0') == std::string::npos ? s.size() : s.find('\0'));
    return s;
}

double read_attr_double(hid_t obj, const char* name) {
    double v = 0;
    hid_t attr = H5Aopen(obj, name, H5P_DEFAULT);
    if (attr < 0) throw std::runtime_error(std::string("missing attribute ") + name);
    H5Aread(attr, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(attr);
    return v;
}

std::vector<double> read_dataset(hid_t loc, const std::string& name) {
    hid_t set = H5Dopen2(loc, name.c_str(), H5P_DEFAULT);
    if (set < 0) throw std::runtime_error("missing dataset " + name);
    hid_t space = H5Dget_space(set);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    std::vector<double> v(static_cast<size_t>(n));
    H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(space);
    H5Dclose(set);
    return v;
}

void write_table(hid_t file, const std::string& group, const std::vector<std::string>& columns,
                 const std::vector<double>& rows) {
    if (H5Lexists(file, group.c_str(), H5P_DEFAULT) <= 0)
        H5Gclose(H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    const hid_t g = H5Gopen2(file, group.c_str(), H5P_DEFAULT);
    if (g < 0) throw std::runtime_error("cannot open group " + group);
    const size_t width = columns.size(), n = rows.size() / width;
    std::vector<double> column(n);
    for (size_t k = 0; k < width; ++k) {
        for (size_t r = 0; r < n; ++r)
            column[r] = rows[r * width + k];
        write_dataset(g, columns[k].c_str(), {n}, column.data());
    }
    H5Gclose(g);
}

OutputFile::OutputFile(const std::string& directory, const std::string& name, const std::string& case_text)
    : directory_(directory), path_((std::filesystem::path(directory) / name).string()) {
    std::filesystem::create_directories(directory);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_file_locking(fapl, false, true);
    file_ = H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    H5Pclose(fapl);
    if (file_ < 0) throw std::runtime_error(path_ + ": cannot create the output file");
    write_attr_string(file_, "case", case_text);
    write_attr_string(file_, "status", "running");
}

OutputFile::~OutputFile() {
    if (file_ >= 0) H5Fclose(file_);
}

void OutputFile::flush() const {
    H5Fflush(file_, H5F_SCOPE_GLOBAL);
}

void OutputFile::set_status(const std::string& status) const {
    write_attr_string(file_, "status", status);
    flush();
}

void OutputFile::write_table(const std::string& group, const std::vector<std::string>& columns,
                             const std::vector<double>& rows) const {
    h5::write_table(file_, group, columns, rows);
    flush();
}

hid_t open_read(const std::string& path) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) throw std::runtime_error(path + ": cannot open (not an HDF5 output of undex?)");
    return f;
}

std::string output_file(const std::string& dir) {
    const std::filesystem::path p(dir);
    if (!std::filesystem::is_directory(p)) return dir;
    if (!std::filesystem::exists(p / "fluid.h5") && std::filesystem::exists(p / "solid.h5"))
        return (p / "solid.h5").string();
    return (p / "fluid.h5").string();
}

StoredRun read_run(const std::string& h5_path) {
    hid_t f = open_read(h5_path);
    StoredRun r;
    r.case_text = read_attr_string(f, "case");
    hid_t fields = H5Gopen2(f, "fields", H5P_DEFAULT);
    H5G_info_t info;
    H5Gget_info(fields, &info);
    for (hsize_t k = 0; k < info.nlinks; ++k) {
        char name[64];
        H5Lget_name_by_idx(fields, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
        hid_t g = H5Gopen2(fields, name, H5P_DEFAULT);
        r.groups.push_back(std::string("fields/") + name);
        r.times.push_back(read_attr_double(g, "time"));
        H5Gclose(g);
    }
    H5Gclose(fields);
    hid_t gauges = H5Gopen2(f, "gauges", H5P_DEFAULT);
    H5Gget_info(gauges, &info);
    for (hsize_t k = 0; k < info.nlinks; ++k) {
        char name[256];
        H5Lget_name_by_idx(gauges, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
        r.gauge_names.push_back(name);
    }
    H5Gclose(gauges);
    H5Fclose(f);
    return r;
}

std::vector<std::vector<double>> read_gauge(const std::string& h5_path, const std::string& name,
                                            const std::vector<std::string>& columns) {
    hid_t f = open_read(h5_path);
    std::vector<std::vector<double>> cols;
    for (const auto& c : columns)
        cols.push_back(read_dataset(f, "gauges/" + name + "/" + c));
    H5Fclose(f);
    return cols;
}

} // namespace undex::h5
