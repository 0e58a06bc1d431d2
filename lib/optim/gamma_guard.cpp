// The Gamma guard (MeshState, mesh_state.hpp): which vertices are near
// Gamma, how many dual arcs of a star cross it, and which edges follow it.
#include <algorithm>

#include "geom/arc_tree.hpp"
#include "optim/mesh_state.hpp"
#include "optim/slide.hpp"
#include "refine/boundary.hpp"
#include "refine/restricted.hpp"

namespace um::optim::detail {

// Vertices this many h from Gamma get the crossing test of their updates
// (flag_near_gamma): a cell reaches about h from its generator, and a vertex
// moves less than h in an outer iteration.
constexpr double kNearGamma = 2.5;

// (Without Gamma the flags stay empty: no update is guarded.) A flag is
// kept for a vertex that is the same one (its id; a slot added since holds
// none), at the same place (not changed since the last call) with the same
// spacing: a late outer iteration moves a few hundred vertices, and a tree
// search for every vertex of the mesh at every iteration was 3 % of the
// coastlines' optimisation at 30 km.
void MeshState::flag_near_gamma() {
    if (arcs.size() == 0) return;
    const size_t n = static_cast<size_t>(tri.vertex_slots());
    near_gamma.resize(n, 0), flagged_for.resize(n);
    ctx.parallel_for(tri.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t v = static_cast<int32_t>(i);
            Flagged &was = flagged_for[v];
            if (!tri.in_triangulation(v)) {
                near_gamma[v] = 0, was = Flagged{};
                continue;
            }
            if (changed_at[v] < flagged_clock && was.id == tri.id(v) && was.h == h_at[v]) continue;
            geom::Box box;
            box.add(tri.direction(v));
            box.grow(kNearGamma * static_cast<double>(h_at[v]));
            near_gamma[v] = arcs.any_overlaps(box);
            was = {tri.id(v), h_at[v]};
        }
    });
    flagged_clock = clock;
}

bool MeshState::crosses_gamma(const Vec3 &c0, const Vec3 &c1) const {
    return arcs.query_crossing_until(c0, c1, [&](int32_t i) {
        Vec3 x;
        return geom::arc_intersection(c0, c1, arcs.arc(i).a, arcs.arc(i).b, x);
    });
}

// One tree query for the whole star (the box of the spokes' dual arcs),
// then each dual arc against the arcs it found: the per-spoke queries were
// 7 % of the Mid-Atlantic case's time. Counts what crosses_gamma per spoke
// would (the same arcs pass the same box test).
int MeshState::gamma_crossings(int32_t v, const Ring &ring, const int32_t *link, const Generator &at) const {
    const Vec3 q = at.lifted();
    const bool v_on_gamma = on_segment[v] >= 0;
    // The orthocentre of triangle k, (v, link k, link k+1): its facet's outward normal.
    Vec3 ortho[Ring::kMax];
    for (int k = 0; k < ring.m; ++k)
        ortho[k] = geom::normalized(geom::cross(ring.q[k] - q, ring.q[k + 1 == ring.m ? 0 : k + 1] - q));
    // Spoke (v, link k) is the dual arc between triangles k - 1 and k.
    geom::Box spoke_box[Ring::kMax], star_box;
    bool counted[Ring::kMax];
    for (int k = 0; k < ring.m; ++k) {
        counted[k] = !(v_on_gamma && on_segment[link[k]] >= 0);
        if (!counted[k]) continue;
        spoke_box[k] = geom::arc_box(ortho[k == 0 ? ring.m - 1 : k - 1], ortho[k]);
        star_box.add(spoke_box[k]);
    }
    constexpr int kMaxNear = 64;
    int32_t near[kMaxNear];
    geom::Box near_box[kMaxNear];
    int n_near = 0;
    const bool overflow = arcs.query_until(star_box, [&](int32_t i) {
        if (n_near == kMaxNear) return true;
        near_box[n_near] = geom::arc_box(arcs.arc(i).a, arcs.arc(i).b);
        near[n_near++] = i;
        return false;
    });
    int count = 0;
    for (int k = 0; k < ring.m; ++k) {
        if (!counted[k]) continue;
        const Vec3 &c0 = ortho[k == 0 ? ring.m - 1 : k - 1], &c1 = ortho[k];
        if (overflow) {  // Gamma is dense here: a query per spoke
            count += crosses_gamma(c0, c1);
            continue;
        }
        for (int j = 0; j < n_near; ++j) {
            Vec3 x;
            if (near_box[j].overlaps(spoke_box[k]) &&
                geom::arc_intersection(c0, c1, arcs.arc(near[j]).a, arcs.arc(near[j]).b, x)) {
                ++count;
                break;
            }
        }
    }
    return count;
}

