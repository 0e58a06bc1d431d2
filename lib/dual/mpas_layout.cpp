#include "dual/mpas_layout.hpp"

#include <algorithm>
#include <atomic>
#include <limits>

#include "core/buffer.hpp"
#include "core/error.hpp"
#include "core/radix_sort.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/spherical.hpp"
#include "tri/spatial_order.hpp"

namespace um::dual {

namespace {

constexpr int64_t kMaxIndex = std::numeric_limits<int32_t>::max();

int next3(int k) { return k == 2 ? 0 : k + 1; }
int prev3(int k) { return k == 0 ? 2 : k - 1; }

int local_index(const tri::Triangulation &tri, int32_t t, int32_t v) {
    for (int k = 0; k < 3; ++k)
        if (tri.vertex(t, k) == v) return k;
    return -1;
}

// Worker threads do not throw: a broken link (a bug upstream) is flagged and
// reported by the host thread after the loop.
void check_links(const std::atomic<bool> &broken) {
    if (broken.load())
        fail(UM_ERR_INTERNAL, "MPAS mesh: the triangulation's neighbour links are inconsistent");
}

// Positions 0..n-1 sorted along the Hilbert curve of position(i), ties by i:
// each key holds the 31-bit curve index above the 32-bit element index, so
// keys are unique and the order does not depend on the sort or on threads.
template <class PositionFn>
HugePageVector<int32_t> hilbert_order(Context &ctx, int64_t n, PositionFn position) {
    Buffer<uint64_t> keys(static_cast<size_t>(n));
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i)
            keys[i] = tri::hilbert_key(position(i)) << 32 | static_cast<uint64_t>(i);
    });
    radix_sort(ctx, keys, 32, 64);  // stable: ties stay in index order
    HugePageVector<int32_t> order;
    size_on_huge_pages(order, keys.size());
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) order[i] = static_cast<int32_t>(keys[i] & 0xffffffffu);
    });
    return order;
}

// v sized to n values, every one `value`, written in parallel.
template <class T>
void fill_in_parallel(Context &ctx, HugePageVector<T> &v, size_t n, T value) {
    size_on_huge_pages(v, n);
    ctx.parallel_for(static_cast<int64_t>(n), 1 << 16, [&](int64_t b, int64_t e) {
        std::fill(v.begin() + b, v.begin() + e, value);
    });
}

// The vertex numbering given, checked against the triangulation.
std::vector<int32_t> checked_vertex_slots(const tri::Triangulation &tri, std::vector<int32_t> slots) {
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

// The triangles around slot s counter-clockwise from `start`, each with the
// half-edge it shares with the next one and the vertex across that edge.
// Returns false when the links do not lead round s.
struct Walk {
    std::vector<int32_t> tris, across;
    std::vector<int64_t> halves;
};

bool walk_ring(const tri::Triangulation &tri, int32_t s, Walk &walk) {
    walk.tris.clear(), walk.halves.clear(), walk.across.clear();
    const int32_t start = tri.incident_triangle(s);
    if (start < 0) return false;
    int32_t t = start;
    do {
        int l = local_index(tri, t, s);
        if (l < 0 || walk.tris.size() > static_cast<size_t>(tri.triangle_slots())) return false;
        walk.tris.push_back(t);
        walk.halves.push_back(3 * int64_t(t) + next3(l));
        walk.across.push_back(tri.vertex(t, prev3(l)));
        t = tri.neighbour(t, next3(l));
    } while (t != start);
    return true;
}

// The largest ring of the cells at slot_of(0..n-1); `broken` set where the
// links do not lead round one.
template <class SlotOf>
int32_t widest_ring(Context &ctx, const tri::Triangulation &tri, int64_t n, SlotOf slot_of, std::atomic<bool> &broken) {
    std::atomic<int32_t> widest{0};
    ctx.parallel_for(n, 1024, [&](int64_t b, int64_t e) {
        Walk walk;
        int32_t local = 0;
        for (int64_t i = b; i < e; ++i) {
            if (!walk_ring(tri, slot_of(i), walk)) broken = true;
            local = std::max(local, static_cast<int32_t>(walk.tris.size()));
        }
        int32_t seen = widest.load();
        while (local > seen && !widest.compare_exchange_weak(seen, local)) {
        }
    });
    return widest.load();
}

// A copy of tri with each point at the geodetic lon/lat of its surface
// point on the unit sphere, keeping its weight, made regular again: the move
// (up to 0.2 degrees for WGS84, smooth, within 2f of conformal) keeps every
// edge of a well-centred mesh regular, and the flips mend the few it does
// not (nearly cocircular quads, as an unoptimised mesh has), so that the
// copy is the power diagram of the moved points. (The tags are the
// original's: a flipped edge's triangles keep their sides, but a flipped
// restricted edge loses its edgeFeatureKind and a river crossing it is not
// found; only unoptimised meshes have flips in practice.)
std::unique_ptr<tri::Triangulation> points_on_sphere(Context &ctx, const tri::Triangulation &tri,
                                                     const geom::Surface &surface) {
    auto copy = std::make_unique<tri::Triangulation>(tri);
    ctx.parallel_for(tri.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int32_t v = static_cast<int32_t>(b); v < e; ++v)
            if (tri.in_triangulation(v))
                copy->set_lifted(v, geom::norm(tri.lifted(v)) * surface.sphere_unit(tri.direction(v)));
    });
    copy->restore_regularity(tri.live_triangles(ctx));
    for (int32_t v = 0; v < tri.vertex_slots(); ++v)
        if (tri.in_triangulation(v) && !copy->in_triangulation(v))
            fail(UM_ERR_DEGENERATE_INPUT, "MPAS mesh: vertex slot ", v,
                 " has no power cell once at its geodetic lon/lat on the sphere (optimise the mesh first)");
    return copy;
}

}  // namespace

