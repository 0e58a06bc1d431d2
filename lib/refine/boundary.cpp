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

// The restricted edges among the edges of the given triangles, each once.
std::vector<RestrictedEdge> restricted_edges_of(const tri::Triangulation &tri,
                                                const std::vector<int32_t> &triangles,
                                                const geom::ArcTree &gamma) {
    std::vector<std::pair<std::pair<int32_t, int32_t>, RestrictedEdge>> found;
    for (int32_t t : triangles) {
        if (tri.is_free(t)) continue;
        for (int k = 0; k < 3; ++k) {
            RestrictedEdge e;
            if (!restricted_crossing(tri, t, k, gamma, &e)) continue;
            int32_t a = tri.vertex(t, (k + 1) % 3), b = tri.vertex(t, (k + 2) % 3);
            found.push_back({{std::min(a, b), std::max(a, b)}, e});
        }
    }
    std::sort(found.begin(), found.end(),
              [](const auto &x, const auto &y) { return x.first < y.first; });
    std::vector<RestrictedEdge> out;
    for (size_t i = 0; i < found.size(); ++i)
        if (i == 0 || found[i].first != found[i - 1].first) out.push_back(found[i].second);
    return out;
}

}  // namespace

// Passes: every bad restricted edge gets its ball centre (or is filtered).
// The first pass looks at every edge; later ones only at the edges around
// the points just inserted - no other edge changed - and a last full scan
// counts the bad edges left (the filtered ones).
BoundaryStats refine_boundary(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                              const geom::ArcTree &gamma, const BoundaryOptions &options,
                              int32_t &next_id, std::vector<int32_t> &on_gamma) {
    BoundaryStats stats;
    on_gamma.resize(static_cast<size_t>(tri.vertex_slots()), -1);
    auto is_bad = [&](const RestrictedEdge &e, EdgeMeasure *m) {
        *m = measure(tri, e, h);
        return m->length >= options.alpha * m->h || m->eps >= options.beta * m->h;
    };
    std::vector<RestrictedEdge> candidates = restricted_edges(ctx, tri, gamma);
    for (;;) {
        ++stats.passes;
        ctx.progress("refine boundary", 0.0);
        std::vector<Bad> bad;
        for (const RestrictedEdge &e : candidates) {
            EdgeMeasure m;
            if (!is_bad(e, &m)) continue;
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
            if (!is_bad(e, &m)) continue;
            // The surface ball is empty, so its radius is the new point's
            // distance to its nearest vertex: too small means over-refining.
            if (e.radius < options.filter * h(e.centre)) continue;
            int32_t v = tri.insert(e.centre, 0.0, next_id++, nullptr, t);
            on_gamma.resize(static_cast<size_t>(tri.vertex_slots()), -1);
            if (!tri.in_triangulation(v)) continue;
            if (nearest_neighbour(tri, v) < options.filter * h(e.centre)) {
                tri.remove(v);
                continue;
            }
            on_gamma[v] = e.arc;
            added.push_back(v);
        }
        stats.inserted += static_cast<int64_t>(added.size());
        if (added.empty()) break;
        std::vector<int32_t> dirty;
        for (int32_t v : added)
            if (tri.in_triangulation(v))
                for (int32_t t : tri.star(v)) dirty.push_back(t);
        std::sort(dirty.begin(), dirty.end());
        dirty.erase(std::unique(dirty.begin(), dirty.end()), dirty.end());
        candidates = restricted_edges_of(tri, dirty, gamma);
    }
    for (const RestrictedEdge &e : restricted_edges(ctx, tri, gamma)) {
        EdgeMeasure m;
        stats.filtered += is_bad(e, &m);
    }
    return stats;
}

}  // namespace um::refine
