// The state every pass of the optimisation reads and writes (internal to
// lib/optim): the triangulation and its generators, the spacing at each
// vertex, the change clock that lets a sweep skip what has not changed, the
// guard that keeps Gamma out of the cells off it, and the stats. The passes
// are units of their own (shape_sweeps, weight_sweeps, centroidal,
// topology, gamma_corners, mends); optimise.cpp holds the schedule.
// Nothing here is public: optimise.hpp is the stage's interface.
#pragma once

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <utility>
#include <unordered_set>
#include <vector>

#include "core/context.hpp"
#include "features/network.hpp"
#include "geom/arc_tree.hpp"
#include "optim/local_quality.hpp"
#include "optim/optimise.hpp"
#include "optim/quality_summary.hpp"
#include "optim/star_graph.hpp"
#include "refine/sides.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::optim::detail {

// The generators of a star's link, gathered once per vertex update: a line
// search scores the same star up to a dozen times, and reading the link
// through the graph each time costs more than the scores themselves.
struct Ring {
    // A larger degree is never updated (improve_valence splits such
    // vertices, except on Gamma).
    static constexpr int kMax = 64;
    int m = 0;
    Generator g[kMax];
    // The stored lifted points: g[k].lifted() is s x rounded from them, and
    // the exact tests must see what the triangulation holds.
    Vec3 q[kMax];
    const Generator &at(int k) const { return g[k]; }
    const Generator &after(int k) const { return g[k + 1 == m ? 0 : k + 1]; }
};

// The star stays a valid piece of triangulated sphere (every triangle
// counter-clockwise, exactly) and every spoke's crossing with its dual edge
// stays inside it.
bool star_is_valid(const Ring &ring, const Generator &at);

constexpr double kInfinity = std::numeric_limits<double>::infinity();

constexpr int kHalvings = 5;  // line searches try steps 1, 1/2, ..., 1/32

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0);
// A fingerprint of every vertex's link, to tell after a topology change
// which links changed (MeshState::mark_changed_links).
std::vector<uint32_t> link_fingerprints(Context &ctx, const StarGraph &g);

// Worst and mean of a star's triangle scores, and which triangle (k: the
// one between link vertices k and k + 1) is the worst.
struct LocalQuality {
    double worst = std::numeric_limits<double>::infinity();
    double mean = 0;
    int worst_k = 0;
};

// Worst and mean score of the star of a vertex at `centre` with link
// `ring`: the shape score for moves, the staggering score for weights.
// Stops (mean unset) as soon as a triangle scores below `floor`: such a
// star cannot be BETTER than one whose worst is `floor`. The triangle at
// `first` is scored first (a trial's old worst is the likeliest to fail);
// the mean is summed in link order all the same.
template <bool kShape>
LocalQuality ring_quality(const Ring &ring, const Generator &centre, double floor, int first = 0) {
    LocalQuality q;
    double score[Ring::kMax];
    for (int i = 0, k = first; i < ring.m; ++i, k = k + 1 == ring.m ? 0 : k + 1) {
        const Generator &a = ring.at(k), &b = ring.after(k);
        score[k] = kShape ? shape_score(centre.x, a.x, b.x) : staggering_score(centre, a, b);
        if (score[k] < q.worst) q.worst = score[k], q.worst_k = k;
        if (q.worst < floor) return q;
    }
    double sum = 0;
    for (int k = 0; k < ring.m; ++k) sum += score[k];
    q.mean = sum / ring.m;
    return q;
}

// BETTER of Algorithm 1: the worst local quality improves, or stays and the
// mean improves, each by more than the tolerance.
inline bool better(const LocalQuality &now, const LocalQuality &before, double tolerance) {
    if (now.worst > before.worst + tolerance) return true;
    return now.worst >= before.worst && now.mean > before.mean + tolerance;
}

class MeshState {
public:
    MeshState(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
              const features::Network *gamma, const refine::SpacingRadians &h, const OptimiseOptions &o,
              const features::Domain *domain = nullptr, const std::vector<refine::Side> *sides = nullptr);