MpasLayout::MpasLayout(Context &ctx, const tri::Triangulation &tri, std::vector<int32_t> slot_of_vertex,
                       const geom::Surface &surface, const std::vector<uint8_t> &region)
    : tri_(&tri) {
    if (!surface.is_sphere()) tri_ = (on_sphere_ = points_on_sphere(ctx, tri, surface)).get();
    // nEdges = 3 nTriangles / 2 is the largest count; every index is int32.
    if (int64_t(tri.triangle_count()) * 3 / 2 > kMaxIndex)
        fail(UM_ERR_LIMIT, "MPAS mesh: ", tri.triangle_count(),
             " triangles give more edges than int32 indices can address");
    number_cells(ctx, checked_vertex_slots(tri, std::move(slot_of_vertex)));
    number_vertices(ctx);
    number_edges(ctx);
    check_rings(ctx);
    if (!region.empty()) number_rows(ctx, region);
}

void MpasLayout::number_cells(Context &ctx, const std::vector<int32_t> &slots) {
    const int64_t n = static_cast<int64_t>(slots.size());
    cell_vertex_ = hilbert_order(ctx, n, [&](int64_t i) { return tri_->lifted(slots[i]); });
    size_on_huge_pages(cell_slot_, slots.size());
    fill_in_parallel(ctx, cell_of_slot_, static_cast<size_t>(tri_->vertex_slots()), kNone);
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t c = b; c < e; ++c) {
            const int32_t s = slots[cell_vertex_[c]];
            cell_slot_[c] = s;
            cell_of_slot_[s] = static_cast<int32_t>(c);
        }
    });
}

void MpasLayout::number_vertices(Context &ctx) {
    const std::vector<int32_t> live = tri_->live_triangles(ctx);
    const int64_t n = static_cast<int64_t>(live.size());
    const HugePageVector<int32_t> order =
        hilbert_order(ctx, n, [&](int64_t i) { return tri_->orthocentre(live[i]); });
    size_on_huge_pages(vertex_tri_, live.size());
    size_on_huge_pages(vertex_unit_, live.size());
    fill_in_parallel(ctx, vertex_of_tri_, static_cast<size_t>(tri_->triangle_slots()), kNone);
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            vertex_tri_[v] = live[order[v]];
            vertex_of_tri_[live[order[v]]] = static_cast<int32_t>(v);
            vertex_unit_[v] = tri_->orthocentre(vertex_tri_[v]);
        }
    });
}

