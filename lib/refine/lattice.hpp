// The lattice the refinement starts from, and its frequency for a spacing.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "features/domain.hpp"
#include "geom/arc_tree.hpp"
#include "geom/sphere.hpp"
#include "refine/geodesic_lattice.hpp"
#include "refine/surface.hpp"

namespace um::refine {

// The lattice frequency whose edges are closest to `spacing` (radians on the
// unit sphere): the n with 10 n^2 + 2 hexagons of that edge closest to the
// sphere's area. At least 1 (the icosahedron); 0 when more than `max_points`.
int64_t lattice_frequency(double spacing, int64_t max_points);

// The points the refinement starts from: the icosahedron's 12 corners (but
// those in the lattice's band along Gamma), and the points of the relaxed
// geodesic lattice of the coarsest spacing h0 (sampled over the sphere) where the spacing holds that value - within 1 % of h0 at
// the point and at six points h0 around it - farther than h0 from Gamma.
// For a uniform spacing that is the whole lattice but for a band along
// Gamma; for a graded one the background where it is flat (beyond the
// refined regions), the rest being the frontal refinement's. Only the
// corners when no lattice point qualifies or the lattice would exceed 2^31
// points.
//
// With a domain (a regional mesh): h0 is the coarsest spacing inside it,
// and only lattice points inside it are kept (and the corners outside, for
// the cover); no lattice when the whole sphere's would hold more than
// kRegionalLatticeRatio times the points the domain needs and over
// kRegionalLatticeFloor points (a small fine domain). The lattice is
// relaxed and placed around the domain only, but its levels still index
// the whole sphere's points (about 30 ns each), while a domain refined
// from the icosahedron instead needs the re-seeding rounds and more
// optimisation (about 25-50 us more per cell): the ratio is about half
// where the two cost the same (tools/bench/HISTORY.md).
constexpr double kRegionalLatticeRatio = 600;
constexpr int64_t kRegionalLatticeFloor = int64_t(1) << 21;
std::vector<geom::Vec3> background_lattice(Context &ctx, const SpacingRadians &h, const geom::ArcTree &gamma,
                                           const features::Domain *domain = nullptr);

}  // namespace um::refine
