// Spacing from the distance d to a set of features (coastlines, rivers):
// fine near the features, growing linearly away from them,
//     h(d) = km_min                                  for d <= distance_km
//          = min(km_max, km_min + rate (d - distance_km))   beyond,
// the usual coastal refinement, combined with a background by make_minimum.
// d is the great-circle distance to the nearest great arc of the polylines,
// on a sphere of radius_km.
#pragma once

#include <vector>

#include "geom/sphere.hpp"
#include "hfun/spacing.hpp"

namespace um::hfun {

struct DistanceRamp {
    double km_min = 0;       // h within distance_km of a feature
    double km_max = 0;       // h far from the features
    double distance_km = 0;  // d0: h = km_min up to this distance
    double rate = 0;         // growth of h beyond d0, km per km

    // The ramp that reaches km_max width_km beyond distance_km.
    static DistanceRamp over_width(double km_min, double km_max, double distance_km,
                                   double width_km);
};

// polylines: each at least 2 points (unit vectors, normalised here; an edge is
// the minor great arc between consecutive points; repeated points are
// skipped). Throws um::Error: UM_ERR_NONFINITE_INPUT (NaN/Inf point or ramp
// value), UM_ERR_INVALID_ARGUMENT (zero vector, no polyline, ramp values out
// of range), UM_ERR_TOO_FEW_POINTS (a polyline with fewer than 2 distinct
// points), UM_ERR_DEGENERATE_INPUT (antipodal consecutive points).
SpacingPtr make_feature_distance(const std::vector<std::vector<geom::Vec3>> &polylines,
                                 const DistanceRamp &ramp, double radius_km = kEarthRadiusKm);

}  // namespace um::hfun
