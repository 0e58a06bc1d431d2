#include "dual/mpas_source.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <utility>

#include "core/error.hpp"
#include "dual/boundary_layers.hpp"
#include "dual/river_routing.hpp"
#include "dual/spherical.hpp"
#include "dual/stages.hpp"
#include "mesh/refined_mesh.hpp"
#include "tri/cell_walk.hpp"

namespace um::dual {

namespace {

void check_input(const tri::Triangulation &tri, const MpasLayout &layout, const MpasMeshInput &in) {
    if (!std::isfinite(in.radius_m) || in.radius_m <= 0)
        fail(UM_ERR_INVALID_ARGUMENT, "MPAS mesh: sphere radius = ", in.radius_m,
             " m; it must be finite and > 0");
    if (in.cell_width_km.empty()) return;
    if (in.cell_width_km.size() != static_cast<size_t>(layout.n_cells()))
        fail(UM_ERR_INTERNAL, "MPAS mesh: ", in.cell_width_km.size(), " cell widths for ",
             layout.n_cells(), " mesh vertices");
    for (int32_t c = 0; c < layout.n_cells(); ++c) {
        const double h = in.cell_width_km[layout.cell_source_vertex(c)];
        if (!std::isfinite(h) || h <= 0) {
            double lon, lat;
            in.surface.geodetic(tri.direction(layout.cell_slot(c)), lon, lat);
            fail(std::isfinite(h) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT,
                 "MPAS mesh: the spacing is ", h, " km at mesh vertex ", layout.cell_source_vertex(c),
                 " (lon ", lon, ", lat ", lat, " degrees); it must be finite and > 0");
        }
    }
}

MpasMeshInput input_of(Context &ctx, const mesh::RefinedMesh &refined) {
    MpasMeshInput input;
    input.slot_of_vertex = refined.slot_of_vertex;
    if (refined.regional()) input.region = refined.region_cells(ctx);
    const geom::Surface &surface = refined.surface;
    input.surface = surface;
    input.radius_m = surface.authalic_radius_m();
    if (refined.spacing) {
        // The spacing the mesh was refined to, at the generators, for meshDensity
        // (check_input refuses values that are not finite and > 0); on an
        // ellipsoid the geodesic km it stands for (hfun/on_ellipsoid.hpp).
        input.cell_width_km.resize(input.slot_of_vertex.size());
        ctx.parallel_for(refined.vertex_count(), 1024, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
                const geom::Vec3 u = refined.tri.direction(input.slot_of_vertex[i]);
                const double km = refined.spacing->km_at(u);
                input.cell_width_km[i] = surface.is_sphere() ? km : km * (surface.radius_along(u) / surface.a());
            }
        });
    }
    return input;
}

// The costly parts of a kind's rows that a caller wanting variable `only`
// (nullptr: every variable) needs: the areas and kites, the TRSK stencils
// and, of those, their weights (the rest is the rings' topology).
struct RowParts {
    bool areas = true, stencils = true, weights = true;
};

RowParts parts_for(const MpasMesh &block, const char *only) {
    if (!only) return {};
    for (const MpasField &f : mpas_fields(block))
        if (std::strcmp(f.name, only) == 0) {
            const bool weights = f.reals == &block.weights_on_edge;
            return {f.reals == &block.area_cell || f.reals == &block.area_triangle ||
                        f.reals == &block.kite_areas_on_vertex,
                    weights || f.ints == &block.n_edges_on_edge || f.ints == &block.edges_on_edge, weights};
        }
    return {};
}

// Grows block's arrays of the variables along `kind` to `count` rows at
// once, an array a task. Grown one after another by the steps that fill
// them, their first touches (page faults and zeroing: about 60 MB for a
// first block of edges) ran on one thread. (The fields point into block,
// which is not const.)
void grow_rows(Context &ctx, MpasDim kind, int64_t count, MpasMesh &block) {
    std::vector<std::pair<MpasField, size_t>> growing;  // (field, values it is to hold)
    for (const MpasField &f : mpas_fields(block)) {
        const size_t n = static_cast<size_t>(count * f.columns(block));
        const size_t have = f.reals ? f.reals->size() : f.ints ? f.ints->size() : n;
        if (f.dims[0] == kind && have < n) growing.emplace_back(f, n);
    }
    ctx.parallel_for(static_cast<int64_t>(growing.size()), 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const auto &[f, n] = growing[i];
            if (f.reals) const_cast<std::vector<double> *>(f.reals)->resize(n);
            else const_cast<std::vector<int32_t> *>(f.ints)->resize(n);
        }
    });
}

