#include "tri/cell_walk.hpp"

#include <algorithm>

namespace um::tri {

namespace {

// Halvings of an arc before two cells are taken as neighbours anyway: 2^-40
// of a quarter turn is far below any cell (the cells then meet at a point).
constexpr int kMaxHalvings = 40;

bool further_along(const Triangulation &tri, const Vec3 &x, int32_t w, int32_t v) {
    const double dw = geom::dot(x, tri.lifted(w)), dv = geom::dot(x, tri.lifted(v));
    return dw > dv || (dw == dv && w < v);
}

bool are_neighbours(const Triangulation &tri, int32_t v, int32_t w) {
    bool found = false;
    tri.for_each_neighbour(v, [&](int32_t u) { found |= u == w; });
    return found;
}

int32_t first_vertex(const Triangulation &tri) {
    for (int32_t v = 0; v < tri.vertex_slots(); ++v)
        if (tri.in_triangulation(v)) return v;
    return -1;
}

// Whether the arc a -> b, from ca's cell into its neighbour cb's, crosses
// their shared boundary where no third cell is higher: else it passes
// through a corner of another cell between them.
bool crosses_directly(const Triangulation &tri, const Vec3 &a, int32_t ca, const Vec3 &b, int32_t cb) {
    const Vec3 d = tri.lifted(ca) - tri.lifted(cb);
    const double da = geom::dot(a, d), db = geom::dot(b, d);
    if (!(da - db > 0)) return true;  // (a degenerate boundary: nothing to find)
    const double t = da / (da - db);
    const Vec3 p = geom::normalized((1 - t) * a + t * b);  // where the two are equally high
    const double top = std::max(geom::dot(p, tri.lifted(ca)), geom::dot(p, tri.lifted(cb)));
    bool direct = true;
    for (int32_t c : {ca, cb})
        tri.for_each_neighbour(c, [&](int32_t w) { direct = direct && !(geom::dot(p, tri.lifted(w)) > top); });
    return direct;
}

// Appends the cells strictly after ca up to and including cb along a -> b.
void append_between(const Triangulation &tri, const Vec3 &a, int32_t ca, const Vec3 &b, int32_t cb,
                     int depth, std::vector<int32_t> &out) {
    if (ca == cb) return;
    if (depth == kMaxHalvings || (are_neighbours(tri, ca, cb) && crosses_directly(tri, a, ca, b, cb))) {
        out.push_back(cb);
        return;
    }
    const Vec3 mid = geom::normalized(a + b);
    const int32_t cm = cell_holding(tri, mid, ca);
    append_between(tri, a, ca, mid, cm, depth + 1, out);
    append_between(tri, mid, cm, b, cb, depth + 1, out);
}

}  // namespace

int32_t cell_holding(const Triangulation &tri, const Vec3 &x, int32_t start) {
    int32_t v = start >= 0 && start < tri.vertex_slots() && tri.in_triangulation(start) ? start : first_vertex(tri);
    if (v < 0) return -1;
    for (;;) {
        int32_t best = v;
        tri.for_each_neighbour(v, [&](int32_t w) {
            if (further_along(tri, x, w, best)) best = w;
        });
        if (best == v) return v;
        v = best;
    }
}

std::vector<int32_t> cells_along_arc(const Triangulation &tri, const Vec3 &a, const Vec3 &b, int32_t start) {
    std::vector<int32_t> cells;
    const int32_t ca = cell_holding(tri, a, start);
    if (ca < 0) return cells;
    cells.push_back(ca);
    append_between(tri, a, ca, b, cell_holding(tri, b, ca), 0, cells);
    return cells;
}

}  // namespace um::tri
