#include "refine/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include "refine/restricted.hpp"

namespace um::refine {

using geom::Vec3;

EdgeMeasure measure(const tri::Triangulation &tri, const RestrictedEdge &e,
                    const SpacingRadians &h) {
    Vec3 a = tri.direction(tri.vertex(e.triangle, (e.edge + 1) % 3));
    Vec3 b = tri.direction(tri.vertex(e.triangle, (e.edge + 2) % 3));
    Vec3 mid = geom::normalized(a + b);
    return {geom::arc_length(a, b), geom::arc_length(mid, e.centre), h(mid)};
}

namespace {

struct Bad {
    double priority;  // l / h, largest first
    int32_t a, b;     // the edge's vertex slots (sorted), to order ties
    RestrictedEdge edge;
    bool operator<(const Bad &o) const {
        return std::tie(o.priority, a, b) < std::tie(priority, o.a, o.b);  // descending
    }
};

bool is_bad(const tri::Triangulation &tri, const RestrictedEdge &e, const SpacingRadians &h,
            const BoundaryOptions &options, EdgeMeasure *m) {
    *m = measure(tri, e, h);
    return m->length >= options.alpha * m->h || m->eps >= options.beta * m->h;
}


}  // namespace

int64_t count_bad(const tri::Triangulation &tri, const std::vector<RestrictedEdge> &edges,
                  const SpacingRadians &h, const BoundaryOptions &options) {
    int64_t bad = 0;
    for (const RestrictedEdge &e : edges) {
        EdgeMeasure m;
        bad += is_bad(tri, e, h, options, &m);
    }
    return bad;
}

// The restricted edges of part `part` at vertex v: its spokes whose dual
// edge crosses an arc of that part (each spoke once: the one leaving v in
// each triangle of its star).
int restricted_degree(const tri::Triangulation &tri, int32_t v, int64_t part, const geom::ArcTree &gamma,
                      const std::vector<int64_t> &part_of_arc) {
    int degree = 0;
    tri.for_each_in_star(v, [&](int32_t t) {
        RestrictedEdge e;
        if (restricted_crossing(tri, t, (tri.local_index(t, v) + 2) % 3, gamma, &e) && part_of_arc[e.arc] == part) ++degree;
    });
    return degree;
}

// The topology check of BoundaryOptions::part_of_arc, with the degrees
// found so far in this pass.
class TopologyCheck {
public:
    TopologyCheck(const tri::Triangulation &tri, const geom::ArcTree &gamma, const std::vector<int64_t> &part_of_arc)
        : tri_(tri), gamma_(gamma), part_of_arc_(part_of_arc) {}
    bool folds(const RestrictedEdge &e) {
        const int64_t part = part_of_arc_[e.arc];
        for (int end = 1; end <= 2; ++end) {
            const int32_t v = tri_.vertex(e.triangle, (e.edge + end) % 3);
            auto [it, fresh] = degree_.try_emplace({v, part}, 0);
            if (fresh) it->second = restricted_degree(tri_, v, part, gamma_, part_of_arc_);
            if (it->second >= 3) return true;
        }
        return false;
    }
    void forget() { degree_.clear(); }  // after insertions

private:
    const tri::Triangulation &tri_;
    const geom::ArcTree &gamma_;
    const std::vector<int64_t> &part_of_arc_;
    std::map<std::pair<int32_t, int64_t>, int> degree_;
};

// Passes: every bad restricted edge gets its ball centre (or is filtered).
// The first pass looks at every edge (or those around `around`); later ones
// only at the edges around the points just inserted - no other edge changed.
BoundaryStats refine_boundary(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                              const geom::ArcTree &gamma, const BoundaryOptions &options,
                              int32_t &next_id, std::vector<int32_t> &on_gamma,
                              const std::vector<int32_t> *around) {
    BoundaryStats stats;
    ctx.progress("refine boundary", 0.0);  // the phase starts (timed by its reports)
    on_gamma.resize(static_cast<size_t>(tri.vertex_slots()), -1);
    std::optional<TopologyCheck> topology;
    if (options.part_of_arc) topology.emplace(tri, gamma, *options.part_of_arc);
    auto bad_edge = [&](const RestrictedEdge &e, EdgeMeasure *m) {
        return is_bad(tri, e, h, options, m) || (topology && topology->folds(e));
    };
    std::vector<RestrictedEdge> candidates =
        around ? restricted_edges(ctx, tri, gamma, tri.triangles_around(*around)) : restricted_edges(ctx, tri, gamma);
    for (;;) {
        ++stats.passes;
        ctx.progress("refine boundary", 0.0);
        std::vector<Bad> bad;
        for (const RestrictedEdge &e : candidates) {
            ctx.heartbeat("refine boundary", 0.0);  // (a slow spacing callback: still cancellable)
            EdgeMeasure m;
            if (!bad_edge(e, &m)) continue;
            int32_t a = tri.vertex(e.triangle, (e.edge + 1) % 3);
            int32_t b = tri.vertex(e.triangle, (e.edge + 2) % 3);
            bad.push_back({m.length / m.h, std::min(a, b), std::max(a, b), e});
        }
        std::sort(bad.begin(), bad.end());
        std::vector<int32_t> added;
        for (const Bad &x : bad) {
            // Earlier insertions of this pass may have moved the crossing: refresh it.
            int32_t t = x.edge.triangle;
            if (tri.is_free(t)) continue;
            int32_t a = tri.vertex(t, (x.edge.edge + 1) % 3), b = tri.vertex(t, (x.edge.edge + 2) % 3);
            if (std::min(a, b) != x.a || std::max(a, b) != x.b) continue;
            RestrictedEdge e;
            if (!restricted_crossing(tri, t, x.edge.edge, gamma, &e)) continue;
            EdgeMeasure m;
            if (!bad_edge(e, &m)) continue;
            // The surface ball is empty, so its radius is the new point's
            // distance to its nearest vertex: too small means over-refining.
            const double filter = options.filter.on_arc(e.arc);
            if (e.radius < filter * h(e.centre)) continue;
            int32_t v = tri.insert(e.centre, 0.0, next_id++, nullptr, t);
            on_gamma.resize(static_cast<size_t>(tri.vertex_slots()), -1);
            if (!tri.in_triangulation(v)) continue;
            if (topology) topology->forget();  // the mesh changed (a removal below changes it again)
            if (nearest_neighbour(tri, v) < filter * h(e.centre)) {
                tri.remove(v);
                continue;
            }
            on_gamma[v] = e.arc;
            added.push_back(v);
        }
        stats.inserted += static_cast<int64_t>(added.size());
        stats.added.insert(stats.added.end(), added.begin(), added.end());
        if (added.empty()) break;
        candidates = restricted_edges(ctx, tri, gamma, tri.triangles_around(added));
    }
    return stats;
}

}  // namespace um::refine
