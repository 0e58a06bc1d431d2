// Parallel construction: each large BRIO round of build() is inserted by
// regions at once (Triangulation::insert_round_in_parallel).
//
// The round's points, sorted along the Hilbert curve, are cut into a fixed
// number of runs; a run and the stretch of the curve it spans make a region,
// which owns every vertex whose Hilbert key falls in that stretch (a vertex
// of an earlier round, or one of its own points). Each region inserts its
// points in order, as the serial path does, but only where it owns every
// vertex of the triangles it changes or walks out of:
//  - an insertion changes its cavity's triangles (all three vertices owned)
//    and the triangles across the horizon (the two of the shared edge), so
//    every triangle a region changes has at least two of its vertices;
//  - two regions own no common vertex, so no triangle is changed by two,
//    and every triangle a region reads (the ones it walks through, its
//    cavity, the triangles next to those) has two of its own vertices, so no
//    other region changes it: no locks, no data races, and what a region
//    does is decided by its own points alone;
//  - a point whose walk or cavity reaches a vertex the region does not own
//    is deferred, and the deferred points are inserted one by one after all
//    regions finished, region by region.
// Nothing depends on the thread count or on timing, so the triangulation is
// bit-identical for any number of threads. The triangle marks of fill_cavity
// are shared, but a region only marks triangles with two of its vertices.
#include <algorithm>

#include "tri/spatial_order.hpp"
#include "tri/triangulation.hpp"

namespace um::tri {

namespace {
// Regions per round: fixed (the result must not depend on the threads),
// enough to keep a few cores busy, few enough that the points deferred at
// their borders stay a few per cent of a big round.
constexpr int kRegions = 16;
// A region's walk from its last point is short (consecutive points are
// neighbours); a long one means an odd input: the serial path takes it.
constexpr int64_t kRegionWalkSteps = 4096;
}  // namespace

struct Triangulation::Region {
    KeyRange keys;
    const int32_t *points = nullptr;  // its points (vertex slots), by key
    int64_t count = 0;
    int32_t hint = kNone;             // a triangle it owns near its last point
    int32_t search_begin = 0, search_end = 0;  // slots, by key, to find starts among
    uint32_t walk = 0;
    SlotPool pool;                    // its own triangle slots: two per point
    std::vector<int32_t> reuse;       // slots its insertions emptied
    std::vector<int32_t> deferred;
    Scratch scratch;
};

void Triangulation::insert_round_in_parallel(Context &ctx, int32_t prev_begin, int32_t begin,
                                             int32_t end, int32_t &hint) {
    std::vector<int32_t> points(static_cast<size_t>(end - begin));
    for (int32_t v = begin; v < end; ++v) points[v - begin] = v;
    std::vector<uint32_t> bounds(kRegions + 1);
    bounds[0] = 0;
    bounds[kRegions] = ~uint32_t(0);
    for (int r = 1; r < kRegions; ++r) bounds[r] = key_[begin + (end - begin) * int64_t(r) / kRegions];
    // (A second pass over the deferred points with regions cut at the
    // middles of these gained nothing: a region borders regions far from
    // it along the curve.)
    for (int32_t v : insert_by_regions(ctx, points, bounds, prev_begin, begin)) {
        // Deferred points are far apart: start next to a vertex of this
        // round or the previous one near v along the curve, else from the
        // last hint (made live: a region may have emptied its slot).
        int32_t start = vertex_near_key(key_[v], begin, end);
        if (start == kNone) start = vertex_near_key(key_[v], prev_begin, begin);
        hint = start != kNone ? start : live_triangle_near(hint);
        int32_t other = kNone;
        if (insert_slot(v, hint, &other) == InsertResult::duplicate) fail_on_duplicates();
    }
}

// vertex_tri_ of a vertex in the triangulation among the slots [begin, end)
// (sorted by key) nearest to `key` in that order, within a few; else kNone.
int32_t Triangulation::vertex_near_key(uint32_t key, int32_t begin, int32_t end) const {
    if (end <= begin) return kNone;
    const int32_t at = static_cast<int32_t>(
        std::lower_bound(key_.begin() + begin, key_.begin() + end, key) - key_.begin());
    for (int32_t d = 0; d < 8; ++d)
        for (int32_t u : {at - 1 - d, at + d})
            if (u >= begin && u < end && vertex_tri_[u] >= 0) return vertex_tri_[u];
    return kNone;
}

// One pass: region r takes the points (sorted by key) whose keys are in
// [bounds[r], bounds[r + 1]) and owns the vertices with those keys; starts
// are found among the slots [search_begin, search_end). Returns the points
// deferred, in order.
std::vector<int32_t> Triangulation::insert_by_regions(Context &ctx,
                                                      const std::vector<int32_t> &points,
                                                      const std::vector<uint32_t> &bounds,
                                                      int32_t search_begin, int32_t search_end) {
    const int n_regions = static_cast<int>(bounds.size()) - 1;
    // A fan has two triangles more than its cavity: two fresh slots per
    // point, a contiguous range per region, so that triangles near each
    // other stay near each other in memory, as on the serial path.
    const int32_t base = static_cast<int32_t>(tris_.size());
    tris_.resize(tris_.size() + 2 * points.size(), {{kNone, kNone, kNone}, {kNone, kNone, kNone}});
    mark_.resize(tris_.size(), 0);
    std::vector<Region> regions(static_cast<size_t>(n_regions));
    auto first_with_key = [&](uint32_t key) {
        return std::lower_bound(points.begin(), points.end(), key,
                                [&](int32_t v, uint32_t k) { return key_[v] < k; }) -
               points.begin();
    };
    for (int r = 0; r < n_regions; ++r) {
        Region &g = regions[r];
        g.keys = {bounds[r], bounds[r + 1]};
        const int64_t first = first_with_key(bounds[r]);
        const int64_t last = r + 1 == n_regions ? static_cast<int64_t>(points.size())
                                                : first_with_key(bounds[r + 1]);
        g.points = points.data() + first;
        g.count = last - first;
        g.search_begin = search_begin, g.search_end = search_end;
        g.walk = static_cast<uint32_t>(first);
        g.pool = {&g.reuse, base + 2 * static_cast<int32_t>(first), base + 2 * static_cast<int32_t>(last)};
    }
    ctx.parallel_for(n_regions, 1, [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
            Region &g = regions[r];
            for (int64_t i = 0; i < g.count; ++i)
                if (insert_in_region(g.points[i], g) == RegionInsert::deferred)
                    g.deferred.push_back(g.points[i]);
        }
    });
    // The regions' unused slots are for the serial path.
    std::vector<int32_t> deferred;
    for (Region &g : regions) {
        free_.insert(free_.end(), g.reuse.begin(), g.reuse.end());
        for (int32_t t = g.pool.fresh; t < g.pool.fresh_end; ++t) free_.push_back(t);
        deferred.insert(deferred.end(), g.deferred.begin(), g.deferred.end());
    }
    return deferred;
}

