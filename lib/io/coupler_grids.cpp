#include "io/coupler_grids.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <netcdf.h>

#include "io/mpas_writer.hpp"
#include "io/nc_output.hpp"
#include "io/netcdf_lock.hpp"
#include "unimesh.h"

namespace um::io {

namespace {

using dual::MpasMesh;

constexpr double kDegrees = 180.0 / M_PI;

// 64-bit offset unless a variable of `bytes` needs CDF-5.
int format_for(uint64_t largest_variable_bytes) {
    return largest_variable_bytes > kOffset64VariableLimit ? NC_64BIT_DATA : NC_64BIT_OFFSET;
}

// Longitudes in [0, 360), the range SCRIP files are usually written in.
double longitude_deg(double lon_rad) {
    double lon = lon_rad * kDegrees;
    if (lon < 0) lon += 360;
    return lon >= 360 ? lon - 360 : lon;
}

int define_var(const NcOutput &nc, const char *name, nc_type type, std::initializer_list<int> dims,
               const char *units) {
    int var = -1;
    const std::vector<int> ids(dims);
    nc.check(nc_def_var(nc.id(), name, type, static_cast<int>(ids.size()), ids.data(), &var), "defining variable ",
             name);
    if (units) nc.put_text(var, "units", units);
    return var;
}

int define_dim(const NcOutput &nc, const char *name, size_t length) {
    int dim = -1;
    nc.check(nc_def_dim(nc.id(), name, length, &dim), "defining dimension ", name);
    return dim;
}

// The areas on the unit sphere.
std::vector<double> unit_areas(const MpasMesh &m) {
    std::vector<double> area(m.area_cell);
    const double r2 = m.radius_m * m.radius_m;
    for (double &a : area) a /= r2;
    return area;
}

}  // namespace

void write_scrip_grid(const MpasMesh &m, const std::string &path) {
    const size_t n = static_cast<size_t>(m.n_cells), w = static_cast<size_t>(m.max_edges);
    std::vector<double> center_lat(n), center_lon(n), corner_lat(n * w), corner_lon(n * w);
    for (size_t c = 0; c < n; ++c) {
        center_lat[c] = m.lat_cell[c] * kDegrees, center_lon[c] = longitude_deg(m.lon_cell[c]);
        const size_t k = static_cast<size_t>(m.n_edges_on_cell[c]);
        for (size_t j = 0; j < w; ++j) {
            const int32_t v = m.vertices_on_cell[c * w + std::min(j, k - 1)];
            corner_lat[c * w + j] = m.lat_vertex[v] * kDegrees, corner_lon[c * w + j] = longitude_deg(m.lon_vertex[v]);
        }
    }
    const std::vector<double> area = unit_areas(m);
    const std::vector<int32_t> mask(n, 1);
    const int32_t dims[1] = {static_cast<int32_t>(n)};

    NetcdfLock lock;
    NcOutput nc(path, format_for(uint64_t(8) * n * w), "SCRIP grid file");
    int old_fill = 0;
    nc.check(nc_set_fill(nc.id(), NC_NOFILL, &old_fill), "setting no-fill mode");
    const int size = define_dim(nc, "grid_size", n), corners = define_dim(nc, "grid_corners", w),
              rank = define_dim(nc, "grid_rank", 1);
    const int v_dims = define_var(nc, "grid_dims", NC_INT, {rank}, nullptr);
    const int v_lat = define_var(nc, "grid_center_lat", NC_DOUBLE, {size}, "degrees");
    const int v_lon = define_var(nc, "grid_center_lon", NC_DOUBLE, {size}, "degrees");
    const int v_mask = define_var(nc, "grid_imask", NC_INT, {size}, "unitless");
    const int v_clat = define_var(nc, "grid_corner_lat", NC_DOUBLE, {size, corners}, "degrees");
    const int v_clon = define_var(nc, "grid_corner_lon", NC_DOUBLE, {size, corners}, "degrees");
    const int v_area = define_var(nc, "grid_area", NC_DOUBLE, {size}, "radians^2");
    nc.put_text(v_area, "long_name", "area of the cell on the unit sphere");
    nc.put_text(NC_GLOBAL, "title", "unimesh power cells (SCRIP)");
    nc.put_text(NC_GLOBAL, "source", "unimesh " UM_VERSION_STRING);
    nc.put_text(NC_GLOBAL, "mesh_file_id", mpas_file_id(m));
    nc.check(nc_enddef(nc.id()), "ending define mode");
    nc.check(nc_put_var_int(nc.id(), v_dims, dims), "writing variable ", "grid_dims");
    nc.check(nc_put_var_double(nc.id(), v_lat, center_lat.data()), "writing variable ", "grid_center_lat");
    nc.check(nc_put_var_double(nc.id(), v_lon, center_lon.data()), "writing variable ", "grid_center_lon");
    nc.check(nc_put_var_int(nc.id(), v_mask, mask.data()), "writing variable ", "grid_imask");
    nc.check(nc_put_var_double(nc.id(), v_clat, corner_lat.data()), "writing variable ", "grid_corner_lat");
    nc.check(nc_put_var_double(nc.id(), v_clon, corner_lon.data()), "writing variable ", "grid_corner_lon");
    nc.check(nc_put_var_double(nc.id(), v_area, area.data()), "writing variable ", "grid_area");
    nc.close();
}

void write_esmf_mesh(const MpasMesh &m, const std::string &path) {
    const size_t n = static_cast<size_t>(m.n_cells), w = static_cast<size_t>(m.max_edges),
                 nodes = static_cast<size_t>(m.n_vertices);
    std::vector<double> node_coords(2 * nodes), center_coords(2 * n);
    for (size_t v = 0; v < nodes; ++v)
        node_coords[2 * v] = longitude_deg(m.lon_vertex[v]), node_coords[2 * v + 1] = m.lat_vertex[v] * kDegrees;
    std::vector<int32_t> conn(n * w, -1), count(n), mask(n, 1);
    for (size_t c = 0; c < n; ++c) {
        center_coords[2 * c] = longitude_deg(m.lon_cell[c]), center_coords[2 * c + 1] = m.lat_cell[c] * kDegrees;
        count[c] = m.n_edges_on_cell[c];
        for (size_t j = 0; j < static_cast<size_t>(count[c]); ++j) conn[c * w + j] = m.vertices_on_cell[c * w + j] + 1;
    }
    const std::vector<double> area = unit_areas(m);

    NetcdfLock lock;
    NcOutput nc(path, format_for(std::max<uint64_t>(uint64_t(16) * nodes, uint64_t(4) * n * w)),
                "ESMF mesh file");
    int old_fill = 0;
    nc.check(nc_set_fill(nc.id(), NC_NOFILL, &old_fill), "setting no-fill mode");
    const int node_dim = define_dim(nc, "nodeCount", nodes), element_dim = define_dim(nc, "elementCount", n),
              max_dim = define_dim(nc, "maxNodePElement", w), coord_dim = define_dim(nc, "coordDim", 2);
    const int v_nodes = define_var(nc, "nodeCoords", NC_DOUBLE, {node_dim, coord_dim}, "degrees");
    const int v_conn = define_var(nc, "elementConn", NC_INT, {element_dim, max_dim}, nullptr);
    nc.put_text(v_conn, "long_name", "Node Indices that define the element connectivity");
    const int32_t fill = -1, start = 1;
    nc.check(nc_put_att_int(nc.id(), v_conn, "_FillValue", NC_INT, 1, &fill), "writing attribute ", "_FillValue");
    nc.check(nc_put_att_int(nc.id(), v_conn, "start_index", NC_INT, 1, &start), "writing attribute ", "start_index");
    const int v_count = define_var(nc, "numElementConn", NC_INT, {element_dim}, nullptr);
    nc.put_text(v_count, "long_name", "Number of nodes per element");
    const int v_centers = define_var(nc, "centerCoords", NC_DOUBLE, {element_dim, coord_dim}, "degrees");
    const int v_area = define_var(nc, "elementArea", NC_DOUBLE, {element_dim}, "radians^2");
    nc.put_text(v_area, "long_name", "area weights");
    const int v_mask = define_var(nc, "elementMask", NC_INT, {element_dim}, nullptr);
    nc.put_text(NC_GLOBAL, "gridType", "unstructured mesh");
    nc.put_text(NC_GLOBAL, "version", "0.9");
    nc.put_text(NC_GLOBAL, "source", "unimesh " UM_VERSION_STRING);
    nc.put_text(NC_GLOBAL, "mesh_file_id", mpas_file_id(m));
    nc.check(nc_enddef(nc.id()), "ending define mode");
    nc.check(nc_put_var_double(nc.id(), v_nodes, node_coords.data()), "writing variable ", "nodeCoords");
    nc.check(nc_put_var_int(nc.id(), v_conn, conn.data()), "writing variable ", "elementConn");
    nc.check(nc_put_var_int(nc.id(), v_count, count.data()), "writing variable ", "numElementConn");
    nc.check(nc_put_var_double(nc.id(), v_centers, center_coords.data()), "writing variable ", "centerCoords");
    nc.check(nc_put_var_double(nc.id(), v_area, area.data()), "writing variable ", "elementArea");
    nc.check(nc_put_var_int(nc.id(), v_mask, mask.data()), "writing variable ", "elementMask");
    nc.close();
}

}  // namespace um::io
