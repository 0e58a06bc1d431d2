// The restricted sub-complex Tri|Gamma (paper section 4): an edge of the
// triangulation is restricted when its dual power edge (the arc between the
// orthocentres of its two triangles, on the bisector great circle) crosses
// an arc of Gamma. Its surface ball is centred at the crossing; when several
// arcs cross, the crossing farthest from the edge's vertices is kept
// (DESIGN.md section 4).
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/arc_tree.hpp"
#include "tri/triangulation.hpp"

namespace um::refine {

using geom::Vec3;

struct RestrictedEdge {
    int32_t triangle = -1;  // the edge is edge `edge` of `triangle`
    int edge = 0;
    int32_t arc = -1;       // the Gamma arc whose crossing is kept
    Vec3 centre;            // the surface ball's centre: the crossing
    double radius = 0;      // its radius: arc distance to the farther edge vertex
};

// The crossing of edge k of t with Gamma, if any.
bool restricted_crossing(const tri::Triangulation &tri, int32_t t, int k,
                         const geom::ArcTree &gamma, RestrictedEdge *out);
// The same with the orthocentres of t and of its neighbour across edge k
// already known (c0, c1).
bool restricted_crossing(const tri::Triangulation &tri, int32_t t, int k, const Vec3 &c0,
                         const Vec3 &c1, const geom::ArcTree &gamma, RestrictedEdge *out);

// All restricted edges, each once (from the triangle with the smaller index),
// in triangle order; evaluated in parallel, the same for any thread count.
std::vector<RestrictedEdge> restricted_edges(Context &ctx, const tri::Triangulation &tri,
                                             const geom::ArcTree &gamma);
// The same among the edges of `triangles` (ascending, each once: what
// Triangulation::triangles_around gives), in that list's order.
std::vector<RestrictedEdge> restricted_edges(Context &ctx, const tri::Triangulation &tri,
                                             const geom::ArcTree &gamma,
                                             const std::vector<int32_t> &triangles);

}  // namespace um::refine
