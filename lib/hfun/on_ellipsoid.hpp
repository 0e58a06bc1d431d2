// A spacing given in geodesic km at geodetic lon/lat, read by the mesher at
// directions (geom/surface.hpp): h_dir(u) = h(lon/lat of u) * a / r(u), the
// km on the sphere of radius a of the directions that the surface point's
// km span there (r(u) the surface's distance from the centre along u; the
// radial map is conformal to within f^2). So the mesher, which measures in
// radians times a, places edges of h geodesic km.
//
// The caller's kinds that measure distances (feature-distance ramps, the
// gradient limit) measure them on the sphere of radius a at geodetic
// lon/lat: within 2f (0.7 % for WGS84) of the geodesic distance.
#pragma once

#include "geom/surface.hpp"
#include "hfun/spacing.hpp"

namespace um::hfun {

// inner as read on surface (an ellipsoid; a sphere returns inner itself).
SpacingPtr make_on_ellipsoid(SpacingPtr inner, const geom::Surface &surface);

}  // namespace um::hfun
