#include "refine/boundary.hpp"

#include <algorithm>
#include <cmath>
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

double nearest_neighbour(const tri::Triangulation &tri, int32_t v) {
    double d = 1e300;
    Vec3 x = tri.direction(v);
    for (int32_t t : tri.star(v))
        for (int k = 0; k < 3; ++k)
            if (tri.vertex(t, k) != v) d = std::min(d, geom::arc_length(x, tri.direction(tri.vertex(t, k))));
    return d;
}

}  // namespace

BoundaryStats refine_boundary(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                              const geom::ArcTree &gamma, const BoundaryOptions &options,
                              int32_t &next_id, std::vector<int32_t> &on_gamma) {
    BoundaryStats stats;
    on_gamma.resize(static_cast<size_t>(tri.vertex_slots()), -1);
    for (;;) {
        ++stats.passes;
        ctx.progress("refine boundary", 0.0);
        std::vector<Bad> bad;
        for (const RestrictedEdge &e : restricted_edges(ctx, tri, gamma)) {
            EdgeMeasure m = measure(tri, e, h);
            if (m.length < options.alpha * m.h && m.eps < options.beta * m.h) continue;
            int32_t a = tri.vertex(e.triangle, (e.edge + 1) % 3);
            int32_t b = tri.vertex(e.triangle, (e.edge + 2) % 3);
            bad.push_back({m.length / m.h, std::min(a, b), std::max(a, b), e});
        }
        std::sort(bad.begin(), bad.end());
        int64_t accepted = 0, filtered = 0;
        for (const Bad &x : bad) {
            // Earlier insertions of this pass may have moved the crossing: refresh it.
            int32_t t = x.edge.triangle;
            if (tri.is_free(t)) continue;
            int32_t a = tri.vertex(t, (x.edge.edge + 1) % 3), b = tri.vertex(t, (x.edge.edge + 2) % 3);
            if (std::min(a, b) != x.a || std::max(a, b) != x.b) continue;
            RestrictedEdge e;
            if (!restricted_crossing(tri, t, x.edge.edge, gamma, &e)) continue;
            EdgeMeasure m = measure(tri, e, h);
            if (m.length < options.alpha * m.h && m.eps < options.beta * m.h) continue;
            // The surface ball is empty, so its radius is the new point's
            // distance to its nearest vertex: too small means over-refining.
            if (e.radius < options.filter * h(e.centre)) {
                ++filtered;
                continue;
            }
            int32_t v = tri.insert(e.centre, 0.0, next_id++, nullptr, t);
            on_gamma.resize(static_cast<size_t>(tri.vertex_slots()), -1);
            if (!tri.in_triangulation(v)) continue;
            if (nearest_neighbour(tri, v) < options.filter * h(e.centre)) {
                tri.remove(v);
                ++filtered;
                continue;
            }
            on_gamma[v] = e.arc;
            ++accepted;
        }
        stats.inserted += accepted;
        stats.filtered = filtered;
        if (accepted == 0) break;
    }
    return stats;
}

}  // namespace um::refine
