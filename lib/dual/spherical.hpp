// Geodesic measures of the staggered mesh on the unit sphere, written so that
// small elements keep their relative accuracy: the output contract asks for
// 1e-10 relative on lengths and areas, and the naive forms (a . (b x c),
// |a x b|) lose it on cells a few km wide, where the parts cancel to h^2.
#pragma once

#include <cmath>

#include "geom/sphere.hpp"

namespace um::dual {

using geom::Vec3;

// Great-circle distance (radians): atan2(|a x b|, a . b), with a x b taken as
// (a - b) x b, whose rounding scales with |a - b| rather than with 1.
inline double arc(Vec3 a, Vec3 b) {
    return std::atan2(geom::norm(geom::cross(a - b, b)), geom::dot(a, b));
}

// The geodesic triangle (a, b, c)'s spherical excess E as tan(E/2) =
// det / den = det / (1 + a.b + b.c + c.a) (Eriksson 1990), with
// det = a . ((b - a) x (c - a)).
struct HalfExcessTangent {
    double det, den;
    HalfExcessTangent(Vec3 a, Vec3 b, Vec3 c)
        : det(geom::dot(a, geom::cross(b - a, c - a))),
          den(1.0 + geom::dot(a, b) + geom::dot(b, c) + geom::dot(c, a)) {}
};

// Signed area (steradians) of the geodesic triangle (a, b, c), positive when
// counter-clockwise seen from outside.
inline double signed_area(Vec3 a, Vec3 b, Vec3 c) {
    const HalfExcessTangent t(a, b, c);
    return 2.0 * std::atan2(t.det, t.den);
}

// Where the dual arc of the primal edge (i, j) crosses the primal great
// circle, from the lifted points q_i, q_j (DESIGN.md section 3): the unit
// point p = a x_i + b x_j with p . (q_i - q_j) = 0, i.e. a = s_j - s_i cos d,
// b = s_i - s_j cos d (s = |q|), with 1 - cos d written as |x_i - x_j|^2 / 2
// so that equal weights do not cancel.
inline Vec3 edge_point(Vec3 qi, Vec3 qj) {
    double si = geom::norm(qi), sj = geom::norm(qj);
    Vec3 xi = (1.0 / si) * qi, xj = (1.0 / sj) * qj;
    Vec3 d = xi - xj;
    double one_minus_cos = 0.5 * geom::dot(d, d);
    double a = (sj - si) + si * one_minus_cos;
    double b = (si - sj) + sj * one_minus_cos;
    return geom::normalized(a * xi + b * xj);
}

// The normal of the great circle through a and b as a x (b - a), whose
// rounding scales with |b - a|: its direction stays accurate for arcs
// metres long, where a x b loses the digits that cancel.
inline Vec3 arc_normal(Vec3 a, Vec3 b) { return geom::cross(a, b - a); }

// xEdge: where the primal great circle (c1, c2) and the dual one (v1, v2)
// cross, on the side of the edge point (edge_point, made by near() only
// where needed). The two meet there in exact arithmetic; in doubles the edge
// point lies on the primal circle to rounding but off the dual one by
// ~1e-16 / |v1 - v2|, and the sliver (v1, xEdge, v2) it leaves between a
// cell's kites and its polygon is ~1e-16 / l relative to a cell of size l:
// 1e-8 on cells a few hundred metres wide, against the 1e-10 the contract
// asks. Crossing the two accurate normals puts the point on both circles to
// rounding. The side: the edge point lies on the primal circle at the
// crossing, near the primal arc, so the crossing within 60 degrees of the
// arc's midpoint c1 + c2 is on its side (every edge of a mesh whose cells
// are smaller than a hemisphere); farther, the edge point is made to
// decide. A dual edge too short to carry a circle (below ~1 mm on the
// Earth) keeps the edge point.
template <class Near>
inline Vec3 arc_crossing(Vec3 c1, Vec3 c2, Vec3 v1, Vec3 v2, Near near) {
    const Vec3 dual = v2 - v1;
    if (geom::dot(dual, dual) < 1e-26) return near();
    const Vec3 x = geom::normalized(geom::cross(arc_normal(c1, c2), arc_normal(v1, v2)));
    const Vec3 mid = c1 + c2;
    double side = geom::dot(x, mid);
    if (side * side < 0.25 * geom::dot(mid, mid)) side = geom::dot(x, near());
    return side < 0 ? -1.0 * x : x;
}

// The distance of u from the polar axis, which its latitude and its local
// east both take (an edge needs both: made once for the two).
inline double axis_distance(Vec3 u) { return std::hypot(u.x, u.y); }

// Latitude and longitude (radians) of a unit vector at axis distance h;
// longitude in (-pi, pi] (0 at the poles).
inline void lat_lon(Vec3 u, double h, double &lat, double &lon) {
    lat = std::atan2(u.z, h);
    lon = std::atan2(u.y, u.x);
    if (lon <= -M_PI) lon = M_PI;
}
inline void lat_lon(Vec3 u, double &lat, double &lon) { lat_lon(u, axis_distance(u), lat, lon); }

// angleEdge: the angle of the normal n (any tangent vector at the unit point
// e, at axis distance h) counter-clockwise from local east, atan2(n . north,
// n . east). At a pole, east is taken as that of longitude 0, which lat_lon
// gives there.
inline double angle_from_east(Vec3 n, Vec3 e, double h) {
    Vec3 east = h > 0 ? Vec3{-e.y / h, e.x / h, 0.0} : Vec3{0.0, 1.0, 0.0};
    Vec3 north = geom::cross(e, east);
    return std::atan2(geom::dot(n, north), geom::dot(n, east));
}

}  // namespace um::dual
