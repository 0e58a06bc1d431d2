#include "dual/mpas_mesh.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "dual/river_routing.hpp"
#include "dual/spherical.hpp"
#include "dual/stages.hpp"
#include "mesh/refined_mesh.hpp"
#include "tri/cell_walk.hpp"
#include "tri/spatial_order.hpp"

namespace um::dual {

namespace {

constexpr int64_t kMaxIndex = std::numeric_limits<int32_t>::max();

// The MPAS numbering of the elements and the maps to and from the
// triangulation.
struct Numbering {
    std::vector<int32_t> cell_slot;     // cell -> vertex slot
    std::vector<int32_t> cell_of_slot;  // vertex slot -> cell, kNone if not a vertex
    std::vector<int32_t> vertex_tri;    // MPAS vertex -> triangle slot
    std::vector<int32_t> vertex_of_tri; // triangle slot -> MPAS vertex, kNone if free
    std::vector<int32_t> edge_of_half;  // 3 * triangle slot + k -> edge across edge k
};

int next3(int k) { return k == 2 ? 0 : k + 1; }
int prev3(int k) { return k == 0 ? 2 : k - 1; }

// Worker threads do not throw: a broken link (a bug upstream) is flagged and
// reported by the host thread after the loop.
int local_index(const tri::Triangulation &tri, int32_t t, int32_t v) {
    for (int k = 0; k < 3; ++k)
        if (tri.vertex(t, k) == v) return k;
    return -1;
}

void check_links(const std::atomic<bool> &broken) {
    if (broken.load())
        fail(UM_ERR_INTERNAL, "MPAS mesh: the triangulation's neighbour links are inconsistent");
}

// Positions 0..n-1 sorted along the Hilbert curve of position(i), ties by i:
// each key holds the 31-bit curve index above the 32-bit element index, so
// keys are unique and the order does not depend on the sort or on threads.
template <class PositionFn>
std::vector<int32_t> hilbert_order(Context &ctx, int64_t n, PositionFn position) {
    std::vector<uint64_t> keys(static_cast<size_t>(n));
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i)
            keys[i] = tri::hilbert_key(position(i)) << 32 | static_cast<uint64_t>(i);
    });
    std::sort(keys.begin(), keys.end());
    std::vector<int32_t> order(keys.size());
    for (size_t i = 0; i < keys.size(); ++i) order[i] = static_cast<int32_t>(keys[i] & 0xffffffffu);
    return order;
}

// The vertex numbering given, checked against the triangulation.
std::vector<int32_t> checked_vertex_slots(const tri::Triangulation &tri, const MpasMeshInput &in) {
    std::vector<int32_t> slots = in.slot_of_vertex;
    if (slots.empty()) {
        for (int32_t v = 0; v < tri.vertex_slots(); ++v)
            if (tri.in_triangulation(v)) slots.push_back(v);
        return slots;
    }
    std::vector<uint8_t> seen(static_cast<size_t>(tri.vertex_slots()), 0);
    for (size_t i = 0; i < slots.size(); ++i) {
        int32_t s = slots[i];
        if (s < 0 || s >= tri.vertex_slots() || !tri.in_triangulation(s) || seen[s])
            fail(UM_ERR_INTERNAL, "MPAS mesh: mesh vertex ", i, " has slot ", s,
                 ", which is not a distinct vertex of the triangulation");
        seen[s] = 1;
    }
    if (static_cast<int64_t>(slots.size()) != tri.vertex_count())
        fail(UM_ERR_INTERNAL, "MPAS mesh: the vertex numbering lists ", slots.size(),
             " vertices but the triangulation has ", tri.vertex_count());
    return slots;
}

