// The Laguerre (regular, weighted Delaunay) triangulation of the sphere,
// held as the convex hull of lifted points (DESIGN.md section 3):
//   q_i = x_i / (1 - w_i / 2),  x_i on the unit sphere, w_i in units of R^2.
// A generator strictly inside the hull is hidden (empty power cell).
//
// Storage is a triangulated sphere: triangle t has vertices v(t,0..2),
// counter-clockwise seen from outside, and neighbour n(t,k) across edge k,
// the edge opposite v(t,k) running from v(t,k+1) to v(t,k+2). Every
// combinatorial decision is an exact predicate (geom/predicates.hpp) with its
// symbolic-perturbation tie rule, so the structure is the exact hull of the
// stored doubles, the same for any insertion order.
//
// Construction starts from a virtual octahedron of six tiny lifted points
// around the centre; real points bury them. If any is left at the end, the
// input does not surround the centre (all in one hemisphere, or on one great
// circle) and construction fails.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/context.hpp"
#include "core/error.hpp"
#include "core/huge_pages.hpp"
#include "core/uninit_vector.hpp"
#include "geom/predicates.hpp"
#include "geom/sphere.hpp"
#include "tri/spatial_order.hpp"

namespace um::tri {

using geom::Vec3;

// Length of the lifted point of a weight: 1 / (1 - w / 2). Needs w < 2.
inline double lifted_scale(double weight) { return 1.0 / (1.0 - 0.5 * weight); }

class Triangulation {
public:
    static constexpr int32_t kNone = -1;
    // Slots 0..kVirtual-1 hold the virtual octahedron while build() inserts.
    static constexpr int kVirtual = 6;
    static constexpr int32_t kRemoved = -2;  // vertex_tri_ of a removed (not hidden) slot

    // Builds the triangulation of n points; direction(i) gives point i's unit
    // vector, weights (may be null = all 0) its weight. Point i gets id i.
    // Throws um::Error: too few points, coincident points (naming both),
    // points that do not surround the centre, memory cap. After it throws
    // (std::bad_alloc too) the triangulation is half built - a parallel
    // round may leave triangle slots unwritten - and only fit to be
    // destroyed or built again; its callers (the C API, the refinement)
    // discard it.
    template <class DirectionFn>
    void build(Context &ctx, int64_t n, DirectionFn direction, const double *weights);
    // build() in two steps: prepare() copies the points in insertion order
    // (BRIO rounds along a Hilbert curve), finish_build() triangulates them;
    // a caller's input for `direction` may live in the build's room (below),
    // which is dead from finish_build() on.
    // The first rounds are inserted one by one in that order, the big ones
    // by up to 16 regions in parallel, then the points those deferred by 4
    // bands (parallel_insertion.cpp); nothing depends on the thread count,
    // so neither do the triangles nor their numbering.
    // key_direction(i) is direction(i) times any positive factor (the
    // input before normalising, say): the Hilbert keys need no more.
    // prefetch(i), when given, asks the cache for what direction(i) will
    // read (the points are gathered in insertion order, at random).
    struct NoPrefetch {
        void operator()(int64_t) const {}
    };
    template <class DirectionFn, class KeyDirectionFn, class PrefetchFn = NoPrefetch>
    void prepare(Context &ctx, int64_t n, DirectionFn direction, const double *weights,
                 KeyDirectionFn key_direction, PrefetchFn prefetch = {});
    void finish_build(Context &ctx) { insert_all(ctx); }

    // The preparation's temporaries (the BRIO words, the sort's buffer, and
    // a caller's unit vectors) live in the storage of the triangles the
    // build makes, 2 (n + 6) of 24 bytes: nothing is written there before
    // insertion starts, and insertion writes nearly all of it (all but the
    // slots of points that end hidden), so the pages the temporaries touch
    // are pages the triangles need anyway, not fresh ones - 16 bytes a point
    // fewer from xyz, 40 from lon/lat. (On the benchmark machine the first
    // touch of a page costs 0.1-4 ms per MB: bench_first_touch.)
    // reserve_build(n) sizes that storage for a build of n points (its
    // values unwritten) and returns the room, where a caller may take its
    // share before prepare(n) takes the words' and ends the room, however
    // it ends. Throws UM_ERR_LIMIT for n outside [0, 2^28].
    class BuildRoom {
    public:
        BuildRoom() = default;
        // A copy of a triangulation has no room (its storage is its own).
        BuildRoom(const BuildRoom &) noexcept {}
        BuildRoom &operator=(const BuildRoom &) noexcept {
            close();
            return *this;
        }
        // Room for `count` values of T (aligned); throws UM_ERR_INTERNAL
        // when there is not enough left.
        template <class T>
        T *take(size_t count);