uint64_t slot_pair(int32_t a, int32_t b) {
    return uint64_t(uint32_t(std::min(a, b))) << 32 | uint32_t(std::max(a, b));
}

}  // namespace

// The unified tags of a refined mesh: per cell its side and mask, per vertex
// its side, per edge the feature its dual crosses, whether a river's line
// crosses it and the river routing. What is per element is read from the
// refined mesh when a block asks; what needs the whole mesh (the river
// crossings and the routing) is computed once here.
struct MpasSource::Tags {
    const mesh::RefinedMesh *refined = nullptr;
    bool sides = false, vertex_sides = false;
    // Per vertex slot, 1 where the cell belongs to the ocean mesh
    // (RefinedMesh::ocean_cells); empty: no masks.
    std::vector<uint8_t> ocean;
    // Restricted edges by their two vertex slots, sorted for lookup.
    std::vector<std::pair<uint64_t, int32_t>> restricted;
    std::vector<uint8_t> edge_on_river;
    RiverRouting routing;

    bool features() const { return refined->gamma != nullptr; }
    // UM_FEATURE_* and part id of the restricted edge that MPAS edge
    // (cells c1, c2) is, or (0, -1).
    std::pair<int32_t, int32_t> edge_feature(const MpasLayout &layout, const EdgeEnds &ends) const {
        const uint64_t key = slot_pair(layout.cell_slot(ends.cell[0]), layout.cell_slot(ends.cell[1]));
        const auto it = std::lower_bound(restricted.begin(), restricted.end(), std::make_pair(key, int32_t(-1)));
        if (it == restricted.end() || it->first != key) return {0, -1};
        const features::Network &gamma = *refined->gamma;
        const features::Part &part = gamma.part(gamma.segment_part(refined->restricted[it->second].arc));
        return {static_cast<int32_t>(part.kind), part.id};
    }
};

namespace {

// Per MPAS edge, 1 where a river's line passes from one of its cells into
// the other: the cells along each river segment, in order, each sharing an
// edge with the one before (tri::cells_along_arc). This is the river
// network as the input draws it, also where the mesh keeps no restricted
// edge of the river (a face crossed by two features keeps one, and a river
// finer than the cells is not followed).
std::vector<uint8_t> river_crossings(Context &ctx, const MpasLayout &layout, const mesh::RefinedMesh &refined) {
    const tri::Triangulation &tri = refined.tri;
    const features::Network &gamma = *refined.gamma;
    std::vector<int64_t> river_parts;
    for (int64_t p = 0; p < gamma.part_count(); ++p)
        if (gamma.part(p).kind == features::Kind::river) river_parts.push_back(p);
    // Each flag is only ever set to 1, so the parts may run in any order.
    // A walk starts where the part's previous segment ended (its first from
    // a fixed vertex): on a tie between two cells the answer depends on the
    // start, which therefore must not depend on how the parts are shared out.
    std::vector<std::atomic<uint8_t>> on_river(static_cast<size_t>(layout.n_edges()));
    ctx.parallel_for(static_cast<int64_t>(river_parts.size()), 4, [&](int64_t b, int64_t e) {
        CellRing ring;
        for (int64_t i = b; i < e; ++i) {
            const features::Part &part = gamma.part(river_parts[i]);
            int32_t hint = -1;
            for (int64_t s = part.first_segment; s < part.first_segment + part.n_segments; ++s) {
                const std::vector<int32_t> slots =
                    tri::cells_along_arc(tri, gamma.segment_a(s), gamma.segment_b(s), hint);
                if (!slots.empty()) hint = slots.back();
                for (size_t k = 1; k < slots.size(); ++k) {
                    const int32_t p = layout.cell_of_slot(slots[k - 1]), q = layout.cell_of_slot(slots[k]);
                    if (p == kNone || q == kNone) continue;
                    layout.cell_ring(p, ring);
                    for (int j = 0; j < ring.degree(); ++j)
                        if (ring.cells[j] == q) on_river[ring.edges[j]].store(1, std::memory_order_relaxed);
                }
            }
        }
    });
    std::vector<uint8_t> flags(on_river.size());
    for (size_t e = 0; e < on_river.size(); ++e) flags[e] = on_river[e].load(std::memory_order_relaxed);
    return flags;
}

}  // namespace

