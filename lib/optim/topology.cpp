#include "optim/topology.hpp"

#include <algorithm>
#include <cmath>

#include "core/growth.hpp"
#include "geom/predicates.hpp"
#include "optim/chord_bounds.hpp"

namespace um::optim::detail {

// The edges whose length over the spacing is below `below` or above `above`.
std::vector<Topology::EdgeRatio> Topology::edge_ratios(double below, double above) const {
    return s_.ctx.collect_in_order<EdgeRatio>(s_.tri.triangle_slots(), 16384, [&](int64_t t, std::vector<EdgeRatio> &out) {
        const int32_t ti = static_cast<int32_t>(t);
        if (s_.tri.is_free(ti)) return;
        for (int k = 0; k < 3; ++k) {
            if (s_.tri.neighbour(ti, k) < ti) continue;  // each edge once
            const int32_t a = s_.tri.vertex(ti, (k + 1) % 3), b = s_.tri.vertex(ti, (k + 2) % 3);
            if (s_.cover(a) || s_.cover(b)) continue;
            const double mean_h = 0.5 * (s_.h_at[a] + s_.h_at[b]);
            const ChordBounds bounds(s_.tri.lifted(a), s_.tri.lifted(b));
            if (bounds.surely_at_least(below * mean_h) && bounds.surely_below(above * mean_h)) continue;
            const double ratio = geom::norm(s_.tri.direction(a) - s_.tri.direction(b)) / mean_h;
            if (ratio < below || ratio > above) out.push_back({ratio, std::min(a, b), std::max(a, b)});
        }
    });
}

// Section 6.4, collapse and refinement from one edge scan.
std::pair<int64_t, int64_t> Topology::collapse_and_split() {
    const double below = s_.options.collapse_ratio > 0 ? s_.options.collapse_ratio : -kInfinity;
    std::vector<EdgeRatio> edges = edge_ratios(below, s_.options.split_ratio);
    const int64_t collapsed = collapse_short_edges(edges);
    if (collapsed > 0) edges = edge_ratios(-kInfinity, s_.options.split_ratio);
    return {collapsed, split_long_edges(std::move(edges))};
}

// An edge much shorter than h, between two vertices off Gamma, loses its
// later slot, the other moving to the edge's midpoint. Shortest first, one
// change per neighbourhood per pass.
int64_t Topology::collapse_short_edges(std::vector<Topology::EdgeRatio> edges) {
    if (s_.options.collapse_ratio <= 0) return 0;
    edges.erase(std::remove_if(edges.begin(), edges.end(),
                               [&](const EdgeRatio &e) { return !(e.ratio < s_.options.collapse_ratio); }),
                edges.end());
    std::sort(edges.begin(), edges.end(), [](const EdgeRatio &x, const EdgeRatio &y) {
        return x.ratio != y.ratio ? x.ratio < y.ratio : (x.a != y.a ? x.a < y.a : x.b < y.b);
    });
    std::vector<uint8_t> locked(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    int64_t done = 0;
    for (const EdgeRatio &e : edges) {
        if (!s_.tri.in_triangulation(e.a) || !s_.tri.in_triangulation(e.b)) continue;
        // Gamma keeps its vertices, and taking out the vertex off it next
        // to one leaves that one a spoke fewer on its side (Mid-Atlantic
        // case: 2 -> 4 triangles not holding their orthocentre).
        if (s_.on_segment[e.a] >= 0 || s_.on_segment[e.b] >= 0) continue;
        // (A move beside a regional mesh's cover might hide one of its vertices.)
        if (s_.beside_cover(e.a) || s_.beside_cover(e.b)) continue;
        const int32_t gone = e.b, kept = e.a;  // e.a < e.b
        if (!s_.removable(gone)) continue;
        const Vec3 mid = geom::normalized(s_.tri.direction(e.a) + s_.tri.direction(e.b));
        if (leaves_long_edge(mid, static_cast<double>(s_.h_at[kept]), {gone, kept})) continue;
        if (!s_.lock_neighbourhood({e.a, e.b}, locked)) continue;
        s_.tri.remove(gone);
        for (int32_t u : s_.tri.move(kept, mid)) s_.changed_at[u] = s_.clock;
        s_.h_at[kept] = static_cast<float>(s_.h(s_.tri.direction(kept)));
        s_.changed_at[kept] = s_.clock;
        ++done;
    }
    return done;
}

// Section 6.4: an edge much longer than h gets a vertex at its midpoint,
// with the mean of its ends' weights. Longest first, one change per
// neighbourhood per pass.
int64_t Topology::split_long_edges(std::vector<Topology::EdgeRatio> edges) {
    edges.erase(std::remove_if(edges.begin(), edges.end(),
                               [&](const EdgeRatio &e) { return !(e.ratio > s_.options.split_ratio); }),
                edges.end());
    std::sort(edges.begin(), edges.end(), [](const EdgeRatio &x, const EdgeRatio &y) {
        return x.ratio != y.ratio ? x.ratio > y.ratio : (x.a != y.a ? x.a < y.a : x.b < y.b);
    });
    std::vector<uint8_t> locked(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    int64_t done = 0;
    for (const EdgeRatio &e : edges) {
        if (!s_.tri.in_triangulation(e.a) || !s_.tri.in_triangulation(e.b)) continue;
        // Gamma gets its vertices from the refinement (a midpoint off it
        // would sit on it, with a degree of 4, and be taken out again).
        if (s_.on_segment[e.a] >= 0 && s_.on_segment[e.b] >= 0) continue;
        if (leaves_short_edge(e.a, e.b)) continue;
        if (!s_.lock_neighbourhood({e.a, e.b}, locked)) continue;
        done += insert_between(e.a, e.b) >= 0;
        locked.resize(static_cast<size_t>(s_.tri.vertex_slots()), 1);
    }
    return done;
}

// Whether a vertex at x (spacing h_x) joined to the links of `ends` would
// have an edge longer than split_ratio h: a collapse that makes one is not
// made, else the split that follows would undo it (and the next collapse
// redo it, each outer iteration, so that the schedule never settles).
bool Topology::leaves_long_edge(const Vec3 &x, double h_x, std::initializer_list<int32_t> ends) const {
    bool long_edge = false;
    for (int32_t v : ends)
        s_.tri.for_each_in_star(v, [&](int32_t t) {
            for (int k = 0; k < 3; ++k) {
                const int32_t u = s_.tri.vertex(t, k);
                if (std::find(ends.begin(), ends.end(), u) != ends.end()) continue;
                const double h = 0.5 * (h_x + static_cast<double>(s_.h_at[u]));
                long_edge = long_edge || geom::norm(x - s_.tri.direction(u)) > s_.options.split_ratio * h;
            }
        });
    return long_edge;
}

// Whether the midpoint of the edge (a, b) is nearer than collapse_ratio h
// to an apex of the edge: such a split is not made (the collapse that
// would follow undoes it).
bool Topology::leaves_short_edge(int32_t a, int32_t b) const {
    const Vec3 mid = geom::normalized(s_.tri.direction(a) + s_.tri.direction(b));
    const double h = 0.5 * (static_cast<double>(s_.h_at[a]) + static_cast<double>(s_.h_at[b]));
    bool short_edge = false;
    s_.tri.for_each_in_star(a, [&](int32_t t) {
        const int i = s_.tri.local_index(t, a);
        if (s_.tri.vertex(t, (i + 1) % 3) != b && s_.tri.vertex(t, (i + 2) % 3) != b) return;
        for (int k = 0; k < 3; ++k) {
            const int32_t u = s_.tri.vertex(t, k);
            if (u != a && u != b)
                short_edge = short_edge || geom::norm(mid - s_.tri.direction(u)) < s_.options.collapse_ratio * h;
        }
    });
    return short_edge;
}

// A new vertex at the midpoint of (a, b), with the mean of their weights;
// its slot, or -1 if it came out hidden or as the next passes would take
// it out again (of degree 4, for the valence repair; with an edge below the
// ocean floor): it is then removed again.
int32_t Topology::insert_between(int32_t a, int32_t b) {
    const Vec3 mid = geom::normalized(s_.tri.direction(a) + s_.tri.direction(b));
    const double w = 0.5 * (s_.tri.weight(a) + s_.tri.weight(b));
    std::vector<int32_t> buried;
    const int32_t v = s_.tri.insert(mid, w, s_.next_id++, &buried, s_.tri.star(a).front());
    s_.grow_slots();
    if (s_.tri.in_triangulation(v)) s_.h_at[v] = static_cast<float>(s_.h(mid));
    if (!s_.tri.in_triangulation(v) || s_.tri.link(v).size() <= 4 || !s_.clear_of_floor(v) || s_.beside_cover(v) ||
        s_.any_cover(buried)) {
        take_back(v, buried);
        return -1;
    }
    for (int32_t u : buried) s_.changed_at[u] = s_.clock;
    s_.changed_at[v] = s_.clock;
    for (int32_t t : s_.tri.star(v))
        for (int k = 0; k < 3; ++k) s_.changed_at[s_.tri.vertex(t, k)] = s_.clock;
    return v;
}

// Vertices of degree 4 or less crowd their neighbours (their power cells are
// small) and those of degree 8 or more leave a gap: the first are removed,
// the second split in two. Vertices
// on Gamma are left alone. One change per neighbourhood per pass, in slot
// order.
int64_t Topology::improve_valence() {
    std::vector<uint8_t> locked(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    int64_t done = 0;
    const int32_t n = s_.tri.vertex_slots();
    const std::vector<int32_t> degree = vertex_degrees(s_.ctx, s_.tri);
    for (int32_t v = 0; v < n; ++v) {
        if (!s_.tri.in_triangulation(v) || s_.on_segment[v] >= 0) continue;
        if (degree[v] > 4 && degree[v] < 8) continue;
        if (s_.beside_cover(v)) continue;  // (after the cheap tests: it looks at the domain)
        std::vector<int32_t> st = s_.tri.star(v);  // now: earlier changes may have altered it
        const int degree_now = static_cast<int>(st.size());
        if (degree_now > 4 && degree_now < 8) continue;
        if (!s_.lock_neighbourhood({v}, locked)) continue;
        if (degree_now <= 4) {
            if (!s_.removable(v)) continue;
            for (int32_t t : st)  // before removal frees these triangles
                for (int k = 0; k < 3; ++k) s_.changed_at[s_.tri.vertex(t, k)] = s_.clock;
            s_.tri.remove(v);
            ++done, ++s_.stats.collapses;
            continue;
        }
        const bool split = split_vertex(v, st);
        done += split, s_.stats.splits += split;
        locked.resize(static_cast<size_t>(s_.tri.vertex_slots()), 1);
    }
    return done;
}

// Takes out vertex v, just inserted, and puts back what its insertion hid.
void Topology::take_back(int32_t v, const std::vector<int32_t> &buried) {
    const int32_t near = s_.tri.remove(v);
    for (int32_t u : buried)
        if (!s_.tri.in_triangulation(u) && !s_.tri.is_removed(u)) s_.tri.restore_hidden(u, near);
}

// Splits a vertex of high degree into two a quarter of its longest spoke
// either side of where it was, along that spoke: each of the two takes
// about half of the old link (degree ~ 6 for a link of 8). Not where the
// two would have more edges off the land below the floor the floor pass
// lifts than v had: that pass would take one out again, and the next
// repair split it again, every outer iteration (a box's ring at 8 km ran
// its shape phase to the limit). Off the land, two closer than that floor
// are refused before any change. A split not made leaves the mesh as it
// was. Whether the split was made.
bool Topology::split_vertex(int32_t v, const std::vector<int32_t> &star) {
    Vec3 far{};
    double far_l = -1;
    for (int32_t t : star)
        for (int k = 0; k < 3; ++k) {
            const int32_t u = s_.tri.vertex(t, k);
            const double l = geom::norm(s_.tri.direction(u) - s_.tri.direction(v));
            if (u != v && l > far_l) far_l = l, far = s_.tri.direction(u);
        }
    const Vec3 x = s_.tri.direction(v), along = 0.25 * (far - x);
    const Vec3 back = geom::normalized(x - along), ahead = geom::normalized(x + along);
    const double floor = s_.floor_to_lift();
    if (s_.keeps_floor() && s_.off_land(v) && geom::norm(ahead - back) < floor * s_.h_at[v]) return false;
    const Vec3 was = s_.tri.lifted(v);
    const float h_was = s_.h_at[v];
    const int below_was = s_.below_floor_at({v}, floor);
    const std::vector<int32_t> hidden_by_move = s_.tri.move(v, back);
    auto put_back = [&] {  // v where it was, bit for bit, and what its move hid
        s_.tri.place(v, was);
        s_.h_at[v] = h_was;
        const int32_t near = s_.tri.star(v).front();
        for (int32_t u : hidden_by_move)
            if (u != v && !s_.tri.in_triangulation(u) && !s_.tri.is_removed(u)) s_.tri.restore_hidden(u, near);
        return false;
    };
    if (!s_.tri.in_triangulation(v)) return put_back();  // (its own cell emptied)
    s_.h_at[v] = static_cast<float>(s_.h(s_.tri.direction(v)));
    std::vector<int32_t> buried;
    const int32_t added = s_.tri.insert(ahead, s_.tri.weight(v), s_.next_id++, &buried, s_.tri.star(v).front());
    s_.grow_slots();
    if (!s_.tri.in_triangulation(added)) {
        s_.tri.remove(added);
        return put_back();
    }
    s_.h_at[added] = static_cast<float>(s_.h(ahead));
    // (Nothing added beside a regional mesh's cover.)
    if (s_.beside_cover(added) || s_.any_cover(buried) || s_.below_floor_at({v, added}, floor) > below_was) {
        take_back(added, buried);
        return put_back();
    }
    for (int32_t u : hidden_by_move) s_.changed_at[u] = s_.clock;
    for (int32_t u : buried) s_.changed_at[u] = s_.clock;
    s_.changed_at[v] = s_.clock;
    for (int32_t t : s_.tri.star(added))
        for (int k = 0; k < 3; ++k) s_.changed_at[s_.tri.vertex(t, k)] = s_.clock;
    return true;
}

// A quad whose diagonal joins two vertices of degree 7 (or more) between two
// of degree 5 (or less) becomes four of degree 6 when flipped - the pairs
// of defects that smoothing alone leaves as the worst triangles of a
// relaxed mesh. The flip is kept only if a few ODT steps of the quad's
// vertices make the new diagonal regular (the triangulation stays the
// regular triangulation of its points); otherwise it is undone. Vertices
// on Gamma are left alone. Serial, in slot order, one flip per
// neighbourhood per pass.
int64_t Topology::flip_for_valence() {
    const int32_t n = s_.tri.vertex_slots();
    std::vector<int32_t> degree = vertex_degrees(s_.ctx, s_.tri);
    auto deviation = [&](int32_t v, int change) { return std::abs(degree[v] + change - 6); };
    std::vector<uint8_t> locked(static_cast<size_t>(n), 0);
    int64_t done = 0;
    for (int32_t t = 0; t < s_.tri.triangle_slots(); ++t) {
        if (s_.tri.is_free(t)) continue;
        for (int k = 0; k < 3; ++k) {
            const int32_t u = s_.tri.neighbour(t, k);
            if (u < t) continue;
            // The edge (b, c) of t, apex a; d the apex across it.
            const int32_t a = s_.tri.vertex(t, k), b = s_.tri.vertex(t, (k + 1) % 3), c = s_.tri.vertex(t, (k + 2) % 3);
            // The flip lowers the deviation by 2 or more only if three of a
            // (<= 5), b (>= 7), c (>= 7) and d (<= 5) gain: two of the first
            // three at least (d is read only then).
            if ((degree[a] <= 5) + (degree[b] >= 7) + (degree[c] >= 7) < 2) continue;
            int32_t d = -1;
            for (int j = 0; j < 3; ++j)
                if (s_.tri.vertex(u, j) != b && s_.tri.vertex(u, j) != c) d = s_.tri.vertex(u, j);
            const int32_t quad[4] = {a, b, c, d};
            bool free = true;
            for (int32_t v : quad) free &= s_.on_segment[v] < 0 && !locked[v] && !s_.cover(v);
            if (!free) continue;
            const int before = deviation(a, 0) + deviation(b, 0) + deviation(c, 0) + deviation(d, 0);
            const int after = deviation(a, 1) + deviation(b, -1) + deviation(c, -1) + deviation(d, 1);
            if (before - after < 2 || degree[b] <= 4 || degree[c] <= 4) continue;
            Vec3 saved[4];  // the stored points, bit for bit: the flip back must be regular again
            for (int i = 0; i < 4; ++i) saved[i] = s_.tri.lifted(quad[i]);
            if (!s_.tri.flip(t, k)) continue;  // t = (a, b, d), u = (d, c, a)
            if (!relax_into_regularity(quad)) {
                for (int i = 0; i < 4; ++i) s_.tri.set_lifted(quad[i], saved[i]);
                s_.tri.flip(t, 1);  // the edge (d, a) of (a, b, d): back to (b, c)
                continue;
            }
            ++degree[a], --degree[b], --degree[c], ++degree[d];
            for (int32_t v : quad) {
                s_.h_at[v] = static_cast<float>(s_.h(s_.tri.direction(v)));
                for (int32_t s : s_.tri.star(v))
                    for (int j = 0; j < 3; ++j) {
                        locked[s_.tri.vertex(s, j)] = 1;
                        s_.changed_at[s_.tri.vertex(s, j)] = s_.clock;
                    }
            }
            ++done;
            break;  // t changed
        }
    }
    s_.stats.flips += done;
    return done;
}

// Moves the four vertices towards their ODT targets in the current topology
// (a few rounds) until every edge around them is locally regular and every
// triangle around them still faces outwards.
bool Topology::relax_into_regularity(const int32_t (&quad)[4]) {
    for (int round = 0; round < 4; ++round) {
        for (int32_t v : quad) s_.set_generator(v, {s_.star_odt_point(v), s_.generator(v).s});
        bool good = true;
        for (int32_t v : quad)
            for (int32_t s : s_.tri.star(v)) {
                const Vec3 qa = s_.tri.lifted(s_.tri.vertex(s, 0)), qb = s_.tri.lifted(s_.tri.vertex(s, 1)),
                           qc = s_.tri.lifted(s_.tri.vertex(s, 2));
                good &= geom::orient_origin(qa.data(), qb.data(), qc.data()) > 0;
                for (int j = 0; j < 3 && good; ++j) good &= s_.tri.is_locally_regular(s, j);
            }
        if (good) return true;
    }
    return false;
}

}  // namespace um::optim::detail