    private:
        friend class Triangulation;
        void close() noexcept { begin_ = next_ = end_ = nullptr, n_ = -1; }
        unsigned char *begin_ = nullptr, *next_ = nullptr, *end_ = nullptr;
        int64_t n_ = -1;  // the build it was made for
    };
    BuildRoom &reserve_build(int64_t n);

    // Counts -------------------------------------------------------------
    // Live triangles. After updates some slots may be free (is_free); build()
    // and compact() leave none, so slots 0..triangle_count()-1 are all live.
    int32_t triangle_count() const { return static_cast<int32_t>(tris_.size() - free_.size()); }
    int32_t triangle_slots() const { return static_cast<int32_t>(tris_.size()); }
    bool is_free(int32_t t) const { return tris_[t].v[0] == kNone; }
    // The live triangles t with pred(t) (every live one without), in slot
    // order, found in parallel in fixed chunks (the same for any thread count).
    template <class Pred>
    std::vector<int32_t> live_triangles_where(Context &ctx, Pred pred) const {
        return ctx.collect_in_order<int32_t>(triangle_slots(), 8192, [&](int64_t t, std::vector<int32_t> &out) {
            if (!is_free(static_cast<int32_t>(t)) && pred(static_cast<int32_t>(t))) out.push_back(static_cast<int32_t>(t));
        });
    }
    std::vector<int32_t> live_triangles(Context &ctx) const {
        return live_triangles_where(ctx, [](int32_t) { return true; });
    }
    // Renumbers the live triangles into 0..triangle_count()-1, keeping their
    // order, and gives back the room insertion left unused.
    void compact();
    // Renumbers the vertex slots along a Hilbert curve (slots not in the
    // triangulation last, in their old order) and then the triangles by
    // their smallest vertex, so that neighbours in the mesh are neighbours
    // in memory: the optimisation sweeps read every star's link, and with
    // the refinement's frontal order those reads miss the cache. Compacts
    // first. Returns the old slot of each new slot, for the caller's
    // per-slot arrays. Reorder::copying gathers each array into a copy in
    // parallel, one array at a time (about 26 bytes a triangle slot more
    // than in place while the triangles are); Reorder::in_place moves the values cycle by cycle
    // on this thread, a chain of dependent cache misses (seconds at millions
    // of cells), for a caller near its memory peak.
    enum class Reorder { copying, in_place };
    std::vector<int32_t> reorder_spatially(Context &ctx, Reorder how = Reorder::copying);

    // Room for that share more vertex slots and triangle slots without
    // reallocating: a caller about to add a few (the optimisation) reserves
    // it while little else is allocated, since a reallocation holds both
    // buffers. (Copied in parallel: vector::reserve copies on one thread,
    // taking every page fault of the new buffers.)
    void reserve_extra(Context &ctx, double vertices, double triangles);

    // What restore() needs to put the triangulation back exactly as it was
    // (slots, numbering, incident triangles): the points and the triangles'
    // vertices, about 56 bytes per vertex against a full copy's 84; the
    // neighbours are found again. For an undo that is rarely taken. If
    // restore() runs out of memory, it leaves the triangulation empty (and
    // throws): consistent, if not what it was.
    struct Snapshot {
        HugePageVector<Vec3> q;
        UninitVector<int32_t> id, vertex_tri;
        std::vector<int32_t> free;
        UninitVector<std::array<int32_t, 3>> triangles;  // kNone for a free slot
    };
    // Copied in parallel (the copies' pages are first touched there too).
    Snapshot snapshot(Context &ctx) const;
    void restore(Snapshot &&s);
    int32_t vertex_slots() const { return static_cast<int32_t>(q_.size()); }
    size_t vertex_capacity() const { return q_.capacity(); }
    // Vertices in the triangulation (not hidden).
    int64_t vertex_count() const;

