// Small vector algebra on the unit sphere and great-arc primitives.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/uninit_vector.hpp"

namespace um::geom {

struct Vec3 {
    double x = 0, y = 0, z = 0;
    const double *data() const { return &x; }
    double *data() { return &x; }
    double operator[](int i) const { return (&x)[i]; }
};

}  // namespace um::geom

// An UninitVector of points leaves new ones unwritten, the zeros above
// notwithstanding: the triangulation's lifted points are first written by
// its parallel gather (tri/triangulation.hpp, prepare()). Declared with the
// type, so that every use of UninitVector<Vec3> sees it.
template <>
struct um::LeftUnwritten<um::geom::Vec3> : std::true_type {};

namespace um::geom {

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(Vec3 a) { return (1.0 / norm(a)) * a; }

// Sine and cosine of an angle in degrees (any finite value), reduced in
// degrees: exact at every multiple of 90, within 1.9e-16 elsewhere, odd
// and even bit for bit (up to the sign of a zero).
void sincos_deg(double deg, double &sin_deg, double &cos_deg);
// Unit vector of a longitude/latitude in degrees, from sincos_deg: the
// poles map exactly to (0, 0, +-1) whatever the longitude (so that every
// longitude at a pole is the same point), and multiples of 90 degrees to
// exact axes.
Vec3 unit_from_lonlat_deg(double lon_deg, double lat_deg);
// Longitude in (-180, 180] and latitude in [-90, 90], degrees.
void lonlat_deg_from_unit(Vec3 u, double &lon_deg, double &lat_deg);

// The longitude/latitude box (degrees) holding the cap of arc radius
// `radius` (radians) about a unit point: latitudes [lat_min, lat_max] within
// [-90, 90]; longitudes from lon_min eastwards to lon_max (lon_max may pass
// 180; lon_max - lon_min < 360), or every longitude when the cap holds a
// pole or reaches round (all_lon). A little wider than exact, never narrower.
struct CapBox {
    double lon_min = 0, lon_max = 0, lat_min = 0, lat_max = 0;
    bool all_lon = false;
};
CapBox cap_box(Vec3 centre, double radius);

// Great-circle distance between unit vectors (radians), accurate for tiny
// and near-antipodal separations (atan2 of |a x b| and a . b).
double arc_length(Vec3 a, Vec3 b);

// The arc (radians) of a chord between unit vectors, 2 asin(chord / 2), at
// a third of atan2's cost (glibc's saves and restores the rounding mode);
// as accurate as arc_length below a quarter circle (chord below sqrt 2),
// losing digits towards a half circle. A chord past 2 (rounding) is 2.
inline double arc_of_chord(double chord) { return 2 * std::asin(std::min(1.0, 0.5 * chord)); }

// Distance (radians) from unit point p to the minor arc (a, b).
double distance_to_arc(Vec3 p, Vec3 a, Vec3 b);

// Signed area (steradians) of the geodesic triangle (a, b, c) of unit
// vectors: positive when counter-clockwise seen from outside. Uses the
// Eriksson/van Oosterom formula tan(E/2) = det / (1 + a.b + b.c + c.a).
double signed_triangle_area(Vec3 a, Vec3 b, Vec3 c);

// Intersection of the minor great arcs (a0, a1) and (b0, b1), unit vectors.
// Returns true and the crossing point when they cross. Arcs that only touch
// within `tolerance` radians of an end point, or overlap along a common great
// circle, count as crossing only if the end point lies within tolerance of
// the other arc (the point returned is then that end point). The default
// tolerance (1e-12 rad, about 6 micrometres on the Earth) is far below any
// spacing the mesher uses and well above the rounding of unit vectors.
bool arc_intersection(Vec3 a0, Vec3 a1, Vec3 b0, Vec3 b1, Vec3 &crossing,
                      double tolerance = 1e-12);

}  // namespace um::geom
