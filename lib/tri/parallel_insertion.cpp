// Parallel construction: each large BRIO round of build() is inserted by
// regions at once (Triangulation::insert_round_in_parallel).
//
// The round's points, sorted along the Hilbert curve, are cut into 2 to 16
// runs (by the round's size); a run and the stretch of the curve it spans
// make a region, which owns every vertex whose Hilbert key falls in that
// stretch (a vertex of an earlier round, or one of its own points). Each
// region inserts its points in order, as the serial path does, but only
// where it owns every vertex of the triangles it changes or walks out of:
//  - an insertion changes its cavity's triangles (all three vertices owned)
//    and the triangles across the horizon (the two of the shared edge), so
//    every triangle a region changes has at least two of its vertices;
//  - two regions own no common vertex, so no triangle is changed by two,
//    and every triangle a region reads (the ones it walks through, its
//    cavity, the triangles next to those) has two of its own vertices, so no
//    other region changes it: no locks, no data races, and what a region
//    does is decided by its own points alone;
//  - a point whose walk or cavity reaches a vertex the region does not own
//    is deferred.
// The deferred points lie along the regions' borders. A second pass inserts
// them by bands of latitude about a tilted axis (kBandAxis), which own
// vertices by the same rule with other keys: the borders of bands cross the regions'
// borders instead of running along them, so most deferred points are well
// inside a band. What is left is inserted one by one after all bands
// finished, band by band.
// Nothing depends on the thread count or on timing, so the triangulation is
// bit-identical for any number of threads. The triangle marks of fill_cavity
// are shared, but a region only marks triangles with two of its vertices.
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "tri/spatial_order.hpp"
#include "tri/triangulation.hpp"