    // Topology -----------------------------------------------------------
    int32_t vertex(int32_t t, int k) const { return tris_[t].v[k]; }
    int32_t neighbour(int32_t t, int k) const { return tris_[t].n[k]; }
    // Input index of a vertex slot.
    int32_t id(int32_t v) const { return id_[v]; }
    bool in_triangulation(int32_t v) const { return vertex_tri_[v] >= 0; }
    // A triangle incident to vertex slot v (negative when v is not in the triangulation).
    int32_t incident_triangle(int32_t v) const { return vertex_tri_[v]; }
    // Removed by remove() (as opposed to hidden by its neighbours).
    bool is_removed(int32_t v) const { return vertex_tri_[v] == kRemoved; }
    // Input indices of the hidden points (empty power cell), ascending.
    std::vector<int32_t> hidden_ids() const;
    // Triangles around v, counter-clockwise seen from outside.
    std::vector<int32_t> star(int32_t v) const;
    // v's neighbours in the same order: the vertex after v in each triangle of its star.
    std::vector<int32_t> link(int32_t v) const;
    // The corner (0, 1, 2) of triangle t at vertex v, a vertex of t.
    int local_index(int32_t t, int32_t v) const {
        const int32_t *tv = tris_[t].v;
        return tv[0] == v ? 0 : (tv[1] == v ? 1 : 2);
    }
    // The index in neighbour(t, k) of the edge it shares with t.
    int mirror_edge(int32_t t, int k) const {
        // The edge runs a -> b in t and b -> a in the neighbour, where a is
        // at the index after the edge's.
        const int32_t a = tris_[t].v[k == 2 ? 0 : k + 1];
        const int i = local_index(tris_[t].n[k], a);
        return i == 2 ? 0 : i + 1;
    }
    // The triangles around any of `vertices` (those in the triangulation),
    // ascending, each once: where a batch of insertions changed the mesh.
    std::vector<int32_t> triangles_around(const std::vector<int32_t> &vertices) const;
    // Calls fn(t) for the triangles around v in the order star() gives,
    // without building the list (for hot loops).
    template <class Fn>
    void for_each_in_star(int32_t v, Fn &&fn) const {
        const int32_t t0 = vertex_tri_[v];
        if (t0 < 0) return;
        int32_t t = t0;
        do {
            fn(t);
            const int32_t *tv = tris_[t].v;
            const int k = tv[0] == v ? 0 : (tv[1] == v ? 1 : 2);
            t = tris_[t].n[k == 2 ? 0 : k + 1];
        } while (t != t0);
    }
    // Calls fn(w) for v's neighbours in the order link() gives (the vertex
    // after v in each triangle of its star), without building the list.
    template <class Fn>
    void for_each_neighbour(int32_t v, Fn &&fn) const {
        for_each_in_star(v, [&](int32_t t) {
            const int32_t *tv = tris_[t].v;
            fn(tv[tv[0] == v ? 1 : (tv[1] == v ? 2 : 0)]);
        });
    }

    // Geometry -----------------------------------------------------------
    const Vec3 &lifted(int32_t v) const { return q_[v]; }
    Vec3 direction(int32_t v) const { return geom::normalized(q_[v]); }
    double weight(int32_t v) const { return 2.0 * (1.0 - 1.0 / geom::norm(q_[v])); }
    // The power vertex of triangle t: unit outward normal of its hull facet.
    Vec3 orthocentre(int32_t t) const;
    // Where the dual arc of edge k of t crosses the primal arc (unit vector).
    Vec3 edge_orthocentre(int32_t t, int k) const;
    // The power cell of v: its corners (orthocentres) counter-clockwise.
    std::vector<Vec3> power_cell(int32_t v) const;

    // Exact tests ----------------------------------------------------------
    // Edge k of t is locally regular (the hull is convex across it).
    bool is_locally_regular(int32_t t, int k) const;
    // Vertex slot v's lifted point lies beyond t's facet (perturbed, exact).
    bool beyond(int32_t t, int32_t v) const { return visible(t, v); }
    // A triangle whose cone holds direction p (walk from `start`, or from
    // the first live triangle when `start` is free or out of range).
    int32_t locate(const Vec3 &p, int32_t start = 0) const {
        int zero_edges[3], n_zero;
        return locate(p, live_triangle_near(start), zero_edges, n_zero);
    }

    // Updates (after build) ------------------------------------------------
    // Each keeps the triangulation the exact regular triangulation of the
    // points it holds. Points hidden earlier are not reconsidered when a
    // vertex is removed or moved.

