// The conversion of longitudes and latitudes in degrees to unit vectors,
// geom::unit_from_lonlat_deg (sine and cosine reduced in degrees, both
// angles in one SSE2 pass), against the way it was done before: the angles
// converted to radians and glibc's sin and cos, four calls a point. Prints
// each one's time per point (the best of the rounds, the two alternating)
// and its largest error in a component against long double, in units of
// 2^-53.
//
//   bench_lonlat [POINTS [ROUNDS]]     (default 2000000 points, 7 rounds)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "geom/sphere.hpp"

namespace {

using um::geom::Vec3;

constexpr double kRadiansPerDegree = M_PI / 180.0;

// The conversion unimesh made before geom::sincos_deg (poles special-cased).
Vec3 through_radians(double lon_deg, double lat_deg) {
    if (lat_deg == 90.0) return {0, 0, 1};
    if (lat_deg == -90.0) return {0, 0, -1};
    const double lon = lon_deg * kRadiansPerDegree, lat = lat_deg * kRadiansPerDegree;
    const double c = std::cos(lat);
    return {c * std::cos(lon), c * std::sin(lon), std::sin(lat)};
}

// Seconds to convert every point with `convert` into `out`.
template <class Convert>
double time_conversion(Convert convert, const std::vector<double> &lon, const std::vector<double> &lat,
                       std::vector<Vec3> &out) {
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < lon.size(); ++i) out[i] = convert(lon[i], lat[i]);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The largest error of a component of out against long double, in units of 2^-53.
double largest_error(const std::vector<Vec3> &out, const std::vector<double> &lon, const std::vector<double> &lat) {
    const long double kDegree = 3.14159265358979323846264338327950288L / 180.0L;
    long double worst = 0;
    for (size_t i = 0; i < out.size(); ++i) {
        const long double a = std::fmod(static_cast<long double>(lon[i]), 360.0L) * kDegree,
                          b = static_cast<long double>(lat[i]) * kDegree;
        const long double exact[3] = {std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b)};
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(out[i][k] - exact[k]));
    }
    return static_cast<double>(worst / 0x1p-53L);
}

long parse(const char *text, const char *what) {
    char *end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (!end || *end || v < 1) {
        std::fprintf(stderr, "bench_lonlat: %s '%s' is not a whole number >= 1\n", what, text);
        std::exit(2);
    }
    return v;
}

}  // namespace

int main(int argc, char **argv) {
    if (argc > 3) {
        std::fprintf(stderr, "usage: bench_lonlat [POINTS [ROUNDS]]\n");
        return 2;
    }
    const long n = argc > 1 ? parse(argv[1], "POINTS") : 2000000, rounds = argc > 2 ? parse(argv[2], "ROUNDS") : 7;
    // Uniform on the sphere, longitudes over two turns (the old way's error
    // grows with the angle), fixed seed.
    std::mt19937_64 random(0x6c6f6e6c6174);
    std::uniform_real_distribution<double> longitude(-360.0, 360.0), sine(-1.0, 1.0);
    std::vector<double> lon(n), lat(n);
    for (long i = 0; i < n; ++i) lon[i] = longitude(random), lat[i] = std::asin(sine(random)) / kRadiansPerDegree;
    std::vector<Vec3> ours(n), before(n);
    double best_ours = 1e300, best_before = 1e300;
    for (long r = 0; r < rounds; ++r) {  // alternating, the first of a round rotating
        if (r % 2) best_before = std::min(best_before, time_conversion(through_radians, lon, lat, before));
        best_ours = std::min(best_ours, time_conversion(um::geom::unit_from_lonlat_deg, lon, lat, ours));
        if (r % 2 == 0) best_before = std::min(best_before, time_conversion(through_radians, lon, lat, before));
    }
    std::printf("# %ld points (longitudes in [-360, 360)), best of %ld rounds\n", n, rounds);
    std::printf("# method                       ns/point   largest error (units of 2^-53)\n");
    std::printf("  unit_from_lonlat_deg         %8.2f   %.2f\n", 1e9 * best_ours / double(n),
                largest_error(ours, lon, lat));
    std::printf("  radians, glibc sin and cos   %8.2f   %.2f\n", 1e9 * best_before / double(n),
                largest_error(before, lon, lat));
    std::printf("# time ratio (unit_from_lonlat_deg / radians): %.3f\n", best_ours / best_before);
    return 0;
}
