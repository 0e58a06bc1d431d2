// The surface a mesh lives on: a sphere, or an oblate ellipsoid of
// revolution (semi-major axis a, flattening f; WGS84 among them).
//
// DESIGN.md section 3: the triangulation is the same lifted hull of unit
// directions whatever the surface; a direction u stands for the surface
// point radius_along(u) * u (directions mapped radially), so that bisector
// planes through the centre cut "great ellipses". Longitudes and latitudes
// are geodetic (the coordinates of coastlines, rivers and spacing grids);
// on a sphere the direction of a lon/lat is its unit vector, bit for bit.
//
// The radial map is conformal to within f^2 (1.1e-5 for WGS84): a length on
// the ellipsoid near u is radius_along(u) times the arc between directions,
// which is how spacing in geodesic km becomes spacing in radians.
#pragma once

#include "geom/sphere.hpp"

namespace um::geom {

class Surface {
public:
    // Flattenings accepted: Earth-like oblate ellipsoids, for which
    // GeographicLib's series geodesics are accurate to rounding.
    static constexpr double kMaxFlattening = 1.0 / 50;
    // WGS84's defining constants.
    static constexpr double kWgs84A = 6378137.0, kWgs84F = 1 / 298.257223563;

    static Surface sphere(double radius_m) { return Surface(radius_m, 0.0); }
    // Throws UM_ERR_INVALID_ARGUMENT naming the value for an a that is not
    // finite and > 0 or an f outside [0, kMaxFlattening].
    static Surface ellipsoid(double a_m, double f);

    bool is_sphere() const { return f_ == 0; }
    double a() const { return a_; }  // metres: the sphere's radius, or the semi-major axis
    double f() const { return f_; }
    double b() const { return a_ * (1 - f_); }

    // The unit direction of the surface point at a geodetic lon/lat (degrees).
    Vec3 direction(double lon_deg, double lat_deg) const;
    // The geodetic lon/lat (degrees, longitude in (-180, 180]) of the surface
    // point in direction u.
    void geodetic(Vec3 u, double &lon_deg, double &lat_deg) const;
    // The point at the same geodetic lon/lat on the unit sphere: where MPAS
    // (which assumes a sphere) puts the surface point of direction u.
    Vec3 sphere_unit(Vec3 u) const;
    // Distance (m) from the centre to the surface along unit direction u.
    double radius_along(Vec3 u) const;
    // The surface point (m) of unit direction u.
    Vec3 point(Vec3 u) const { return radius_along(u) * u; }

    // The surface's area (m^2), and the radius of the sphere of that area
    // (the authalic radius; a on a sphere).
    double area_m2() const;
    double authalic_radius_m() const;

private:
    Surface(double a, double f) : a_(a), f_(f) {}
    double a_, f_;
};

}  // namespace um::geom
