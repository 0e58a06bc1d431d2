// The schedule of Algorithm 1 (optimise.hpp): the passes in their order.
// Each pass is a unit of its own over the shared mesh state (mesh_state.hpp):
// shape_sweeps, defect_reseeding, weight_sweeps, centroidal, topology,
// gamma_corners, ocean_floor, mends.
#include "optim/optimise.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <tuple>

#include "core/text.hpp"
#include "optim/centroidal.hpp"
#include "optim/defect_reseeding.hpp"
#include "optim/gamma_corners.hpp"
#include "optim/mends.hpp"
#include "optim/mesh_state.hpp"
#include "optim/ocean_floor.hpp"
#include "optim/shape_sweeps.hpp"
#include "optim/star_graph.hpp"
#include "optim/topology.hpp"
#include "optim/weight_sweeps.hpp"

namespace um::optim {

namespace detail {

namespace {

// The re-seeding rounds (defect_reseeding.hpp): the first takes out more
// rings around the defects than the later ones (it breaks up the grains the
// refinement's fronts left; the later ones mend what is left locally); the
// shape phase keeps kSettleIterations after the last round to relax its new
// vertices (with one, the worst triangles were left poor); the rounds stop
// when one would start from more than (1 - kLeastDefectDrop) of the defects
// the last one started from. Measurements: tools/bench/HISTORY.md.
constexpr int kFirstRings = 3, kLaterRings = 1;
constexpr int kSettleIterations = 3;
constexpr double kLeastDefectDrop = 0.1;
// The floor passes after the mends, at most (each stops when one changes
// nothing).
constexpr int kLastFloorPasses = 4;

// The passes of Algorithm 1 in their order over the shared mesh state.
class Schedule {
public:
    Schedule(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
             const features::Network *gamma, const refine::SpacingRadians &h, const OptimiseOptions &o,
             const features::Domain *domain, const std::vector<refine::Side> *sides)
        : s_(ctx, tri, on_segment, gamma, h, o, domain, sides), shape_(s_), weights_(s_), centroidal_(s_), topology_(s_),
          corners_(s_), floor_(s_), mends_(s_), reseeding_(s_) {}

    OptimiseStats run();

private:
    // What one outer iteration changed.
    struct Changes {
        int64_t updates = 0, flips = 0, collapsed = 0, split = 0, valence = 0, corners = 0, reseeded = 0, floor = 0;
        int64_t topology() const { return flips + collapsed + split + valence + corners + reseeded + floor; }
    };
    void begin_weight_phase();
    int64_t inner_sweeps(bool shape_phase);
    int64_t polish_poor_stars();
    void change_topology(int n, bool shape_phase, int32_t outer_start, Changes &changes);
    int64_t reseed_defects(int n);
    bool settled(const MeshState::Summary &now, const MeshState::Summary &last) const;
    void log_outer(int n, bool shape_phase, const Changes &changes, const MeshState::Summary &now);
    int64_t mend_off_centre_triangles();
    void mend_obtuse_triangles();
    void mend_off_centre_after_moves();

