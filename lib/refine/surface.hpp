// Surface refinement (paper section 5.2): from the icosahedron, insert
// off-centre points until every triangle is small enough (sqrt(3) r < alpha h
// at its circumcentre) and well shaped (r / e_min < rho). Frontal-Delaunay
// order: a bad triangle beside a good one gets a point off their shared edge,
// at the apex of the triangle whose new edges have the target length h
// (capped by its circumcentre and the off-centre of radius-edge ratio rho),
// so the mesh grows from the first good triangles in layers of edges close
// to h. Bad triangles away from any good one (at the start) take the point on
// their shortest edge's bisector at the least of the same three distances.
// Deterministic: the front is first in, first out (the initial triangles in
// slot order, then each new fan in its star order), the rest last in, first
// out; see surface.cpp. A big first pass grows many such fronts at once, one
// per territory of the sphere, from sparse seeds (surface.cpp).
#pragma once

#include <functional>

#include "core/context.hpp"
#include "geom/arc_tree.hpp"
#include "geom/sphere.hpp"
#include "refine/bounds.hpp"
#include "tri/triangulation.hpp"

namespace um::refine {

// Target edge length in radians at a unit point (the spacing h / R).
using SpacingRadians = std::function<double(const geom::Vec3 &)>;
// A lower bound of the target edge length (radians) over the cap of arc
// radius r about a unit point, which may stop tightening once it is at least
// `enough` (hfun::Spacing::smallest_in_cap).
using SmallestSpacingRadians = std::function<double(const geom::Vec3 &centre, double r, double enough)>;

struct SurfaceOptions {
    double alpha = kDefaultAlpha;  // size bound: sqrt(3) r < alpha h
    double rho = kDefaultRho;      // shape bound: r / e_min < rho
    // When given, a triangle whose circumcircle holds a spacing feature
    // narrower than itself is sized by that feature (surface.cpp); else by
    // h at its circumcentre only.
    SmallestSpacingRadians smallest;
    double smallest_scale = 1;  // the sizes asked for, over the spacing's
    // A candidate that would make an edge shorter than filter h is not
    // inserted. With Gamma, a candidate inside the surface ball of a
    // restricted edge (it would change Tri|Gamma) is replaced by that ball's
    // centre, on Gamma (and filtered as the boundary refinement filters it).
    const geom::ArcTree *gamma = nullptr;
    InsertionFilter filter;
    std::vector<int32_t> *on_gamma = nullptr;  // per vertex slot: Gamma arc or -1
    // Slots of removed vertices the serial pass inserts into (last first)
    // before it adds new slots (Triangulation::insert_into_removed).
    std::vector<int32_t> *free_vertex_slots = nullptr;
};

struct SurfaceStats {
    int64_t inserted = 0;
    int64_t rejected = 0;  // candidates hidden or too close (left as they were)
    int32_t next_id = 0;   // the first id not given out
    int64_t by_territories = 0;  // of the inserted: in parallel, by territories (surface.cpp)
    // Vertices inserted near Gamma (where they may change Tri|Gamma), in
    // insertion order; only with options.gamma.
    std::vector<int32_t> near_gamma;
};

// Refines `tri` in place; new points get ids from next_id upwards. With
// `around`, only the triangles of the stars of those vertices are looked
// at first (the others are known to be good), serially; else all of them,
// and a big mesh by territories in parallel (surface.cpp): the result does
// not depend on the number of threads.
SurfaceStats refine_surface(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                            const SurfaceOptions &options, int32_t next_id,
                            const std::vector<int32_t> *around = nullptr);

// A triangulation of the 12 vertices of the icosahedron, ids 0..11.
tri::Triangulation icosahedron(Context &ctx);

// Arc distance (radians) from vertex v to its nearest neighbour.
double nearest_neighbour(const tri::Triangulation &tri, int32_t v);

// Circumradius (radians) and shortest edge of triangle t (unweighted view),
// and its circumcentre when asked.
void triangle_size(const tri::Triangulation &tri, int32_t t, double *radius, double *shortest,
                   geom::Vec3 *circumcentre = nullptr);

}  // namespace um::refine