// Whether the edge (b, c), between the apexes a and d, follows Gamma: both
// ends on one part of it, that part passing within a quarter of the edge's
// length of its midpoint, and neither apex on the part between them (a
// chord across a bend or an inlet does not follow it).
bool MeshState::runs_along_gamma(int32_t b, int32_t c, int32_t a, int32_t d) const {
    if (!gamma) return false;
    const int32_t sb = on_segment[b], sc = on_segment[c];
    if (sb < 0 || sc < 0) return false;
    const int64_t part = gamma->segment_part(sb);
    if (gamma->segment_part(sc) != part) return false;
    const Vec3 xb = tri.direction(b), xc = tri.direction(c);
    const Vec3 mid = geom::normalized(xb + xc);
    if (geom::norm(slide_along(*gamma, sb, mid).x - mid) >= 0.25 * geom::norm(xb - xc)) return false;
    // Between b and c along the part: on a closed one, the shorter way round.
    const double pb = position_along_part(b), pc = position_along_part(c);
    const double lo = std::min(pb, pc), hi = std::max(pb, pc);
    const features::Part &p = gamma->part(part);
    const bool wraps = p.closed && hi - lo > 0.5 * double(p.n_segments);
    for (int32_t apex : {a, d}) {
        if (apex < 0 || on_segment[apex] < 0 || gamma->segment_part(on_segment[apex]) != part) continue;
        const double pa = position_along_part(apex);
        if (wraps ? (pa < lo || pa > hi) : (pa > lo && pa < hi)) return false;
    }
    return true;
}

// Where vertex v (on Gamma) lies along its part: the index of its segment
// within the part plus the fraction of that segment's chord up to v.
double MeshState::position_along_part(int32_t v) const {
    const int32_t s = on_segment[v];
    const features::Part &p = gamma->part(gamma->segment_part(s));
    const Vec3 a = gamma->segment_a(s), b = gamma->segment_b(s), x = tri.direction(v);
    const double length = geom::norm(b - a);
    const double along = length > 0 ? std::min(1.0, geom::norm(x - a) / length) : 0.0;
    return double(s - p.first_segment) + along;
}

// The boundary refinement's own measure (paper section 5.1), h at the
// restricted edge's midpoint.
bool MeshState::chord_carries_gamma(int32_t a, int32_t c, double alpha, double beta) const {
    bool carries = false;
    tri.for_each_in_star(a, [&](int32_t s) {
        const int i = tri.local_index(s, a);
        if (tri.vertex(s, (i + 1) % 3) != c) return;
        const int k = (i + 2) % 3;  // the edge opposite the apex: (a, c)
        const int32_t apex = tri.vertex(s, k), across = tri.vertex(tri.neighbour(s, k), tri.mirror_edge(s, k));
        refine::RestrictedEdge e;
        if (!runs_along_gamma(a, c, apex, across) || !refine::restricted_crossing(tri, s, k, arcs, &e)) return;
        if (gamma->segment_part(e.arc) != gamma->segment_part(on_segment[a])) return;
        const refine::EdgeMeasure m = refine::measure(tri, e, h);  // the boundary refinement's own measure
        carries = m.length < alpha * m.h && m.eps < beta * m.h;
    });
    return carries;
}

std::vector<std::pair<int32_t, int32_t>> MeshState::gamma_edges_among(const std::vector<int32_t> &vertices) const {
    std::vector<std::pair<int32_t, int32_t>> edges;
    for (int32_t v : vertices) {
        if (on_segment[v] < 0) continue;
        tri.for_each_in_star(v, [&](int32_t s) {
            const int i = tri.local_index(s, v);
            const int32_t c = tri.vertex(s, (i + 1) % 3);  // the edge (v, c) once, from v's side
            if (on_segment[c] < 0 || v > c) return;
            const int32_t apex = tri.vertex(s, (i + 2) % 3);
            const int e = (i + 2) % 3;  // the edge opposite apex: (v, c)
            const int32_t across = tri.vertex(tri.neighbour(s, e), tri.mirror_edge(s, e));
            if (runs_along_gamma(v, c, apex, across)) edges.push_back({v, c});
        });
    }
    return edges;
}

bool MeshState::gamma_edges_stay(const std::vector<std::pair<int32_t, int32_t>> &edges, int32_t gone) const {
    for (const auto &[u, w] : edges)
        if (u != gone && w != gone && !has_edge(u, w)) return false;
    return true;
}

bool MeshState::has_edge(int32_t a, int32_t b) const {
    bool found = false;
    tri.for_each_neighbour(a, [&](int32_t w) { found = found || w == b; });
    return found;
}

}  // namespace um::optim::detail