// The input is taken by value and its arrays moved (8 + 4 bytes per cell,
// held while the mesh's own are).
MpasSource::MpasSource(Context &ctx, const tri::Triangulation &tri, MpasMeshInput input)
    : layout_(ctx, tri, std::move(input.slot_of_vertex), input.surface, input.region), radius_m_(input.radius_m),
      surface_(input.surface) {
    check_input(tri, layout_, input);
    boundary_layer_ = cell_boundary_layers(ctx, layout_);
    cell_width_km_ = std::move(input.cell_width_km);
    if (!cell_width_km_.empty()) min_width_km_ = *std::min_element(cell_width_km_.begin(), cell_width_km_.end());
}

MpasSource::MpasSource(Context &ctx, const mesh::RefinedMesh &refined)
    : MpasSource(ctx, refined.tri, input_of(ctx, refined)) {
    tags_ = std::make_unique<Tags>();
    Tags &t = *tags_;
    t.refined = &refined;
    t.sides = !refined.vertex_side.empty();
    t.vertex_sides = !refined.triangle_side.empty();
    if (t.sides) t.ocean = refined.ocean_cells();
    if (!t.features()) return;
    const tri::Triangulation &tri = refined.tri;
    t.restricted.reserve(refined.restricted.size());
    for (size_t r = 0; r < refined.restricted.size(); ++r) {
        const auto &e = refined.restricted[r];
        t.restricted.emplace_back(slot_pair(tri.vertex(e.triangle, (e.edge + 1) % 3), tri.vertex(e.triangle, (e.edge + 2) % 3)),
                                  static_cast<int32_t>(r));
    }
    std::sort(t.restricted.begin(), t.restricted.end());
    t.edge_on_river = river_crossings(ctx, layout_, refined);
    // The routing needs the whole river graph: the topology and tags it reads,
    // for every cell and edge, held only while it runs. A regional mesh's is
    // the region's, as its file and its components hold it: the cells
    // outside are no neighbours, an edge with one cell inside has it first
    // (the row's turn: a river crossing there leaves the mesh), an edge with
    // none carries no river.
    MpasMesh graph;
    graph.n_cells = layout_.n_cells(), graph.n_edges = layout_.n_edges(), graph.n_vertices = layout_.n_vertices();
    graph.max_edges = layout_.max_edges();
    const size_t w = static_cast<size_t>(layout_.max_edges());
    graph.n_edges_on_cell.resize(static_cast<size_t>(graph.n_cells));
    graph.cells_on_cell.assign(w * graph.n_cells, kNone);
    auto inside = [&](int32_t c) { return c != kNone && layout_.row_of_cell(c) != kNone; };
    ctx.parallel_for(graph.n_cells, 1024, [&](int64_t b, int64_t e) {
        CellRing ring;
        for (int64_t c = b; c < e; ++c) {
            layout_.cell_ring(static_cast<int32_t>(c), ring);
            graph.n_edges_on_cell[c] = ring.degree();
            for (int j = 0; j < ring.degree(); ++j) graph.cells_on_cell[w * c + j] = inside(ring.cells[j]) ? ring.cells[j] : kNone;
        }
    });
    if (t.sides) cell_sides(0, graph.n_cells, graph, true);
    graph.cells_on_edge.resize(2 * static_cast<size_t>(graph.n_edges));
    graph.edge_feature_kind.resize(static_cast<size_t>(graph.n_edges));
    graph.edge_on_river.assign(t.edge_on_river.begin(), t.edge_on_river.end());
    std::vector<uint8_t> turned(static_cast<size_t>(graph.n_edges), 0);  // the inside cell put first
    ctx.parallel_for(graph.n_edges, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const EdgeEnds ends = layout_.edge_ends(static_cast<int32_t>(i));
            const bool in0 = inside(ends.cell[0]), in1 = inside(ends.cell[1]);
            turned[i] = !in0 && in1;
            graph.cells_on_edge[2 * i] = turned[i] ? ends.cell[1] : ends.cell[0];
            graph.cells_on_edge[2 * i + 1] = in0 && in1 ? ends.cell[1] : in0 || in1 ? kNone : ends.cell[1];
            graph.edge_feature_kind[i] = in0 || in1 ? t.edge_feature(layout_, ends).first : 0;
            if (!in0 && !in1) graph.edge_on_river[i] = 0;
        }
    });
    t.routing = river_routing(graph);
    // (Each edge's flow back to its ends' order: edge_tags turns it with its row.)
    for (size_t i = 0; i < turned.size(); ++i)
        if (turned[i]) t.routing.edge_river_downstream[i] = -t.routing.edge_river_downstream[i];
}