    // Inserts a point (unit direction, weight < 2) with input index `id`;
    // returns its vertex slot. The slot is hidden (in_triangulation false)
    // when its power cell is empty; vertices it buries become hidden and are
    // appended to *buried when given. Throws UM_ERR_DUPLICATE_POINTS when
    // a vertex has its lifted point (the same direction, and weights whose
    // lifted lengths round alike); on a vertex's direction with another
    // lifted point, the lighter of the two is hidden.
    // `hint` is a triangle near the point, where the walk starts.
    int32_t insert(const Vec3 &direction, double weight, int32_t id,
                   std::vector<int32_t> *buried = nullptr, int32_t hint = 0);
    // insert(), into the slot of a removed vertex instead of a new one
    // (which then holds the new point and id): a pass that takes many
    // vertices out and puts as many in keeps the slot count, and with it
    // every per-slot array, from growing.
    int32_t insert_into_removed(int32_t slot, const Vec3 &direction, double weight, int32_t id,
                                std::vector<int32_t> *buried = nullptr, int32_t hint = 0);
    // Removes vertex v (its slot becomes hidden); its star is re-triangulated
    // by ears that are facets of the hull of the remaining points.
    // Returns a live triangle where v was (a hint for later walks).
    int32_t remove(int32_t v);
    // Inserts a removed vertex again at its stored point (same slot and id):
    // undoes remove(v), the triangles being the same regular ones (their
    // slots may differ). `hint`: a triangle near v.
    void restore_removed(int32_t v, int32_t hint = 0);
    // Inserts a vertex hidden by an insertion or a move again at its stored
    // point: with the vertex that hid it removed first, undoes the hiding
    // (the same regular triangles, their slots may differ).
    void restore_hidden(int32_t v, int32_t hint = 0);
    // Moves v to a new direction keeping its weight / sets its weight, then
    // restores regularity. Returns the vertices that became hidden (v itself
    // when its power cell became empty).
    std::vector<int32_t> move(int32_t v, const Vec3 &direction);
    // Moves v to a stored lifted point (direction and weight), bit for bit:
    // how an undo puts a vertex back where it was. Returns as move() does.
    std::vector<int32_t> place(int32_t v, const Vec3 &lifted) { return replace_point(v, lifted); }
    std::vector<int32_t> set_weight(int32_t v, double weight);
    // Flips edge k of t when the two triangles form a quad that is convex
    // seen from the centre; returns false (and changes nothing) otherwise.
    bool flip(int32_t t, int k);

    // Geometry-only updates (the optimisation sweeps) ----------------------
    // Stores a new lifted point for vertex v without touching the topology,
    // so the triangulation may stop being regular until restore_regularity()
    // runs. Writes only v's slot: calls for different vertices may run
    // concurrently (nothing else may read v meanwhile).
    void set_lifted(int32_t v, const Vec3 &lifted) { q_[v] = lifted; }
    // Lawson flips until every edge is locally regular, starting from the
    // edges of `triangles` (those around the points that changed) and
    // following every flip. An edge that is not regular but cannot be
    // flipped (its quad is not convex seen from the centre) has its apex
    // re-inserted exactly, which settles such knots (the apex may become
    // hidden). Serial, in a fixed order: deterministic. Returns the flips made
    // plus the vertices re-inserted: 0 exactly when the topology is unchanged.
    int64_t restore_regularity(std::vector<int32_t> triangles);