    MeshState s_;
    ShapeSweeps shape_;
    WeightSweeps weights_;
    Centroidal centroidal_;
    Topology topology_;
    GammaCorners corners_;
    OceanFloor floor_;
    Mends mends_;
    DefectReseeding reseeding_;
    std::unique_ptr<StarGraph> graph_;
    int shape_iterations_ = 0;
    int64_t last_defects_ = -1;  // the defects the last re-seeding round started from
    bool reseeding_over_ = false;
};

OptimiseStats Schedule::run() {
    const OptimiseOptions &o = s_.options;
    for (int32_t v = 0; v < s_.tri.vertex_slots(); ++v) s_.next_id = std::max(s_.next_id, s_.tri.id(v) + 1);
    s_.load_spacing();
    if (o.ocean_floor > 0) s_.refresh_sides();  // (every move keeps the floor, from the first sweep)
    MeshState::Summary last = s_.summarise();
    graph_ = std::make_unique<StarGraph>(s_.ctx, s_.tri);
    // The first half of the outer iterations shapes the triangles (moves,
    // flips, valence repairs, weights held); the second half adds the weight
    // ascent for the staggering. Weights first would lock the topology in:
    // a weighted triangulation keeps badly shaped triangles regular (and
    // well-centred), so no flip would ever mend them.
    const int shape_iterations = o.weights ? o.outer_iterations / 2 : o.outer_iterations;
    shape_iterations_ = shape_iterations;
    for (int n = 0; n < o.outer_iterations; ++n) {
        s_.ctx.progress("optimise", double(n) / o.outer_iterations);
        const bool shape_phase = n < shape_iterations;
        if (!shape_phase && !s_.weighing) begin_weight_phase();
        s_.flag_near_gamma();
        const int32_t outer_start = s_.clock;
        Changes changes;
        changes.updates = inner_sweeps(shape_phase);
        if (shape_phase && o.polish_poor_stars && shape_.wants_polish(changes.updates))
            changes.updates += polish_poor_stars();
        change_topology(n, shape_phase, outer_start, changes);
        ++s_.stats.outer_iterations;

        const MeshState::Summary now = s_.summarise();
        const bool quiet = changes.updates + changes.topology() == 0 || (settled(now, last) && changes.topology() == 0);
        log_outer(n, shape_phase, changes, now);
        last = now;
        if (quiet && shape_phase && n + 1 < shape_iterations) {
            n = shape_iterations - 1;  // shaped: go on to the staggering
        } else if (quiet && !shape_phase) {
            break;
        }
    }
    if (!s_.weighing && o.outer_iterations > 0) s_.stats.moves += centroidal_.relax_to_centroids(graph_);
    const bool mends = o.mends && o.outer_iterations > 0;
    // What the last outer iteration's pass left, while the mends can still
    // re-tune the weights around a removal.
    for (int pass = 0; pass < kLastFloorPasses && o.outer_iterations > 0; ++pass)
        if (floor_.lift(OceanFloor::Stage::before_mends).changes() == 0) break;
    const int64_t off_centre_left = mends && o.weights ? mend_off_centre_triangles() : 0;
    if (mends) mend_obtuse_triangles();
    if (off_centre_left > 0) mend_off_centre_after_moves();
    // After the mends' moves: what they brought below the floor, where a
    // removal keeps what they reached, judged by the sides the report finds.
    // (Each pass changes a neighbourhood once: a few more for what one left.)
    if (o.ocean_floor > 0 && o.outer_iterations > 0) s_.find_sides_anew();
    for (int pass = 0; pass < kLastFloorPasses && o.outer_iterations > 0; ++pass)
        if (floor_.lift(OceanFloor::Stage::after_mends).changes() == 0) break;
    s_.ctx.log(UM_LOG_INFO, concat("optimise: ocean floor ", o.ocean_floor, " h: ", s_.stats.floor_removals,
                                   " vertices taken out, ", floor_.count_below(), " edges off the land still below"));
    s_.ctx.progress("optimise", 1.0);
    return s_.stats;
}

// The centroidal pass places the generators, then the weights begin.
void Schedule::begin_weight_phase() {
    s_.stats.moves += centroidal_.relax_to_centroids(graph_);
    s_.weighing = true, s_.grow_slots();
}

// M inner sweeps, or fewer when one changes nothing; the updates taken.
int64_t Schedule::inner_sweeps(bool shape_phase) {
    int64_t changes = 0;
    for (int m = 0; m < s_.options.inner_iterations; ++m) {
        const bool forward = m % 2 == 0;
        auto t0 = Clock::now();
        // After the shape phase the centroidal pass has placed the generators
        // in the bulk; near Gamma, where the features force poor triangles,
        // the shape moves go on with the weights (without them the
        // Mid-Atlantic case kept 1-2 triangles off-centre).
        int64_t moved = !s_.options.moves ? 0
                        : shape_phase     ? shape_.sweep(*graph_, forward)
                                          : shape_.sweep_near_gamma(*graph_, forward);
        s_.stats.seconds_moves += seconds_since(t0);
        t0 = Clock::now();
        int64_t weighted = s_.options.weights && !shape_phase ? weights_.sweep(*graph_, forward) : 0;
        s_.stats.seconds_weights += seconds_since(t0);
        s_.stats.moves += moved, s_.stats.weight_updates += weighted;
        changes += moved + weighted;
        s_.ctx.log(UM_LOG_DEBUG, concat("optimise: inner sweep ", m + 1, ": ", moved, " moves, ",
                                        weighted, " weight updates"));
        if (moved + weighted == 0) break;
    }
    return changes;
}

int64_t Schedule::polish_poor_stars() {
    auto t0 = Clock::now();
    const int64_t polished = shape_.polish_poor_stars(*graph_);
    s_.stats.moves += polished;
    s_.stats.seconds_moves += seconds_since(t0);
    return polished;
}

// Flips restoring regularity, collapses and splits, the repair of vertex
// degrees (not after the last iteration) and the support of obtuse corners
// on Gamma (shape phase); then the graph of the new topology.
void Schedule::change_topology(int n, bool shape_phase, int32_t outer_start, Changes &c) {
    const OptimiseOptions &o = s_.options;
    auto t0 = Clock::now();
    c.flips = s_.restore_regularity(outer_start);
    if (o.collapse_and_split) std::tie(c.collapsed, c.split) = topology_.collapse_and_split();
    const OceanFloor::Lifted lifted = floor_.lift();
    c.floor = lifted.taken_out, c.updates += lifted.moved;
    if (o.valence_repair && n + 1 < o.outer_iterations)
        c.valence = topology_.improve_valence() + (n < 2 ? topology_.flip_for_valence() : 0);
    c.corners = shape_phase && o.corner_vertices ? corners_.support_gamma_corners() : 0;
    c.reseeded = shape_phase ? reseed_defects(n) : 0;
    // A push or slide of the floor pass is a move for the stopping test, but
    // it puts the vertex in again (Triangulation::move): its links may change.
    const bool relinked = c.topology() > 0 || lifted.moved > 0;
    // The sides of the vertices these made, found once for the sweeps
    // (else each floor check of one would infer it again).
    if (o.ocean_floor > 0 && relinked) s_.refresh_sides();
    s_.stats.flips += c.flips, s_.stats.collapses += c.collapsed, s_.stats.splits += c.split;
    // Else the spacing (h_at) and the graph are still those of the mesh.
    if (relinked) s_.rebuild_graph(graph_);
    ++s_.clock;
    s_.stats.seconds_topology += seconds_since(t0);
}

// A round of the re-seeding of defects while they pay, in the first outer
// iterations of the shape phase; the vertices it took out.
int64_t Schedule::reseed_defects(int n) {
    if (reseeding_over_ || n >= s_.options.reseed_rounds || n + kSettleIterations >= shape_iterations_) return 0;
    const int64_t most = last_defects_ < 0 ? INT64_MAX
                                           : static_cast<int64_t>((1 - kLeastDefectDrop) * static_cast<double>(last_defects_));
    const DefectReseeding::Round r = reseeding_.reseed(n == 0 ? kFirstRings : kLaterRings, most);
    s_.ctx.log(UM_LOG_INFO, concat("optimise: re-seeding round ", n + 1, ": ", r.defects, " defects away from Gamma; ",
                                   r.removed, " vertices taken out, ", r.inserted, " put in"));
    if (r.removed == 0) {
        reseeding_over_ = true;
        return 0;
    }
    last_defects_ = r.defects;
    ++s_.stats.reseed_rounds, s_.stats.reseeded += r.removed;
    return r.removed + r.inserted;
}

// No quality summary changed by more than the tolerance.
bool Schedule::settled(const MeshState::Summary &now, const MeshState::Summary &last) const {
    const double tolerance = s_.options.tolerance;
    return std::abs(now.qt_min - last.qt_min) <= tolerance && std::abs(now.qt_mean - last.qt_mean) <= tolerance &&
           std::abs(now.qp_min - last.qp_min) <= tolerance && std::abs(now.qp_mean - last.qp_mean) <= tolerance;
}

void Schedule::log_outer(int n, bool shape_phase, const Changes &c, const MeshState::Summary &now) {
    const OptimiseStats &stats = s_.stats;
    s_.ctx.log(UM_LOG_INFO,
               concat("optimise: outer iteration ", n + 1, shape_phase ? " (shape)" : " (weights)",
                      ": ", c.updates, " updates, ", c.flips, " flips, ", c.collapsed + c.split + c.valence,
                      " collapses/splits, ", c.floor, " taken out for the ocean floor, ", c.corners, " vertices added or taken out at obtuse corners on Gamma; Q^T min ", now.qt_min, " mean ", now.qt_mean, ", Q^P min ",
                      now.qp_min, " mean ", now.qp_mean, "; ", stats.seconds_moves, " s moves, ",
                      stats.seconds_weights, " s weights, ", stats.seconds_topology, " s topology"));
}

// The joint weights for the triangles not holding their orthocentre; how
// many are left.
int64_t Schedule::mend_off_centre_triangles() {
    auto t0 = Clock::now();
    const Mends::Mended m = mends_.mend_off_centre_triangles(false);
    s_.stats.weight_updates += m.mended;
    s_.stats.seconds_weights += seconds_since(t0);
    // tests/capi/test_optimise_api.c reads this line.
    s_.ctx.log(UM_LOG_INFO, concat("optimise: joint weights mended ", m.mended, " of ", m.met,
                                   " triangles not holding their orthocentre; Q^P floor ", m.floors.qp, "; ",
                                   m.slid, " of them with vertices sliding along Gamma, ", m.flipped,
                                   " by a flip; ", seconds_since(t0), " s"));
    return m.met - m.mended;
}

void Schedule::mend_obtuse_triangles() {
    auto t0 = Clock::now();
    const Mends::Mended m = mends_.mend_obtuse_triangles();
    s_.stats.moves += m.mended;
    s_.stats.seconds_moves += seconds_since(t0);
    // tests/capi/test_optimise_api.c reads this line.
    s_.ctx.log(UM_LOG_INFO, concat("optimise: joint moves mended ", m.mended, " of ", m.met, " obtuse triangles (",
                                   m.flipped, " by a flip); ", seconds_since(t0), " s"));
}

// The moves have changed the neighbourhoods of the off-centre triangles
// left (without adding any): another search may now mend some. It only
// ever lowers their number, and its moves add no obtuse triangle (so the
// obtuse mend's count stands).
void Schedule::mend_off_centre_after_moves() {
    auto t0 = Clock::now();
    const Mends::Mended m = mends_.mend_off_centre_triangles(true);
    s_.stats.weight_updates += m.mended;
    s_.stats.seconds_weights += seconds_since(t0);
    s_.ctx.log(UM_LOG_INFO, concat("optimise: after the joint moves, joint weights mended ", m.mended, " of ",
                                   m.met, " triangles not holding their orthocentre (", m.flipped, " by a flip); ",
                                   seconds_since(t0), " s"));
}

}  // namespace

}  // namespace detail

OptimiseStats optimise(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
                       const features::Network *gamma, const refine::SpacingRadians &h,
                       const OptimiseOptions &options, const features::Domain *domain,
                       const std::vector<refine::Side> *sides) {
    detail::Schedule schedule(ctx, tri, on_segment, gamma, h, options, domain, sides);
    return schedule.run();
}

}  // namespace um::optim
