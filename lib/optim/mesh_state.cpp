#include "optim/mesh_state.hpp"

#include <algorithm>
#include <cmath>
#include <chrono>

#include "core/growth.hpp"
#include "core/splitmix.hpp"
#include "geom/predicates.hpp"

namespace um::optim::detail {

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Edge orthocentres must stay this far inside their primal edge (as a share
// of it): the generator stays in its own power cell and no weight can hide
// a vertex (issue "Weighted primal-dual optimisation", item 3).
constexpr double kCrossingMargin = 0.05;

// An update must raise its star's worst (or mean) quality by this many
// tolerances: smaller gains cost a sweep each and change no summary.
constexpr double kGainOverTolerance = 10;

// changed_near marks the stars of the changed vertices when they are at
// most one in this many (else every vertex is looked at, as without it).
constexpr size_t kChangedNearShare = 8;

// ----------------------------------------------------------- per-slot state

MeshState::MeshState(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
                     const features::Network *gamma, const refine::SpacingRadians &h, const OptimiseOptions &o,
                     const features::Domain *domain, const std::vector<refine::Side> *sides)
    : ctx(ctx), tri(tri), on_segment(on_segment), gamma(gamma), h(h), options(o),
      gain(kGainOverTolerance * o.tolerance), arcs(features::segment_arc_tree(gamma)), domain(domain),
      given_sides(sides) {}

void MeshState::grow_slots() {
    const size_t n = static_cast<size_t>(tri.vertex_slots());
    if (h_at.capacity() == 0) {  // the room the triangulation has (Triangulation::reserve_extra)
        const size_t room = std::max(n, tri.vertex_capacity());
        h_at.reserve(room), changed_at.reserve(room), move_failed_at.reserve(room);
        on_segment.reserve(room);
    }
    reserve_for(h_at, n), reserve_for(changed_at, n);
    reserve_for(move_failed_at, n), reserve_for(on_segment, n);
    h_at.resize(n, 0);
    changed_at.resize(n, clock);
    move_failed_at.resize(n, 0);
    on_segment.resize(n, -1);
    // Only from the weight phase on (the shape phase, where the topology
    // changes and memory peaks, has no use for it).
    if (weighing) reserve_for(weight_failed_at, n), weight_failed_at.resize(n, 0);
}

void MeshState::load_spacing() {
    grow_slots();
    if (domain) {
        in_cover.assign(static_cast<size_t>(tri.vertex_slots()), 0);
        reserve_for(loaded, static_cast<size_t>(tri.vertex_slots()));
        loaded.resize(static_cast<size_t>(tri.vertex_slots()));
    }
    ctx.parallel_for_with_heartbeat("optimise", tri.vertex_slots(), 256, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t v = static_cast<int32_t>(i);
            if (!tri.in_triangulation(v)) continue;
            const Vec3 x = tri.direction(v);
            if (!domain) {
                h_at[v] = static_cast<float>(h(x));
                continue;
            }
            LoadedSpacing &l = loaded[v];
            if (!(l.at.x == x.x && l.at.y == x.y && l.at.z == x.z && l.segment == on_segment[v]))
                l = {x, on_segment[v], static_cast<float>(h(x)), domain->in_cover(x, on_segment[v])};
            h_at[v] = l.h, in_cover[v] = l.cover;
        }
    });
}

bool MeshState::beside_cover(int32_t v) const {
    if (!domain) return false;
    bool beside = tri.in_triangulation(v) && !domain->contains(tri.direction(v));
    if (tri.in_triangulation(v)) tri.for_each_neighbour(v, [&](int32_t u) { beside = beside || cover(u); });
    return beside;
}

// ------------------------------------------------------------------ sweeps

bool MeshState::nothing_changed_since(const StarGraph &g, int32_t v, int32_t tried) const {
    if (changed_at[v] >= tried) return false;
    const int32_t *link = g.link(v);
    for (int k = 0; k < g.degree(v); ++k)
        if (changed_at[link[k]] >= tried) return false;
    return true;
}

std::vector<uint8_t> MeshState::changed_near(const StarGraph &g, int32_t since) const {
    const int32_t n = g.vertex_slots();
    const std::vector<int32_t> recent =
        ctx.collect_in_order<int32_t>(n, 1 << 14, [&](int64_t v, std::vector<int32_t> &out) {
            if (changed_at[v] >= since) out.push_back(static_cast<int32_t>(v));
        });
    // (Past that share, marking the stars one by one costs more than the
    // sweep's own look at every vertex.)
    if (recent.size() > static_cast<size_t>(n) / kChangedNearShare) return {};
    std::vector<uint8_t> near(static_cast<size_t>(tri.vertex_slots()), 0);
    for (int32_t u : recent) {  // (the links are symmetric: v is near u when u is in v's link)
        near[u] = 1;
        flag_link(g, u, near);
    }
    return near;
}

bool MeshState::gather_ring(const StarGraph &g, int32_t v, Ring &ring) const {
    ring.m = g.degree(v);
    if (ring.m > Ring::kMax) return false;
    const int32_t *link = g.link(v);
    for (int k = 0; k < ring.m; ++k) ring.g[k] = generator(link[k]), ring.q[k] = tri.lifted(link[k]);
    return true;
}

bool star_is_valid(const Ring &ring, const Generator &at) {
    const Vec3 q = at.lifted();  // what set_generator stores
    for (int k = 0; k < ring.m; ++k) {
        const Vec3 &a = ring.q[k], &b = ring.q[k + 1 == ring.m ? 0 : k + 1];
        if (geom::orient_origin(q.data(), a.data(), b.data()) <= 0) return false;
        const double share = edge_crossing_share(at, ring.at(k));
        if (!(share > kCrossingMargin && share < 1 - kCrossingMargin)) return false;
    }
    return true;
}

