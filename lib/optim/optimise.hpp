// The weighted primal-dual optimisation (paper section 6, Algorithm 1):
// N outer iterations of M inner sweeps of vertex moves (weighted ODT towards
// orthocentres, eq. 7-8) and weight ascent on the worst adjacent Q^P (eq.
// 4-6), then flips restoring regularity, then edge collapse and refinement
// (section 6.4) and the repair of vertex degrees: removal of degree <= 4,
// splitting of degree >= 8, and (first two iterations) flips that turn a
// 7-7 diagonal between 5s into 6s, kept when a few ODT steps make them
// regular; in the first iterations, the re-seeding of the 5-7 defects away
// from Gamma (defect_reseeding.hpp).
//
// The first half of the outer iterations holds the weights (shape phase):
// weights tuned early keep badly shaped triangles regular and would lock
// the topology in. Then the centroidal pass (centroidal.cpp) takes the
// generators to their power cells' centroids, and the second half runs the
// weight ascent (moves only near Gamma, where the features force poor
// triangles; in the bulk they would undo the centroids), on the stars whose
// worst triangle scores below 0.99 only,
// scored by Q^P less a penalty for a triangle that does not hold its
// orthocentre: the bulk keeps equal weights, where xEdge is the primal
// edge's midpoint.
//
// Sweeps are graph-coloured (optim/star_graph.hpp): the vertices of one
// colour update in parallel with the topology held fixed, colours in
// sequence, forward on even inner iterations and in reverse on odd ones
// (symmetric Gauss-Seidel over each pair). Every decision reads only data
// no other update of its colour writes, and every reduction runs in a fixed
// order, so the result is bit-identical for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "features/domain.hpp"
#include "features/network.hpp"
#include "optim/defaults.hpp"
#include "refine/sides.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::optim {

struct OptimiseOptions {
    int outer_iterations = 20;  // N
    int inner_iterations = 8;   // M
    // Stop when an outer iteration changes no quality summary (min and mean
    // of Q^T and Q^P) by more than this. An update is taken only if it raises
    // its star's worst (or mean) quality by 10 tolerances.
    double tolerance = 1e-4;
    // The passes (each on unless switched off here; see optimise.cpp).
    bool moves = true;           // the shape sweeps' vertex moves (shape_sweeps.cpp)
    bool polish_poor_stars = true;  // the compass search of the poor stars (shape_sweeps.cpp)
    bool weights = true;         // weight ascent on (else only moves and topology)
    bool collapse_and_split = true;  // collapse short edges, split long ones (topology.cpp)
    bool valence_repair = true;  // remove, split and flip for vertex degrees (topology.cpp)
    bool mends = true;           // the joint searches after the schedule (mends.cpp)
    bool fix_boundary = false;   // vertices on Gamma stay put (else they slide along it)
    double collapse_ratio = kDefaultCollapseRatio; // collapse edges shorter than this times h
    double split_ratio = kDefaultSplitRatio;       // split edges longer than this times h
    // The time-step floor (ocean_floor.hpp): edges off the land at least
    // this times h (0: no floor).
    double ocean_floor = kDefaultOceanFloor;
    bool corner_vertices = true; // vertices for obtuse corners on Gamma (support_gamma_corners)
    bool corner_cells_clear = false;  // ... only where the new cell stays clear of Gamma
    // Lloyd sweeps towards the power cells' centroids after the shape phase
    // (centroidal.cpp; 0: none).
    int centroidal_sweeps = 8;
    // At most this many rounds of the re-seeding of 5-7 defects in the shape
    // phase (defect_reseeding.hpp; 0: none), and the refinement's bounds
    // (refine_alpha, refine_rho) its holes are filled to.
    int reseed_rounds = 7;
    double refill_alpha = refine::kDefaultAlpha, refill_rho = refine::kDefaultRho;
    // The boundary refinement's bounds (refine_alpha, refine_beta): where a
    // vertex on Gamma at an obtuse corner is taken out, the restricted edge
    // left in its place must meet them.
    double gamma_alpha = refine::kDefaultAlpha, gamma_beta = refine::kDefaultBeta;
};

struct OptimiseStats {
    int outer_iterations = 0;  // done (fewer than N when it stopped early)
    int64_t moves = 0, weight_updates = 0, flips = 0, collapses = 0, splits = 0;
    int64_t corner_vertices = 0;  // added at obtuse corners on Gamma (not among the splits)
    int64_t gamma_vertices_removed = 0;  // taken out at obtuse corners on Gamma (not among the collapses)
    int64_t floor_removals = 0;          // taken out for the ocean floor (ocean_floor.hpp)
    int reseed_rounds = 0;               // rounds of the re-seeding of defects done
    int64_t reseeded = 0;                // vertices those rounds took out (their holes refilled)
    double seconds_moves = 0, seconds_weights = 0, seconds_topology = 0;
};

// Optimises tri in place. on_segment (per vertex slot: the Gamma segment a
// vertex lies on, or -1) is kept up to date as vertices slide, vanish and
// appear; gamma may be null when no vertex is on a segment. h is the spacing
// in radians. Reports progress as stage "optimise" once per outer iteration
// (cancellable: then tri is left valid but part-optimised). With a domain
// (a regional mesh), the cover outside it is left as it is: the vertices
// outside, off its rings, are not moved, weighted, hidden or taken out,
// no vertex is added outside the domain or (when added) beside them, and
// the triangles touching them count in no quality summary and no mend's
// judgement - no kept cell has one in its star
// (mesh::RefinedMesh::region_cells), so no output reads them; only the
// flips that keep the triangulation regular reach there. (A vertex inside
// may still come to neighbour the cover through later flips, or move out
// through a gap in the rings: it is then the cover's from the next
// outer iteration.) `sides`, when given, are the vertices' sides as
// refine::vertex_sides finds them for tri as it is, one per vertex slot (a
// refined mesh keeps them; the caller checks they are of tri): the time-step floor then starts from them instead of finding them
// again (a scan of every dual edge against Gamma).
OptimiseStats optimise(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
                       const features::Network *gamma, const refine::SpacingRadians &h,
                       const OptimiseOptions &options, const features::Domain *domain = nullptr,
                       const std::vector<refine::Side> *sides = nullptr);

}  // namespace um::optim