void check_input(Context &ctx, const tri::Triangulation &tri, const MpasMeshInput &in,
                 const std::vector<int32_t> &slots) {
    const size_t n_vertices = slots.size();
    if (!std::isfinite(in.radius_m) || in.radius_m <= 0)
        fail(UM_ERR_INVALID_ARGUMENT, "MPAS mesh: sphere radius = ", in.radius_m,
             " m; it must be finite and > 0");
    if (!in.cell_width_km.empty()) {
        if (in.cell_width_km.size() != n_vertices)
            fail(UM_ERR_INTERNAL, "MPAS mesh: ", in.cell_width_km.size(),
                 " cell widths for ", n_vertices, " mesh vertices");
        for (size_t i = 0; i < n_vertices; ++i) {
            double h = in.cell_width_km[i];
            if (!std::isfinite(h) || h <= 0) {
                double lon, lat;
                geom::lonlat_deg_from_unit(tri.direction(slots[i]), lon, lat);
                fail(std::isfinite(h) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT,
                     "MPAS mesh: the spacing is ", h, " km at mesh vertex ", i, " (lon ", lon,
                     ", lat ", lat, " degrees); it must be finite and > 0");
            }
        }
    }
    // nEdges = 3 nTriangles / 2 is the largest count; every index is int32.
    if (int64_t(tri.triangle_count()) * 3 / 2 > kMaxIndex)
        fail(UM_ERR_LIMIT, "MPAS mesh: ", tri.triangle_count(),
             " triangles give more edges than int32 indices can address");
    ctx.check_memory(kMpasBytesPerCell * static_cast<int64_t>(n_vertices), "the MPAS mesh");
}

void number_cells(Context &ctx, const tri::Triangulation &tri, const std::vector<int32_t> &slots,
                  Numbering &num, UnitPositions &pos, MpasMesh &m) {
    const int64_t n = static_cast<int64_t>(slots.size());
    m.cell_source_vertex = hilbert_order(ctx, n, [&](int64_t i) { return tri.lifted(slots[i]); });
    num.cell_slot.resize(slots.size());
    num.cell_of_slot.assign(static_cast<size_t>(tri.vertex_slots()), kNone);
    pos.cell.resize(slots.size());
    for (int64_t c = 0; c < n; ++c) {
        int32_t s = slots[m.cell_source_vertex[c]];
        num.cell_slot[c] = s;
        num.cell_of_slot[s] = static_cast<int32_t>(c);
        pos.cell[c] = tri.direction(s);
    }
    m.n_cells = static_cast<int32_t>(n);
}

void number_vertices(Context &ctx, const tri::Triangulation &tri, Numbering &num,
                     UnitPositions &pos, MpasMesh &m) {
    std::vector<int32_t> live;
    live.reserve(static_cast<size_t>(tri.triangle_count()));
    for (int32_t t = 0; t < tri.triangle_slots(); ++t)
        if (!tri.is_free(t)) live.push_back(t);
    const int64_t n = static_cast<int64_t>(live.size());
    std::vector<Vec3> centre(live.size());
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) centre[i] = tri.orthocentre(live[i]);
    });
    std::vector<int32_t> order = hilbert_order(ctx, n, [&](int64_t i) { return centre[i]; });
    num.vertex_tri.resize(live.size());
    num.vertex_of_tri.assign(static_cast<size_t>(tri.triangle_slots()), kNone);
    pos.vertex.resize(live.size());
    for (int64_t v = 0; v < n; ++v) {
        num.vertex_tri[v] = live[order[v]];
        num.vertex_of_tri[live[order[v]]] = static_cast<int32_t>(v);
        pos.vertex[v] = centre[order[v]];
    }
    m.vertex_source_triangle = num.vertex_tri;
    m.n_vertices = static_cast<int32_t>(n);
}

