#include "refine/lattice.hpp"

#include <algorithm>
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

namespace {

constexpr double kFlat = 0.01;            // relative spread of h that counts as one value
constexpr int64_t kSampleFrequency = 64;  // 40,962 samples for the coarsest spacing
constexpr int kProbes = 6;                // around each lattice point, at distance h0
constexpr double kGammaClearance = 1.0;   // in units of h0
constexpr const char *kStage = "refine lattice";  // progress (the spacing may be a slow callback)

double coarsest_spacing(Context &ctx, const SpacingRadians &h) {
    const std::vector<Vec3> samples = geodesic_lattice(kSampleFrequency);
    std::vector<double> value(samples.size());
    ctx.parallel_for_with_heartbeat(kStage, static_cast<int64_t>(samples.size()), 16, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) value[i] = h(samples[i]);
    });
    return *std::max_element(value.begin(), value.end());
}

// Whether h is h0 (within kFlat) at p and at kProbes points h0 around it.
bool flat_around(const SpacingRadians &h, const Vec3 &p, double h0) {
    auto flat = [&](const Vec3 &q) { return std::fabs(h(q) - h0) <= kFlat * h0; };
    if (!flat(p)) return false;
    const Vec3 axis = std::fabs(p.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
    const Vec3 e1 = geom::normalized(geom::cross(p, axis)), e2 = geom::cross(p, e1);
    for (int k = 0; k < kProbes; ++k) {
        const double angle = 2 * M_PI * k / kProbes;
        const Vec3 q = std::cos(h0) * p + std::sin(h0) * (std::cos(angle) * e1 + std::sin(angle) * e2);
        if (!flat(geom::normalized(q))) return false;
    }
    return true;
}

}  // namespace

std::vector<Vec3> background_lattice(Context &ctx, const SpacingRadians &h, const geom::ArcTree &gamma) {
    const double h0 = coarsest_spacing(ctx, h);
    const int64_t n = lattice_frequency(h0, int64_t{1} << 31);
    std::vector<Vec3> points = geodesic_lattice(std::max<int64_t>(n, 1));
    std::vector<uint8_t> keep(points.size(), 0);
    ctx.parallel_for_with_heartbeat(kStage, static_cast<int64_t>(points.size()), 16, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            double d = 1e300;
            if (gamma.size() > 0) gamma.nearest(points[i], &d);
            const bool near_gamma = d < kGammaClearance * h0;
            const bool flat = n > 0 && !(i >= 12 && near_gamma) && flat_around(h, points[i], h0);
            // A corner stays where the lattice does not reach (the
            // icosahedron's start there), unless the lattice has a band
            // along Gamma there.
            keep[i] = i < 12 ? !(flat && near_gamma) : flat && !near_gamma;
        }
    });
    size_t kept = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (keep[i]) points[kept++] = points[i];
    points.resize(kept);
    return points;
}

}  // namespace um::refine
