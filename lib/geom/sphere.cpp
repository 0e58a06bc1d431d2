#include "geom/sphere.hpp"

#include <algorithm>
#include <cstdint>

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

namespace {

// Two doubles side by side (GCC's and Clang's vector extension; SSE2 on
// x86-64): the longitude and the latitude of a point take one pass.
typedef double Double2 __attribute__((vector_size(16)));
typedef int64_t Int2 __attribute__((vector_size(16)));

// Where mask is all ones, a, else b (bit by bit).
inline Double2 select(Int2 mask, Double2 a, Double2 b) {
    return reinterpret_cast<Double2>((reinterpret_cast<Int2>(a) & mask) | (reinterpret_cast<Int2>(b) & ~mask));
}

// Sine and cosine of angles in degrees, |angle| < 2^40.
//
// Why not std::sin(deg * pi / 180): that rounds the angle in radians
// first (1.2e-16 off at 180 degrees, so sin 180 = 1.2e-16 and cos 90 =
// 6e-17, not 0; the error grows with the angle: measured up to 2.6 units
// of 2^-53 within +-180 degrees, 5 within +-360), and glibc's four calls
// cost 37.5 ns a point against 15.5 here (tools/bench/bench_lonlat). Reduced in degrees instead:
// q = a nearest multiple of 90 (deg / 90 is rounded before it is rounded
// to an integer, so q may be the other one where deg is within a few ulps
// of an odd multiple of 45), r = deg - 90 q, which is exact (Sterbenz: for
// q != 0, 90 |q| is within a factor 2 of |deg|), so every multiple of 90
// degrees gives exactly 0 and +-1, and sin(-d) = -sin(d), cos(-d) = cos(d)
// bit for bit up to the sign of a zero. r (|r| <= 45 and a hair) in
// radians, then Taylor series to x^17 and x^16: on |x| <= pi/4 the first
// term left out is below 1e-19 for the sine and 2e-18 for the cosine.
// Measured against long double and mpmath over some 10^9 angles: at most
// 1.69 units of 2^-53 (1.9e-16) off, in the cosine near 45 degrees.
//
// Needs IEEE arithmetic as written: reassociation (-ffast-math) would fold
// (v + kRound) - kRound into v. The library's one guard against such a
// build is in geom/predicates.cpp (the exact predicates need it too).
inline void sincos_deg2(Double2 deg, Double2 &sin_out, Double2 &cos_out) {
    // Adding 1.5 * 2^52 rounds to an integer (to nearest, ties to even) and
    // leaves it in the low bits of the sum: q mod 4 is read from them.
    constexpr double kRound = 0x1.8p52;
    const Double2 rounded = deg * (1.0 / 90.0) + kRound;
    const Double2 q = rounded - kRound;
    const Double2 x = (deg - 90.0 * q) * kDegree, x2 = x * x;
    const Double2 sin_tail =
        -1.0 / 6 +
        x2 * (1.0 / 120 +
              x2 * (-1.0 / 5040 +
                    x2 * (1.0 / 362880 +
                          x2 * (-1.0 / 39916800 +
                                x2 * (1.0 / 6227020800.0 +
                                      x2 * (-1.0 / 1307674368000.0 + x2 * (1.0 / 355687428096000.0)))))));
    const Double2 cos_tail =
        1.0 / 24 +
        x2 * (-1.0 / 720 +
              x2 * (1.0 / 40320 +
                    x2 * (-1.0 / 3628800 +
                          x2 * (1.0 / 479001600 + x2 * (-1.0 / 87178291200.0 + x2 * (1.0 / 20922789888000.0))))));
    const Double2 sin_x = x + x * x2 * sin_tail;
    const Double2 cos_x = 1.0 - 0.5 * x2 + x2 * x2 * cos_tail;
    // sin(r + 90 q) by q mod 4: sin r, cos r, -sin r, -cos r; cos likewise
    // a quarter turn on. (0 - v, not -v: +0 stays +0.)
    const Int2 k = reinterpret_cast<Int2>(rounded);
    const Int2 odd = -(k & 1), sin_negative = -((k >> 1) & 1), cos_negative = -(((k + 1) >> 1) & 1);
    const Double2 s = select(odd, cos_x, sin_x), c = select(odd, sin_x, cos_x);
    sin_out = select(sin_negative, 0.0 - s, s);
    cos_out = select(cos_negative, 0.0 - c, c);
}

// Longitudes beyond 2^40 degrees (any finite value is accepted) are first
// brought within one turn, exactly.
inline double within_range(double deg) { return std::fabs(deg) < 0x1p40 ? deg : std::fmod(deg, 360.0); }

}  // namespace

void sincos_deg(double deg, double &sin_deg, double &cos_deg) {
    Double2 s, c;
    deg = within_range(deg);
    sincos_deg2(Double2{deg, deg}, s, c);
    sin_deg = s[0], cos_deg = c[0];
}

Vec3 unit_from_lonlat_deg(double lon_deg, double lat_deg) {
    // (cos 90 is 0 below too, but 0 times a negative cosine would be -0.)
    if (lat_deg == 90.0) return {0, 0, 1};
    if (lat_deg == -90.0) return {0, 0, -1};
    Double2 s, c;  // [0]: longitude, [1]: latitude
    sincos_deg2(Double2{within_range(lon_deg), within_range(lat_deg)}, s, c);
    return {c[1] * c[0], c[1] * s[0], s[1]};
}

void lonlat_deg_from_unit(Vec3 u, double &lon_deg, double &lat_deg) {
    lon_deg = std::atan2(u.y, u.x) / kDegree;
    if (lon_deg <= -180.0) lon_deg += 360.0;
    lat_deg = std::atan2(u.z, std::hypot(u.x, u.y)) / kDegree;
}

CapBox cap_box(Vec3 centre, double radius) {
    // Rounding of the trigonometry, in degrees, added on every side.
    constexpr double kSlackDeg = 1e-9;
    double lon, lat;
    lonlat_deg_from_unit(centre, lon, lat);
    const double r_deg = radius / kDegree;
    CapBox box;
    box.lat_min = std::max(-90.0, lat - r_deg - kSlackDeg);
    box.lat_max = std::min(90.0, lat + r_deg + kSlackDeg);
    // The cap's widest longitude reach: sin(dlon) = sin(r) / cos(lat).
    const double reach = std::sin(radius) / std::cos(lat * kDegree);
    if (box.lat_min <= -90.0 || box.lat_max >= 90.0 || !(reach < 1.0) || radius >= M_PI / 2) {
        box.all_lon = true;
        box.lon_min = -180.0, box.lon_max = 180.0;
        return box;
    }
    const double dlon = std::asin(reach) / kDegree + kSlackDeg;
    box.lon_min = lon - dlon, box.lon_max = lon + dlon;
    return box;
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