namespace um::tri {

namespace {
// Regions per round: a power of two set by the round's size alone (the
// result must not depend on the threads), up to 16 to keep a few cores busy,
// and at least 16384 points each, so that the points deferred at their
// borders stay few: each round inserts into a mesh of 1/8 of its density,
// whose triangles along a border are wide. (16 regions of a 10^5-point
// input deferred 22 % of its points; 4 regions of at least 16384 points
// brought that case from 0.025-0.028 s to 0.021 s on two threads, larger
// inputs unchanged.)
constexpr int kMaxRegions = 16;
constexpr int32_t kMinRegionPoints = 16384;
int regions_for(int32_t points) {
    int regions = 2;
    while (regions < kMaxRegions && points / (2 * regions) >= kMinRegionPoints) regions *= 2;
    return regions;
}
// Bands for the deferred points: likewise set by their number alone. Each
// band border defers points again: of the 52,600 the regions deferred at
// 10^6 points, 4 bands left 2,600 to the serial pass, 8 left 6,200 and 16
// left 11,000.
constexpr int kMaxBands = 4;
constexpr size_t kMinBandPoints = 1024;
// A region's walk from its last point is short (consecutive points are
// neighbours); a long one means an odd input: the serial path takes it.
constexpr int64_t kRegionWalkSteps = 4096;

// Bands are of latitude about a tilted axis. Not about z: the regions'
// borders follow the Hilbert curve's first cuts, which on four cube faces
// run along the equator, and so did most deferred points (a band border
// there deferred them again).
constexpr double kBandAxis[3] = {0.2672612419124244, 0.5345224838248488, 0.8017837257372732};  // (1, 2, 3) / sqrt(14)
}  // namespace

struct Triangulation::Region {
    KeyRange keys;
    // Its points: the vertex slots [begin, end) (sorted by key), or `listed`.
    int32_t begin = 0, end = 0;
    std::vector<int32_t> listed;
    int32_t hint = kNone;             // a triangle it owns near its last point
    // Where to look for a start near a point: runs of slots sorted by
    // Hilbert key (rounds), tried in order.
    struct Slots {
        int32_t begin, end;
    };
    Slots starts[2] = {{0, 0}, {0, 0}};
    bool start_near_each_point = false;  // (not from the last point's fan)
    uint32_t walk = 0;
    SlotPool pool;                    // its own triangle slots: two per point
    std::vector<int32_t> reuse;       // slots its insertions emptied (or it was given)
    std::vector<int32_t> deferred;
    Scratch scratch;
};

Triangulation::RoundDeferred Triangulation::insert_round_in_parallel(Context &ctx, int32_t prev_begin,
                                                                    int32_t begin, int32_t end,
                                                                    int32_t &hint) {
    // (A second pass with regions cut at the middles of these gained
    // nothing: a region borders regions far from it along the curve.)
    std::vector<int32_t> deferred = insert_by_regions(ctx, prev_begin, begin, end);
    RoundDeferred count;
    count.by_regions = static_cast<int64_t>(deferred.size());
    deferred = insert_by_bands(ctx, std::move(deferred), prev_begin, begin, end);
    for (int32_t v : deferred) {
        // Deferred points are far apart: start next to a vertex of this
        // round or the previous one near v along the curve, else from the
        // last hint (made live: a region may have emptied its slot).
        int32_t start = vertex_near_key(v, begin, end);
        if (start == kNone) start = vertex_near_key(v, prev_begin, begin);
        hint = start != kNone ? start : live_triangle_near(hint);
        int32_t other = kNone;
        if (insert_slot(v, hint, &other) == InsertResult::duplicate) fail_on_duplicates();
    }
    count.to_serial = static_cast<int64_t>(deferred.size());
    return count;
}

// The first slot in [begin, end) (sorted by key) whose key is >= key.
int32_t Triangulation::first_slot_with_key(uint32_t key, int32_t begin, int32_t end) const {
    return static_cast<int32_t>(std::lower_bound(key_.begin() + begin, key_.begin() + end, key) -
                                key_.begin());
}

// first_slot_with_key(key_[v], begin, end), found without a search when v
// is one of the slots: the slots before it with its key, if any, come first.
// (The bands and the serial pass start every point so, and a binary search
// over a round misses the cache at each of its some twenty steps.)
int32_t Triangulation::first_slot_with_key_of(int32_t v, int32_t begin, int32_t end) const {
    const uint32_t key = key_[v];
    if (v < begin || v >= end) return first_slot_with_key(key, begin, end);
    int32_t at = v;
    while (at > begin && key_[at - 1] == key) --at;
    return at;
}

// vertex_tri_ of a vertex in the triangulation among the slots [begin, end)
// (sorted by key) nearest to v's key in that order, within a few; else kNone.
int32_t Triangulation::vertex_near_key(int32_t v, int32_t begin, int32_t end) const {
    const int32_t at = first_slot_with_key_of(v, begin, end);
    for (int32_t d = 0; d < 8; ++d)
        for (int32_t u : {at - 1 - d, at + d})
            if (u >= begin && u < end && vertex_tri_[u] >= 0) return vertex_tri_[u];
    return kNone;
}

// The round [begin, end) in regions_for() runs of equal length; region r owns
// the keys from its first point's to the next region's. Returns the points
// deferred, in order.
std::vector<int32_t> Triangulation::insert_by_regions(Context &ctx, int32_t prev_begin,
                                                      int32_t begin, int32_t end) {
    // A fan has two triangles more than its cavity: two fresh slots per
    // point, a contiguous range per region, so that triangles near each
    // other stay near each other in memory, as on the serial path.
    const int32_t base = static_cast<int32_t>(tris_.size());
    // The slots are not written here but by the regions that use them
    // (stitch_new_triangles), in parallel, which is where their pages are
    // first touched; the ones left over are freed below.
    tris_.resize(tris_.size() + 2 * static_cast<size_t>(end - begin));
    mark_.resize(tris_.size());
    const int n_regions = regions_for(end - begin);
    uint32_t bounds[kMaxRegions + 1];
    bounds[0] = 0;
    bounds[n_regions] = ~uint32_t(0);  // the virtual vertices' key: owned by none
    for (int r = 1; r < n_regions; ++r) bounds[r] = key_[begin + (end - begin) * int64_t(r) / n_regions];
    std::vector<Region> regions(n_regions);
    for (int r = 0; r < n_regions; ++r) {
        Region &g = regions[r];
        g.keys = {key_.data(), bounds[r], bounds[r + 1]};
        // Equal keys all go to one region (the first with that key).
        g.begin = first_slot_with_key(bounds[r], begin, end);
        g.end = r + 1 == n_regions ? end : first_slot_with_key(bounds[r + 1], begin, end);
        g.starts[0] = {prev_begin, begin};
        g.walk = static_cast<uint32_t>(g.begin - begin);
        g.pool = {&g.reuse, base + 2 * (g.begin - begin), base + 2 * (g.end - begin)};
    }
    return run_regions(ctx, regions);
}

// Inserts every region's points, the regions in parallel; then gives the
// slots they did not use to free_ (for the passes after) and returns the
// points they deferred, region by region.
std::vector<int32_t> Triangulation::run_regions(Context &ctx, std::vector<Region> &regions) {
    ctx.parallel_for(static_cast<int64_t>(regions.size()), 1, [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
            Region &g = regions[r];
            auto insert = [&](int32_t v) {
                if (insert_in_region(v, g) == RegionInsert::deferred) g.deferred.push_back(v);
            };
            for (int32_t v = g.begin; v < g.end; ++v) insert(v);
            for (int32_t v : g.listed) insert(v);
        }
    });
    std::vector<int32_t> deferred;
    for (Region &g : regions) {
        free_.insert(free_.end(), g.reuse.begin(), g.reuse.end());
        for (int32_t t = g.pool.fresh; t < g.pool.fresh_end; ++t) {
            tris_[t] = {{kNone, kNone, kNone}, {kNone, kNone, kNone}};  // never written
            mark_[t] = Mark::none;
            free_.push_back(t);
        }
        deferred.insert(deferred.end(), g.deferred.begin(), g.deferred.end());
    }
    return deferred;
}

