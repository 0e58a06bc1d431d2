// Point sets for the geometry tests: random, icosahedral, circles.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "geom/sphere.hpp"

namespace um::test {

using geom::Vec3;

inline std::vector<Vec3> random_points(int64_t n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::vector<Vec3> out(static_cast<size_t>(n));
    for (auto &p : out) p = geom::normalized({g(rng), g(rng), g(rng)});
    return out;
}

// Vertices of the icosahedron subdivided `level` times (each triangle into 4
// by projected edge midpoints): 10 * 4^level + 2 points, full of cocircular
// quadruples.
inline std::vector<Vec3> icosahedral_points(int level) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> pts = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0},
                             {0, -1, p}, {0, 1, p},  {0, -1, -p}, {0, 1, -p},
                             {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    for (auto &v : pts) v = geom::normalized(v);
    std::vector<std::array<int, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            pts.push_back(geom::normalized(pts[a] + pts[b]));
            return midpoint[key] = static_cast<int>(pts.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        next.reserve(faces.size() * 4);
        for (auto &f : faces) {
            int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
            next.push_back({f[0], ab, ca});
            next.push_back({f[1], bc, ab});
            next.push_back({f[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        faces.swap(next);
    }
    return pts;
}

// n points on each of the given latitude circles (equal longitude steps,
// every one cocircular) plus both poles.
inline std::vector<Vec3> latitude_circles(const std::vector<double> &lat_deg, int n) {
    std::vector<Vec3> out = {{0, 0, 1}, {0, 0, -1}};
    for (double lat : lat_deg)
        for (int i = 0; i < n; ++i)
            out.push_back(geom::unit_from_lonlat_deg(360.0 * i / n, lat));
    return out;
}

// n points on each of three great circles (equator and two meridian planes).
inline std::vector<Vec3> great_circles(int n) {
    std::vector<Vec3> out;
    for (int i = 0; i < n; ++i) {
        double a = 2 * M_PI * (i + 0.5) / n;
        out.push_back({std::cos(a), std::sin(a), 0});
        out.push_back({std::cos(a), 0, std::sin(a)});
        out.push_back({0, std::cos(a + 0.1), std::sin(a + 0.1)});
    }
    return out;
}

}  // namespace um::test
