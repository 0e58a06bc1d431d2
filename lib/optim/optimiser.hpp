// The optimiser's state and its parts (internal to lib/optim): the schedule
// of Algorithm 1, the sweeps and the mends are in optimise.cpp, the support
// of obtuse corners on Gamma in gamma_corners.cpp. Nothing here is public:
// optimise.hpp is the stage's interface.
#pragma once

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "core/context.hpp"
#include "features/network.hpp"
#include "geom/arc_tree.hpp"
#include "optim/local_quality.hpp"
#include "optim/optimise.hpp"
#include "optim/star_graph.hpp"
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

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0);
// A fingerprint of every vertex's link, to tell after a topology change
// which links changed (Optimiser::mark_changed_links).
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

class Optimiser {
public:
    Optimiser(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
              const features::Network *gamma, const refine::SpacingRadians &h,
              const OptimiseOptions &o);

    OptimiseStats run();

private:
    // Per-slot state -------------------------------------------------------
    // Grows the per-slot state to the slots and reads h at every vertex.
    void load_spacing();
    void grow_slots();

    // Sweeps ---------------------------------------------------------------
    enum class Sweep { moves, weights, centroidal };
    // Over every vertex, or only over those flagged in *only.
    int64_t sweep(const StarGraph &g, Sweep kind, bool forward,
                  const std::vector<uint8_t> *only = nullptr);
    bool update_position(const StarGraph &g, int32_t v);
    bool update_weight(const StarGraph &g, int32_t v);
    // The centroidal pass (centroidal.cpp): Lloyd sweeps with flips between
    // them, until the generators stop moving or kCentroidalSweeps.
    int64_t relax_to_centroids(std::unique_ptr<StarGraph> &graph);
    bool update_centroidal(const StarGraph &g, int32_t v);
    Vec3 centroid_target(const StarGraph &g, int32_t v, const Generator &here, const Ring &ring) const;
    bool nothing_changed_since(const StarGraph &g, int32_t v, int32_t tried) const;
    int64_t polish_poor_stars(const StarGraph &g);
    // What a mend met and mended (slid: of those, with a vertex sliding
    // along Gamma).
    // What a mend keeps: no Q^P below qp; where vertices move, no Q^T below
    // qt and no angle larger than the one of cosine largest_angle_cosine.
    struct MendFloors {
        double qp = 0, qt = 0, largest_angle_cosine = -1;
    };
    struct Mended {
        int64_t met = 0, mended = 0, slid = 0, flipped = 0;
        MendFloors floors;  // what it kept (from a summary, made only when it met any)
    };
    // The floors from a fresh summary: the mesh's least Q^P (or kMendQpFloor,
    // when `qp_floor` and that is lower), least Q^T and largest angle.
    MendFloors mend_floors(bool qp_floor);
    // keep_obtuse: its moves may not add obtuse triangles (after the obtuse mend).
    Mended mend_off_centre_triangles(bool keep_obtuse);
    struct Candidate {  // a generator a vertex may take, and its segment of Gamma
        Generator g;
        int32_t segment;
    };
    std::vector<Candidate> mend_candidates(int32_t v, int steps, int slides, bool off_gamma_moves = false) const;
    // The live triangles t with pred(t), found in parallel, in slot order
    // (the mends then work through them serially).
    template <class Pred>
    std::vector<int32_t> live_triangles_where(Pred pred) const {
        return ctx_.collect_in_order<int32_t>(tri_.triangle_slots(), 8192, [&](int64_t t, std::vector<int32_t> &out) {
            if (!tri_.is_free(static_cast<int32_t>(t)) && pred(static_cast<int32_t>(t))) out.push_back(static_cast<int32_t>(t));
        });
    }
    // What a joint search lowers: the triangles not holding their
    // orthocentre (also without adding obtuse ones), or the obtuse ones
    // (then without adding to the former).
    enum class MendGoal { off_centre, off_centre_keeping_obtuse, obtuse };
    // The off-centre and obtuse triangles around, counted before a flip
    // that left the mesh as it is not regular (mend_by_flip): what a joint
    // search after it must beat, instead of the counts as they are.
    struct Baseline {
        int off_centre, obtuse;
        int gamma_crossings;  // stars_gamma_crossings of the quad before the flip
    };
    bool mend_jointly(const int32_t *v, int n, const std::vector<Candidate> *candidates, const MendFloors &floors,
                      bool moves, MendGoal goal = MendGoal::off_centre, const Baseline *baseline = nullptr);
    bool mend_by_flip(int32_t &t, int k, const MendFloors &floors, MendGoal goal);
    bool runs_along_gamma(int32_t b, int32_t c, int32_t a, int32_t d) const;
    double position_along_part(int32_t v) const;
    Mended mend_obtuse_triangles();
    // False when v's degree is beyond Ring::kMax.
    bool gather_ring(const StarGraph &g, int32_t v, Ring &ring) const;
    // Gamma and the cells off it. The refinement leaves Gamma crossing the
    // cells of the vertices placed on it (Tri|Gamma runs from one to the
    // next); a move or weight that lets it into a cell off it adds edges to
    // Tri|Gamma that branch off the feature's chain (the river and coast
    // tags of the MPAS edges). Sweeps and mends therefore take no update
    // that adds such a crossing around the vertex. near_gamma_ flags the
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
            tri_.for_each_neighbour(v[i], [&](int32_t w) {
                if (ring.m == Ring::kMax) return void(fits = false);
                link[ring.m] = w, ring.g[ring.m] = at(w), ring.q[ring.m] = at(w).lifted(), ++ring.m;
            });
            if (!fits || (require_valid && !star_is_valid(ring, at(v[i])))) return -1;
            if (arcs_.size() > 0) crossings += gamma_crossings(v[i], ring, link, at(v[i]));
        }
        return crossings;
    }
    // The ODT target of a move of v (at `here`, link `ring` from the graph).
    Vec3 odt_target(const StarGraph &g, int32_t v, const Generator &here, const Ring &ring) const;

    // Topology -------------------------------------------------------------
    int64_t restore_regularity(int32_t since);
    void mark_changed_links(const std::vector<uint32_t> &before, const StarGraph &now);
    int64_t improve_valence();
    int64_t flip_for_valence();
    bool relax_into_regularity(const int32_t (&quad)[4]);
    Vec3 star_odt_point(int32_t v) const;
    int32_t insert_between(int32_t a, int32_t b);
    int64_t support_gamma_corners();
    // An obtuse triangle with its corner on Gamma, and what a vertex put
    // there to support the corner is judged against.
    struct GammaCorner {
        int32_t triangle;       // its slot (where the insertion starts)
        int32_t b, p, q;        // the corner on Gamma and the triangle's other two vertices
        std::vector<int32_t> region;  // the closed stars of b, p, q (sorted): what may change
        std::vector<std::pair<int32_t, int32_t>> gamma_edges;  // the edges along Gamma there
        int obtuse_before;      // the obtuse triangles touching the region
    };
    // A trial of a corner vertex: its slot when kept, and the obtuse
    // triangles around it when it helps (else -1).
    struct CornerTrial {
        int32_t vertex = -1;
        int obtuse = -1;
    };
    CornerTrial try_corner_vertex(const Vec3 &at, const GammaCorner &corner, bool keep = true);
    enum class CornerChange { none, vertex_added, vertex_removed };
    CornerChange support_gamma_corner(const GammaCorner &corner, bool opposite_gamma, std::vector<uint8_t> &locked);
    int32_t keep_best_corner_vertex(const std::vector<Vec3> &sites, size_t from, size_t to, const GammaCorner &corner);
    std::vector<Vec3> corner_sites(const GammaCorner &corner) const;
    struct MovedVertex {  // a vertex as it was before a trial moved it
        int32_t v;
        Vec3 lifted;
        float h;
    };
    std::vector<int32_t> odt_step(int32_t v);
    std::vector<int32_t> relax_link(int32_t d, const GammaCorner &corner, std::vector<MovedVertex> &moved);
    int32_t try_corner_relocation(const Vec3 &at, const GammaCorner &corner, std::vector<uint8_t> &locked);
    int corner_vertex_helps(int32_t d, const GammaCorner &corner) const;
    bool try_gamma_vertex_removal(int32_t v, const GammaCorner &corner);
    bool chord_carries_gamma(int32_t a, int32_t c) const;
    bool has_triangle(int32_t a, int32_t b, int32_t c) const;
    int obtuse_touching(const std::vector<int32_t> &vertices) const;
    std::vector<std::pair<int32_t, int32_t>> gamma_edges_among(const std::vector<int32_t> &vertices) const;
    bool has_edge(int32_t a, int32_t b) const;
    bool leaves_long_edge(const Vec3 &x, double h_x, std::initializer_list<int32_t> ends) const;
    bool leaves_short_edge(int32_t a, int32_t b) const;
    void split_vertex(int32_t v, const std::vector<int32_t> &star);
    struct EdgeRatio {
        double ratio;
        int32_t a, b;
    };
    std::vector<EdgeRatio> edge_ratios(double below, double above) const;
    // Collapses the edges shorter than collapse_ratio h, then splits those
    // longer than split_ratio h: one scan finds both kinds (the long ones are
    // found again when a collapse changed the mesh).
    std::pair<int64_t, int64_t> collapse_and_split();
    int64_t collapse_short_edges(std::vector<EdgeRatio> edges);
    int64_t split_long_edges(std::vector<EdgeRatio> edges);
    // The given vertices and their neighbours (sorted, each once).
    std::vector<int32_t> closed_stars(std::initializer_list<int32_t> vertices) const;
    // Claims `vertices` for this pass's one change around them; false
    // (nothing claimed) if any is taken.
    static bool claim(const std::vector<int32_t> &vertices, std::vector<uint8_t> &locked);
    bool lock_neighbourhood(std::initializer_list<int32_t> vertices, std::vector<uint8_t> &locked) const {
        return claim(closed_stars(vertices), locked);
    }

    // Stopping ---------------------------------------------------------------
    struct Summary {
        double qt_min, qt_mean, qp_min, qp_mean;
        double largest_angle_cosine;  // of the mesh's largest angle
    };
    // with_largest_angle: also the cosine of the largest angle (else 1).
    Summary summarise(bool with_largest_angle = false) const;

    Context &ctx_;
    tri::Triangulation &tri_;
    std::vector<int32_t> &on_segment_;
    const features::Network *gamma_;
    const refine::SpacingRadians &h_;
    OptimiseOptions o_;
    double gain_;  // the least gain in local quality an update must bring
    geom::ArcTree arcs_;               // Gamma's arcs (empty without Gamma)
    std::vector<uint8_t> near_gamma_;  // per slot, from flag_near_gamma

    // The generator of vertex v, read from its lifted point q = s x: the
    // triangulation holds the only copy (a second one would cost 32 bytes
    // per cell), and the sweeps write it in place (Triangulation::set_lifted).
    Generator generator(int32_t v) const {
        const Vec3 &q = tri_.lifted(v);
        const double s = geom::norm(q);
        return {(1.0 / s) * q, s};
    }
    void set_generator(int32_t v, const Generator &g) { tri_.set_lifted(v, g.lifted()); }

    // Spacing at each generator (radians), in single precision: it weighs
    // the ODT target and scales steps, where 1e-7 is far below what matters.
    std::vector<float> h_at_;
    // Stamps of the sweep clock: when a vertex last changed (position,
    // weight or link) and when an update of it last failed. A vertex whose
    // closed star has not changed since its last failure is skipped.
    std::vector<int32_t> changed_at_, move_failed_at_, weight_failed_at_;
    bool weighing_ = false;  // the weight phase has begun (weight_failed_at_ exists)
    int32_t clock_ = 1;
    int32_t next_id_ = 0;
    double poor_star_ = -std::numeric_limits<double>::infinity();  // stars scoring below get the compass search
    OptimiseStats stats_;
};

}  // namespace um::optim::detail