MpasSource::~MpasSource() = default;

MpasMesh MpasSource::shape() const {
    MpasMesh m;
    m.radius_m = radius_m_;
    if (!surface_.is_sphere()) m.ellipsoid_a_m = surface_.a(), m.ellipsoid_f = surface_.f();
    m.n_cells = layout_.cell_rows(), m.n_edges = layout_.edge_rows(), m.n_vertices = layout_.vertex_rows();
    m.max_edges = layout_.row_max_edges();
    return m;
}

MpasMesh MpasSource::probe(Context &ctx) const {
    MpasMesh m = shape();
    // (No row of a kind the mesh has none of: an emptied mesh lists no tags.)
    for (MpasDim kind : {MpasDim::nCells, MpasDim::nEdges, MpasDim::nVertices})
        rows(ctx, kind, 0, std::min<int64_t>(1, mpas_dim_length(m, kind)), m);
    return m;
}

RiverReport MpasSource::river_report() const {
    return tags_ && tags_->features() ? tags_->routing.report : RiverReport{};
}

void MpasSource::cell_lat_lon(int32_t c, double &lat, double &lon) const { lat_lon(layout_.cell_unit(c), lat, lon); }

void for_each_block_of(Context &ctx, const MpasSource &source, MpasMesh probe, const MpasField &variable,
                       const std::function<void(const MpasField &, int64_t, int64_t)> &take) {
    MpasMesh &block = probe;  // every variable listed, for RowParts
    const MpasDim kind = variable.dims[0];
    const int64_t rows = mpas_dim_length(block, kind);
    for (int64_t first = 0; first < rows; first += kMpasBlockRows) {
        const int64_t count = std::min(kMpasBlockRows, rows - first);
        if (variable.kind != MpasKind::id) source.rows(ctx, kind, first, count, block, variable.name);
        for (const MpasField &f : mpas_fields(block))
            if (std::strcmp(f.name, variable.name) == 0) take(f, first, count);
    }
}

void MpasSource::rows(Context &ctx, MpasDim kind, int64_t first, int64_t count, MpasMesh &block,
                      const char *only) const {
    const MpasMesh s = shape();
    block.radius_m = s.radius_m;
    block.n_cells = s.n_cells, block.n_edges = s.n_edges, block.n_vertices = s.n_vertices;
    block.max_edges = s.max_edges;
    const size_t n = static_cast<size_t>(count);
    const RowParts parts = parts_for(block, only);
    if (!only) grow_rows(ctx, kind, count, block);
    switch (kind) {
        case MpasDim::nCells:
            cell_rows(ctx, layout_, radius_m_, first, count, block, parts.areas);
            block.cell_source_vertex.resize(n);
            block.mesh_density.assign(n, 1.0);
            for (size_t i = 0; i < n; ++i) {
                block.cell_source_vertex[i] = layout_.cell_source_vertex(layout_.cell_of_row(first + i));
                if (cell_width_km_.empty()) continue;
                // MPAS-Tools' inject_meshDensity: (min h / h)^4.
                const double r = min_width_km_ / cell_width_km_[block.cell_source_vertex[i]];
                block.mesh_density[i] = (r * r) * (r * r);
            }
            cell_tags(first, count, block);
            boundary_masks(kind, first, count, block);
            return;
        case MpasDim::nEdges:
            edge_rows(ctx, layout_, radius_m_, first, count, block);
            if (parts.stencils)
                trsk_rows(ctx, layout_, radius_m_, first, count, block, parts.weights ? &kites(ctx) : nullptr);
            edge_tags(first, count, block);
            boundary_masks(kind, first, count, block);
            return;
        case MpasDim::nVertices:
            vertex_rows(ctx, layout_, radius_m_, first, count, block, parts.areas ? &kites(ctx) : nullptr);
            block.vertex_source_triangle.resize(n);
            for (size_t i = 0; i < n; ++i)
                block.vertex_source_triangle[i] = layout_.vertex_triangle(layout_.vertex_of_row(first + i));
            vertex_tags(first, count, block);
            boundary_masks(kind, first, count, block);
            return;
        default: fail(UM_ERR_INTERNAL, "MPAS mesh: rows along ", mpas_dim_name(kind), " asked for");
    }
}