    Context &ctx;
    tri::Triangulation &tri;
    std::vector<int32_t> &on_segment;
    const features::Network *gamma;
    const refine::SpacingRadians &h;
    const OptimiseOptions options;
    const double gain;  // the least gain in local quality an update must bring
    const geom::ArcTree arcs;        // Gamma's arcs (empty without Gamma)
    std::vector<uint8_t> near_gamma;  // per slot, from flag_near_gamma
    // What each flag was found for (id -1: none), and the clock then.
    struct Flagged {
        int32_t id = -1;
        float h = 0;
    };
    std::vector<Flagged> flagged_for;
    int32_t flagged_clock = 0;
    // A regional mesh's domain (else null) and, per slot, whether the vertex
    // is of the cover outside it (optimise.hpp): found with the spacing
    // (load_spacing); a vertex added since counts as not.
    const features::Domain *domain;
    std::vector<uint8_t> in_cover;
    // A regional mesh's spacing and cover as load_spacing found them, per
    // slot, with the place and Gamma segment they were found for: the
    // cover's spacing searches the rings near them, and few vertices move
    // between two loads.
    struct LoadedSpacing {
        geom::Vec3 at{std::numeric_limits<double>::quiet_NaN(), 0, 0};  // (matches no place)
        int32_t segment = -1;
        float h = 0;
        uint8_t cover = 0;
    };
    std::vector<LoadedSpacing> loaded;
    bool cover(int32_t v) const { return static_cast<size_t>(v) < in_cover.size() && in_cover[v]; }
    bool touches_cover(int32_t t) const {
        return !in_cover.empty() && (cover(tri.vertex(t, 0)) || cover(tri.vertex(t, 1)) || cover(tri.vertex(t, 2)));
    }
    // Whether a vertex at v (one just added, say) lies outside the domain or
    // has a neighbour in the cover: where nothing may be added.
    bool beside_cover(int32_t v) const;
    // Whether any of `vertices` is of the cover (what an insertion hid).
    bool any_cover(const std::vector<int32_t> &vertices) const {
        for (int32_t u : vertices)
            if (cover(u)) return true;
        return false;
    }

    // Spacing at each generator (radians), in single precision: it weighs
    // the ODT target and scales steps, where 1e-7 is far below what matters.
    std::vector<float> h_at;
    // Stamps of the sweep clock: when a vertex last changed (position,
    // weight or link) and when an update of it last failed. A vertex whose
    // closed star has not changed since its last failure is skipped. The
    // kept summary and near-Gamma flags trust them too: every pass stamps
    // what it changes, and a trial it undoes puts every point back bit for bit.
    std::vector<int32_t> changed_at, move_failed_at, weight_failed_at;
    // Per slot, ocean, land or coastal (ocean_sides.cpp; empty without a
    // floor), and the id of the vertex each was found for (-1: none).
    std::vector<refine::Side> side;
    std::vector<int32_t> side_id;
    int32_t sides_clock = -1;  // the clock at the last refresh (changed_at since: looked at again)
    // The sides given for the starting triangulation (optimise's `sides`):
    // what the first refresh takes; null once taken.
    const std::vector<refine::Side> *given_sides = nullptr;
    bool weighing = false;  // the weight phase has begun (weight_failed_at exists)
    int32_t clock = 1;
    int32_t next_id = 0;
    OptimiseStats stats;

    // The generator of vertex v, read from its lifted point q = s x: the
    // triangulation holds the only copy (a second one would cost 32 bytes
    // per cell), and the sweeps write it in place (Triangulation::set_lifted).
    Generator generator(int32_t v) const {
        const Vec3 &q = tri.lifted(v);
        const double s = geom::norm(q);
        return {(1.0 / s) * q, s};
    }
    void set_generator(int32_t v, const Generator &g) { tri.set_lifted(v, g.lifted()); }

    // Per-slot state -------------------------------------------------------
    // Grows the per-slot state to the slots and reads h at every vertex.
    void load_spacing();
    void grow_slots();

    // Sweeps ---------------------------------------------------------------
    // One graph-coloured sweep of update(g, v) over every vertex off the
    // cover, or only over those flagged in *only: the vertices of one colour
    // in parallel, colours in sequence (forward or in reverse); the updates
    // taken. With `near` (changed_near's flags at the sweep's start), only
    // the flagged vertices are visited, and each update taken flags its
    // link for the colours after it: the vertices an update that skips
    // what has not changed since its last failure could take.
    template <class Update>
    int64_t sweep(const StarGraph &g, bool forward, const std::vector<uint8_t> *only, Update &&update,
                  std::vector<uint8_t> *near = nullptr) {
        const auto &colours = g.colours();
        const int n_colours = static_cast<int>(colours.size());
        int64_t accepted = 0;
        std::vector<int32_t> subset;
        for (int i = 0; i < n_colours; ++i) {
            const std::vector<int32_t> *list = &colours[forward ? i : n_colours - 1 - i];
            if (only || near || !in_cover.empty()) {
                subset.clear();
                for (int32_t v : *list)
                    if ((!only || (*only)[v]) && (!near || (*near)[v]) && !cover(v)) subset.push_back(v);
                list = &subset;
            }
            std::vector<uint8_t> took(list->size(), 0);
            ctx.parallel_for(static_cast<int64_t>(list->size()), 256, [&](int64_t b, int64_t e) {
                for (int64_t k = b; k < e; ++k) took[k] = update(g, (*list)[k]);
            });
            for (size_t k = 0; k < took.size(); ++k) {
                accepted += took[k];
                if (near && took[k]) flag_link(g, (*list)[k], *near);
            }
            ++clock;  // the next colour sees this one's changes as newer than its failures
        }
        return accepted;
    }
    bool nothing_changed_since(const StarGraph &g, int32_t v, int32_t tried) const;
    // The vertices (flags per slot) whose closed star in g holds one
    // changed at `since` or later; empty (all of them) when that is more
    // than a few. After a sweep that began at `since` (of every vertex, or
    // of these flags as it went), only these can be found changed since
    // their last failure: each other one failed, or was skipped, in that
    // sweep or later, and every change since is stamped (a new link by
    // rebuild_graph). What lowers a failure stamp must stamp the vertex or
    // visit it at once (the re-seeding and the polish do).
    std::vector<uint8_t> changed_near(const StarGraph &g, int32_t since) const;
    // Flags v's link in `flags`.
    static void flag_link(const StarGraph &g, int32_t v, std::vector<uint8_t> &flags) {
        const int32_t *link = g.link(v);
        for (int k = 0; k < g.degree(v); ++k) flags[link[k]] = 1;
    }
    // False when v's degree is beyond Ring::kMax.
    bool gather_ring(const StarGraph &g, int32_t v, Ring &ring) const;

