// Boundary refinement (paper section 5.1): insert points on Gamma, at the
// centres of the surface balls of bad restricted edges, until every
// restricted edge e is short enough (l_e < alpha h) and close enough to
// Gamma (eps(e) < beta h, eps = distance from the edge midpoint to the ball
// centre). A candidate that would make an edge shorter than filter * h is
// not inserted: features of Gamma smaller than the local spacing are
// filtered out instead of followed.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/arc_tree.hpp"
#include "refine/bounds.hpp"
#include "refine/restricted.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::refine {

struct BoundaryOptions {
    double alpha = kDefaultAlpha;  // restricted edges shorter than alpha h
    double beta = kDefaultBeta;    // Hausdorff bound eps < beta h
    InsertionFilter filter;    // no new edge shorter than this (times h)
    // The topology check (when given: the part of each Gamma arc): a
    // restricted edge is also bad when one of its ends has three or more
    // restricted edges of the same part - Tri|Gamma is then no curve there
    // (the part passes through the vertex's cell twice: a narrow inlet,
    // peninsula or channel). Refining stops at the same filter, so features
    // below the spacing still go. A spoke counts for the part of the
    // crossing restricted_crossing keeps (the largest ball) only, so folds
    // where two parts cross one dual edge can go unseen; count_bad does not
    // count folds.
    const std::vector<int64_t> *part_of_arc = nullptr;
};

struct BoundaryStats {
    int64_t inserted = 0;
    int passes = 0;
    std::vector<int32_t> added;  // the vertices inserted, in order
};

// Refines `tri` in place. on_gamma (indexed by vertex slot, grown as points
// are added) receives the Gamma arc each inserted vertex lies on, -1 for
// the others. New points get ids from next_id upwards (updated). With
// `around`, only the restricted edges of the stars of those vertices are
// looked at first (the others are known to be good); else all of them.
BoundaryStats refine_boundary(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                              const geom::ArcTree &gamma, const BoundaryOptions &options,
                              int32_t &next_id, std::vector<int32_t> &on_gamma,
                              const std::vector<int32_t> *around = nullptr);

// The restricted edges among `edges` that are bad (too long or too far from
// Gamma): after refine_boundary, those of features below the spacing.
int64_t count_bad(const tri::Triangulation &tri, const std::vector<RestrictedEdge> &edges,
                  const SpacingRadians &h, const BoundaryOptions &options);

// The length and Hausdorff distance of a restricted edge, and h at its midpoint.
struct EdgeMeasure {
    double length, eps, h;
};
EdgeMeasure measure(const tri::Triangulation &tri, const RestrictedEdge &e, const SpacingRadians &h);

}  // namespace um::refine
