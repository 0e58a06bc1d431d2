// Edge-length relaxation after refinement. The surface criteria bound every
// triangle's circumradius (sqrt(3) r < alpha h) and shape (r / e_min < rho),
// but where two fronts meet they leave pairs of near-right triangles whose
// shared diagonal is up to 2 alpha / sqrt(3) = 1.54 h long (2 % of the edges
// of a uniform mesh above 1.35 h). No inserted point mends such a near-square
// (every point inside it is within 0.71 h of a corner), so this pass moves
// vertices instead: each vertex with an edge outside a band of lengths (in
// units of h at the edge's midpoint) is pulled along its edges' length
// errors. A move is kept only when
//   - it lowers the number of the vertex's edges outside the band, or as many
//     by less;
//   - no edge of the vertex that was inside the band, or inside [lower,
//     upper], leaves it, and none outside [lower, upper] goes farther out
//     (so no edge ends shorter than the shortest before, or longer than the
//     longest);
//   - every triangle around the vertex stays within the surface criteria;
//   - it needs no flip: the star stays a regular star, so nothing beyond it
//     changes and the triangulation stays the regular one of its points.
// Where that is stuck, the stretch of mesh around is crowded or stretched as
// a whole and needs room made first: the rings of vertices around are
// relaxed towards narrower bands (by each of `margins` in turn), then the
// band is tried again, over wider rings while any are stuck. A crowded spot
// left after that has a vertex too many: it is removed when its hole comes
// out good, or put at the circumcentre of the hole's largest triangle when
// that leaves fewer edges around outside the band, none worse and every
// triangle within the criteria. Vertices on Gamma, or whose dual edges could
// reach Gamma, stay where they are: the restricted edges and the sides do not
// change. Serial, in slot order: deterministic for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/arc_tree.hpp"
#include "refine/bounds.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::refine {

struct RelaxOptions {
    // The band every edge should end in, in units of h: 0.005 inside the
    // issue's [0.75, 1.35], so that lengths measured another way (chords,
    // another Earth radius: within 1e-4 of these) are inside that too.
    double lower = 0.755, upper = 1.345;
    // Where vertices are stuck: the rings around them, relaxed towards the
    // bands [lower + m, upper - m] for each margin m in turn, before the band
    // is tried again; for each ring count in turn while any are left.
    std::vector<int> rings{3, 6, 12};
    std::vector<double> margins{0.08, 0.04};
    int rounds = 8;                        // per band: passes over the vertices left outside it
    int crowded_attempts = 3;              // ring stage + crowded spots, while they change anything
    double alpha = kDefaultAlpha, rho = kDefaultRho;  // the surface criteria the moves keep
    const geom::ArcTree *gamma = nullptr;  // with Gamma: vertices near it stay
    const std::vector<int32_t> *on_gamma = nullptr;  // per vertex slot: Gamma arc or -1
};

struct RelaxStats {
    int64_t outside_before = 0, outside_after = 0;  // edges outside [lower, upper]
    int64_t moves = 0;                              // moves kept
    int64_t removed = 0;                            // vertices removed (crowded spots)
    int64_t replaced = 0;                           // vertices put elsewhere (crowded spots)
};

RelaxStats relax_edge_lengths(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                              const RelaxOptions &options);

// Edges not strictly inside (lower, upper) h, each once.
int64_t count_edges_outside(Context &ctx, const tri::Triangulation &tri, const SpacingRadians &h,
                            double lower, double upper);

}  // namespace um::refine
