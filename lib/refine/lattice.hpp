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
// corners when no lattice point qualifies or the lattice would exceed
// 2^tri::kBrioIndexBits points: the whole sphere's (h0 finer than about
// 1.5 km), or for a domain the points held around its cap (and for a
// domain, when those would not fit the context's memory cap).
//
// With a domain (a regional mesh): h0 is the coarsest spacing inside it,
// and only lattice points inside it are kept (and the corners outside, for
// the cover). The lattice is relaxed, placed and held around the domain
// only, at a cost that goes with the domain's area, so that a domain of any
// size starts from it: refined from the icosahedron instead, a domain needs the
// re-seeding rounds and more optimisation, and keeps more defects.
std::vector<geom::Vec3> background_lattice(Context &ctx, const SpacingRadians &h, const geom::ArcTree &gamma,
                                           const features::Domain *domain = nullptr);

}  // namespace um::refine
