// Vertices on Gamma stay on Gamma (DESIGN.md section 4): a vertex placed on a
// feature segment moves only along that feature's polyline, to the point of
// the polyline nearest to where the unconstrained update would take it.
#pragma once

#include <cstdint>

#include "features/network.hpp"

namespace um::optim {

struct PointOnGamma {
    geom::Vec3 x;         // unit vector on the polyline
    int64_t segment = -1;  // the segment it lies on
};

// The point of the polyline of `segment`'s part nearest to the unit vector p,
// searched from `segment` along the part in both directions while the
// distance decreases (at most max_steps segments each way).
PointOnGamma slide_along(const features::Network &gamma, int64_t segment, const geom::Vec3 &p,
                         int max_steps = 256);

}  // namespace um::optim
