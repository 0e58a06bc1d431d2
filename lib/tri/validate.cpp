#include "tri/validate.hpp"

#include <vector>

#include "core/text.hpp"
#include "geom/predicates.hpp"

namespace um::tri {

namespace {
inline int next(int k) { return k == 2 ? 0 : k + 1; }
inline int prev(int k) { return k == 0 ? 2 : k - 1; }

std::string check_links(const Triangulation &tri) {
    for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
        if (tri.is_free(t)) continue;
        for (int k = 0; k < 3; ++k) {
            int32_t u = tri.neighbour(t, k);
            if (u < 0 || u >= tri.triangle_slots() || tri.is_free(u))
                return concat("triangle ", t, " edge ", k, " has no neighbour");
            int32_t a = tri.vertex(t, next(k)), b = tri.vertex(t, prev(k));
            bool found = false;
            for (int m = 0; m < 3; ++m)
                if (tri.neighbour(u, m) == t && tri.vertex(u, next(m)) == b &&
                    tri.vertex(u, prev(m)) == a)
                    found = true;
            if (!found) return concat("triangles ", t, " and ", u, " are not linked back");
        }
    }
    return "";
}

std::string check_orientation_and_regularity(const Triangulation &tri) {
    const double origin[3] = {0, 0, 0};
    for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
        if (tri.is_free(t)) continue;
        const Vec3 &a = tri.lifted(tri.vertex(t, 0)), &b = tri.lifted(tri.vertex(t, 1)),
                   &c = tri.lifted(tri.vertex(t, 2));
        if (geom::orient3d(a.data(), b.data(), c.data(), origin) >= 0)
            return concat("triangle ", t, " does not have the centre strictly behind it");
        for (int k = 0; k < 3; ++k)
            if (!tri.is_locally_regular(t, k))
                return concat("edge ", k, " of triangle ", t, " is not locally regular");
    }
    return "";
}

std::string check_vertices(const Triangulation &tri) {
    int64_t stars = 0;
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) {
        if (!tri.in_triangulation(v)) continue;
        auto s = tri.star(v);
        if (s.size() < 3) return concat("vertex ", tri.id(v), " has a star of ", s.size());
        for (int32_t t : s)
            if (tri.vertex(t, 0) != v && tri.vertex(t, 1) != v && tri.vertex(t, 2) != v)
                return concat("star of vertex ", tri.id(v), " holds triangle ", t,
                              " without it");
        stars += static_cast<int64_t>(s.size());
    }
    if (stars != 3 * static_cast<int64_t>(tri.triangle_count()))
        return concat("stars cover ", stars, " corners, expected ", 3 * tri.triangle_count());
    int64_t V = tri.vertex_count(), F = tri.triangle_count(), E = 3 * F / 2;
    if (V - E + F != 2) return concat("Euler characteristic ", V - E + F, " (V ", V, ")");
    return "";
}
// A hidden point must be inside the hull: not beyond the facet in its direction.
std::string check_hidden(const Triangulation &tri) {
    int32_t hint = 0;
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) {
        if (tri.in_triangulation(v) || tri.is_removed(v)) continue;
        hint = tri.locate(tri.direction(v), hint);
        if (tri.beyond(hint, v))
            return concat("point ", tri.id(v), " is reported hidden but lies outside the hull");
    }
    return "";
}
}  // namespace

std::string check_triangulation(const Triangulation &tri) {
    for (auto check : {check_links, check_orientation_and_regularity, check_vertices,
                        check_hidden}) {
        std::string problem = check(tri);
        if (!problem.empty()) return problem;
    }
    return "";
}

}  // namespace um::tri