    // Parallel updates by territories (territory.cpp) -----------------------
    // A territory owns the vertices whose Hilbert keys fall in its range of
    // keys, as a region of a parallel build round does (parallel_insertion.cpp),
    // and may only change triangles with all three vertices its own and the
    // triangles across their edges: territories with disjoint ranges insert
    // at once without locks, and what each does depends on its own part of the
    // mesh only - not on the threads. An insertion that would reach beyond is
    // deferred (left to the caller's serial path). Weights must be 0 (nothing
    // is buried) while territories are open.
    class Territory;
    // The key that decides ownership in a layout: 0, the Hilbert key of p;
    // 1, that of p turned by a fixed rotation (another set of borders).
    static uint32_t territory_key(const Vec3 &p, int layout);
    // Opens cuts.size() + 1 territories of a layout: keys [0, cuts[0]),
    // [cuts[0], cuts[1]), ... (cuts ascending). Territory i gets
    // vertex_budget[i] new vertex slots, appended in territory order with ids
    // from first_id up, and two fresh triangle slots per vertex slot.
    std::vector<Territory> open_territories(Context &ctx, const std::vector<uint32_t> &cuts,
                                            const std::vector<int32_t> &vertex_budget,
                                            int32_t first_id, int layout);
    // Whether territory g owns all three vertices of t / would own a vertex at p.
    bool owns(const Territory &g, int32_t t) const;
    bool owns_point(const Territory &g, const Vec3 &p) const;
    // A triangle of g whose cone holds p, walking from g's triangle `hint`
    // through g's triangles only; kNone if p lies beyond them.
    int32_t locate_in(const Territory &g, const Vec3 &p, int32_t hint) const;
    enum class TerritoryInsert { inserted, deferred, too_close, hidden };
    // Inserts p (weight 0) into g's next vertex slot (*v), unless a vertex of
    // its link would lie within chord length min_chord of it (too_close:
    // nothing changes), it is hidden, or g does not own everything it needs.
    TerritoryInsert insert_in(Territory &g, const Vec3 &p, int32_t hint, double min_chord,
                              int32_t *v);
    // What closing territories did to the vertex slots they reserved: the
    // unused ones are gone and the used ones moved down, in order, with ids
    // renumbered in the same order (so every exact decision stays as it was).
    struct TerritoryClose {
        int32_t first_slot = 0;            // the first reserved slot
        std::vector<int32_t> new_slot;     // per reserved slot (from first_slot): new slot or kNone
        int32_t next_id = 0;               // the first id not given out
    };
    // Closes them all: call once their work is done, with no other update
    // in between. Unused triangle slots become free ones. If it throws (out
    // of memory), nothing has changed: the territories are still open.
    // open_territories too changes nothing when it throws.
    TerritoryClose close_territories(Context &ctx, std::vector<Territory> &territories);

private:
    enum class InsertResult { inserted, hidden, duplicate };
    struct HorizonEdge {
        int32_t a, b;     // directed as in the cavity triangle
        int32_t outside;  // triangle across the edge, not in the cavity
        int outside_edge; // the edge's index in `outside`
    };
    // The lists of one insertion: one set for the serial path, one per
    // region of a parallel round.
    struct Scratch {
        std::vector<int32_t> cavity;  // after stitching, its first horizon.size() are the new fan
        std::vector<int32_t> cavity_vertices;  // filled only when an insertion buries vertices
        std::vector<HorizonEdge> horizon;
        // A cavity of k triangles bounded by m edges has (k - m + 2) / 2
        // vertices inside it, which the new point buries (hides).
        bool cavity_buries() const { return cavity.size() + 2 != horizon.size(); }
    };
    // Where an insertion's new triangle slots come from: `reuse` first (last
    // in, first out: the cavity's own slots), then [fresh, fresh_end), then
    // the end of tris_ (only on the serial path).
    struct SlotPool {
        std::vector<int32_t> *reuse;
        int32_t fresh = 0, fresh_end = 0;
    };
    // The vertices a region of a parallel round owns: those whose key, in a
    // per-slot array of keys (key_, the Hilbert keys, or a band pass's
    // keys), is in [lo, hi).
    struct KeyRange {
        const uint32_t *keys;
        uint32_t lo, hi;
    };
    struct Region;  // parallel_insertion.cpp