    // Gamma guard (gamma_guard.cpp) ----------------------------------------
    // Gamma and the cells off it. The refinement leaves Gamma crossing the
    // cells of the vertices placed on it (Tri|Gamma runs from one to the
    // next); a move or weight that lets it into a cell off it adds edges to
    // Tri|Gamma that branch off the feature's chain (the river and coast
    // tags of the MPAS edges). Sweeps and mends therefore take no update
    // that adds such a crossing around the vertex. near_gamma flags the
    // vertices within kNearGamma h of an arc of Gamma (the others cannot
    // reach it in one outer iteration); gamma_crossings counts the spokes of
    // v's star, v at `at`, that do not join two vertices on Gamma and whose
    // dual arc crosses Gamma.
    void flag_near_gamma();
    int gamma_crossings(int32_t v, const Ring &ring, const int32_t *link, const Generator &at) const;
    bool crosses_gamma(const Vec3 &c0, const Vec3 &c1) const;
    // gamma_crossings summed over the stars of v[0..n), the generators read
    // through at(u); -1 when a star is beyond Ring::kMax or, with
    // require_valid, not valid (star_is_valid) for its centre's generator.
    template <class At>
    int stars_gamma_crossings(const int32_t *v, int n, At &&at, bool require_valid) const {
        int crossings = 0;
        for (int i = 0; i < n; ++i) {
            Ring ring;
            int32_t link[Ring::kMax];
            bool fits = true;
            tri.for_each_neighbour(v[i], [&](int32_t w) {
                if (ring.m == Ring::kMax) return void(fits = false);
                link[ring.m] = w, ring.g[ring.m] = at(w), ring.q[ring.m] = at(w).lifted(), ++ring.m;
            });
            if (!fits || (require_valid && !star_is_valid(ring, at(v[i])))) return -1;
            if (arcs.size() > 0) crossings += gamma_crossings(v[i], ring, link, at(v[i]));
        }
        return crossings;
    }
    bool runs_along_gamma(int32_t b, int32_t c, int32_t a, int32_t d) const;
    double position_along_part(int32_t v) const;
    // Whether the edge (a, c), both on Gamma, is a restricted edge of their
    // part within the boundary refinement's bounds: l < alpha h, eps < beta h.
    bool chord_carries_gamma(int32_t a, int32_t c, double alpha, double beta) const;
    // The edges along Gamma (runs_along_gamma) between two of `vertices`
    // (sorted), each once.
    std::vector<std::pair<int32_t, int32_t>> gamma_edges_among(const std::vector<int32_t> &vertices) const;
    bool has_edge(int32_t a, int32_t b) const;
    // Every edge of `edges` is still an edge, but those of vertex `gone`
    // (-1: none).
    bool gamma_edges_stay(const std::vector<std::pair<int32_t, int32_t>> &edges, int32_t gone = -1) const;
    // The obtuse triangles with a vertex among `vertices` (each counted once).
    int obtuse_touching(const std::vector<int32_t> &vertices) const;

