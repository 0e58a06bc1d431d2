#include "geom/sphere.hpp"

#include <algorithm>

namespace um::geom {

namespace {
constexpr double kDegree = M_PI / 180.0;
}  // namespace

double distance_to_arc(Vec3 p, Vec3 a, Vec3 b) {
    Vec3 n = cross(a, b);
    double nn = norm(n);
    if (nn == 0) return arc_length(p, a);
    n = (1.0 / nn) * n;
    // Foot of the perpendicular on the great circle, if it lies within the arc.
    Vec3 foot = p - dot(p, n) * n;
    double fl = norm(foot);
    if (fl > 0) {
        foot = (1.0 / fl) * foot;
        if (dot(cross(a, foot), n) >= 0 && dot(cross(foot, b), n) >= 0)
            return std::asin(std::min(1.0, std::fabs(dot(p, n))));
    }
    return std::min(arc_length(p, a), arc_length(p, b));
}

Vec3 unit_from_lonlat_deg(double lon_deg, double lat_deg) {
    if (lat_deg == 90.0) return {0, 0, 1};
    if (lat_deg == -90.0) return {0, 0, -1};
    double lon = lon_deg * kDegree, lat = lat_deg * kDegree;
    double c = std::cos(lat);
    return {c * std::cos(lon), c * std::sin(lon), std::sin(lat)};
}

void lonlat_deg_from_unit(Vec3 u, double &lon_deg, double &lat_deg) {
    lon_deg = std::atan2(u.y, u.x) / kDegree;
    if (lon_deg <= -180.0) lon_deg += 360.0;
    lat_deg = std::atan2(u.z, std::hypot(u.x, u.y)) / kDegree;
}

double arc_length(Vec3 a, Vec3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

double signed_triangle_area(Vec3 a, Vec3 b, Vec3 c) {
    double det = dot(a, cross(b, c));
    double den = 1.0 + dot(a, b) + dot(b, c) + dot(c, a);
    return 2.0 * std::atan2(det, den);
}

bool arc_intersection(Vec3 a0, Vec3 a1, Vec3 b0, Vec3 b1, Vec3 &crossing, double tolerance) {
    Vec3 na = cross(a0, a1), nb = cross(b0, b1);
    // Quick rejection: both ends of one arc strictly on one side of the other's
    // great circle, farther than the tolerance (and rounding) from it.
    const double margin = tolerance + 1e-15;
    const double la = norm(na), lb = norm(nb);
    const double sb0 = dot(na, b0), sb1 = dot(na, b1), sa0 = dot(nb, a0), sa1 = dot(nb, a1);
    if ((sb0 > margin * la && sb1 > margin * la) || (sb0 < -margin * la && sb1 < -margin * la) ||
        (sa0 > margin * lb && sa1 > margin * lb) || (sa0 < -margin * lb && sa1 < -margin * lb))
        return false;
    Vec3 line = cross(na, nb);
    double ll = norm(line);
    if (ll > 0) {
        line = (1.0 / ll) * line;
        // The two great circles meet at +-line; a crossing must lie on both minor arcs.
        for (double s : {1.0, -1.0}) {
            Vec3 x = s * line;
            bool on_a = dot(cross(a0, x), na) >= 0 && dot(cross(x, a1), na) >= 0;
            bool on_b = dot(cross(b0, x), nb) >= 0 && dot(cross(x, b1), nb) >= 0;
            if (on_a && on_b) {
                crossing = x;
                return true;
            }
        }
    }
    // Touching or overlapping within the tolerance: report the end point.
    for (Vec3 p : {b0, b1})
        if (distance_to_arc(p, a0, a1) <= tolerance) return crossing = p, true;
    for (Vec3 p : {a0, a1})
        if (distance_to_arc(p, b0, b1) <= tolerance) return crossing = p, true;
    return false;
}

}  // namespace um::geom