// One edge per pair of neighbouring triangles, from the one of lower slot,
// numbered along the Hilbert curve of its edge point.
void MpasLayout::number_edges(Context &ctx) {
    const tri::Triangulation &tri = *tri_;
    // 3 * t + k, by slot: independent of the vertex order.
    const std::vector<int64_t> halves =
        ctx.collect_in_order<int64_t>(tri.triangle_slots(), 1 << 16, [&](int64_t t, std::vector<int64_t> &out) {
            const int32_t slot = static_cast<int32_t>(t);
            if (tri.is_free(slot)) return;
            for (int k = 0; k < 3; ++k)
                if (slot < tri.neighbour(slot, k)) out.push_back(3 * t + k);
        });
    const int64_t n = static_cast<int64_t>(halves.size());
    const HugePageVector<int32_t> order = hilbert_order(ctx, n, [&](int64_t i) {
        const int32_t t = static_cast<int32_t>(halves[i] / 3);
        const int k = static_cast<int>(halves[i] % 3);
        return edge_point(tri.lifted(tri.vertex(t, next3(k))), tri.lifted(tri.vertex(t, prev3(k))));
    });
    size_on_huge_pages(edge_half_, halves.size());
    fill_in_parallel(ctx, edge_of_half_, 3 * static_cast<size_t>(tri.triangle_slots()), kNone);
    std::atomic<bool> broken{false};
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t end) {
        for (int64_t e = b; e < end; ++e) {
            const int64_t h = halves[order[e]];
            const int32_t t = static_cast<int32_t>(h / 3);
            const int k = static_cast<int>(h % 3);
            const int32_t u = tri.neighbour(t, k), p = tri.vertex(t, next3(k));
            // In u the edge runs q -> p: it is edge k' with v(u, k' + 2) = p.
            const int lp = local_index(tri, u, p);
            const int ku = lp < 0 ? 0 : next3(lp);
            if (lp < 0 || tri.neighbour(u, ku) != t) {
                broken = true;
                continue;
            }
            edge_half_[e] = h;
            edge_of_half_[h] = static_cast<int32_t>(e);
            edge_of_half_[3 * int64_t(u) + ku] = static_cast<int32_t>(e);
        }
    });
    check_links(broken);
}

// Walks every cell's ring once: the links must lead round each cell, and
// maxEdges is the largest ring.
void MpasLayout::check_rings(Context &ctx) {
    std::atomic<bool> broken{false};
    max_edges_ = widest_ring(ctx, *tri_, n_cells(), [&](int64_t c) { return cell_slot_[c]; }, broken);
    check_links(broken);
}

// A regional mesh's rows: of each kind, the elements whole[] of the whole
// numbering that are the region's cells or touch one, in that numbering's
// order (found in parallel in fixed chunks: the same for any thread count).
void MpasLayout::number_rows(Context &ctx, const std::vector<uint8_t> &region) {
    if (region.size() != static_cast<size_t>(tri_->vertex_slots()))
        fail(UM_ERR_INTERNAL, "MPAS mesh: ", region.size(), " region flags for ", tri_->vertex_slots(), " vertex slots");
    auto in_region = [&](int32_t slot) { return region[slot] != 0; };
    auto rows_where = [&](Rows &rows, int64_t n, auto kept) {
        std::vector<int32_t> whole = ctx.collect_in_order<int32_t>(n, 1 << 14, [&](int64_t i, std::vector<int32_t> &out) {
            if (kept(static_cast<int32_t>(i))) out.push_back(static_cast<int32_t>(i));
        });
        size_on_huge_pages(rows.whole, whole.size());
        std::copy(whole.begin(), whole.end(), rows.whole.begin());
        fill_in_parallel(ctx, rows.row, static_cast<size_t>(n), kNone);
        ctx.parallel_for(rows.count(), 4096, [&](int64_t b, int64_t e) {
            for (int64_t r = b; r < e; ++r) rows.row[rows.whole[r]] = static_cast<int32_t>(r);
        });
    };
    rows_where(cells_, n_cells(), [&](int32_t c) { return in_region(cell_slot_[c]); });
    if (cells_.count() == 0) fail(UM_ERR_INTERNAL, "MPAS mesh: the region has no cell");
    rows_where(vertices_, n_vertices(), [&](int32_t v) {
        const int32_t t = vertex_tri_[v];
        return in_region(tri_->vertex(t, 0)) || in_region(tri_->vertex(t, 1)) || in_region(tri_->vertex(t, 2));
    });
    rows_where(edges_, n_edges(), [&](int32_t e) {
        const int32_t t = static_cast<int32_t>(edge_half_[e] / 3);
        const int k = static_cast<int>(edge_half_[e] % 3);
        return in_region(tri_->vertex(t, next3(k))) || in_region(tri_->vertex(t, prev3(k)));
    });
    regional_ = true;
    std::atomic<bool> broken{false};  // (checked by check_rings)
    row_max_edges_ = widest_ring(ctx, *tri_, cells_.count(), [&](int64_t r) { return cell_slot_[cells_.whole[r]]; }, broken);
}

