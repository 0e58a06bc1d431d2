// Which power cell holds a point, and which cells a line passes through: the
// queries behind lines drawn on a mesh (passages kept open in the ocean).
#pragma once

#include <cstdint>
#include <vector>

#include "tri/triangulation.hpp"

namespace um::tri {

// The vertex whose power cell holds direction x (unit vector): the vertex of
// the lifted hull furthest along x, found by walking to a neighbour further
// along until none is (on a convex hull the first such vertex is the
// furthest). start: any vertex slot in the triangulation, or -1 for the
// first one. On a cell boundary (a tie) either cell may be the answer, the
// same one for the same start.
int32_t cell_holding(const Triangulation &tri, const Vec3 &x, int32_t start = -1);

// The cells the minor arc a -> b passes through, in order from a's cell to
// b's, each sharing an edge with the one before (found by halving the arc
// until consecutive cells are neighbours and the arc crosses straight from
// one into the other, not through the corner of a third).
std::vector<int32_t> cells_along_arc(const Triangulation &tri, const Vec3 &a, const Vec3 &b,
                                     int32_t start = -1);

}  // namespace um::tri