    // Topology -------------------------------------------------------------
    // Whether v may be taken out: every neighbour within kLargestRemovableStar
    // of it. A star reaching towards a hemisphere (the 12-vertex start of a
    // spacing of 10,000 km or a radius of 1 mm; a merged hole of the
    // re-seeding) cannot be re-triangulated by hull facets.
    static constexpr double kLargestRemovableStar = 0.5;  // radians (29 degrees)
    bool removable(int32_t v) const;
    int64_t restore_regularity(int32_t since);
    void mark_changed_links(const std::vector<uint32_t> &before, const StarGraph &now);
    // After a topology change: the spacing reloaded, the graph built anew
    // and the vertices whose link changed marked.
    void rebuild_graph(std::unique_ptr<StarGraph> &graph);
    Vec3 star_odt_point(int32_t v) const;
    // The given vertices and their neighbours (sorted, each once).
    std::vector<int32_t> closed_stars(std::initializer_list<int32_t> vertices) const;
    // Claims `vertices` for this pass's one change around them; false
    // (nothing claimed) if any is taken.
    static bool claim(const std::vector<int32_t> &vertices, std::vector<uint8_t> &locked);
    bool lock_neighbourhood(std::initializer_list<int32_t> vertices, std::vector<uint8_t> &locked) const {
        return claim(closed_stars(vertices), locked);
    }

    // The ids of the vertices the corner pass added to support obtuse corners
    // on Gamma (gamma_corners.hpp): in the shape phase the floor pass lifts
    // their edges only below the floor itself, where the moves stop. With the
    // shape phase's margin it took out what the sweeps had pulled towards the
    // corner, and the corner pass put it back, every iteration (coast 60 km:
    // 40 of each per iteration, ten iterations without end).
    std::unordered_set<int32_t> corner_supports;
    bool supports_corner(int32_t v) const { return corner_supports.count(tri.id(v)) != 0; }

    // The time-step floor's sides (ocean_sides.cpp) ---------------------------
    // Brings `side` up to date: found once, then kept for the vertices that
    // stay and inferred for those made since.
    void refresh_sides();
    // Finds every side anew, as the quality report will (refine::vertex_sides):
    // a side kept or inferred for a vertex the passes made may differ from it
    // (a new vertex beside the coast takes a land neighbour's side, its
    // triangles all on the ocean side), and the report would then count an
    // ocean edge below the floor that the pass took for one on the land.
    void find_sides_anew() {
        side_id.clear();
        refresh_sides();
        sides_clock = clock;  // (a later refresh looks at what changed since)
    }
    // Whether v's cell is off the land (ocean or coastal: the cells the
    // ocean mesh may take), from its side or, for a vertex made since the
    // last refresh, the side it would be given.
    bool off_land(int32_t v) const;
    // The floor the ocean-floor pass lifts the edges below (over h): in the
    // shape phase with a margin over the option (not for the edges of a
    // corner's support: corner_supports).
    double floor_to_lift() const;
    // With a floor: whether v, off the land, has no edge shorter than
    // floor h to another generator off the land (true on the land).
    bool clear_of_floor(int32_t v) const { return below_floor_at({v}) == 0; }
    // With a floor: whether moving v, off the land, to `to` makes no edge to
    // a generator off the land shorter than floor h that was not, nor a
    // shorter one shorter still (true on the land).
    bool move_keeps_floor(int32_t v, const Vec3 &to) const;
    // The same for a sweep's trial, from v's ring and link (the ring holds
    // the neighbours' positions). `slack` is floor_slack's: moves shorter
    // than it keep the floor without a look at the neighbours (the sweeps
    // try many per vertex).
    bool move_keeps_floor(int32_t v, const Vec3 &to, double slack, const Ring &ring, const int32_t *link) const;
    // How far v may move before an edge of it could pass below the floor
    // (whatever the sides): the least of its edges' chords less floor h;
    // infinite without a floor.
    double floor_slack(int32_t v, const Ring &ring, const int32_t *link) const;
    // With a floor: the edges at `vertices` (each once) between two
    // generators off the land shorter than floor h (0 without a floor), or
    // than `floor` h (floor_to_lift: what the floor pass would lift).
    int below_floor_at(const std::vector<int32_t> &vertices) const {
        return below_floor_at(vertices, options.ocean_floor);
    }
    int below_floor_at(const std::vector<int32_t> &vertices, double floor) const;
    // Whether the floor is kept: one is asked for and the sides are known.
    bool keeps_floor() const { return options.ocean_floor > 0 && !side_id.empty(); }

    // Stopping ---------------------------------------------------------------
    using Summary = detail::Summary;
    // with_largest_angle: also the cosine of the largest angle (else 1).
    Summary summarise(bool with_largest_angle = false) { return summary_.summarise(*this, with_largest_angle); }

private:
    QualitySummary summary_;
};

// When the last sweep of one kind (the shape moves, or the weights) began,
// and so what the next one needs to visit (MeshState::changed_near).
class SweepStart {
public:
    // The next sweep's flags (empty: every vertex, as for the first); it
    // begins now.
    std::vector<uint8_t> next(const MeshState &s, const StarGraph &g) {
        std::vector<uint8_t> near = began_ < 0 ? std::vector<uint8_t>{} : s.changed_near(g, began_);
        began_ = s.clock;
        return near;
    }

private:
    int32_t began_ = -1;  // (clocks start at 1)
};

}  // namespace um::optim::detail