// The second pass over the points the regions deferred (in their order):
// bands of latitude about kBandAxis, cut where the points' keys split them
// into equal shares. Returns the points deferred again, band by band.
std::vector<int32_t> Triangulation::insert_by_bands(Context &ctx, std::vector<int32_t> points,
                                                    int32_t prev_begin, int32_t begin,
                                                    int32_t end) {
    const size_t n_bands = std::min<size_t>(kMaxBands, points.size() / kMinBandPoints);
    // Every insertion takes at most two slots more than its cavity gives
    // back, and the regions left two for each point they deferred.
    if (n_bands < 2 || free_.size() < 2 * points.size()) return points;
    // Keys for every vertex a band may meet (those of this round and
    // before): the lifted point's height along the axis, scaled from
    // [-longest, longest] to the keys. It is the latitude of the
    // direction when the weights are equal, and a band's share of the
    // vertices is only less tidy when they are not. (Without a square root
    // or a division: this runs over every vertex.) The virtual vertices
    // get ~0, which no band owns.
    Buffer<uint32_t> band_key(static_cast<size_t>(end));
    const double scale = 0x1p31 / longest_lifted_;
    ctx.parallel_for(end, 16384, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            const Vec3 &q = q_[v];
            const double key = (kBandAxis[0] * q.x + kBandAxis[1] * q.y + kBandAxis[2] * q.z) * scale + 0x1p31;
            band_key[v] = key <= 0 ? 0u : static_cast<uint32_t>(std::min(key, 4294967294.0));
        }
    });
    std::fill_n(band_key.begin(), std::min(end, kVirtual), ~uint32_t(0));
    // Cuts at equal shares of the points, from a histogram of their keys'
    // top bits (a cut falls between two bins: near enough).
    constexpr int kBinBits = 12;
    std::vector<uint32_t> bins(size_t(1) << kBinBits, 0);
    for (int32_t v : points) ++bins[band_key[v] >> (32 - kBinBits)];
    std::vector<uint32_t> cuts(n_bands + 1);
    cuts[0] = 0, cuts[n_bands] = ~uint32_t(0);
    size_t seen = 0, band = 1;
    for (size_t bin = 0; bin < bins.size() && band < n_bands; ++bin) {
        seen += bins[bin];
        while (band < n_bands && seen * n_bands >= band * points.size())
            // (After the last bin: ~0, where 2^32 would wrap to 0.)
            cuts[band++] = bin + 1 < bins.size() ? static_cast<uint32_t>((bin + 1) << (32 - kBinBits)) : ~uint32_t(0);
    }
    // (Bands with overlapping keys could change one triangle at once.)
    if (!std::is_sorted(cuts.begin(), cuts.end()))
        fail(UM_ERR_INTERNAL, "insert_by_bands: the band cuts do not ascend");
    std::vector<Region> bands(n_bands);
    for (size_t b = 0; b < n_bands; ++b) {
        Region &g = bands[b];
        g.keys = {band_key.data(), cuts[b], cuts[b + 1]};
        g.starts[0] = {begin, end}, g.starts[1] = {prev_begin, begin};
        g.start_near_each_point = true;  // the band's points are far apart
        g.pool = {&g.reuse, 0, 0};
    }
    // Two free slots per point, from the back of the list, band by band.
    // (The cuts ascend; a band between two equal ones is empty.)
    for (int32_t v : points) {
        const auto above = std::upper_bound(cuts.begin() + 1, cuts.end() - 1, band_key[v]);
        Region &g = bands[static_cast<size_t>(above - (cuts.begin() + 1))];
        for (int k = 0; k < 2; ++k) g.reuse.push_back(free_.back()), free_.pop_back();
        g.listed.push_back(v);
    }
    return run_regions(ctx, bands);
}