// Inserts the point in slot v if the region owns everything it needs.
Triangulation::RegionInsert Triangulation::insert_in_region(int32_t v, Region &g) {
    // No start yet (the first point): one near v.
    if (g.hint == kNone) g.hint = region_start(g.keys, key_[v], g.search_begin, g.search_end);
    if (g.hint == kNone) return RegionInsert::deferred;
    int zero_edges[3], n_zero = 0;
    int32_t last_owned = g.hint;
    int32_t t = walk(q_[v], g.hint, zero_edges, n_zero, g.walk, kRegionWalkSteps, &g.keys,
                     &last_owned);
    if (t == kNone) {
        // The walk reached the border (deferred points leave the hint
        // behind them): start again from a vertex of the previous round
        // next to v along the curve.
        const int32_t restart = region_start(g.keys, key_[v], g.search_begin, g.search_end);
        if (restart != kNone)
            t = walk(q_[v], restart, zero_edges, n_zero, g.walk, kRegionWalkSteps, &g.keys,
                     &last_owned);
    }
    g.hint = last_owned;  // even for a deferred point: the next ones are near it
    // On a vertex's direction (a duplicate, or a virtual vertex to bury):
    // the serial path's special cases.
    if (t == kNone || n_zero >= 2) return RegionInsert::deferred;
    int32_t start = kNone;
    if (visible(t, v)) {
        start = t;
    } else if (n_zero == 1) {
        if (!owns(g.keys, t)) return RegionInsert::deferred;  // its neighbour may be changing
        const int32_t u = tris_[t].n[zero_edges[0]];
        if (visible(u, v)) start = u;
    }
    if (start == kNone) return RegionInsert::hidden;  // the hull only grows: hidden for good
    if (!owns(g.keys, start) || !fill_cavity(v, start, g.scratch, &g.keys))
        return RegionInsert::deferred;
    collect_horizon(g.scratch);
    stitch_new_triangles(v, g.scratch, g.pool);
    // The next walk starts from the new fan, which the region owns (v and
    // the horizon vertices are its own).
    g.hint = g.scratch.new_tris[0];
    return RegionInsert::inserted;
}

// A triangle the region owns around one of the first vertices among the
// slots [prev_begin, prev_end) (a round: sorted by key) from `key` on, in
// the region's range; kNone if none of the first few has one. Safe while other regions insert:
// a triangle around a vertex the region owns keeps its vertices, and the
// edges at that vertex their neighbours (other regions change neither).
int32_t Triangulation::region_start(const KeyRange &range, uint32_t key, int32_t prev_begin,
                                    int32_t prev_end) const {
    const int32_t first = static_cast<int32_t>(
        std::lower_bound(key_.begin() + prev_begin, key_.begin() + prev_end, key) -
        key_.begin());
    constexpr int kTries = 64;
    for (int32_t u = first; u < prev_end && u < first + kTries && key_[u] < range.hi; ++u) {
        if (key_[u] < range.lo || vertex_tri_[u] < 0) continue;
        int32_t found = kNone;
        for_each_in_star(u, [&](int32_t t) {
            if (found == kNone && owns(range, t)) found = t;
        });
        if (found != kNone) return found;
    }
    return kNone;
}

}  // namespace um::tri