EdgeEnds MpasLayout::edge_ends(int32_t e) const {
    const tri::Triangulation &tri = *tri_;
    const int64_t h = edge_half_[e];
    const int32_t t = static_cast<int32_t>(h / 3);
    const int k = static_cast<int>(h % 3);
    const int32_t u = tri.neighbour(t, k);
    const int32_t cp = cell_of_slot_[tri.vertex(t, next3(k))], cq = cell_of_slot_[tri.vertex(t, prev3(k))];
    const int32_t vt = vertex_of_tri_[t], vu = vertex_of_tri_[u];
    // t lies on the left of p -> q (its corners run p, q, r counter-clockwise),
    // so with the normal from p to q the tangent k x n runs from u to t.
    const bool forward = cp < cq;
    EdgeEnds ends;
    ends.cell[0] = forward ? cp : cq, ends.cell[1] = forward ? cq : cp;
    ends.vertex[0] = forward ? vu : vt, ends.vertex[1] = forward ? vt : vu;
    ends.lower = t, ends.k = k;
    return ends;
}

// verticesOnCell(j) = ring triangle j, edgesOnCell(j) = the edge between
// ring triangles j - 1 and j, cellsOnCell(j) across it.
void MpasLayout::cell_ring(int32_t c, CellRing &ring) const {
    thread_local Walk walk;
    walk_ring(*tri_, cell_slot_[c], walk);  // checked by check_rings
    const int d = static_cast<int>(walk.tris.size());
    int first = 0;
    for (int j = 1; j < d; ++j)
        if (vertex_of_tri_[walk.tris[j]] < vertex_of_tri_[walk.tris[first]]) first = j;
    ring.vertices.resize(d), ring.edges.resize(d), ring.cells.resize(d);
    for (int j = 0; j < d; ++j) {
        const int here = (first + j) % d, before = (first + j + d - 1) % d;
        ring.vertices[j] = vertex_of_tri_[walk.tris[here]];
        ring.edges[j] = edge_of_half_[walk.halves[before]];
        ring.cells[j] = cell_of_slot_[walk.across[before]];
    }
}

// cellsOnVertex = the triangle's corners counter-clockwise from the lowest
// cell; edgesOnVertex(j) = the edge between cellsOnVertex(j - 1) and (j),
// which is the triangle edge opposite the third corner.
void MpasLayout::vertex_corners(int32_t v, int32_t cells[3], int32_t edges[3]) const {
    const int32_t t = vertex_tri_[v];
    int32_t cell[3];
    const int r = triangle_cells(t, cell);
    for (int j = 0; j < 3; ++j) {
        cells[j] = cell[(r + j) % 3];
        edges[j] = edge_of_half_[3 * int64_t(t) + (r + j + 1) % 3];
    }
}

int MpasLayout::corner_of(int32_t v, int32_t c) const {
    int32_t cell[3];
    const int r = triangle_cells(vertex_tri_[v], cell);
    for (int k = 0; k < 3; ++k)
        if (cell[k] == c) return (k - r + 3) % 3;
    return -1;
}

int MpasLayout::triangle_cells(int32_t t, int32_t cell[3]) const {
    for (int k = 0; k < 3; ++k) cell[k] = cell_of_slot_[tri_->vertex(t, k)];
    return static_cast<int>(std::min_element(cell, cell + 3) - cell);
}

Vec3 MpasLayout::edge_unit(const EdgeEnds &ends, Vec3 c1, Vec3 c2, Vec3 v1, Vec3 v2) const {
    const tri::Triangulation &tri = *tri_;
    return arc_crossing(c1, c2, v1, v2, [&] {
        return edge_point(tri.lifted(tri.vertex(ends.lower, next3(ends.k))),
                          tri.lifted(tri.vertex(ends.lower, prev3(ends.k))));
    });
}

Vec3 MpasLayout::edge_unit(int32_t e) const {
    const EdgeEnds ends = edge_ends(e);
    return edge_unit(ends, cell_unit(ends.cell[0]), cell_unit(ends.cell[1]), vertex_unit(ends.vertex[0]),
                     vertex_unit(ends.vertex[1]));
}

}  // namespace um::dual
