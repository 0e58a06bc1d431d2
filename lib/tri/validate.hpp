// Exhaustive consistency check of a triangulation, with exact predicates:
// used by the tests and by um_triangulation_check for callers who want proof.
#pragma once

#include <string>

#include "tri/triangulation.hpp"

namespace um::tri {

// "" when every invariant holds, else the first violation found:
// neighbour links reciprocal with matching edges; Euler V - E + F = 2;
// each facet has the centre strictly behind it (orientation); every edge
// locally regular; every vertex's star a closed fan; every hidden point
// inside the hull.
std::string check_triangulation(const Triangulation &tri);

}  // namespace um::tri