// One edge per pair of neighbouring triangles, from the one of lower slot.
// cellsOnEdge = (c1, c2) with c1 < c2; the triangle on the left of c1 -> c2
// (where k x n_e points) is verticesOnEdge(e, 2).
void number_edges(Context &ctx, const tri::Triangulation &tri, Numbering &num,
                  UnitPositions &pos, MpasMesh &m) {
    std::vector<int64_t> halves;  // 3 * t + k
    halves.reserve(static_cast<size_t>(tri.triangle_count()) * 3 / 2);
    for (int32_t t : num.vertex_tri)
        for (int k = 0; k < 3; ++k)
            if (t < tri.neighbour(t, k)) halves.push_back(3 * int64_t(t) + k);
    std::sort(halves.begin(), halves.end());  // by slot: independent of the vertex order
    const int64_t n = static_cast<int64_t>(halves.size());
    std::vector<Vec3> point(halves.size());
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            int32_t t = static_cast<int32_t>(halves[i] / 3);
            int k = static_cast<int>(halves[i] % 3);
            point[i] = edge_point(tri.lifted(tri.vertex(t, next3(k))),
                                  tri.lifted(tri.vertex(t, prev3(k))));
        }
    });
    std::vector<int32_t> order = hilbert_order(ctx, n, [&](int64_t i) { return point[i]; });

    m.n_edges = static_cast<int32_t>(n);
    pos.edge.resize(halves.size());
    m.cells_on_edge.resize(2 * halves.size());
    m.vertices_on_edge.resize(2 * halves.size());
    num.edge_of_half.assign(3 * static_cast<size_t>(tri.triangle_slots()), kNone);
    std::atomic<bool> broken{false};
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t end) {
        for (int64_t e = b; e < end; ++e) {
            int64_t h = halves[order[e]];
            int32_t t = static_cast<int32_t>(h / 3);
            int k = static_cast<int>(h % 3);
            int32_t u = tri.neighbour(t, k);
            int32_t p = tri.vertex(t, next3(k)), q = tri.vertex(t, prev3(k));
            // In u the edge runs q -> p: it is edge k' with v(u, k' + 2) = p.
            int lp = local_index(tri, u, p);
            int ku = lp < 0 ? 0 : next3(lp);
            if (lp < 0 || tri.neighbour(u, ku) != t) {
                broken = true;
                continue;
            }
            num.edge_of_half[h] = static_cast<int32_t>(e);
            num.edge_of_half[3 * int64_t(u) + ku] = static_cast<int32_t>(e);
            pos.edge[e] = point[order[e]];
            int32_t cp = num.cell_of_slot[p], cq = num.cell_of_slot[q];
            int32_t vt = num.vertex_of_tri[t], vu = num.vertex_of_tri[u];
            // t lies on the left of p -> q (its corners run p, q, r counter-clockwise).
            bool forward = cp < cq;
            m.cells_on_edge[2 * e] = forward ? cp : cq;
            m.cells_on_edge[2 * e + 1] = forward ? cq : cp;
            m.vertices_on_edge[2 * e] = forward ? vu : vt;
            m.vertices_on_edge[2 * e + 1] = forward ? vt : vu;
        }
    });
    check_links(broken);
}

// The triangles around cell slot s, counter-clockwise, each with the edge it
// shares with the next one and the cell across that edge.
struct Ring {
    std::vector<int32_t> tris, across;
    std::vector<int64_t> halves;
};

// Returns false when the links do not lead round s.
bool walk_ring(const tri::Triangulation &tri, int32_t s, int32_t start, Ring &ring) {
    ring.tris.clear(), ring.halves.clear(), ring.across.clear();
    int32_t t = start;
    do {
        int l = local_index(tri, t, s);
        if (l < 0 || ring.tris.size() > static_cast<size_t>(tri.triangle_slots())) return false;
        ring.tris.push_back(t);
        ring.halves.push_back(3 * int64_t(t) + next3(l));
        ring.across.push_back(tri.vertex(t, prev3(l)));
        t = tri.neighbour(t, next3(l));
    } while (t != start);
    return true;
}