// ---------------------------------------------------------------- topology

// Flips from the triangles around every vertex that changed since `since`.
int64_t MeshState::restore_regularity(int32_t since) {
    // The seeds: triangles with a vertex changed since `since` and an edge
    // that is not locally regular, found in parallel (the exact tests are
    // most of the work, and most triangles pass them); the flips are serial.
    // A triangle left out cannot need a flip before one next to it has
    // flipped, and the flip puts it back on the stack.
    std::vector<int32_t> seeds =
        ctx.collect_in_order<int32_t>(tri.triangle_slots(), 8192, [&](int64_t t, std::vector<int32_t> &out) {
            const int32_t ti = static_cast<int32_t>(t);
            if (tri.is_free(ti)) return;
            bool changed = false, regular = true;
            for (int k = 0; k < 3; ++k) changed |= changed_at[tri.vertex(ti, k)] >= since;
            for (int k = 0; k < 3 && changed && regular; ++k) regular = tri.is_locally_regular(ti, k);
            if (!regular) out.push_back(ti);
        });
    return tri.restore_regularity(std::move(seeds));
}

// A fingerprint of each vertex's link that does not depend on where the
// cycle starts: the sum of a mix of every (neighbour, next neighbour) pair.
uint64_t link_fingerprint(const StarGraph &g, int32_t v) {
    const int32_t *link = g.link(v);
    const int m = g.degree(v);
    uint64_t sum = static_cast<uint64_t>(m);
    for (int k = 0; k < m; ++k) {
        const uint64_t here = static_cast<uint32_t>(link[k]);
        const uint64_t next = static_cast<uint32_t>(link[(k + 1) % m]);
        sum += splitmix64(here << 32 | next);
    }
    return sum;
}

// Kept in 32 bits (4 bytes per vertex at the moment the new graph is built,
// where memory peaks): a collision only leaves one changed link unmarked.
uint32_t folded(uint64_t x) { return static_cast<uint32_t>(x ^ (x >> 32)); }

std::vector<uint32_t> link_fingerprints(Context &ctx, const StarGraph &g) {
    std::vector<uint32_t> out(static_cast<size_t>(g.vertex_slots()), 0);
    ctx.parallel_for(g.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) out[v] = folded(link_fingerprint(g, static_cast<int32_t>(v)));
    });
    return out;
}

// A vertex whose link changed (by flips, collapses or splits) counts as
// changed, so that it and its neighbours are tried again.
void MeshState::mark_changed_links(const std::vector<uint32_t> &before, const StarGraph &now) {
    // Compared as they are computed: a second list would be alive with the
    // new graph, where the optimisation's memory peaks.
    ctx.parallel_for(now.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v)
            if (v >= static_cast<int64_t>(before.size()) ||
                before[v] != folded(link_fingerprint(now, static_cast<int32_t>(v))))
                changed_at[v] = clock;
    });
}

bool MeshState::removable(int32_t v) const {
    const double cos_largest = std::cos(kLargestRemovableStar);
    const Vec3 x = tri.direction(v);
    bool small = true;
    tri.for_each_neighbour(v, [&](int32_t u) { small = small && geom::dot(x, tri.direction(u)) > cos_largest; });
    return small;
}

void MeshState::rebuild_graph(std::unique_ptr<StarGraph> &graph) {
    load_spacing();
    const std::vector<uint32_t> links_before = link_fingerprints(ctx, *graph);
    graph.reset();  // one graph alive at a time
    graph = std::make_unique<StarGraph>(ctx, tri);
    mark_changed_links(links_before, *graph);
}

std::vector<int32_t> MeshState::closed_stars(std::initializer_list<int32_t> vertices) const {
    std::vector<int32_t> around(vertices);
    for (int32_t v : vertices)
        tri.for_each_in_star(v, [&](int32_t t) {
            for (int k = 0; k < 3; ++k) around.push_back(tri.vertex(t, k));
        });
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    return around;
}

// (An edge's two ends are claimed at once, through closed_stars: claimed one
// after the other, the second would always find itself claimed, as a
// neighbour of the first.)
bool MeshState::claim(const std::vector<int32_t> &vertices, std::vector<uint8_t> &locked) {
    for (int32_t u : vertices)
        if (locked[u]) return false;
    for (int32_t u : vertices) locked[u] = 1;
    return true;
}

// The ODT point of v's star as the triangulation has it: the mean of its
// triangles' orthocentres weighted by their (chord) areas.
Vec3 MeshState::star_odt_point(int32_t v) const {
    Vec3 sum{};
    tri.for_each_in_star(v, [&](int32_t s) {
        const Vec3 a = tri.direction(tri.vertex(s, 0));
        const double area = 0.5 * geom::norm(geom::cross(tri.direction(tri.vertex(s, 1)) - a,
                                                         tri.direction(tri.vertex(s, 2)) - a));
        sum = sum + area * tri.orthocentre(s);
    });
    return geom::normalized(sum);
}

int MeshState::obtuse_touching(const std::vector<int32_t> &vertices) const {
    int obtuse = 0;
    for (int32_t s : tri.triangles_around(vertices))
        obtuse += largest_angle_cosine(tri.direction(tri.vertex(s, 0)), tri.direction(tri.vertex(s, 1)),
                                       tri.direction(tri.vertex(s, 2))) < 0;
    return obtuse;
}

}  // namespace um::optim::detail