const CornerKites &MpasSource::kites(Context &ctx) const {
    std::call_once(kites_made_, [&] { kites_ = std::make_unique<CornerKites>(ctx, layout_, radius_m_); });
    return *kites_;
}

// The ocean mesh takes the cells of RefinedMesh::ocean_cells (the ocean
// cells, the coastal ones mostly on the ocean side and those a passage keeps
// open); the land + river mesh takes every other cell, so the two are exact
// complements. whole: first and count in the whole numbering (the routing's
// graph), else rows.
void MpasSource::cell_sides(int64_t first, int64_t count, MpasMesh &block, bool whole) const {
    const Tags &t = *tags_;
    const size_t n = static_cast<size_t>(count);
    block.cell_side.resize(n), block.cell_ocean_mask.resize(n), block.cell_land_mask.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const int64_t c = first + static_cast<int64_t>(i);
        const int32_t slot = layout_.cell_slot(whole ? static_cast<int32_t>(c) : layout_.cell_of_row(c));
        block.cell_side[i] = static_cast<int32_t>(t.refined->vertex_side[slot]);
        block.cell_ocean_mask[i] = t.ocean[slot] != 0 ? 1 : 0;
        block.cell_land_mask[i] = 1 - block.cell_ocean_mask[i];
    }
}

void MpasSource::cell_tags(int64_t first, int64_t count, MpasMesh &block) const {
    if (!tags_) return;
    const Tags &t = *tags_;
    if (t.sides) cell_sides(first, count, block);
    if (!t.features()) return;
    const size_t n = static_cast<size_t>(count);
    block.cell_downstream.resize(n), block.cell_river_kind.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const int32_t c = layout_.cell_of_row(first + static_cast<int64_t>(i));
        block.cell_downstream[i] = layout_.row_of_cell(t.routing.cell_downstream[c]);  // (kNone: outside)
        block.cell_river_kind[i] = t.routing.cell_river_kind[c];
    }
}

void MpasSource::edge_tags(int64_t first, int64_t count, MpasMesh &block) const {
    if (!tags_ || !tags_->features()) return;
    const Tags &t = *tags_;
    const size_t n = static_cast<size_t>(count);
    block.edge_feature_kind.resize(n), block.edge_feature_id.resize(n);
    block.edge_on_river.resize(n), block.edge_river_downstream.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const int32_t e = layout_.edge_of_row(first + static_cast<int64_t>(i));
        const EdgeEnds ends = layout_.edge_ends(e);
        const auto feature = t.edge_feature(layout_, ends);
        block.edge_feature_kind[i] = feature.first, block.edge_feature_id[i] = feature.second;
        block.edge_on_river[i] = t.edge_on_river[e];
        // (Relative to cellsOnEdge: reversed with a turned row.)
        const int32_t downstream = t.routing.edge_river_downstream[e];
        block.edge_river_downstream[i] = layout_.turned(ends) ? -downstream : downstream;
    }
}

void MpasSource::vertex_tags(int64_t first, int64_t count, MpasMesh &block) const {
    if (!tags_ || !tags_->vertex_sides) return;
    const size_t n = static_cast<size_t>(count);
    block.vertex_side.resize(n);
    for (size_t i = 0; i < n; ++i)
        block.vertex_side[i] = static_cast<int32_t>(
            tags_->refined->triangle_side[layout_.vertex_triangle(layout_.vertex_of_row(first + static_cast<int64_t>(i)))]);
}

// A regional mesh's bdyMask* of the rows (their cellsOnEdge and
// cellsOnVertex made).
void MpasSource::boundary_masks(MpasDim kind, int64_t first, int64_t count, MpasMesh &block) const {
    if (boundary_layer_.empty()) return;
    const size_t n = static_cast<size_t>(count);
    switch (kind) {
        case MpasDim::nCells:
            block.bdy_mask_cell.assign(boundary_layer_.begin() + first, boundary_layer_.begin() + first + count);
            return;
        case MpasDim::nEdges:
            block.bdy_mask_edge.resize(n);
            for (size_t i = 0; i < n; ++i)
                block.bdy_mask_edge[i] = least_boundary_layer(&block.cells_on_edge[2 * i], 2, boundary_layer_);
            return;
        default:
            block.bdy_mask_vertex.resize(n);
            for (size_t i = 0; i < n; ++i)
                block.bdy_mask_vertex[i] =
                    least_boundary_layer(&block.cells_on_vertex[kVertexDegree * i], kVertexDegree, boundary_layer_);
    }
}

}  // namespace um::dual