// edgesOnCell, verticesOnCell, cellsOnCell counter-clockwise, starting at the
// cell's lowest-numbered MPAS vertex: verticesOnCell(j) = ring triangle j,
// edgesOnCell(j) = the edge between ring triangles j - 1 and j.
void cell_connectivity(Context &ctx, const tri::Triangulation &tri, const Numbering &num,
                       MpasMesh &m) {
    std::vector<int32_t> start(static_cast<size_t>(tri.vertex_slots()), kNone);
    for (int32_t t : num.vertex_tri)
        for (int k = 0; k < 3; ++k)
            if (start[tri.vertex(t, k)] == kNone) start[tri.vertex(t, k)] = t;
    const int64_t n = m.n_cells;
    m.n_edges_on_cell.assign(static_cast<size_t>(n), 0);
    std::atomic<bool> broken{false};
    ctx.parallel_for(n, 1024, [&](int64_t b, int64_t e) {
        Ring ring;
        for (int64_t c = b; c < e; ++c) {
            if (!walk_ring(tri, num.cell_slot[c], start[num.cell_slot[c]], ring)) broken = true;
            m.n_edges_on_cell[c] = static_cast<int32_t>(ring.tris.size());
        }
    });
    check_links(broken);
    m.max_edges = n ? *std::max_element(m.n_edges_on_cell.begin(), m.n_edges_on_cell.end()) : 0;
    const size_t w = static_cast<size_t>(m.max_edges);
    m.edges_on_cell.assign(w * n, kNone);
    m.vertices_on_cell.assign(w * n, kNone);
    m.cells_on_cell.assign(w * n, kNone);
    ctx.parallel_for(n, 1024, [&](int64_t b, int64_t e) {
        Ring ring;
        for (int64_t c = b; c < e; ++c) {
            if (!walk_ring(tri, num.cell_slot[c], start[num.cell_slot[c]], ring)) continue;
            const int d = static_cast<int>(ring.tris.size());
            int first = 0;
            for (int j = 1; j < d; ++j)
                if (num.vertex_of_tri[ring.tris[j]] < num.vertex_of_tri[ring.tris[first]]) first = j;
            for (int j = 0; j < d; ++j) {
                int here = (first + j) % d, before = (first + j + d - 1) % d;
                m.vertices_on_cell[w * c + j] = num.vertex_of_tri[ring.tris[here]];
                m.edges_on_cell[w * c + j] = num.edge_of_half[ring.halves[before]];
                m.cells_on_cell[w * c + j] = num.cell_of_slot[ring.across[before]];
            }
        }
    });
}

// cellsOnVertex = the triangle's corners counter-clockwise from the lowest
// cell; edgesOnVertex(j) = the edge between cellsOnVertex(j - 1) and (j),
// which is the triangle edge opposite the third corner.
void vertex_connectivity(Context &ctx, const tri::Triangulation &tri, const Numbering &num,
                         MpasMesh &m) {
    const int64_t n = m.n_vertices;
    m.cells_on_vertex.resize(3 * static_cast<size_t>(n));
    m.edges_on_vertex.resize(3 * static_cast<size_t>(n));
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            int32_t t = num.vertex_tri[v];
            int32_t cell[3];
            for (int k = 0; k < 3; ++k) cell[k] = num.cell_of_slot[tri.vertex(t, k)];
            int r = static_cast<int>(std::min_element(cell, cell + 3) - cell);
            for (int j = 0; j < 3; ++j) {
                m.cells_on_vertex[3 * v + j] = cell[(r + j) % 3];
                m.edges_on_vertex[3 * v + j] = num.edge_of_half[3 * int64_t(t) + (r + j + 1) % 3];
            }
        }
    });
}

// MPAS-Tools' inject_meshDensity: (min h / h)^4.
void fill_mesh_density(const MpasMeshInput &in, MpasMesh &m) {
    m.mesh_density.assign(static_cast<size_t>(m.n_cells), 1.0);
    if (in.cell_width_km.empty()) return;
    double h_min = *std::min_element(in.cell_width_km.begin(), in.cell_width_km.end());
    for (int32_t c = 0; c < m.n_cells; ++c) {
        double r = h_min / in.cell_width_km[m.cell_source_vertex[c]];
        m.mesh_density[c] = (r * r) * (r * r);
    }
}

}  // namespace

