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
#include "geom/sphere.hpp"

namespace um::refine {

// The 10 n^2 + 2 unit points of the frequency-n lattice: the 12 corners, then
// the points inside the 30 edges, then inside the 20 faces. Points along an
// edge are equally spaced in arc; inside a face each point is the mean of the
// three great-circle interpolations through it (one per corner), so that the
// lattice keeps the icosahedron's symmetry and its cells differ in area by a
// few percent only (a gnomonic projection's differ by twice).
std::vector<geom::Vec3> geodesic_lattice(int64_t frequency);

// The same points, in the same order, relaxed towards equal edge lengths:
// each point moved to where springs of one rest length to its neighbours
// balance (the spring dynamics of Tomita et al. 2001 for icosahedral grids),
// the corners held, the springs stiffer where an edge would be short. The
// twelve pentagons strain the lattice whatever its placement; the springs
// spread that strain over the faces instead of leaving it in the pattern of
// the placement above, which the optimisation's local (Lloyd) moves keep:
// on the optimised uniform meshes the curl's error falls by 6 % (25 % for a
// solid-body rotation), the divergence's and kinetic energy's by 11-22 %,
// and the edges' spread (std of dcEdge/h) from 0.046 to 0.041, what twelve
// pentagons allow in least squares (tools/bench/HISTORY.md). Solved coarse
// to fine: the relaxed lattice of half the frequency, interpolated, then a
// few sweeps at each frequency, about eleven sweeps of the finest in all.
// Deterministic for any thread count.
std::vector<geom::Vec3> relaxed_geodesic_lattice(Context &ctx, int64_t frequency);

// A regional mesh's part of the relaxed lattice, around a cap (centre,
// radius in radians): each frequency relaxes only its points within a
// margin of kCapMargin of its edge lengths beyond the cap, those farther
// held where the coarser one put them (the margin keeps that edge, and what
// the coarser ones left there, beyond a relaxation's reach); and places
// only the points within kHeldMargin edge lengths beyond those (what the
// relaxation reads, and the finer frequency's placement), so that the work
// goes with the cap's area, not the sphere's. Returned: the points placed
// at the finest frequency (every point within the cap, and the 12 corners
// first), in geodesic_lattice's order, with each one's place in it.
struct Cap {
    geom::Vec3 centre;
    double radius;
};
constexpr double kCapMargin = 16;
constexpr double kHeldMargin = 4;
struct LatticeRegion {
    std::vector<geom::Vec3> points;
    std::vector<int64_t> index;  // ascending
};
LatticeRegion relaxed_lattice_region(Context &ctx, int64_t frequency, const Cap &cap);
// About how many points relaxed_lattice_region holds at its finest
// frequency: those within the reach of its placement around the cap (its
// memory goes with this, not with the whole sphere's lattice).
double lattice_region_points(int64_t frequency, const Cap &cap);

}  // namespace um::refine
