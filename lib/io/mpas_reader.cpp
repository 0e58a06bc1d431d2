#include "io/mpas_reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <netcdf.h>

#include "core/error.hpp"
#include "dual/mpas_fields.hpp"
#include "geom/surface.hpp"
#include "io/error_text.hpp"
#include "io/nc_input.hpp"
#include "io/netcdf_lock.hpp"

namespace um::io {

namespace {

using dual::kNone;
using dual::MpasDim;
using dual::MpasField;
using dual::MpasKind;
using dual::MpasMesh;

constexpr const char *kWhat = "MPAS mesh file";

template <class... Parts>
[[noreturn]] void format_error(const std::string &path, const Parts &...parts) {
    fail(UM_ERR_FILE_FORMAT, kWhat, " '", path, "': ", parts...);
}

size_t dimension(const NcInput &file, const std::string &path, const char *name) {
    int id = -1;
    size_t length = 0;
    if (nc_inq_dimid(file.id(), name, &id) != NC_NOERR || nc_inq_dimlen(file.id(), id, &length) != NC_NOERR)
        format_error(path, "no dimension ", name, " (not an MPAS mesh file)");
    return length;
}

bool has_variable(const NcInput &file, const char *name) {
    int id = -1;
    return nc_inq_varid(file.id(), name, &id) == NC_NOERR;
}

// Whether the file has global attribute `name`.
bool has_global(const NcInput &file, const char *name) {
    return nc_inq_att(file.id(), NC_GLOBAL, name, nullptr, nullptr) == NC_NOERR;
}

// Global attribute `name` into value when it is one number; false otherwise.
bool global_number(const NcInput &file, const char *name, double &value) {
    nc_type type = NC_NAT;
    size_t count = 0;
    return nc_inq_att(file.id(), NC_GLOBAL, name, &type, &count) == NC_NOERR && count == 1 && type != NC_CHAR &&
           type != NC_STRING && nc_get_att_double(file.id(), NC_GLOBAL, name, &value) == NC_NOERR;
}

// The ellipsoid a mesh was made on (the writer's ellipsoid_semi_major_axis
// and ellipsoid_flattening), kept so that files made from it say so too;
// none for a sphere.
void read_ellipsoid(const NcInput &file, const std::string &path, MpasMesh &m) {
    auto attribute = [&](const char *name, double &value) {
        if (!has_global(file, name)) return false;
        if (!global_number(file, name, value)) format_error(path, name, " is not one number");
        return true;
    };
    double a = 0, f = 0;
    const bool has_a = attribute("ellipsoid_semi_major_axis", a), has_f = attribute("ellipsoid_flattening", f);
    if (!has_a && !has_f) return;
    if (has_a != has_f)
        format_error(path, has_a ? "ellipsoid_flattening" : "ellipsoid_semi_major_axis", " is missing (the other is ",
                     has_a ? a : f, ")");
    if (!std::isfinite(a) || !(a > 0) || !(f >= 0) || f > geom::Surface::kMaxFlattening)
        format_error(path, "ellipsoid_semi_major_axis ", a, " and ellipsoid_flattening ", f,
                     ": expected a finite a > 0 m and f in [0, ", geom::Surface::kMaxFlattening, "]");
    if (f == 0) return;  // a sphere
    m.ellipsoid_a_m = a, m.ellipsoid_f = f;
}

void read_dimensions(const NcInput &file, const std::string &path, MpasMesh &m) {
    const size_t cells = dimension(file, path, "nCells"), edges = dimension(file, path, "nEdges"),
                 vertices = dimension(file, path, "nVertices"), max_edges = dimension(file, path, "maxEdges"),
                 max_edges2 = dimension(file, path, "maxEdges2"), degree = dimension(file, path, "vertexDegree");
    constexpr size_t kMax = std::numeric_limits<int32_t>::max();
    if (cells > kMax || edges > kMax || vertices > kMax)
        fail(UM_ERR_LIMIT, kWhat, " '", path, "': more than 2^31 - 1 cells, edges or vertices");
    if (cells < 1 || edges < 3 || vertices < 1 || max_edges < 3 || max_edges > 64)
        format_error(path, "nCells ", cells, ", nEdges ", edges, ", nVertices ", vertices, ", maxEdges ",
                     max_edges, ": not the dimensions of a mesh");
    if (edges > max_edges * cells || vertices > max_edges * cells)
        format_error(path, "nEdges ", edges, " or nVertices ", vertices, " exceeds maxEdges * nCells = ",
                     max_edges * cells, ": not the dimensions of a mesh");
    if (max_edges2 != 2 * max_edges || degree != 3)
        format_error(path, "maxEdges2 ", max_edges2, " and vertexDegree ", degree,
                     ": expected 2 * maxEdges and 3 (a mesh of power cells)");
    m.n_cells = static_cast<int32_t>(cells), m.n_edges = static_cast<int32_t>(edges);
    m.n_vertices = static_cast<int32_t>(vertices), m.max_edges = static_cast<int32_t>(max_edges);
    double radius = 0;
    if (!global_number(file, "sphere_radius", radius) || !(radius > 0) || radius > 1e12)
        format_error(path, "sphere_radius is missing or not a radius in (0, 1e12] m (read: ", radius, ")");
    m.radius_m = radius;
    read_ellipsoid(file, path, m);
}

// Sizes every array the file has (the contract's always, the tags when the
// file holds them), so that mpas_fields(m) lists what is to be read.
void size_arrays(const NcInput &file, MpasMesh &m) {
    const size_t c = m.n_cells, e = m.n_edges, v = m.n_vertices, w = m.max_edges, d = dual::kVertexDegree;
    for (auto *a : {&m.x_cell, &m.y_cell, &m.z_cell, &m.lat_cell, &m.lon_cell, &m.area_cell, &m.mesh_density})
        a->resize(c);
    for (auto *a : {&m.x_edge, &m.y_edge, &m.z_edge, &m.lat_edge, &m.lon_edge, &m.dc_edge, &m.dv_edge, &m.angle_edge})
        a->resize(e);
    for (auto *a : {&m.x_vertex, &m.y_vertex, &m.z_vertex, &m.lat_vertex, &m.lon_vertex, &m.area_triangle})
        a->resize(v);
    m.n_edges_on_cell.resize(c);
    for (auto *a : {&m.edges_on_cell, &m.vertices_on_cell, &m.cells_on_cell}) a->resize(c * w);
    for (auto *a : {&m.cells_on_edge, &m.vertices_on_edge}) a->resize(2 * e);
    m.n_edges_on_edge.resize(e);
    m.edges_on_edge.resize(2 * w * e);
    m.weights_on_edge.resize(2 * w * e);
    for (auto *a : {&m.cells_on_vertex, &m.edges_on_vertex}) a->resize(d * v);
    m.kite_areas_on_vertex.resize(d * v);
    m.boundary_vertex.resize(v);
    const struct {
        const char *name;
        std::vector<int32_t> &array;
        size_t n;
    } tags[] = {{"cellSide", m.cell_side, c},           {"vertexSide", m.vertex_side, v},
                {"cellOceanMask", m.cell_ocean_mask, c}, {"cellLandMask", m.cell_land_mask, c},
                {"edgeFeatureKind", m.edge_feature_kind, e}, {"edgeFeatureId", m.edge_feature_id, e},
                {"edgeRiverDownstream", m.edge_river_downstream, e}, {"downstreamCell", m.cell_downstream, c},
                {"riverCellKind", m.cell_river_kind, c}, {"edgeOnRiver", m.edge_on_river, e},
                {"bdyMaskCell", m.bdy_mask_cell, c},     {"bdyMaskEdge", m.bdy_mask_edge, e},
                {"bdyMaskVertex", m.bdy_mask_vertex, v}};
    for (const auto &tag : tags)
        if (has_variable(file, tag.name)) tag.array.resize(tag.n);
    // The tags come in their groups or not at all.
    if (m.cell_ocean_mask.empty() != m.cell_land_mask.empty()) m.cell_ocean_mask.clear(), m.cell_land_mask.clear();
    if (m.edge_feature_kind.empty() || m.edge_feature_id.empty() || m.edge_river_downstream.empty())
        m.edge_feature_kind.clear(), m.edge_feature_id.clear(), m.edge_river_downstream.clear();
    if (m.cell_downstream.empty() != m.cell_river_kind.empty()) m.cell_downstream.clear(), m.cell_river_kind.clear();
    if (m.edge_feature_kind.empty()) m.edge_on_river.clear();
    if (m.bdy_mask_cell.empty() || m.bdy_mask_edge.empty() || m.bdy_mask_vertex.empty())
        m.bdy_mask_cell.clear(), m.bdy_mask_edge.clear(), m.bdy_mask_vertex.clear();
}

void read_field(const NcInput &file, const std::string &path, const MpasField &f) {
    int var = -1, ndims = 0, dims[NC_MAX_VAR_DIMS];
    if (nc_inq_varid(file.id(), f.name, &var) != NC_NOERR) format_error(path, "no variable ", f.name);
    nc_inq_varndims(file.id(), var, &ndims);
    if (ndims != static_cast<int>(f.dims.size())) format_error(path, "variable ", f.name, " has ", ndims, " dimensions");
    nc_inq_vardimid(file.id(), var, dims);
    for (int k = 0; k < ndims; ++k) {
        char name[NC_MAX_NAME + 1] = "";
        nc_inq_dimname(file.id(), dims[k], name);
        if (std::string(name) != dual::mpas_dim_name(f.dims[k]))
            format_error(path, "variable ", f.name, " has dimension ", name, " where ",
                         dual::mpas_dim_name(f.dims[k]), " belongs");
    }
    int status = NC_NOERR;
    if (f.kind == MpasKind::real) {
        status = nc_get_var_double(file.id(), var, const_cast<double *>(f.reals->data()));
    } else {
        std::vector<int32_t> &ints = const_cast<std::vector<int32_t> &>(*f.ints);
        status = nc_get_var_int(file.id(), var, ints.data());
        // 1-based, 0 padding -> 0-based, kNone; a negative index (a fill
        // value) becomes one the range checks refuse.
        if (f.kind == MpasKind::index)
            for (int32_t &i : ints) i = i >= 0 ? i - 1 : std::numeric_limits<int32_t>::min();
    }
    if (status != NC_NOERR) format_error(path, "cannot read variable ", f.name, ": ", netcdf_status_text(status));
}

// Every index in range; padding beyond a row's count set to kNone. 0 (a
// missing element) is allowed where a cut mesh has one.
void check_connectivity(const std::string &path, MpasMesh &m) {
    // value: 0-based as read less 1; INT32_MIN stands for a negative value in the file.
    auto bad = [&](const char *name, int64_t row, int64_t column, int32_t value) {
        if (value == std::numeric_limits<int32_t>::min())
            format_error(path, name, "(", row + 1, ", ", column + 1, ") is negative, not an index");
        format_error(path, name, "(", row + 1, ", ", column + 1, ") = ", int64_t(value) + 1,
                     " is not an index in range");
    };
    auto in = [](int32_t i, int32_t n, bool missing_allowed) { return (i >= 0 && i < n) || (missing_allowed && i == kNone); };
    const int64_t w = m.max_edges;
    for (int64_t c = 0; c < m.n_cells; ++c) {
        const int32_t k = m.n_edges_on_cell[c];
        if (k < 3 || k > m.max_edges) format_error(path, "nEdgesOnCell(", c + 1, ") = ", k, " is not in [3, maxEdges]");
        for (int64_t j = 0; j < w; ++j) {
            const int64_t at = c * w + j;
            if (j >= k) {
                m.edges_on_cell[at] = m.vertices_on_cell[at] = m.cells_on_cell[at] = kNone;
                continue;
            }
            if (!in(m.edges_on_cell[at], m.n_edges, false)) bad("edgesOnCell", c, j, m.edges_on_cell[at]);
            if (!in(m.vertices_on_cell[at], m.n_vertices, false)) bad("verticesOnCell", c, j, m.vertices_on_cell[at]);
            if (!in(m.cells_on_cell[at], m.n_cells, true)) bad("cellsOnCell", c, j, m.cells_on_cell[at]);
        }
    }
    for (int64_t e = 0; e < m.n_edges; ++e) {
        if (!in(m.cells_on_edge[2 * e], m.n_cells, false)) bad("cellsOnEdge", e, 0, m.cells_on_edge[2 * e]);
        if (!in(m.cells_on_edge[2 * e + 1], m.n_cells, true)) bad("cellsOnEdge", e, 1, m.cells_on_edge[2 * e + 1]);
        for (int k = 0; k < 2; ++k)
            if (!in(m.vertices_on_edge[2 * e + k], m.n_vertices, false))
                bad("verticesOnEdge", e, k, m.vertices_on_edge[2 * e + k]);
        const int32_t n = m.n_edges_on_edge[e];
        if (n < 0 || n > 2 * m.max_edges) format_error(path, "nEdgesOnEdge(", e + 1, ") = ", n, " is out of range");
        for (int64_t j = 0; j < 2 * w; ++j) {
            int32_t &f = m.edges_on_edge[2 * w * e + j];
            if (j >= n) f = kNone;
            else if (!in(f, m.n_edges, false)) bad("edgesOnEdge", e, j, f);
        }
    }
    for (int64_t v = 0; v < 3 * int64_t(m.n_vertices); ++v) {
        if (!in(m.cells_on_vertex[v], m.n_cells, true)) bad("cellsOnVertex", v / 3, v % 3, m.cells_on_vertex[v]);
        if (!in(m.edges_on_vertex[v], m.n_edges, true)) bad("edgesOnVertex", v / 3, v % 3, m.edges_on_vertex[v]);
    }
    for (size_t c = 0; c < m.cell_downstream.size(); ++c)
        if (!in(m.cell_downstream[c], m.n_cells, true)) bad("downstreamCell", int64_t(c), 0, m.cell_downstream[c]);
    for (size_t c = 0; c < m.cell_ocean_mask.size(); ++c)
        if ((m.cell_ocean_mask[c] != 0 && m.cell_ocean_mask[c] != 1) || m.cell_land_mask[c] != 1 - m.cell_ocean_mask[c])
            format_error(path, "cellOceanMask(", c + 1, ") and cellLandMask are not 0 and 1, or 1 and 0");
}

// The lists agree with each other: each edge and vertex a cell lists has
// that cell among its own, and an edge's vertices are corners of its first
// cell. (A cut would otherwise keep an edge none of whose cells it keeps.)
void check_cross_references(const std::string &path, const MpasMesh &m) {
    const int64_t w = m.max_edges;
    auto lists = [](const int32_t *row, int n, int32_t x) { return std::find(row, row + n, x) != row + n; };
    for (int64_t c = 0; c < m.n_cells; ++c)
        for (int64_t j = 0; j < m.n_edges_on_cell[c]; ++j) {
            const int32_t e = m.edges_on_cell[c * w + j], v = m.vertices_on_cell[c * w + j];
            if (!lists(&m.cells_on_edge[2 * int64_t(e)], 2, int32_t(c)))
                format_error(path, "edgesOnCell(", c + 1, ", ", j + 1, ") = ", int64_t(e) + 1,
                             ", but cellsOnEdge of that edge does not hold cell ", c + 1);
            if (!lists(&m.cells_on_vertex[3 * int64_t(v)], 3, int32_t(c)))
                format_error(path, "verticesOnCell(", c + 1, ", ", j + 1, ") = ", int64_t(v) + 1,
                             ", but cellsOnVertex of that vertex does not hold cell ", c + 1);
        }
    for (int64_t e = 0; e < m.n_edges; ++e) {
        const int32_t c = m.cells_on_edge[2 * e];
        for (int k = 0; k < 2; ++k)
            if (!lists(&m.vertices_on_cell[c * w], m.n_edges_on_cell[c], m.vertices_on_edge[2 * e + k]))
                format_error(path, "verticesOnEdge(", e + 1, ", ", k + 1, ") is not a vertex of cellsOnEdge(", e + 1,
                             ", 1) = ", int64_t(c) + 1);
    }
}

// Every real value finite, and cell areas and cell distances > 0: the
// component files (weights, grids, the river report) are computed from them.
void check_values(const std::string &path, const MpasMesh &m) {
    for (const MpasField &f : dual::mpas_fields(m)) {
        if (f.kind != MpasKind::real) continue;
        const bool positive = f.reals == &m.area_cell || f.reals == &m.dc_edge;
        const std::vector<double> &values = *f.reals;
        for (size_t i = 0; i < values.size(); ++i)
            if (!std::isfinite(values[i]) || (positive && !(values[i] > 0)))
                format_error(path, f.name, " value ", i + 1, " is ", values[i],
                             positive ? ": expected a finite value > 0" : ": expected a finite value");
    }
}

}  // namespace

MpasMesh read_mpas_mesh(Context &ctx, const std::string &path) {
    NetcdfLock lock;  // before the file: the file closes first, then the lock opens
    NcInput file(path, kWhat);
    MpasMesh m;
    read_dimensions(file, path, m);
    // The arrays the dimensions call for, twice: the mesh and its components.
    const int64_t w = m.max_edges;
    const int64_t bytes = int64_t(m.n_cells) * (64 + 12 * w) + int64_t(m.n_edges) * (84 + 24 * w) +
                          int64_t(m.n_vertices) * (96);
    ctx.check_memory(2 * bytes, "the MPAS mesh read from the file and its components");
    size_arrays(file, m);
    for (const MpasField &f : dual::mpas_fields(m))
        if (f.kind != MpasKind::id) read_field(file, path, f);
    check_connectivity(path, m);
    check_cross_references(path, m);
    check_values(path, m);
    return m;
}

}  // namespace um::io
