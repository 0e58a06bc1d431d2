// Ocean or land: which side of the closed coastlines each triangle (its
// orthocentre, an MPAS vertex) and each generator (an MPAS cell) lies on.
// A point is land when it lies inside an odd number of closed coastline
// rings, the inside of a ring being the smaller of the two regions it
// bounds. One anchor point is classified directly; every other triangle by
// walking the dual graph and flipping at each crossing of its dual arc with a
// coastline, so the classification is consistent with Tri|Gamma itself.
#pragma once

#include <cstdint>
#include <vector>

#include "features/network.hpp"
#include "geom/arc_tree.hpp"
#include "refine/restricted.hpp"
#include "tri/triangulation.hpp"

namespace um::refine {

enum class Side : int8_t { ocean = 0, land = 1, coastal = 2 };

// A closed coastline: the parts whose rings bound the land.
bool is_closed_coastline(const features::Part &p);

// Whether x is land: inside an odd number of the closed coastline parts.
bool is_land(const features::Network &net, const geom::Vec3 &x);

// The closed coastline segments of net as arcs, and their segment indices.
geom::ArcTree closed_coastline_arcs(const features::Network &net, std::vector<int64_t> *segments);

// Per triangle slot: ocean or land (free slots: ocean). `may_cross`, when
// given, lists every dual edge that crosses any arc of net (the restricted
// edges of the same triangulation, found with a tolerance that makes them a
// superset): only those are tested, the rest cross nothing.
std::vector<Side> triangle_sides(const tri::Triangulation &tri, const features::Network &net,
                                 const std::vector<RestrictedEdge> *may_cross = nullptr);

// Per vertex slot: coastal when on_gamma marks it on a closed coastline,
// else the side of its incident triangles (the first one, which all share
// unless a coastline passes between them: then coastal too).
std::vector<Side> vertex_sides(const tri::Triangulation &tri, const std::vector<Side> &triangles,
                               const std::vector<int32_t> &on_gamma_segment,
                               const features::Network &net);

// Per vertex slot, 1 when its cell is in the ocean mesh: an ocean vertex,
// or a coastal one with at least as many of its triangles on the ocean side
// as not (the MPAS cellOceanMask; the land + river mesh takes the rest).
std::vector<uint8_t> ocean_mesh_cells(const tri::Triangulation &tri, const std::vector<Side> &vertices,
                                      const std::vector<Side> &triangles);

}  // namespace um::refine
