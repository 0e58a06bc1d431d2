#include "components/cut_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "dual/stages.hpp"
#include "unimesh.h"

namespace um::components {

using dual::kNone;
using dual::kVertexDegree;
using dual::MpasMesh;

namespace {

// Old index -> new index (kNone where dropped) and new -> old, of the
// elements with keep set, in the old order.
struct Renumbering {
    std::vector<int32_t> to_new, to_old;

    explicit Renumbering(const std::vector<uint8_t> &keep) : to_new(keep.size(), kNone) {
        for (size_t i = 0; i < keep.size(); ++i)
            if (keep[i]) to_new[i] = static_cast<int32_t>(to_old.size()), to_old.push_back(static_cast<int32_t>(i));
    }
    int32_t operator()(int32_t old) const { return old == kNone ? kNone : to_new[old]; }
    int32_t size() const { return static_cast<int32_t>(to_old.size()); }
};

// The rows of src (width values each) of the kept elements, each row cut or
// padded to new_width (padding `pad`).
template <class T>
std::vector<T> rows(const std::vector<T> &src, const Renumbering &r, size_t width, size_t new_width, T pad) {
    if (src.empty()) return {};
    std::vector<T> out(r.to_old.size() * new_width, pad);
    for (size_t i = 0; i < r.to_old.size(); ++i)
        std::copy_n(&src[r.to_old[i] * width], std::min(width, new_width), &out[i * new_width]);
    return out;
}

template <class T>
std::vector<T> values(const std::vector<T> &src, const Renumbering &r) {
    return rows(src, r, 1, 1, T{});
}

// Indices renumbered in place (kNone stays kNone).
void renumber(std::vector<int32_t> &indices, const Renumbering &r) {
    for (int32_t &i : indices) i = r(i);
}

struct Kept {
    Renumbering cells, edges, vertices;
};

Kept kept_elements(const MpasMesh &base, const std::vector<uint8_t> &keep) {
    std::vector<uint8_t> edge(static_cast<size_t>(base.n_edges), 0), vertex(static_cast<size_t>(base.n_vertices), 0);
    const size_t w = static_cast<size_t>(base.max_edges);
    for (int32_t c = 0; c < base.n_cells; ++c) {
        if (!keep[c]) continue;
        for (int32_t j = 0; j < base.n_edges_on_cell[c]; ++j) {
            edge[base.edges_on_cell[w * c + j]] = 1;
            vertex[base.vertices_on_cell[w * c + j]] = 1;
        }
    }
    return {Renumbering(keep), Renumbering(edge), Renumbering(vertex)};
}

void cut_cells(const MpasMesh &base, const Kept &k, MpasMesh &m) {
    const Renumbering &r = k.cells;
    m.n_cells = r.size();
    m.max_edges = 0;
    for (int32_t c : r.to_old) m.max_edges = std::max(m.max_edges, base.n_edges_on_cell[c]);
    const size_t w = static_cast<size_t>(base.max_edges), nw = static_cast<size_t>(m.max_edges);
    for (auto [to, from] : {std::pair{&m.x_cell, &base.x_cell}, {&m.y_cell, &base.y_cell}, {&m.z_cell, &base.z_cell},
                            {&m.lat_cell, &base.lat_cell}, {&m.lon_cell, &base.lon_cell},
                            {&m.area_cell, &base.area_cell}, {&m.mesh_density, &base.mesh_density}})
        *to = values(*from, r);
    for (auto [to, from] :
         {std::pair{&m.n_edges_on_cell, &base.n_edges_on_cell}, {&m.cell_side, &base.cell_side},
          {&m.cell_ocean_mask, &base.cell_ocean_mask}, {&m.cell_land_mask, &base.cell_land_mask},
          {&m.cell_downstream, &base.cell_downstream}, {&m.cell_river_kind, &base.cell_river_kind},
          {&m.bdy_mask_cell, &base.bdy_mask_cell}})
        *to = values(*from, r);
    renumber(m.cell_downstream, r);
    m.edges_on_cell = rows(base.edges_on_cell, r, w, nw, kNone);
    m.vertices_on_cell = rows(base.vertices_on_cell, r, w, nw, kNone);
    m.cells_on_cell = rows(base.cells_on_cell, r, w, nw, kNone);
    renumber(m.edges_on_cell, k.edges);
    renumber(m.vertices_on_cell, k.vertices);
    renumber(m.cells_on_cell, r);
    m.base_cell = r.to_old;
}

// An edge whose cell 1 is cut off, turned around: the other cell first, the
// vertices swapped with it (the tangent stays k x n), the normal's angle
// and the river's direction reversed.
void turn_around(MpasMesh &m, int64_t e) {
    std::swap(m.cells_on_edge[2 * e], m.cells_on_edge[2 * e + 1]);
    std::swap(m.vertices_on_edge[2 * e], m.vertices_on_edge[2 * e + 1]);
    double angle = m.angle_edge[e] + M_PI;
    if (angle > M_PI) angle -= 2 * M_PI;
    m.angle_edge[e] = angle;
    if (!m.edge_river_downstream.empty()) m.edge_river_downstream[e] = -m.edge_river_downstream[e];
}

void cut_edges(const MpasMesh &base, const Kept &k, MpasMesh &m) {
    const Renumbering &r = k.edges;
    m.n_edges = r.size();
    for (auto [to, from] : {std::pair{&m.x_edge, &base.x_edge}, {&m.y_edge, &base.y_edge}, {&m.z_edge, &base.z_edge},
                            {&m.lat_edge, &base.lat_edge}, {&m.lon_edge, &base.lon_edge},
                            {&m.dc_edge, &base.dc_edge}, {&m.dv_edge, &base.dv_edge},
                            {&m.angle_edge, &base.angle_edge}})
        *to = values(*from, r);
    for (auto [to, from] : {std::pair{&m.edge_feature_kind, &base.edge_feature_kind},
                            {&m.edge_feature_id, &base.edge_feature_id},
                            {&m.edge_river_downstream, &base.edge_river_downstream},
                            {&m.edge_on_river, &base.edge_on_river}, {&m.bdy_mask_edge, &base.bdy_mask_edge}})
        *to = values(*from, r);
    m.cells_on_edge = rows(base.cells_on_edge, r, 2, 2, kNone);
    m.vertices_on_edge = rows(base.vertices_on_edge, r, 2, 2, kNone);
    renumber(m.cells_on_edge, k.cells);
    renumber(m.vertices_on_edge, k.vertices);
    for (int64_t e = 0; e < m.n_edges; ++e)
        if (m.cells_on_edge[2 * e] == kNone) turn_around(m, e);
    m.base_edge = r.to_old;
}

void cut_vertices(const MpasMesh &base, const Kept &k, MpasMesh &m) {
    const Renumbering &r = k.vertices;
    m.n_vertices = r.size();
    for (auto [to, from] :
         {std::pair{&m.x_vertex, &base.x_vertex}, {&m.y_vertex, &base.y_vertex}, {&m.z_vertex, &base.z_vertex},
          {&m.lat_vertex, &base.lat_vertex}, {&m.lon_vertex, &base.lon_vertex},
          {&m.area_triangle, &base.area_triangle}})
        *to = values(*from, r);
    m.vertex_side = values(base.vertex_side, r);
    m.bdy_mask_vertex = values(base.bdy_mask_vertex, r);
    const size_t d = kVertexDegree;
    m.kite_areas_on_vertex = rows(base.kite_areas_on_vertex, r, d, d, 0.0);
    m.cells_on_vertex = rows(base.cells_on_vertex, r, d, d, kNone);
    m.edges_on_vertex = rows(base.edges_on_vertex, r, d, d, kNone);
    renumber(m.cells_on_vertex, k.cells);
    renumber(m.edges_on_vertex, k.edges);
    m.boundary_vertex.assign(static_cast<size_t>(m.n_vertices), 0);
    for (size_t v = 0; v < static_cast<size_t>(m.n_vertices); ++v)
        for (size_t j = 0; j < d; ++j)
            if (m.cells_on_vertex[d * v + j] == kNone) m.boundary_vertex[v] = 1;
    m.base_vertex = r.to_old;
}

}  // namespace

MpasMesh cut_mesh(Context &ctx, const MpasMesh &base, const std::vector<uint8_t> &keep) {
    if (keep.size() != static_cast<size_t>(base.n_cells))
        fail(UM_ERR_INTERNAL, "cut_mesh: ", keep.size(), " cell flags for ", base.n_cells, " cells");
    const Kept k = kept_elements(base, keep);
    if (k.cells.size() == 0) fail(UM_ERR_INTERNAL, "cut_mesh: no cell to keep");
    MpasMesh m;
    m.radius_m = base.radius_m;
    m.ellipsoid_a_m = base.ellipsoid_a_m, m.ellipsoid_f = base.ellipsoid_f;
    cut_cells(base, k, m);
    cut_edges(base, k, m);
    cut_vertices(base, k, m);
    dual::fill_trsk_weights(ctx, m);
    return m;
}

}  // namespace um::components