    void init_virtual_octahedron();
    void insert_all(Context &ctx);
    // Inserts the vertex in slot v; `hint` is a triangle to start the walk
    // from, updated to a triangle near v. On duplicate, *other is the
    // coinciding vertex.
    InsertResult insert_slot(int32_t v, int32_t &hint, int32_t *other);
    int32_t locate(const Vec3 &p, int32_t start, int zero_edges[3], int &n_zero) const;
    // The visibility walk of locate(): at most max_steps, and with `owner`
    // it leaves only triangles the region owns (*last_owned: the last one it
    // left). kNone when it gave up.
    int32_t walk(const Vec3 &p, int32_t t, int zero_edges[3], int &n_zero, uint32_t &counter,
                 int64_t max_steps, const KeyRange *owner, int32_t *last_owned) const;
    // The first walk of the parallel rounds' insertions (insert_in_region;
    // static bounds on): every edge decided by the static filter alone, and
    // an edge it cannot decide not crossed but listed in undecided[]
    // (n_undecided of them). It ends in a triangle whose cone holds p
    // strictly when none is listed; else p may lie on or just beyond a
    // listed edge, which only the exact walk (walk()) tells: most ends need
    // no more (filtered_start). Points on or within rounding of the great
    // circles of edges - longitude-latitude grids, icosahedral subdivisions -
    // made the exact walk compute many exact signs on its way (bench_ab on
    // ico-9 and grid-0.25: README, Benchmarks). The serial path (the first
    // rounds, the points the regions deferred, small builds) keeps the exact
    // walk: little time goes there, and a start other than the exact walk's
    // - either triangle at an edge p lies on - numbers the same triangles
    // differently, which would change what the refinement builds from its
    // first twelve points.
    int32_t walk_filtered(const Vec3 &p, int32_t t, int undecided[3], int &n_undecided,
                          uint32_t &counter, int64_t max_steps, const KeyRange *owner,
                          int32_t *last_owned) const;
    template <bool kStaticBound, bool kFilterOnly>
    int32_t walk_with(const Vec3 &p, int32_t t, int zero_edges[3], int &n_zero,
                      uint32_t &counter, int64_t max_steps, const KeyRange *owner,
                      int32_t *last_owned) const;
    // Whether the end t of walk_filtered() for slot v, with one edge
    // listed, is the start of v's cavity as it stands: v's lifted point
    // lies strictly beyond t's facet (an exact sign, not a tie). (With none
    // listed t holds v strictly in its cone, and the visibility test of the
    // exact walk's end decides.) A facet v sees starts the cavity whichever
    // cone near the edge holds v (the facets v sees are connected). A point on a vertex's
    // direction, which only the exact walk reports as a duplicate, lists
    // the two edges at the vertex when t is around it; any other facet it
    // sees is one it sees only by a larger weight, and then its cavity
    // buries the vertex: callers leave an insertion from a listed edge
    // whose cavity buries a vertex (rare, weights only) to the exact path.
    bool filtered_start(int32_t t, int32_t v) const {
        const int32_t *tv = tris_[t].v;
        return geom::orient3d_static(q_[tv[0]].data(), q_[tv[1]].data(), q_[tv[2]].data(), q_[v].data(),
                                     build_bound_) > 0;
    }
    // One unsigned comparison.
    static bool owns_vertex(const KeyRange &range, int32_t v) {
        return range.keys[v] - range.lo < range.hi - range.lo;
    }
    bool owns(const KeyRange &range, int32_t t) const {
        // No early exit: this runs at every step of a region's walks, where
        // the branches would cost more.
        const int32_t *tv = tris_[t].v;
        return owns_vertex(range, tv[0]) & owns_vertex(range, tv[1]) & owns_vertex(range, tv[2]);
    }
    // Parallel insertion of one BRIO round, region by region, then band by
    // band (parallel_insertion.cpp); returns how many of its points the
    // regions deferred, and how many of those were left to the serial pass.
    struct RoundDeferred {
        int64_t by_regions = 0, to_serial = 0;
    };
    RoundDeferred insert_round_in_parallel(Context &ctx, int32_t prev_begin, int32_t begin,
                                           int32_t end, int32_t &hint);
    std::vector<int32_t> insert_by_regions(Context &ctx, int32_t prev_begin, int32_t begin,
                                           int32_t end);
    std::vector<int32_t> insert_by_bands(Context &ctx, std::vector<int32_t> deferred,
                                         int32_t prev_begin, int32_t begin, int32_t end);
    std::vector<int32_t> run_regions(Context &ctx, std::vector<Region> &regions);
    enum class RegionInsert { inserted, hidden, deferred };
    RegionInsert insert_in_region(int32_t v, Region &region);
    // The cavity filled in region.scratch made v's fan.
    RegionInsert stitch_in_region(int32_t v, Region &region);
    int32_t region_start(const Region &region, int32_t v) const;
    int32_t vertex_near_key(int32_t v, int32_t begin, int32_t end) const;
    int32_t first_slot_with_key(uint32_t key, int32_t begin, int32_t end) const;
    int32_t first_slot_with_key_of(int32_t v, int32_t begin, int32_t end) const;
    int32_t locate_brute_force(const Vec3 &p) const;
    int32_t live_triangle_near(int32_t t) const;
    int32_t find_visible_start(int32_t v, int32_t t, const int zero_edges[3], int n_zero,
                               int32_t *coincident);
    // The visible triangles connected to `start`. With `owner`, false (and
    // nothing marked) when `start` or one of them is not the region's.
    bool fill_cavity(int32_t v, int32_t start, Scratch &s, const KeyRange *owner);
    template <bool kStaticBound>
    bool fill_cavity_with(int32_t v, int32_t start, Scratch &s, const KeyRange *owner);
    // Undoes fill_cavity's marks (an insertion given up before it stitched).
    void clear_cavity_marks(const Scratch &s);
    // locate_in's walk; n_zero: the edges of the triangle found that hold p.
    int32_t walk_in(const Territory &g, const Vec3 &p, int32_t hint, int &n_zero) const;
    void stitch_new_triangles(int32_t v, Scratch &s, SlotPool &pool);
    // Whether vertex slot v's lifted point lies beyond t's facet (exact,
    // perturbed). The cavity search has its own copy of this test, inlined
    // with the static filter only (fill_cavity_with).
    bool visible(int32_t t, int32_t v) const {
        const int32_t *tv = tris_[t].v;
        const double *a = q_[tv[0]].data(), *b = q_[tv[1]].data(), *c = q_[tv[2]].data();
        const int s = build_bound_ < kNoBound ? geom::orient3d_static(a, b, c, q_[v].data(), build_bound_)
                                             : geom::orient3d(a, b, c, q_[v].data());
        return s != 0 ? s > 0 : visible_on_tie(t, v);
    }
    // The exact tie's symbolic perturbation (predicates.hpp).
    bool visible_on_tie(int32_t t, int32_t v) const;
    int64_t priority(int32_t v) const;
    // The neighbour of `outer` across its edge from -> to becomes t.
    void set_neighbour(int32_t outer, int32_t from, int32_t to, int32_t t);
    // Inline for the usual case, a slot of the pool's fresh run.
    int32_t new_triangle_slot(SlotPool &pool) {
        if (pool.reuse->empty() && pool.fresh < pool.fresh_end) return pool.fresh++;
        return new_triangle_slot_slow(pool);
    }
    int32_t new_triangle_slot_slow(SlotPool &pool);
    void free_triangle_slot(int32_t t);
    void free_triangle_slot(int32_t t, SlotPool &pool);
    bool flippable(int32_t t, int k) const;
    int32_t remove_degree_three(int32_t v);
    bool nudge_off_diagonals(int32_t v, const std::vector<int32_t> &link);
    bool ear_is_hull_facet(const std::vector<int32_t> &link, size_t i) const;
    int32_t reinsert(int32_t v, std::vector<int32_t> *buried, int32_t hint = 0);
    std::vector<int32_t> replace_point(int32_t v, const Vec3 &lifted);
    void compact_triangles(int32_t vertex_shift);
    template <class Vector>
    static void gather_copy(Context &ctx, Vector &values, const std::vector<int32_t> &old_of_new);
    // values with room for `capacity` (no less than it has), copied in parallel.
    template <class Vector>
    static void grow_capacity(Context &ctx, Vector &values, size_t capacity);
    void permute_vertices_in_place(const std::vector<int32_t> &new_of_old);
    template <class Smallest, class Remap>
    std::vector<int32_t> reorder_triangles_copying(Context &ctx, Smallest smallest, Remap remap);
    template <class Smallest, class Remap>
    std::vector<int32_t> reorder_triangles_in_place(int32_t n, Smallest smallest, Remap remap);
    void compact_after_build(Context &ctx);
    [[noreturn]] void fail_on_duplicates() const;

