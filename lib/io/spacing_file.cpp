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
#include "io/nc_input.hpp"
#include "io/netcdf_lock.hpp"

namespace um::io {

namespace {

constexpr int64_t kMaxCells = int64_t(1) << 40;
const hfun::GridNames kFileNames{"lon", "lat", "cellWidth"};


template <class... Parts>
[[noreturn]] void format_error(const std::string &path, const Parts &...parts) {
    fail(UM_ERR_FILE_FORMAT, "spacing file '", path, "': ", parts...);
}

struct Variable {
    const char *name = "";
    int id = -1;
    nc_type type = NC_NAT;
    std::vector<int> dims;
    std::vector<size_t> shape;
};

bool numeric(nc_type t) { return t != NC_CHAR && t != NC_STRING && t >= NC_BYTE && t <= NC_UINT64; }

Variable find_variable(const NcInput &file, const std::string &path, const char *name) {
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
std::string units(const NcInput &file, const Variable &v) {
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

void check_units(const NcInput &file, const Variable &v, const std::string &path) {
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

std::vector<double> read_values(const NcInput &file, const Variable &v, size_t count,
                                const std::string &path) {
    std::vector<double> values(count);
    int status = nc_get_var_double(file.id(), v.id, values.data());
    if (status != NC_NOERR)
        format_error(path, "cannot read variable '", v.name, "': ", netcdf_status_text(status));
    return values;
}

// Unwritten cells read back as the fill value: missing data, not a width.
void check_fill(const NcInput &file, const Variable &v, const std::vector<double> &cells,
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

struct Arrays {
    std::vector<double> lon, lat, cells;
};

Arrays read_arrays(const std::string &path, const Context &ctx) {
    NetcdfLock lock;  // before the file: the file closes first, then the lock opens
    NcInput file(path, "spacing file");
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
