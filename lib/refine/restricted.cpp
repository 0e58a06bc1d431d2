#include "refine/restricted.hpp"

#include <algorithm>

#include "core/uninit_vector.hpp"

namespace um::refine {

bool restricted_crossing(const tri::Triangulation &tri, int32_t t, int k,
                         const geom::ArcTree &gamma, RestrictedEdge *out) {
    return restricted_crossing(tri, t, k, tri.orthocentre(t), tri.orthocentre(tri.neighbour(t, k)),
                               gamma, out);
}

bool restricted_crossing(const tri::Triangulation &tri, int32_t t, int k, const Vec3 &c0,
                         const Vec3 &c1, const geom::ArcTree &gamma, RestrictedEdge *out) {
    const Vec3 xi = tri.direction(tri.vertex(t, (k + 1) % 3));
    const Vec3 xj = tri.direction(tri.vertex(t, (k + 2) % 3));
    bool found = false;
    gamma.query_crossing(c0, c1, [&](int32_t a) {
        Vec3 x;
        const auto &arc = gamma.arc(a);
        if (!geom::arc_intersection(c0, c1, arc.a, arc.b, x)) return;
        double r = std::max(geom::arc_length(x, xi), geom::arc_length(x, xj));
        // Larger ball first; the lower arc index on a tie keeps it deterministic.
        if (!found || r > out->radius || (r == out->radius && a < out->arc)) {
            *out = {t, k, a, x, r};
            found = true;
        }
    });
    return found;
}

namespace {

// The restricted edges among the edges of `count` triangles, triangle i
// being slot_of(i) and index_of(u) the position of slot u among them (-1 if
// not listed): each edge once, from its smaller triangle, each listed
// triangle's orthocentre computed once; in list order.
template <class SlotOf, class IndexOf>
std::vector<RestrictedEdge> restricted_edges_among(Context &ctx, const tri::Triangulation &tri,
                                                   const geom::ArcTree &gamma, int64_t count,
                                                   SlotOf slot_of, IndexOf index_of) {
    // (Unwritten until the parallel loop: a plain vector would first zero
    // it on one thread, taking every page fault of its 24 bytes a triangle
    // there - about as long as the orthocentres. A free slot's is never read.)
    UninitVector<Vec3> centre(static_cast<size_t>(count));
    ctx.parallel_for(count, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i)
            if (!tri.is_free(slot_of(i))) centre[i] = tri.orthocentre(slot_of(i));
    });
    return ctx.collect_in_order<RestrictedEdge>(count, 1024, [&](int64_t i, std::vector<RestrictedEdge> &out) {
        const int32_t t = slot_of(i);
        if (tri.is_free(t)) return;
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri.neighbour(t, k);
            const int64_t j = index_of(u);
            if (j >= 0 && u < t) continue;  // found from u
            const Vec3 cu = j >= 0 ? centre[j] : tri.orthocentre(u);
            RestrictedEdge e;
            const bool found = u < t ? restricted_crossing(tri, u, tri.mirror_edge(t, k), cu, centre[i], gamma, &e)
                                     : restricted_crossing(tri, t, k, centre[i], cu, gamma, &e);
            if (found) out.push_back(e);
        }
    });
}

}  // namespace

std::vector<RestrictedEdge> restricted_edges(Context &ctx, const tri::Triangulation &tri,
                                             const geom::ArcTree &gamma) {
    return restricted_edges_among(
        ctx, tri, gamma, tri.triangle_slots(), [](int64_t i) { return static_cast<int32_t>(i); },
        [](int32_t u) { return int64_t(u); });
}

std::vector<RestrictedEdge> restricted_edges(Context &ctx, const tri::Triangulation &tri,
                                             const geom::ArcTree &gamma,
                                             const std::vector<int32_t> &triangles) {
    return restricted_edges_among(
        ctx, tri, gamma, static_cast<int64_t>(triangles.size()), [&](int64_t i) { return triangles[i]; },
        [&](int32_t u) -> int64_t {
            auto it = std::lower_bound(triangles.begin(), triangles.end(), u);
            return it != triangles.end() && *it == u ? it - triangles.begin() : -1;
        });
}

}  // namespace um::refine
