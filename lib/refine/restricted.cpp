#include "refine/restricted.hpp"

#include <algorithm>

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
    gamma.query(geom::arc_box(c0, c1), [&](int32_t a) {
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

std::vector<RestrictedEdge> restricted_edges(Context &ctx, const tri::Triangulation &tri,
                                             const geom::ArcTree &gamma) {
    const int64_t n = tri.triangle_slots();
    // Every orthocentre once (each is shared by three dual edges).
    std::vector<Vec3> centre(static_cast<size_t>(n));
    ctx.parallel_for(n, 8192, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t)
            if (!tri.is_free(static_cast<int32_t>(t))) centre[t] = tri.orthocentre(static_cast<int32_t>(t));
    });
    return ctx.collect_in_order<RestrictedEdge>(n, 4096, [&](int64_t t, std::vector<RestrictedEdge> &out) {
        const int32_t ti = static_cast<int32_t>(t);
        if (tri.is_free(ti)) return;
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri.neighbour(ti, k);
            if (u < ti) continue;  // each edge once
            RestrictedEdge r;
            if (restricted_crossing(tri, ti, k, centre[t], centre[u], gamma, &r)) out.push_back(r);
        }
    });
}

}  // namespace um::refine
