// The quality report's measures of a mesh of an ellipsoid taken on the
// ellipsoid itself, with GeographicLib's geodesics and geodesic polygon
// areas (not the sphere's formulas): each edge's geodesic length between
// the geodetic lon/lat of its ends over h (in geodesic km) at its midpoint,
// and each power cell's area as the geodesic polygon of its corners. The
// other metrics of the report are ratios of lengths and angles, which the
// radial map from directions to the ellipsoid keeps to within f^2.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/surface.hpp"
#include "quality/metrics.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::quality {

// h: the spacing in radians of the directions (h times the surface's
// radius along a direction is geodesic length there). cells (per vertex
// slot; null: all) restricts it as measure() does. The same result for any
// thread count.
Report::Geodesic measure_geodesic(Context &ctx, const tri::Triangulation &tri, const geom::Surface &surface,
                                  const refine::SpacingRadians &h, const std::vector<uint8_t> *cells = nullptr);

}  // namespace um::quality
