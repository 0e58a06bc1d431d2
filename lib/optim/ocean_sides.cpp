// The sides of the generators for the time-step floor (MeshState::side):
// which cells are off the land, the ones whose edges the floor bounds.
#include <algorithm>

#include "geom/arc_tree.hpp"
#include "optim/mesh_state.hpp"
#include "refine/restricted.hpp"

namespace um::optim::detail {

namespace {

bool known(const std::vector<int32_t> &side_id, const tri::Triangulation &tri, int32_t v) {
    return static_cast<size_t>(v) < side_id.size() && side_id[v] >= 0 && side_id[v] == tri.id(v);
}

// The side of a vertex made since the sides were found (a split, a corner
// vertex, a refilled hole): coastal on a closed coastline, else land if a
// neighbour of known side off Gamma is land, else ocean. A vertex off Gamma
// never crosses it (the Gamma guard), so it shares the side of its
// neighbours off Gamma.
refine::Side inferred_side(const MeshState &s, int32_t v) {
    const int32_t segment = s.on_segment[v];
    if (segment >= 0 && refine::is_closed_coastline(s.gamma->part(s.gamma->segment_part(segment))))
        return refine::Side::coastal;
    bool land = false;
    s.tri.for_each_neighbour(v, [&](int32_t w) {
        land = land || (known(s.side_id, s.tri, w) && s.on_segment[w] < 0 && s.side[w] == refine::Side::land);
    });
    return land ? refine::Side::land : refine::Side::ocean;
}

// Whether a closed coastline crosses an edge of v's power cell (the dual
// arcs between the orthocentres of consecutive triangles of its star).
bool coastline_enters_cell(const MeshState &s, int32_t v) {
    Vec3 first{}, last{};
    bool any = false, crossed = false;
    auto crosses = [&](const Vec3 &c0, const Vec3 &c1) {
        return s.arcs.query_crossing_until(c0, c1, [&](int32_t i) {
            Vec3 x;
            return refine::is_closed_coastline(s.gamma->part(s.gamma->segment_part(i))) &&
                   geom::arc_intersection(c0, c1, s.arcs.arc(i).a, s.arcs.arc(i).b, x);
        });
    };
    s.tri.for_each_in_star(v, [&](int32_t t) {
        if (crossed) return;
        const Vec3 qa = s.tri.lifted(s.tri.vertex(t, 0)), qb = s.tri.lifted(s.tri.vertex(t, 1)),
                   qc = s.tri.lifted(s.tri.vertex(t, 2));
        const Vec3 ortho = geom::normalized(geom::cross(qb - qa, qc - qa));
        if (any) crossed = crosses(last, ortho);
        else first = ortho, any = true;
        last = ortho;
    });
    return crossed || (any && crosses(last, first));
}

}  // namespace

// The sides are found once, by the first refresh (Tri|Gamma and the walk of
// refine::sides: about 90 ms at 60 km), then kept: a vertex off Gamma never
// crosses Gamma, so its side stays. A reused slot shows by its id.
void MeshState::refresh_sides() {
    const int32_t n = tri.vertex_slots();
    if (!gamma || arcs.size() == 0) {
        side.assign(static_cast<size_t>(n), refine::Side::ocean);
        side_id.assign(static_cast<size_t>(n), -1);
        for (int32_t v = 0; v < n; ++v) side_id[v] = tri.id(v);
        return;
    }
    if (side_id.empty()) {
        if (given_sides) {
            side = *given_sides;
        } else {
            const std::vector<refine::RestrictedEdge> restricted = refine::restricted_edges(ctx, tri, arcs);
            const std::vector<refine::Side> triangles = refine::triangle_sides(tri, *gamma, &restricted);
            side = refine::vertex_sides(tri, triangles, on_segment, *gamma);
        }
        given_sides = nullptr;  // (they are of the starting triangulation only)
        side_id.assign(static_cast<size_t>(n), -1);
        for (int32_t v = 0; v < n; ++v)
            if (tri.in_triangulation(v)) side_id[v] = tri.id(v);
        return;
    }
    side.resize(static_cast<size_t>(n), refine::Side::ocean);
    side_id.resize(static_cast<size_t>(n), -1);
    std::vector<int32_t> fresh;
    for (int32_t v = 0; v < n; ++v)
        if (tri.in_triangulation(v) && side_id[v] != tri.id(v)) fresh.push_back(v), side_id[v] = -1;
    // In slot order, each seeing the ones before it: deterministic.
    for (int32_t v : fresh) side[v] = inferred_side(*this, v), side_id[v] = tri.id(v);
    // A vertex on the land beside the coast may have had a coastline come
    // into its cell as the mesh changed around it (it or a neighbour moved,
    // or its link changed, since the last refresh): coastal from then on
    // (its cell may be an ocean one). Only one with a neighbour off the land
    // can: the coastline passes between them.
    const int32_t since = sides_clock;
    auto changed_since = [&](int32_t u) { return static_cast<size_t>(u) >= changed_at.size() || changed_at[u] >= since; };
    const std::vector<int32_t> entered = ctx.collect_in_order<int32_t>(n, 4096, [&](int64_t i, std::vector<int32_t> &out) {
        const int32_t v = static_cast<int32_t>(i);
        if (!tri.in_triangulation(v) || on_segment[v] >= 0 || side[v] != refine::Side::land) return;
        bool beside = false, changed = changed_since(v);
        tri.for_each_neighbour(v, [&](int32_t w) {
            beside = beside || side[w] != refine::Side::land;
            changed = changed || changed_since(w);
        });
        if (beside && changed && coastline_enters_cell(*this, v)) out.push_back(v);
    });
    for (int32_t v : entered) side[v] = refine::Side::coastal;
    sides_clock = clock;
}

// (A vertex made since the last refresh is off the land also where a
// coastline comes into its cell, as the next refresh would find.)
bool MeshState::off_land(int32_t v) const {
    if (!gamma || arcs.size() == 0) return true;
    if (known(side_id, tri, v)) return side[v] != refine::Side::land;
    return inferred_side(*this, v) != refine::Side::land || coastline_enters_cell(*this, v);
}

// In the shape phase the floor pass lifts the edges below this many floors:
// every move stops at the floor, and where the moves pin edges at it the
// mesh is too crowded to shape (coast + rivers 60 km: obtuse triangles
// 83 -> 51, and none left below the floor against 2; 1.05: 58, 1.2: 54).
constexpr double kShapeMargin = 1.1;

double MeshState::floor_to_lift() const {
    return options.ocean_floor * (weighing ? 1.0 : kShapeMargin);
}

double MeshState::floor_slack(int32_t v, const Ring &ring, const int32_t *link) const {
    const double floor = options.ocean_floor;
    if (!(floor > 0) || side_id.empty()) return kInfinity;
    const Vec3 x = tri.direction(v);
    double slack = kInfinity;
    for (int k = 0; k < ring.m; ++k) {
        const double least = floor * 0.5 * (static_cast<double>(h_at[v]) + static_cast<double>(h_at[link[k]]));
        slack = std::min(slack, geom::norm(x - ring.at(k).x) - least);
    }
    return slack;
}

namespace {

// move_keeps_floor over v's neighbours, each given to `each` as (slot, direction).
template <class ForEachNeighbour>
bool keeps_floor_among(const MeshState &s, int32_t v, const Vec3 &to, double slack, ForEachNeighbour &&each) {
    const double floor = s.options.ocean_floor;
    if (!(floor > 0) || s.side_id.empty()) return true;
    const Vec3 x = s.tri.direction(v);
    if (slack >= 0 && geom::norm(to - x) <= slack) return true;
    int v_off_land = -1;  // not looked up yet
    bool keeps = true;
    each([&](int32_t w, const Vec3 &y) {
        if (!keeps) return;
        const double now = geom::norm(to - y);
        const double least = floor * 0.5 * (static_cast<double>(s.h_at[v]) + static_cast<double>(s.h_at[w]));
        if (now >= least || now >= geom::norm(x - y)) return;
        if (v_off_land < 0) v_off_land = s.off_land(v);
        keeps = !v_off_land || !s.off_land(w);
    });
    return keeps;
}

}  // namespace

bool MeshState::move_keeps_floor(int32_t v, const Vec3 &to) const {
    return keeps_floor_among(*this, v, to, -1, [&](auto &&f) {
        tri.for_each_neighbour(v, [&](int32_t w) { f(w, tri.direction(w)); });
    });
}

bool MeshState::move_keeps_floor(int32_t v, const Vec3 &to, double slack, const Ring &ring,
                                 const int32_t *link) const {
    return keeps_floor_among(*this, v, to, slack, [&](auto &&f) {
        for (int k = 0; k < ring.m; ++k) f(link[k], ring.at(k).x);
    });
}

// (The sides are looked up only for the edges that are short: most are not.)
int MeshState::below_floor_at(const std::vector<int32_t> &vertices, double floor) const {
    if (!keeps_floor()) return 0;
    int below = 0;
    for (int32_t v : vertices) {
        if (!tri.in_triangulation(v)) continue;
        const Vec3 x = tri.direction(v);
        tri.for_each_neighbour(v, [&](int32_t w) {
            const double h = 0.5 * (static_cast<double>(h_at[v]) + static_cast<double>(h_at[w]));
            if (geom::norm(x - tri.direction(w)) >= floor * h) return;
            // (An edge between two of `vertices` counts at its lower slot.)
            if (w < v && std::find(vertices.begin(), vertices.end(), w) != vertices.end()) return;
            below += off_land(v) && off_land(w);
        });
    }
    return below;
}

}  // namespace um::optim::detail