MpasMesh build_mpas_mesh(Context &ctx, const tri::Triangulation &tri, const MpasMeshInput &input) {
    std::vector<int32_t> slots = checked_vertex_slots(tri, input);
    check_input(ctx, tri, input, slots);
    MpasMesh m;
    m.radius_m = input.radius_m;
    Numbering num;
    UnitPositions pos;
    number_cells(ctx, tri, slots, num, pos, m);
    number_vertices(ctx, tri, num, pos, m);
    number_edges(ctx, tri, num, pos, m);
    cell_connectivity(ctx, tri, num, m);
    vertex_connectivity(ctx, tri, num, m);
    num = Numbering();
    cross_edge_points(ctx, pos, m);
    fill_geometry(ctx, pos, m);
    pos = UnitPositions();
    fill_trsk_weights(ctx, m);
    fill_mesh_density(input, m);
    m.boundary_vertex.assign(static_cast<size_t>(m.n_vertices), 0);
    return m;
}

namespace {

// The ocean mesh takes the cells of RefinedMesh::ocean_cells (the ocean
// cells, the coastal ones mostly on the ocean side and those a passage keeps
// open); the land + river mesh takes every other cell, so the two are exact
// complements.
void add_cell_masks(const mesh::RefinedMesh &refined, MpasMesh &m) {
    const std::vector<uint8_t> ocean = refined.ocean_cells();
    m.cell_ocean_mask.assign(static_cast<size_t>(m.n_cells), 0);
    m.cell_land_mask.assign(static_cast<size_t>(m.n_cells), 0);
    for (int32_t c = 0; c < m.n_cells; ++c) {
        const bool in_ocean = ocean[refined.slot_of_vertex[m.cell_source_vertex[c]]] != 0;
        m.cell_ocean_mask[c] = in_ocean ? 1 : 0;
        m.cell_land_mask[c] = in_ocean ? 0 : 1;
    }
}

// Per MPAS edge, the feature of the restricted edge it is (if any).
void add_edge_features(const mesh::RefinedMesh &refined, MpasMesh &m) {
    m.edge_feature_kind.assign(static_cast<size_t>(m.n_edges), 0);
    m.edge_feature_id.assign(static_cast<size_t>(m.n_edges), -1);
    // Restricted edges by their two vertex slots, sorted for lookup.
    struct Key {
        uint64_t slots;
        int32_t restricted;
        bool operator<(const Key &o) const { return slots < o.slots; }
    };
    auto key = [](int32_t a, int32_t b) {
        return uint64_t(uint32_t(std::min(a, b))) << 32 | uint32_t(std::max(a, b));
    };
    const tri::Triangulation &tri = refined.tri;
    std::vector<Key> keys;
    keys.reserve(refined.restricted.size());
    for (size_t r = 0; r < refined.restricted.size(); ++r) {
        const auto &e = refined.restricted[r];
        keys.push_back({key(tri.vertex(e.triangle, (e.edge + 1) % 3), tri.vertex(e.triangle, (e.edge + 2) % 3)),
                        static_cast<int32_t>(r)});
    }
    std::sort(keys.begin(), keys.end());
    const features::Network &gamma = *refined.gamma;
    for (int32_t e = 0; e < m.n_edges; ++e) {
        const int32_t c1 = m.cells_on_edge[2 * size_t(e)], c2 = m.cells_on_edge[2 * size_t(e) + 1];
        const int32_t s1 = refined.slot_of_vertex[m.cell_source_vertex[c1]];
        const int32_t s2 = refined.slot_of_vertex[m.cell_source_vertex[c2]];
        const Key probe{key(s1, s2), 0};
        auto it = std::lower_bound(keys.begin(), keys.end(), probe);
        if (it == keys.end() || it->slots != probe.slots) continue;
        const int64_t segment = refined.restricted[it->restricted].arc;
        const features::Part &part = gamma.part(gamma.segment_part(segment));
        m.edge_feature_kind[e] = static_cast<int32_t>(part.kind);
        m.edge_feature_id[e] = part.id;
    }
}

// Per MPAS edge, 1 where a river's line passes from one of its cells into
// the other: the cells along each river segment, in order, each sharing an
// edge with the one before (tri::cells_along_arc). This is the river
// network as the input draws it, also where the mesh keeps no restricted
// edge of the river (a face crossed by two features keeps one, and a river
// finer than the cells is not followed).
void add_river_crossings(Context &ctx, const mesh::RefinedMesh &refined, MpasMesh &m) {
    const tri::Triangulation &tri = refined.tri;
    const features::Network &gamma = *refined.gamma;
    std::vector<int32_t> cell_of_slot(static_cast<size_t>(tri.vertex_slots()), kNone);
    for (int32_t c = 0; c < m.n_cells; ++c) cell_of_slot[refined.slot_of_vertex[m.cell_source_vertex[c]]] = c;
    std::vector<int64_t> river_parts;
    for (int64_t p = 0; p < gamma.part_count(); ++p)
        if (gamma.part(p).kind == features::Kind::river) river_parts.push_back(p);
    m.edge_on_river.assign(static_cast<size_t>(m.n_edges), 0);
    if (river_parts.empty()) return;
    const size_t w = static_cast<size_t>(m.max_edges);
    // Each flag is only ever set to 1, so the parts may run in any order.
    // A walk starts where the part's previous segment ended (its first from
    // a fixed vertex): on a tie between two cells the answer depends on the
    // start, which therefore must not depend on how the parts are shared out.
    std::vector<std::atomic<uint8_t>> on_river(static_cast<size_t>(m.n_edges));
    ctx.parallel_for(static_cast<int64_t>(river_parts.size()), 4, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const features::Part &part = gamma.part(river_parts[i]);
            int32_t hint = -1;
            for (int64_t s = part.first_segment; s < part.first_segment + part.n_segments; ++s) {
                const std::vector<int32_t> slots =
                    tri::cells_along_arc(tri, gamma.segment_a(s), gamma.segment_b(s), hint);
                if (!slots.empty()) hint = slots.back();
                for (size_t k = 1; k < slots.size(); ++k) {
                    const int32_t p = cell_of_slot[slots[k - 1]], q = cell_of_slot[slots[k]];
                    if (p == kNone || q == kNone) continue;
                    for (int32_t j = 0; j < m.n_edges_on_cell[p]; ++j)
                        if (m.cells_on_cell[w * p + j] == q)
                            on_river[m.edges_on_cell[w * p + j]].store(1, std::memory_order_relaxed);
                }
            }
        }
    });
    for (size_t e = 0; e < on_river.size(); ++e) m.edge_on_river[e] = on_river[e].load(std::memory_order_relaxed);
}

}  // namespace

