// The geodesic lattice: the icosahedron's faces cut into n x n triangles and
// put on the sphere, 10 n^2 + 2 points of which only the 12 corners have five
// neighbours. For a spacing that is the same everywhere it is the point set
// the refinement is after: every point six-valent but the twelve the sphere's
// topology needs, where a frontal refinement leaves thousands of 5-7 pairs
// wherever two fronts meet (the cells where the MPAS divergence and kinetic
// energy lose their accuracy, and do not regain it with resolution).
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/arc_tree.hpp"
#include "geom/sphere.hpp"
#include "refine/surface.hpp"

namespace um::refine {

// The lattice frequency whose edges are closest to `spacing` (radians on the
// unit sphere): the n with 10 n^2 + 2 hexagons of that edge closest to the
// sphere's area. At least 1 (the icosahedron); 0 when more than `max_points`.
int64_t lattice_frequency(double spacing, int64_t max_points);

// The 10 n^2 + 2 unit points of the frequency-n lattice: the 12 corners, then
// the points inside the 30 edges, then inside the 20 faces. Points along an
// edge are equally spaced in arc; inside a face each point is the mean of the
// three great-circle interpolations through it (one per corner), so that the
// lattice keeps the icosahedron's symmetry and its cells differ in area by a
// few percent only (a gnomonic projection's differ by twice).
std::vector<geom::Vec3> geodesic_lattice(int64_t frequency);

// The points the refinement starts from: the icosahedron's 12 corners (but
// those in the lattice's band along Gamma), and the points of the geodesic lattice of the coarsest spacing h0 (sampled
// over the sphere) where the spacing holds that value - within 1 % of h0 at
// the point and at six points h0 around it - farther than h0 from Gamma.
// For a uniform spacing that is the whole lattice but for a band along
// Gamma; for a graded one the background where it is flat (beyond the
// refined regions), the rest being the frontal refinement's. Only the
// corners when no lattice point qualifies or the lattice would exceed 2^31
// points.
std::vector<geom::Vec3> background_lattice(Context &ctx, const SpacingRadians &h, const geom::ArcTree &gamma);

}  // namespace um::refine
