#include "io/spacing_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>
#include <vector>

#include <netcdf.h>

#include "core/error.hpp"
#include "io/error_text.hpp"
#include "io/input_file.hpp"
#include "io/netcdf_header.hpp"
#include "io/netcdf_lock.hpp"

namespace um::io {

namespace {

constexpr int64_t kMaxCells = int64_t(1) << 40;
const hfun::GridNames kFileNames{"lon", "lat", "cellWidth"};


template <class... Parts>
[[noreturn]] void format_error(const std::string &path, const Parts &...parts) {
    fail(UM_ERR_FILE_FORMAT, "spacing file '", path, "': ", parts...);
}

// An open file, closed on every way out. Lives inside a NetcdfLock.
class NcFile {
public:
    explicit NcFile(const std::string &path) {
        require_regular_input(path, "spacing file");
        // netCDF-C trusts a classic header's counts and name lengths.
        const std::string problem = classic_header_problem(path);
        if (!problem.empty()) format_error(path, "its netCDF header is malformed: ", problem);
        int status = nc_open(path.c_str(), NC_NOWRITE, &id_);
        // netCDF returns errno values (> 0) for system errors and its own
        // negative codes when the bytes are not a readable netCDF file.
        if (status > 0) fail(UM_ERR_IO, "cannot open spacing file '", path, "': ", netcdf_status_text(status));
        if (status != NC_NOERR)
            format_error(path, "not a readable netCDF file (", netcdf_status_text(status),
                         "): not netCDF, damaged or truncated");
    }
    ~NcFile() { nc_close(id_); }
    NcFile(const NcFile &) = delete;
    NcFile &operator=(const NcFile &) = delete;
    int id() const { return id_; }

private:
    int id_ = -1;
};

struct Variable {
    const char *name = "";
    int id = -1;
    nc_type type = NC_NAT;
    std::vector<int> dims;
    std::vector<size_t> shape;
};

bool numeric(nc_type t) { return t != NC_CHAR && t != NC_STRING && t >= NC_BYTE && t <= NC_UINT64; }

Variable find_variable(const NcFile &file, const std::string &path, const char *name) {
    Variable v;
    v.name = name;
    int status = nc_inq_varid(file.id(), name, &v.id);
    if (status == NC_ENOTVAR)
        format_error(path, "no variable '", name, "' (an MPAS spacing file has lon(lon) and "
                     "lat(lat) in degrees and cellWidth(lat, lon) in km)");
    int ndims = 0;
    if (status == NC_NOERR) status = nc_inq_var(file.id(), v.id, nullptr, &v.type, &ndims, nullptr, nullptr);
    if (status == NC_NOERR) {
        v.dims.resize(static_cast<size_t>(ndims));
        v.shape.resize(v.dims.size());
        status = nc_inq_vardimid(file.id(), v.id, v.dims.data());
        for (size_t k = 0; k < v.dims.size() && status == NC_NOERR; ++k)
            status = nc_inq_dimlen(file.id(), v.dims[k], &v.shape[k]);
    }
    if (status != NC_NOERR) format_error(path, "variable '", name, "': ", netcdf_status_text(status));
    if (!numeric(v.type)) format_error(path, "variable '", name, "' is not numeric");
    return v;
}

std::string shape_text(const std::vector<size_t> &shape) {
    std::string text = "(";
    for (size_t k = 0; k < shape.size(); ++k) text += concat(k ? ", " : "", shape[k]);
    return text + ")";
}

void check_axis_shape(const Variable &v, const std::string &path) {
    if (v.shape.size() != 1)
        format_error(path, "variable '", v.name, "' has shape ", shape_text(v.shape),
                     "; expected one dimension");
}

void check_cell_shape(const Variable &cells, const Variable &lon, const Variable &lat,
                      const std::string &path) {
    const std::vector<size_t> expected{lat.shape[0], lon.shape[0]};
    const bool transposed = cells.dims.size() == 2 && lon.dims[0] != lat.dims[0] &&
                            cells.dims[0] == lon.dims[0] && cells.dims[1] == lat.dims[0];
    if (cells.shape != expected || transposed)
        format_error(path, "variable 'cellWidth' has shape ", shape_text(cells.shape),
                     transposed ? " = (lon, lat)" : "", "; expected (lat, lon) = ",
                     shape_text(expected));
}

// The text of a units attribute, lower case and trimmed; "" when absent.
std::string units(const NcFile &file, const Variable &v) {
    nc_type type = NC_NAT;
    size_t length = 0;
    if (nc_inq_att(file.id(), v.id, "units", &type, &length) != NC_NOERR) return "";
    std::string text;
    if (type == NC_CHAR) {
        text.resize(length);
        if (nc_get_att_text(file.id(), v.id, "units", text.data()) != NC_NOERR) return "";
    } else if (type == NC_STRING && length == 1) {
        char *value = nullptr;
        if (nc_get_att_string(file.id(), v.id, "units", &value) != NC_NOERR) return "";
        if (value) text = value;
        nc_free_string(1, &value);
    }
    std::string out;
    for (char c : text)
        if (c != ' ' && c != '\0') out += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    return out;
}

void check_units(const NcFile &file, const Variable &v, const std::string &path) {
    const std::string u = units(file, v);
    if (u.empty()) return;
    if (std::strcmp(v.name, kFileNames.cells) == 0) {
        for (const char *km : {"km", "kilometer", "kilometers", "kilometre", "kilometres"})
            if (u == km) return;
        format_error(path, "variable 'cellWidth' has units '", u, "'; expected km");
    }
    if (u.rfind("rad", 0) == 0)
        format_error(path, "variable '", v.name, "' has units '", u, "'; expected degrees");
}

std::vector<double> read_values(const NcFile &file, const Variable &v, size_t count,
                                const std::string &path) {
    std::vector<double> values(count);
    int status = nc_get_var_double(file.id(), v.id, values.data());
    if (status != NC_NOERR)
        format_error(path, "cannot read variable '", v.name, "': ", netcdf_status_text(status));
    return values;
}

// Unwritten cells read back as the fill value: missing data, not a width.
void check_fill(const NcFile &file, const Variable &v, const std::vector<double> &cells,
                size_t n_lon, const std::string &path) {
    int no_fill = 0;
    double fill = 0;
    if (v.type == NC_DOUBLE) {
        if (nc_inq_var_fill(file.id(), v.id, &no_fill, &fill) != NC_NOERR) return;
    } else if (v.type == NC_FLOAT) {
        float f = 0;
        if (nc_inq_var_fill(file.id(), v.id, &no_fill, &f) != NC_NOERR) return;
        fill = f;
    } else {
        return;  // integer fill values are negative: the grid check rejects them
    }
    if (no_fill) return;
    for (size_t k = 0; k < cells.size(); ++k)
        if (cells[k] == fill)
            format_error(path, "cellWidth[", k / n_lon, ", ", k % n_lon, "] holds the fill value ",
                         fill, " (missing data)");
}

// Classic-format (CDF-1/2/5) header size, from the structure the format
// specification gives; CDF-5 widens counts and lengths to 8 bytes.
class ClassicHeaderSize {
public:
    ClassicHeaderSize(int ncid, int format) : id_(ncid), wide_(format == NC_FORMAT_CDF5 ? 8 : 4) {}
    int64_t total() const {
        int ndims = 0, nvars = 0, ngatts = 0;
        if (nc_inq(id_, &ndims, &nvars, &ngatts, nullptr) != NC_NOERR) return 0;
        int64_t size = 4 + wide_ + list(ndims, [&](int d) { return dimension(d); }) +
                       attributes(NC_GLOBAL, ngatts);
        return size + list(nvars, [&](int v) { return variable(v); });
    }

private:
    static int64_t pad4(int64_t n) { return (n + 3) / 4 * 4; }
    template <class Item>
    int64_t list(int n, Item item) const {  // tag, count, items
        int64_t size = 4 + wide_;
        for (int k = 0; k < n; ++k) size += item(k);
        return size;
    }
    int64_t name(const char *text) const { return wide_ + pad4(int64_t(std::strlen(text))); }
    int64_t dimension(int d) const {
        char text[NC_MAX_NAME + 1] = "";
        nc_inq_dimname(id_, d, text);
        return name(text) + wide_;
    }
    int64_t attributes(int var, int n) const {
        return list(n, [&](int a) {
            char text[NC_MAX_NAME + 1] = "";
            nc_type type = NC_NAT;
            size_t count = 0, type_size = 0;
            nc_inq_attname(id_, var, a, text);
            nc_inq_att(id_, var, text, &type, &count);
            nc_inq_type(id_, type, nullptr, &type_size);
            return name(text) + 4 + wide_ + pad4(int64_t(count * type_size));
        });
    }
    int64_t variable(int v) const {
        char text[NC_MAX_NAME + 1] = "";
        int ndims = 0, natts = 0;
        nc_inq_var(id_, v, text, nullptr, &ndims, nullptr, &natts);
        return name(text) + wide_ + wide_ * ndims + attributes(v, natts) + 4 + wide_ +
               (wide_ == 8 ? 8 : offset_size());
    }
    int64_t offset_size() const {  // "begin" is 8 bytes from CDF-2 on
        int format = 0;
        nc_inq_format(id_, &format);
        return format == NC_FORMAT_CLASSIC ? 4 : 8;
    }