// Inserts the point in slot v if the region owns everything it needs.
Triangulation::RegionInsert Triangulation::insert_in_region(int32_t v, Region &g) {
    // No start yet (the first point), or none near enough: one near v.
    if (g.hint == kNone || g.start_near_each_point) {
        const int32_t near = region_start(g, v);
        if (near != kNone) g.hint = near;
    }
    if (g.hint == kNone) return RegionInsert::deferred;
    int zero_edges[3], n_zero = 0;
    int32_t last_owned = g.hint;
    // The filtered walk first (walk_filtered); the exact one from its end
    // when that is not a start as it stands.
    int32_t t = walk_filtered(q_[v], g.hint, zero_edges, n_zero, g.walk, kRegionWalkSteps, &g.keys,
                              &last_owned);
    if (t == kNone && !g.start_near_each_point) {
        // The walk reached the border (deferred points leave the hint
        // behind them): start again from a vertex of the previous round
        // next to v along the curve.
        const int32_t restart = region_start(g, v);
        if (restart != kNone)
            t = walk_filtered(q_[v], restart, zero_edges, n_zero, g.walk, kRegionWalkSteps, &g.keys,
                              &last_owned);
    }
    // With no edge listed t holds v strictly in its cone, as the exact walk
    // would have ended (the common path below).
    if (t != kNone && n_zero > 0) {
        if (n_zero == 1 && filtered_start(t, v)) {
            g.hint = last_owned;
            if (!fill_cavity(v, t, g.scratch, &g.keys)) return RegionInsert::deferred;
            if (!g.scratch.cavity_buries()) return stitch_in_region(v, g);
            clear_cavity_marks(g.scratch);  // the exact path decides
        }
        t = walk(q_[v], t, zero_edges, n_zero, g.walk, kRegionWalkSteps, &g.keys, &last_owned);
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
    if (!fill_cavity(v, start, g.scratch, &g.keys))
        return RegionInsert::deferred;
    return stitch_in_region(v, g);
}

Triangulation::RegionInsert Triangulation::stitch_in_region(int32_t v, Region &g) {
    stitch_new_triangles(v, g.scratch, g.pool);
    // The next walk starts from the new fan, which the region owns (v and
    // the horizon vertices are its own).
    g.hint = vertex_tri_[v];
    return RegionInsert::inserted;
}

// A triangle the region owns around one of the vertices nearest to v's key
// (either way) among the slots of g.starts (each sorted by Hilbert key), in
// the region's range; kNone if none of the few tried has one. Safe while
// other regions insert: a triangle around a vertex the region owns keeps
// its vertices, and the edges at that vertex their neighbours (other
// regions change neither).
int32_t Triangulation::region_start(const Region &g, int32_t v) const {
    constexpr int kTries = 32;  // each way
    const uint32_t span = g.keys.hi - g.keys.lo;
    for (const Region::Slots &slots : g.starts) {
        if (slots.begin == slots.end) continue;
        const int32_t at = first_slot_with_key_of(v, slots.begin, slots.end);
        for (int32_t d = 0; d < kTries; ++d)
            for (int32_t u : {at + d, at - 1 - d}) {
                if (u < slots.begin || u >= slots.end) continue;
                if (g.keys.keys[u] - g.keys.lo >= span || vertex_tri_[u] < 0) continue;
                int32_t found = kNone;
                for_each_in_star(u, [&](int32_t t) {
                    if (found == kNone && owns(g.keys, t)) found = t;
                });
                if (found != kNone) return found;
            }
    }
    return kNone;
}

}  // namespace um::tri
