#include "optim/ocean_floor.hpp"

#include <algorithm>
#include <cmath>

#include "optim/chord_bounds.hpp"
#include "optim/slide.hpp"
#include "refine/restricted.hpp"

namespace um::optim::detail {

namespace {

// The scan's cheap ratio (chord over the ends' mean h) is within a few per
// cent of the report's measure (arc over h at xEdge) where h is smooth:
// edges below this many floors get that measure.
constexpr double kScanMargin = 1.2;
// A vertex pushed off a too near neighbour lands this many floors from it.
constexpr double kPushPast = 1.02;

}  // namespace

// The edges between two generators off the land shorter than floor h,
// shortest first (ties by slots).
std::vector<OceanFloor::ShortEdge> OceanFloor::short_ocean_edges() const {
    const double floor = s_.floor_to_lift();
    std::vector<ShortEdge> edges =
        s_.ctx.collect_in_order<ShortEdge>(s_.tri.triangle_slots(), 16384, [&](int64_t t, std::vector<ShortEdge> &out) {
            const int32_t ti = static_cast<int32_t>(t);
            if (s_.tri.is_free(ti)) return;
            for (int k = 0; k < 3; ++k) {
                if (s_.tri.neighbour(ti, k) < ti) continue;  // each edge once
                const int32_t a = s_.tri.vertex(ti, (k + 1) % 3), b = s_.tri.vertex(ti, (k + 2) % 3);
                if (s_.cover(a) || s_.cover(b)) continue;
                const double mean_h = 0.5 * (s_.h_at[a] + s_.h_at[b]), limit = kScanMargin * floor * mean_h;
                if (ChordBounds(s_.tri.lifted(a), s_.tri.lifted(b)).surely_at_least(limit)) continue;
                const Vec3 xa = s_.tri.direction(a), xb = s_.tri.direction(b);
                const double chord = geom::norm(xa - xb);
                if (!(chord < limit)) continue;
                if (!s_.off_land(a) || !s_.off_land(b)) continue;
                // Until the mends, the guards' measure (MeshState::below_floor_at):
                // an edge a split or a move let through is not taken out again
                // (which the split would undo, every iteration). After them, the
                // report's: the arc over h where the dual edge crosses (xEdge).
                const double ratio = stage_ != Stage::after_mends
                                         ? chord / mean_h
                                         : geom::arc_of_chord(chord) / s_.h(s_.tri.edge_orthocentre(ti, k));
                const bool support = !s_.weighing && (s_.supports_corner(a) || s_.supports_corner(b));
                if (ratio < (support ? s_.options.ocean_floor : floor))
                    out.push_back({ratio, std::min(a, b), std::max(a, b)});
            }
        });
    std::sort(edges.begin(), edges.end(), [](const ShortEdge &x, const ShortEdge &y) {
        return x.ratio != y.ratio ? x.ratio < y.ratio : (x.a != y.a ? x.a < y.a : x.b < y.b);
    });
    return edges;
}

int64_t OceanFloor::count_below() {
    if (!(s_.options.ocean_floor > 0)) return 0;
    s_.refresh_sides();
    return static_cast<int64_t>(short_ocean_edges().size());
}

OceanFloor::Lifted OceanFloor::lift(Stage stage) {
    if (!(s_.options.ocean_floor > 0)) return {};
    stage_ = stage;
    moved_ = 0;
    s_.refresh_sides();
    std::vector<uint8_t> locked(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    int64_t lifted = 0;
    for (const ShortEdge &e : short_ocean_edges()) {
        if (!s_.tri.in_triangulation(e.a) || !s_.tri.in_triangulation(e.b)) continue;
        const std::vector<int32_t> region = s_.closed_stars({e.a, e.b});
        if (!MeshState::claim(region, locked)) continue;
        const bool done = lift_edge(e);
        lifted += done;
        if (!done)  // nothing changed there: free for the next edge
            for (int32_t u : region) locked[u] = 0;
    }
    const Lifted l{lifted - moved_, moved_};
    s_.stats.floor_removals += l.taken_out, s_.stats.moves += l.moved;
    return l;
}

bool OceanFloor::lift_edge(const ShortEdge &e) {
    fixing_ = e.ratio;
    return lift_keeping_gamma(e) || lift_at_any_cost_to_gamma(e);
}

bool OceanFloor::lift_keeping_gamma(const ShortEdge &e) {
    const bool a_on = s_.on_segment[e.a] >= 0, b_on = s_.on_segment[e.b] >= 0;
    const int32_t off = a_on ? e.b : e.a, on = a_on ? e.a : e.b;
    // A push only where no weight sweep follows that would move it back
    // (and the next pass push it again): in the shape phase, or after the
    // mends. (A fixed boundary keeps Gamma's vertices where they are.)
    const bool may_push = !s_.weighing || stage_ == Stage::after_mends;
    // (A slide along Gamma only after the mends: in the shape phase the
    // corner passes put the vertices back, every iteration.)
    const bool may_slide = stage_ == Stage::after_mends && !s_.options.fix_boundary;
    return !a_on && !b_on ? merge_at_midpoint(e.a, e.b) || (may_push && (push_away(e.b, e.a) || push_away(e.a, e.b)))
           : a_on != b_on ? take_out(off) || (may_push && push_away(off, on)) || (may_slide && slide_apart(on, off))
           : s_.options.fix_boundary
               ? false
               : merge_along_gamma(e.a, e.b) || take_out_of_gamma(e.b) || take_out_of_gamma(e.a) ||
                     (may_slide && (slide_apart(e.b, e.a) || slide_apart(e.a, e.b)));
}

// Either end taken out, the one off Gamma first, Gamma free to pass through
// more cells (a fixed boundary keeps Gamma's vertices); where either hole
// would leave a long edge (the two shores of a channel narrower than the
// floor), the two merge into one off Gamma at the edge's midpoint.
bool OceanFloor::lift_at_any_cost_to_gamma(const ShortEdge &e) {
    const bool only_b_on = s_.on_segment[e.b] >= 0 && s_.on_segment[e.a] < 0;
    const int32_t first = only_b_on ? e.a : e.b, second = only_b_on ? e.b : e.a;
    auto may_go = [&](int32_t v) { return s_.on_segment[v] < 0 || !s_.options.fix_boundary; };
    gamma_may_spread_ = true;
    const bool done = (may_go(first) && take_out(first)) || (may_go(second) && take_out(second)) ||
                      (stage_ != Stage::iteration && may_go(first) && may_go(second) && merge_off_gamma(second, first));
    gamma_may_spread_ = false;
    return done;
}

// What a removal is judged against: the region it may change (the closed
// stars of the vertices involved) as it was.
struct OceanFloor::Before {
    std::vector<int32_t> link;  // the neighbours of the vertices involved
    int crossings = 0;          // the spokes of their stars crossing Gamma
    int obtuse = 0;             // the obtuse triangles touching the region
    int off_centre = 0;         // ... and those not holding their orthocentre
    int below_floor = 0;        // the edges off the land below the floor at the link and the vertices
};

int OceanFloor::off_centre_touching(const std::vector<int32_t> &vertices) const {
    int off = 0;
    for (int32_t t : s_.tri.triangles_around(vertices))
        off += staggering_score(s_.generator(s_.tri.vertex(t, 0)), s_.generator(s_.tri.vertex(t, 1)),
                                s_.generator(s_.tri.vertex(t, 2))) < 0;
    return off;
}

OceanFloor::Before OceanFloor::before(std::initializer_list<int32_t> vertices) const {
    Before b;
    for (int32_t v : vertices)
        for (int32_t u : s_.tri.link(v))
            if (std::find(vertices.begin(), vertices.end(), u) == vertices.end() &&
                std::find(b.link.begin(), b.link.end(), u) == b.link.end())
                b.link.push_back(u);
    auto at = [&](int32_t u) { return s_.generator(u); };
    b.crossings = s_.stars_gamma_crossings(b.link.data(), static_cast<int>(b.link.size()), at, false);
    const std::vector<int32_t> region = s_.closed_stars(vertices);
    b.obtuse = s_.obtuse_touching(region);
    b.off_centre = off_centre_touching(region);
    std::vector<int32_t> involved = b.link;
    involved.insert(involved.end(), vertices.begin(), vertices.end());
    b.below_floor = s_.below_floor_at(involved);
    return b;
}

// After the removal: Gamma in no more cells off it (but for the last
// resort), the vertex that moved (kept) with no edge shorter than the one
// being lifted, no edge across the hole longer than split_ratio h (the split
// that would follow would put a vertex back) nor more edges off the land
// below the floor around, and once the weights are tuned no more obtuse
// triangles and (but just before the mends, which re-tune them) none more
// not holding its orthocentre. `kept`, when not -1, is a vertex that moved
// and stays.
bool OceanFloor::acceptable(const Before &b, int32_t kept) const {
    std::vector<int32_t> region = b.link;
    if (kept >= 0) region.push_back(kept);
    auto at = [&](int32_t u) { return s_.generator(u); };
    const int crossings = s_.stars_gamma_crossings(region.data(), static_cast<int>(region.size()), at, false);
    if (b.crossings < 0 || crossings < 0 || (crossings > b.crossings && !gamma_may_spread_)) return false;
    if (kept >= 0 && shortest_edge(kept) < fixing_) return false;
    if (leaves_long_edge(region)) return false;
    if (s_.below_floor_at(region) > b.below_floor) return false;
    if (!s_.weighing) return true;
    // Triangles not holding their orthocentre the mends re-tune (in an outer
    // iteration a split could undo the removal every iteration); the last
    // resort leaves them the obtuse ones too.
    if (stage_ == Stage::before_mends && gamma_may_spread_) return true;
    std::sort(region.begin(), region.end());
    return s_.obtuse_touching(region) <= b.obtuse &&
           (stage_ == Stage::before_mends || off_centre_touching(region) <= b.off_centre);
}

// The shortest edge of v over h (the scan's chord measure).
double OceanFloor::shortest_edge(int32_t v) const {
    double shortest = kInfinity;
    const Vec3 x = s_.tri.direction(v);
    s_.tri.for_each_neighbour(v, [&](int32_t w) {
        const double h = 0.5 * (static_cast<double>(s_.h_at[v]) + static_cast<double>(s_.h_at[w]));
        shortest = std::min(shortest, geom::norm(x - s_.tri.direction(w)) / h);
    });
    return shortest;
}

void OceanFloor::mark_changed(const std::vector<int32_t> &link) {
    for (int32_t u : link) s_.changed_at[u] = s_.clock;
}

// A vertex that moved and stays: its spacing read again, it and its link
// marked for the sweeps.
void OceanFloor::keep_moved(int32_t v, const std::vector<int32_t> &link) {
    s_.h_at[v] = static_cast<float>(s_.h(s_.tri.direction(v)));
    s_.changed_at[v] = s_.clock;
    mark_changed(link);
}


// Two vertices off Gamma: `gone` is taken out and `kept` moves to the
// edge's midpoint (as the collapse of short edges does).
bool OceanFloor::merge_at_midpoint(int32_t kept, int32_t gone) {
    if (!s_.removable(gone)) return false;
    const Before b = before({kept, gone});
    const Vec3 was = s_.tri.lifted(kept);
    const Vec3 mid = geom::normalized(s_.tri.direction(kept) + s_.tri.direction(gone));
    const int32_t hint = s_.tri.remove(gone);
    if (!s_.tri.move(kept, mid).empty() || !acceptable(b, kept)) {
        s_.tri.place(kept, was);
        s_.tri.restore_removed(gone, hint);
        return false;
    }
    keep_moved(kept, b.link);
    return true;
}

// merge_at_midpoint where either may be on Gamma: the one kept leaves it.
bool OceanFloor::merge_off_gamma(int32_t kept, int32_t gone) {
    const int32_t segment_was = s_.on_segment[kept];
    s_.on_segment[kept] = -1;
    if (merge_at_midpoint(kept, gone)) return true;
    s_.on_segment[kept] = segment_was;
    return false;
}

// A vertex off Gamma taken out where its neighbour on Gamma is too near.
bool OceanFloor::take_out(int32_t v) {
    if (!s_.removable(v)) return false;
    const Before b = before({v});
    const int32_t hint = s_.tri.remove(v);
    if (!acceptable(b, -1)) {
        s_.tri.restore_removed(v, hint);
        return false;
    }
    mark_changed(b.link);
    return true;
}

// A vertex off Gamma that cannot go (its removal would leave a poor
// triangle or a long edge) moves away from its too near neighbour to just
// past floor h from it.
// Where a push puts v: on the arc from `from` through v, just past floor h
// from `from`. False where that is further than the stars a removal may
// open (on a mesh of a few huge cells a push would go round the sphere).
bool OceanFloor::push_target(int32_t v, int32_t from, Vec3 &to) const {
    const double reach = kPushPast * s_.options.ocean_floor * s_.h_at[v];
    if (!s_.removable(v) || !(reach < MeshState::kLargestRemovableStar)) return false;
    const Vec3 x = s_.tri.direction(v), y = s_.tri.direction(from);
    const Vec3 away = geom::normalized(x - geom::dot(x, y) * y);  // tangent at y towards x
    to = geom::normalized(std::cos(reach) * y + std::sin(reach) * away);
    return true;
}

bool OceanFloor::push_away(int32_t v, int32_t from) {
    Vec3 to;
    if (!push_target(v, from, to)) return false;
    const Before b = before({v});
    const Vec3 was = s_.tri.lifted(v);
    if (!s_.tri.move(v, to).empty() || !acceptable(b, v)) {
        s_.tri.place(v, was);
        return false;
    }
    keep_moved(v, b.link);
    ++moved_;
    return true;
}

// A vertex on Gamma slid along its part away from a too near neighbour,
// to the point of the part nearest to where a push would put it (just past
// floor h from the neighbour), where every edge along Gamma around stays.
bool OceanFloor::slide_apart(int32_t v, int32_t from) {
    Vec3 to;
    if (!push_target(v, from, to)) return false;
    const auto gamma_edges = s_.gamma_edges_among(s_.closed_stars({v}));
    const Before b = before({v});
    const Vec3 was = s_.tri.lifted(v);
    const int32_t segment_was = s_.on_segment[v];
    const PointOnGamma p = slide_along(*s_.gamma, segment_was, to);
    const bool hid = !s_.tri.move(v, p.x).empty();
    s_.on_segment[v] = static_cast<int32_t>(p.segment);
    if (hid || !s_.gamma_edges_stay(gamma_edges) || !acceptable(b, v)) {
        s_.tri.place(v, was);
        s_.on_segment[v] = segment_was;
        return false;
    }
    keep_moved(v, b.link);
    ++moved_;
    return true;
}

// Two neighbours along one part of Gamma: one goes and the other moves to
// the point of the part nearest their midpoint (a collapse along Gamma:
// both chords to their outer neighbours stay short).
bool OceanFloor::merge_along_gamma(int32_t a, int32_t b) {
    int32_t along[2];
    if (!neighbours_along_gamma(a, along) || (along[0] != b && along[1] != b)) return false;
    if (!s_.removable(b)) return false;
    const auto gamma_edges = s_.gamma_edges_among(s_.closed_stars({a, b}));
    const Before bf = before({a, b});
    const Vec3 was = s_.tri.lifted(a);
    const int32_t segment_was = s_.on_segment[a];
    const PointOnGamma p = slide_along(*s_.gamma, s_.on_segment[a],
                                       geom::normalized(s_.tri.direction(a) + s_.tri.direction(b)));
    const int32_t hint = s_.tri.remove(b);
    const bool hid = !s_.tri.move(a, p.x).empty();
    s_.on_segment[a] = static_cast<int32_t>(p.segment);
    if (hid || !s_.gamma_edges_stay(gamma_edges, b) || !acceptable(bf, a)) {
        s_.tri.place(a, was);
        s_.on_segment[a] = segment_was;
        s_.tri.restore_removed(b, hint);
        return false;
    }
    keep_moved(a, bf.link);
    return true;
}

// A vertex on Gamma between two neighbours on the same part of it (the
// nearest before and after it along the part), taken out where the chord
// between those two is then an edge within floor h of where the vertex
// was, and every other edge along Gamma around stays.
bool OceanFloor::take_out_of_gamma(int32_t v) {
    if (!s_.tri.in_triangulation(v) || !s_.removable(v)) return false;
    int32_t along[2];
    if (!neighbours_along_gamma(v, along)) return false;
    const auto gamma_edges = s_.gamma_edges_among(s_.closed_stars({v}));
    const Before b = before({v});
    const Vec3 x = s_.tri.direction(v);
    const int32_t hint = s_.tri.remove(v);
    const bool chord_near = s_.has_edge(along[0], along[1]) &&
                            geom::distance_to_arc(x, s_.tri.direction(along[0]), s_.tri.direction(along[1])) <
                                s_.options.ocean_floor * s_.h_at[v];
    if (!chord_near || !s_.gamma_edges_stay(gamma_edges, v) || !acceptable(b, -1)) {
        s_.tri.restore_removed(v, hint);
        return false;
    }
    mark_changed(b.link);
    return true;
}

// v's nearest neighbours on its part of Gamma before and after it along
// the part (on a closed part, the shorter way round); false without both.
bool OceanFloor::neighbours_along_gamma(int32_t v, int32_t (&along)[2]) const {
    const int64_t part = s_.gamma->segment_part(s_.on_segment[v]);
    const features::Part &p = s_.gamma->part(part);
    const double pv = s_.position_along_part(v), n = static_cast<double>(p.n_segments);
    double nearest[2] = {kInfinity, kInfinity};
    along[0] = along[1] = -1;
    s_.tri.for_each_neighbour(v, [&](int32_t u) {
        if (s_.on_segment[u] < 0 || s_.gamma->segment_part(s_.on_segment[u]) != part) return;
        double d = s_.position_along_part(u) - pv;
        if (p.closed && d > 0.5 * n) d -= n;
        if (p.closed && d < -0.5 * n) d += n;
        const int side = d < 0 ? 0 : 1;
        if (d != 0 && std::abs(d) < nearest[side]) nearest[side] = std::abs(d), along[side] = u;
    });
    return along[0] >= 0 && along[1] >= 0;
}

// Whether an edge between two of `vertices` (the hole a removal
// re-triangulated) is longer than split_ratio h: the split that would
// follow would put a vertex back.
bool OceanFloor::leaves_long_edge(const std::vector<int32_t> &vertices) const {
    bool long_edge = false;
    for (int32_t u : vertices)
        s_.tri.for_each_neighbour(u, [&](int32_t w) {
            if (w < u || std::find(vertices.begin(), vertices.end(), w) == vertices.end()) return;
            const double h = 0.5 * (static_cast<double>(s_.h_at[u]) + static_cast<double>(s_.h_at[w]));
            long_edge = long_edge || geom::norm(s_.tri.direction(u) - s_.tri.direction(w)) > s_.options.split_ratio * h;
        });
    return long_edge;
}

}  // namespace um::optim::detail
