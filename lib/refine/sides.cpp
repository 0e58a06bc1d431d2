#include "refine/sides.hpp"

#include <cmath>

#include "features/domain.hpp"

namespace um::refine {

using geom::Vec3;

bool is_closed_coastline(const features::Part &p) {
    return p.closed && p.kind == features::Kind::coastline;
}

namespace {

// Number of coastline arcs the minor arc (a, b) crosses.
int crossings(const geom::ArcTree &coast, const Vec3 &a, const Vec3 &b) {
    int n = 0;
    coast.query_crossing(a, b, [&](int32_t i) {
        Vec3 x;
        const auto &arc = coast.arc(i);
        if (geom::arc_intersection(a, b, arc.a, arc.b, x, 0.0)) ++n;
    });
    return n;
}
}  // namespace

bool is_land(const features::Network &net, const Vec3 &x) {
    bool land = false;
    for (int64_t p = 0; p < net.part_count(); ++p)
        if (is_closed_coastline(net.part(p)) && features::ring_encloses(net, p, x)) land = !land;
    return land;
}

geom::ArcTree closed_coastline_arcs(const features::Network &net, std::vector<int64_t> *segments) {
    std::vector<geom::ArcTree::Arc> arcs;
    for (int64_t s = 0; s < net.segment_count(); ++s)
        if (is_closed_coastline(net.part(net.segment_part(s)))) {
            arcs.push_back({net.segment_a(s), net.segment_b(s)});
            if (segments) segments->push_back(s);
        }
    return geom::ArcTree(std::move(arcs));
}

std::vector<Side> triangle_sides(const tri::Triangulation &tri, const features::Network &net,
                                 const std::vector<RestrictedEdge> *may_cross) {
    std::vector<Side> side(static_cast<size_t>(tri.triangle_slots()), Side::ocean);
    geom::ArcTree coast = closed_coastline_arcs(net, nullptr);
    if (coast.size() == 0) return side;
    // Per triangle, a bit per edge whose dual edge may cross a coastline.
    std::vector<uint8_t> tested;
    if (may_cross) {
        tested.assign(side.size(), 0);
        for (const RestrictedEdge &e : *may_cross) {
            const int32_t u = tri.neighbour(e.triangle, e.edge);
            tested[e.triangle] |= uint8_t(1u << e.edge);
            tested[u] |= uint8_t(1u << tri.mirror_edge(e.triangle, e.edge));
        }
    }
    auto may_flip = [&](int32_t t, int k) { return !may_cross || (tested[t] >> k & 1u); };
    std::vector<uint8_t> seen(side.size(), 0);
    std::vector<int32_t> stack;
    // Each connected piece of the dual graph (one, on a sphere) from an anchor.
    for (int32_t start = 0; start < tri.triangle_slots(); ++start) {
        if (tri.is_free(start) || seen[start]) continue;
        side[start] = is_land(net, tri.orthocentre(start)) ? Side::land : Side::ocean;
        seen[start] = 1;
        stack.push_back(start);
        while (!stack.empty()) {
            int32_t t = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                int32_t u = tri.neighbour(t, k);
                if (seen[u]) continue;
                // From the smaller triangle to the larger, as restricted_edges()
                // tests them: the same arithmetic even where a compiler
                // contracts the cross products differently for the two ways.
                // (The orthocentres only where a crossing may be: few edges.)
                bool flip = false;
                if (may_flip(t, k)) {
                    const Vec3 ct = tri.orthocentre(t), cu = tri.orthocentre(u);
                    flip = (t < u ? crossings(coast, ct, cu) : crossings(coast, cu, ct)) % 2 == 1;
                }
                side[u] = flip ? (side[t] == Side::land ? Side::ocean : Side::land) : side[t];
                seen[u] = 1;
                stack.push_back(u);
            }
        }
    }
    return side;
}

std::vector<uint8_t> ocean_mesh_cells(const tri::Triangulation &tri, const std::vector<Side> &vertices,
                                      const std::vector<Side> &triangles) {
    std::vector<uint8_t> ocean(static_cast<size_t>(tri.vertex_slots()), 0);
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) {
        if (!tri.in_triangulation(v)) continue;
        const Side side = static_cast<size_t>(v) < vertices.size() ? vertices[v] : Side::ocean;
        if (side != Side::coastal) {
            ocean[v] = side == Side::ocean;
            continue;
        }
        int balance = 0;  // triangles on the ocean side minus the others
        tri.for_each_in_star(v, [&](int32_t t) {
            balance += static_cast<size_t>(t) >= triangles.size() || triangles[t] == Side::ocean ? 1 : -1;
        });
        ocean[v] = balance >= 0;
    }
    return ocean;
}

std::vector<Side> vertex_sides(const tri::Triangulation &tri, const std::vector<Side> &triangles,
                               const std::vector<int32_t> &on_gamma_segment,
                               const features::Network &net) {
    std::vector<Side> side(static_cast<size_t>(tri.vertex_slots()), Side::ocean);
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) {
        if (!tri.in_triangulation(v)) continue;
        int32_t s = v < static_cast<int32_t>(on_gamma_segment.size()) ? on_gamma_segment[v] : -1;
        if (s >= 0 && is_closed_coastline(net.part(net.segment_part(s)))) {
            side[v] = Side::coastal;
            continue;
        }
        bool first = true;
        tri.for_each_in_star(v, [&](int32_t t) {
            if (first) side[v] = triangles[t], first = false;
            else if (triangles[t] != side[v]) side[v] = Side::coastal;
        });
    }
    return side;
}

}  // namespace um::refine