    int id_;
    int64_t wide_;
};

// netCDF-C reads the missing tail of a truncated classic file as zeros without
// an error, so the length is checked against its header plus its data.
void check_classic_length(const NcFile &file, const std::string &path) {
    int format = 0;
    if (nc_inq_format(file.id(), &format) != NC_NOERR ||
        (format != NC_FORMAT_CLASSIC && format != NC_FORMAT_64BIT_OFFSET && format != NC_FORMAT_CDF5))
        return;
    int nvars = 0;
    nc_inq_nvars(file.id(), &nvars);
    int64_t needed = ClassicHeaderSize(file.id(), format).total();
    for (int v = 0; v < nvars; ++v) {
        nc_type type = NC_NAT;
        int ndims = 0, dims[NC_MAX_VAR_DIMS];
        size_t type_size = 0, length = 0;
        nc_inq_var(file.id(), v, nullptr, &type, &ndims, dims, nullptr);
        nc_inq_type(file.id(), type, nullptr, &type_size);
        int64_t bytes = int64_t(type_size);
        for (int k = 0; k < ndims; ++k) {
            nc_inq_dimlen(file.id(), dims[k], &length);
            bytes *= int64_t(length);
        }
        needed += bytes;
    }
    std::error_code error;
    const auto actual = std::filesystem::file_size(path, error);
    if (!error && int64_t(actual) < needed)
        format_error(path, "the file is truncated: it has ", int64_t(actual),
                     " bytes, its header and data need at least ", needed);
}

struct Arrays {
    std::vector<double> lon, lat, cells;
};

Arrays read_arrays(const std::string &path, const Context &ctx) {
    NetcdfLock lock;  // before the file: the file closes first, then the lock opens
    NcFile file(path);
    check_classic_length(file, path);
    Variable lon = find_variable(file, path, "lon"), lat = find_variable(file, path, "lat"),
             cells = find_variable(file, path, "cellWidth");
    check_axis_shape(lon, path);
    check_axis_shape(lat, path);
    check_cell_shape(cells, lon, lat, path);
    for (const Variable *v : {&lon, &lat, &cells}) check_units(file, *v, path);
    const size_t n_lon = lon.shape[0], n_lat = lat.shape[0];
    if (n_lon != 0 && n_lat > size_t(kMaxCells) / n_lon)
        fail(UM_ERR_LIMIT, "spacing file '", path, "': cellWidth has ", n_lat, " x ", n_lon,
             " cells, more than the limit of ", kMaxCells);
    ctx.check_memory(int64_t(8 * (n_lat * n_lon + n_lat + n_lon)), "the spacing grid");
    Arrays a;
    a.lon = read_values(file, lon, n_lon, path);
    a.lat = read_values(file, lat, n_lat, path);
    a.cells = read_values(file, cells, n_lat * n_lon, path);
    check_fill(file, cells, a.cells, n_lon, path);
    return a;
}

}  // namespace

std::shared_ptr<const hfun::GridSpacing> read_spacing_file(const std::string &path,
                                                           const Context &ctx) {
    Arrays a = read_arrays(path, ctx);
    // The grid's own checks, outside the netCDF lock, reported as file content.
    try {
        return std::make_shared<const hfun::GridSpacing>(std::move(a.lon), std::move(a.lat),
                                                         std::move(a.cells), kFileNames);
    } catch (const Error &e) {
        format_error(path, e.what());
    }
}

}  // namespace um::io
