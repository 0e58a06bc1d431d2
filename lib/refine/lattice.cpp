#include "refine/lattice.hpp"

#include <array>
#include <cmath>

namespace um::refine {

using geom::Vec3;

namespace {

// The point a fraction t of the way from a to b along their great circle.
Vec3 slerp(const Vec3 &a, const Vec3 &b, double t) {
    const double angle = std::acos(std::max(-1.0, std::min(1.0, geom::dot(a, b))));
    if (angle == 0) return a;
    const double s = std::sin(angle);
    return geom::normalized((std::sin((1 - t) * angle) / s) * a + (std::sin(t * angle) / s) * b);
}

std::array<Vec3, 12> icosahedron_corners() {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    const Vec3 v[12] = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                        {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    std::array<Vec3, 12> corners;
    for (int i = 0; i < 12; ++i) corners[i] = geom::normalized(v[i]);
    return corners;
}

// Two corners share an edge when they are nearest neighbours: the edge's
// chord is 1.05 on the unit sphere, the next distance 1.70.
bool adjacent(const Vec3 &a, const Vec3 &b) {
    const Vec3 d = a - b;
    return geom::dot(d, d) < 1.21;
}

// The point of face (a, b, c) with barycentric weights (i, j, k) / n, on the
// row of points at weight i of a: from the point of edge ab to that of edge ac.
Vec3 row_point(const Vec3 &a, const Vec3 &b, const Vec3 &c, int64_t i, int64_t k, int64_t n) {
    const double towards = static_cast<double>(n - i) / static_cast<double>(n);
    const Vec3 from = slerp(a, b, towards), to = slerp(a, c, towards);
    return slerp(from, to, static_cast<double>(k) / static_cast<double>(n - i));
}

}  // namespace

int64_t lattice_frequency(double spacing, int64_t max_points) {
    if (!(spacing > 0)) return 0;
    const double hexagons = 4 * M_PI / (0.8660254037844386 * spacing * spacing);
    const double n = std::round(std::sqrt(std::max(0.0, hexagons - 2) / 10));
    if (n > std::sqrt(static_cast<double>(max_points) / 10)) return 0;
    return std::max<int64_t>(1, static_cast<int64_t>(n));
}

std::vector<Vec3> geodesic_lattice(int64_t n) {
    const std::array<Vec3, 12> corner = icosahedron_corners();
    std::vector<Vec3> points(corner.begin(), corner.end());
    points.reserve(static_cast<size_t>(10 * n * n + 2));
    for (int a = 0; a < 12; ++a)
        for (int b = a + 1; b < 12; ++b)
            if (adjacent(corner[a], corner[b]))
                for (int64_t s = 1; s < n; ++s)
                    points.push_back(slerp(corner[a], corner[b], static_cast<double>(s) / static_cast<double>(n)));
    for (int a = 0; a < 12; ++a)
        for (int b = a + 1; b < 12; ++b)
            for (int c = b + 1; c < 12; ++c) {
                if (!adjacent(corner[a], corner[b]) || !adjacent(corner[b], corner[c]) ||
                    !adjacent(corner[a], corner[c]))
                    continue;
                const Vec3 &A = corner[a], &B = corner[b], &C = corner[c];
                for (int64_t i = 1; i < n; ++i)
                    for (int64_t j = 1; i + j < n; ++j) {
                        const int64_t k = n - i - j;
                        points.push_back(geom::normalized(row_point(A, B, C, i, k, n) + row_point(B, C, A, j, i, n) +
                                                          row_point(C, A, B, k, j, n)));
                    }
            }
    return points;
}

}  // namespace um::refine