MpasMesh build_mpas_mesh(Context &ctx, const mesh::RefinedMesh &refined) {
    MpasMeshInput input;
    input.slot_of_vertex = refined.slot_of_vertex;
    input.radius_m = refined.radius_m;
    if (refined.spacing) {
        // The spacing the mesh was refined to, at the generators, for meshDensity
        // (check_input refuses values that are not finite and > 0).
        input.cell_width_km.resize(input.slot_of_vertex.size());
        ctx.parallel_for(refined.vertex_count(), 1024, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i)
                input.cell_width_km[i] = refined.spacing->km_at(refined.tri.direction(input.slot_of_vertex[i]));
        });
    }
    MpasMesh m = build_mpas_mesh(ctx, refined.tri, input);
    if (!refined.vertex_side.empty()) {
        m.cell_side.resize(static_cast<size_t>(m.n_cells));
        for (int32_t c = 0; c < m.n_cells; ++c)
            m.cell_side[c] = static_cast<int32_t>(
                refined.vertex_side[refined.slot_of_vertex[m.cell_source_vertex[c]]]);
    }
    if (!refined.triangle_side.empty()) {
        m.vertex_side.resize(static_cast<size_t>(m.n_vertices));
        for (int32_t v = 0; v < m.n_vertices; ++v)
            m.vertex_side[v] = static_cast<int32_t>(refined.triangle_side[m.vertex_source_triangle[v]]);
    }
    if (!m.cell_side.empty()) add_cell_masks(refined, m);
    if (refined.gamma) {
        add_edge_features(refined, m);
        add_river_crossings(ctx, refined, m);
        route_rivers(m);
    }
    return m;
}

}  // namespace um::dual