    // (UninitVector: the construction writes each element once, in parallel;
    // HugePageVector: and from many points places them on huge pages.)
    HugePageVector<Vec3> q_;            // lifted point per vertex slot
    UninitVector<int32_t> id_;        // input index; < 0 for the virtual octahedron
    UninitVector<int32_t> vertex_tri_;  // a triangle incident to the vertex; kNone hidden, kRemoved
    // One record per triangle so that a visit touches one cache line.
    struct Tri {
        int32_t v[3];  // vertices; v[0] == kNone for a free slot
        int32_t n[3];  // neighbours across the edges opposite v[k]
    };
    HugePageVector<Tri> tris_;
    // A triangle's state during one insertion. Not a plain byte: stores
    // through a character type may alias anything, so after each mark
    // written the compiler would reload every pointer and bound the
    // insertion's loops hold.
    enum class Mark : uint8_t { none = 0, cavity = 1, outside = 2 };
    UninitVector<Mark> mark_;         // per-triangle scratch of the insertion; none between insertions
    std::vector<int32_t> free_;       // free triangle slots

    Scratch scratch_;                 // the serial path's
    UninitVector<uint32_t> key_;      // Hilbert key per vertex slot, while building
    mutable uint32_t walk_counter_ = 0;  // rotates the walk's first edge
    // While build() inserts: orient3d's static error bound for its points
    // (geom::orient3d_static_bound), which decides most visibility tests
    // with one comparison; kNoBound otherwise (weights may change later).
    // walk_bound_: orient_origin's (the walk's test), likewise.
    static constexpr double kNoBound = 1e300;
    double build_bound_ = kNoBound, walk_bound_ = kNoBound;
    double longest_lifted_ = 1.0;     // prepare()'s longest lifted point (the band keys' scale)
    BuildRoom room_;                  // from reserve_build() to the end of prepare()
};

template <class T>
T *Triangulation::BuildRoom::take(size_t count) {
    static_assert(std::is_trivially_copyable<T>::value && std::is_trivially_destructible<T>::value,
                  "the room holds plain values");
    const uintptr_t at = (reinterpret_cast<uintptr_t>(next_) + alignof(T) - 1) / alignof(T) * alignof(T);
    const uintptr_t end = reinterpret_cast<uintptr_t>(end_);
    if (!next_ || at > end || count > (end - at) / sizeof(T))
        fail(UM_ERR_INTERNAL, "the build's room has no space for ", count, " values of ", sizeof(T), " bytes");
    next_ = reinterpret_cast<unsigned char *>(at + count * sizeof(T));
    return reinterpret_cast<T *>(at);
}

class Triangulation::Territory {
public:
    int32_t vertices_inserted() const { return next_vertex_ - first_vertex_; }
    int32_t vertex_budget_left() const { return vertex_end_ - next_vertex_; }
    // The triangle slots it was given: free ones, and [first_fresh, fresh_end).
    const std::vector<int32_t> &free_slots_given() const { return given_; }
    int32_t first_fresh_slot() const { return first_fresh_; }
    int32_t fresh_slot_end() const { return pool_.fresh_end; }

private:
    friend class Triangulation;
    KeyRange keys_{nullptr, 0, 0};
    int layout_ = 0;
    int32_t first_vertex_ = 0, next_vertex_ = 0, vertex_end_ = 0;
    int32_t first_id_ = 0;  // the id of its first vertex slot
    std::vector<int32_t> reuse_;  // free triangle slots: given at opening, then emptied by it
    std::vector<int32_t> given_;  // the free ones given at opening
    SlotPool pool_;
    int32_t first_fresh_ = 0;
    Scratch scratch_;
    mutable uint32_t walk_ = 0;
};

template <class DirectionFn, class KeyDirectionFn, class PrefetchFn>
void Triangulation::prepare(Context &ctx, int64_t n, DirectionFn direction, const double *weights,
                            KeyDirectionFn key_direction, PrefetchFn prefetch) {
    // The room a caller opened for this build, else one of its own.
    if (room_.end_ && (room_.n_ != n || room_.begin_ != reinterpret_cast<unsigned char *>(tris_.data()))) {
        const int64_t made_for = room_.n_;
        room_.close();  // ended, as by any prepare()
        fail(UM_ERR_INTERNAL, "prepare(", n, "): the build's room was made for ", made_for, " points");
    }
    BuildRoom &room = room_.end_ ? room_ : reserve_build(n);
    struct RoomEnds {  // here, however prepare() ends
        BuildRoom &room;
        ~RoomEnds() { room.close(); }
    } room_ends{room};
    const Buffer<uint64_t> order = brio_words(ctx, n, key_direction, room.take<uint64_t>(2 * static_cast<size_t>(n)));
    const size_t slots = static_cast<size_t>(n) + kVirtual;
    // Sized without being written (the gather below writes each element
    // first, in parallel), and advised before that first touch, which is
    // what places the pages.
    auto size_for_gather = [slots](auto &values) {
        values.clear();
        values.reserve(slots);
        advise_huge_pages(values.data(), values.capacity() * sizeof(values[0]));
        values.resize(slots);
    };
    size_on_huge_pages(q_, slots);  // as the triangles (reserve_build)
    size_for_gather(id_), size_for_gather(key_), size_for_gather(vertex_tri_);
    std::fill_n(key_.begin(), kVirtual, ~uint32_t(0));  // the virtual vertices: owned by no region
    std::fill_n(vertex_tri_.begin(), kVirtual, kNone);
    double largest = 1.0;  // the longest lifted point (the virtual ones are tiny)
    if (weights)
        for (int64_t i = 0; i < n; ++i) largest = std::max(largest, lifted_scale(weights[i]));
    longest_lifted_ = largest;
    build_bound_ = geom::orient3d_static_bound(largest);
    walk_bound_ = geom::orient_origin_static_bound(largest);
    // A gather from the input in a random order: each read misses the
    // cache and the TLB, so the point a few places ahead is asked for early.
    constexpr int64_t kAhead = 16;
    ctx.parallel_for(n, 8192, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            if (i + kAhead < e) prefetch(brio_point(order[i + kAhead]));
            const int32_t src = brio_point(order[i]);
            double s = weights ? lifted_scale(weights[src]) : 1.0;
            q_[kVirtual + i] = s * direction(src);
            id_[kVirtual + i] = src;
            key_[kVirtual + i] = brio_hilbert(order[i]);
            vertex_tri_[kVirtual + i] = kNone;
        }
    });
}

template <class DirectionFn>
void Triangulation::build(Context &ctx, int64_t n, DirectionFn direction, const double *weights) {
    prepare(ctx, n, direction, weights, direction);
    finish_build(ctx);
}

}  // namespace um::tri
