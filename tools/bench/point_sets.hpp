// The point sets of the triangulation benchmarks (bench_triangulation,
// bench_ab): uniformly random directions, icosahedral grids and regular
// longitude-latitude grids, each named by a case ("random-1e6", "ico-9",
// "grid-0.25"). Header-only; generated the same on every platform.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <unordered_map>
#include <vector>

namespace bench {

constexpr uint64_t kSeed = 0x756e696d657368ULL;  // fixed seed of the random cases
constexpr double kPi = 3.14159265358979323846;

// A small self-contained generator (xoshiro256** seeded through splitmix64) so
// the random cases are the same on every platform and standard library.
class Rng {
public:
    explicit Rng(uint64_t seed) {
        for (auto &word : s_) {
            seed += 0x9e3779b97f4a7c15ULL;
            uint64_t z = seed;
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
            word = z ^ (z >> 31);
        }
    }
    uint64_t next() {
        const uint64_t result = rotl(s_[1] * 5, 7) * 9;
        const uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = rotl(s_[3], 45);
        return result;
    }
    // Uniform in the open interval (0, 1).
    double uniform_open() { return (double(next() >> 11) + 0.5) * 0x1.0p-53; }
    // Standard normal deviate (Marsaglia's polar method, spare value cached).
    double normal() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        double u, v, s;
        do {
            u = 2.0 * uniform_open() - 1.0;
            v = 2.0 * uniform_open() - 1.0;
            s = u * u + v * v;
        } while (s >= 1.0 || s == 0.0);
        const double f = std::sqrt(-2.0 * std::log(s) / s);
        spare_ = v * f;
        has_spare_ = true;
        return u * f;
    }

private:
    static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    uint64_t s_[4];
    double spare_ = 0.0;
    bool has_spare_ = false;
};

struct PointSet {
    std::vector<double> xyz;  // 3 per point, unit vectors
    std::vector<double> lon;  // degrees
    std::vector<double> lat;  // degrees
    int64_t size() const { return int64_t(xyz.size() / 3); }
};

inline void normalise(double *p) {
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    p[0] /= r;
    p[1] /= r;
    p[2] /= r;
}

// Uniformly random points: normalised vectors of three independent normal deviates.
inline std::vector<double> random_points(int64_t n, uint64_t seed) {
    Rng rng(seed);
    std::vector<double> xyz(size_t(3 * n));
    for (int64_t i = 0; i < n; ++i) {
        double *p = &xyz[size_t(3 * i)];
        double r2;
        do {
            p[0] = rng.normal();
            p[1] = rng.normal();
            p[2] = rng.normal();
            r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        } while (r2 < 1e-20);
        normalise(p);
    }
    return xyz;
}

using Tri = std::array<int32_t, 3>;

inline double det3(const double *a, const double *b, const double *c) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// The icosahedral grid of a level: the icosahedron, then `level` times every
// triangle split into four by its edge midpoints pushed out to the sphere. Each
// edge gets one midpoint shared by its two triangles, so the result is a proper
// mesh. Fails (returns false, with a message) if a count is not as it must be.
inline bool icosahedral_points(int level, std::vector<double> &xyz, std::string &error) {
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    xyz.clear();
    // The 12 vertices: cyclic permutations of (0, +-1, +-phi).
    for (int perm = 0; perm < 3; ++perm)
        for (int s1 = -1; s1 <= 1; s1 += 2)
            for (int s2 = -1; s2 <= 1; s2 += 2) {
                double v[3];
                v[perm] = 0.0;
                v[(perm + 1) % 3] = s1;
                v[(perm + 2) % 3] = s2 * phi;
                normalise(v);
                xyz.insert(xyz.end(), v, v + 3);
            }
    // The 20 faces: triples of mutually adjacent vertices (adjacent = at the
    // edge length, the smallest distance), ordered counter-clockwise seen from outside.
    auto d2 = [&](int a, int b) {
        double s = 0;
        for (int k = 0; k < 3; ++k) s += (xyz[3 * a + k] - xyz[3 * b + k]) * (xyz[3 * a + k] - xyz[3 * b + k]);
        return s;
    };
    double min_d2 = 1e300;
    for (int a = 0; a < 12; ++a)
        for (int b = a + 1; b < 12; ++b) min_d2 = std::min(min_d2, d2(a, b));
    auto adjacent = [&](int a, int b) { return d2(a, b) < min_d2 * 1.01; };
    std::vector<Tri> tris;
    for (int a = 0; a < 12; ++a)
        for (int b = a + 1; b < 12; ++b)
            for (int c = b + 1; c < 12; ++c)
                if (adjacent(a, b) && adjacent(b, c) && adjacent(a, c)) {
                    if (det3(&xyz[3 * a], &xyz[3 * b], &xyz[3 * c]) > 0)
                        tris.push_back({a, b, c});
                    else
                        tris.push_back({a, c, b});
                }
    if (tris.size() != 20) {
        error = "icosahedron has " + std::to_string(tris.size()) + " faces, not 20";
        return false;
    }

    for (int l = 1; l <= level; ++l) {
        std::unordered_map<uint64_t, int32_t> midpoint;
        midpoint.reserve(tris.size() * 3 / 2);
        xyz.reserve(xyz.size() + 3 * (tris.size() * 3 / 2));
        auto mid = [&](int32_t a, int32_t b) -> int32_t {
            const uint64_t key = (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
            auto found = midpoint.find(key);
            if (found != midpoint.end()) return found->second;
            const int32_t index = int32_t(xyz.size() / 3);
            double m[3];
            for (int k = 0; k < 3; ++k) m[k] = xyz[size_t(3 * a + k)] + xyz[size_t(3 * b + k)];
            normalise(m);
            xyz.insert(xyz.end(), m, m + 3);
            midpoint.emplace(key, index);
            return index;
        };
        std::vector<Tri> finer;
        finer.reserve(tris.size() * 4);
        for (const Tri &t : tris) {
            const int32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
            finer.push_back({t[0], ab, ca});
            finer.push_back({t[1], bc, ab});
            finer.push_back({t[2], ca, bc});
            finer.push_back({ab, bc, ca});
        }
        // Every edge of a closed triangle mesh is shared by exactly two triangles.
        if (midpoint.size() * 2 != tris.size() * 3) {
            error = "level " + std::to_string(l) + ": " + std::to_string(midpoint.size()) +
                    " edges for " + std::to_string(tris.size()) + " triangles (not a closed mesh)";
            return false;
        }
        tris.swap(finer);
    }
    const int64_t expected = 10 * (int64_t(1) << (2 * level)) + 2;
    const int64_t n = int64_t(xyz.size() / 3);
    if (n != expected) {
        error = "level " + std::to_string(level) + " grid has " + std::to_string(n) +
                " points, expected 10*4^L+2 = " + std::to_string(expected);
        return false;
    }
    if (int64_t(tris.size()) != 2 * n - 4) {
        error = "level " + std::to_string(level) + " grid has " + std::to_string(tris.size()) +
                " triangles, expected 2V-4 = " + std::to_string(2 * n - 4);
        return false;
    }
    return true;
}

inline void fill_lonlat(PointSet &ps) {
    const int64_t n = ps.size();
    ps.lon.resize(size_t(n));
    ps.lat.resize(size_t(n));
    for (int64_t i = 0; i < n; ++i) {
        const double *p = &ps.xyz[size_t(3 * i)];
        ps.lon[size_t(i)] = std::atan2(p[1], p[0]) * (180.0 / kPi);
        ps.lat[size_t(i)] = std::atan2(p[2], std::hypot(p[0], p[1])) * (180.0 / kPi);
    }
}

// A regular grid of `step` degrees, as a climate model's input: latitudes
// -90 + j step strictly between the poles, longitudes -180 + i step over a
// turn, and the two poles once each. Degrees exact as given (the lon/lat
// call reads them), unit vectors from them through radians. Many points lie
// exactly on one meridian or parallel: cocircular quadruples everywhere,
// and directions on the great circles of many edges.
inline void lonlat_grid(double step, PointSet &ps) {
    const int64_t per_turn = std::llround(360.0 / step), rows = std::llround(180.0 / step) - 1;
    ps.lon.clear(), ps.lat.clear(), ps.xyz.clear();
    auto add = [&](double lon, double lat) {
        ps.lon.push_back(lon), ps.lat.push_back(lat);
        const double l = lon * (kPi / 180.0), f = lat * (kPi / 180.0);
        ps.xyz.insert(ps.xyz.end(), {std::cos(f) * std::cos(l), std::cos(f) * std::sin(l), std::sin(f)});
    };
    add(0.0, -90.0);
    for (int64_t j = 1; j <= rows; ++j)
        for (int64_t i = 0; i < per_turn; ++i) add(-180.0 + double(i) * step, -90.0 + double(j) * step);
    add(0.0, 90.0);
}

struct CaseSpec {
    enum Kind { random, icosahedral, grid };
    std::string name;
    Kind kind = random;
    int64_t n = 0;      // points
    int level = 0;      // icosahedral level
    double step = 0.0;  // grid spacing in degrees
};

// "random-<points>" (e.g. random-1e6), "ico-<level>" (0..11) or
// "grid-<degrees>" (a divisor of 180 down to 0.05, e.g. grid-0.25).
inline bool parse_case(const std::string &text, CaseSpec &spec) {
    spec.name = text;
    char *end = nullptr;
    if (text.rfind("random-", 0) == 0) {
        const char *num = text.c_str() + 7;
        const double v = std::strtod(num, &end);
        if (end == num || *end != '\0' || !(v >= 4) || v > 2e8 || v != std::floor(v)) return false;
        spec.kind = CaseSpec::random;
        spec.n = int64_t(v);
        return true;
    }
    if (text.rfind("ico-", 0) == 0) {
        const char *num = text.c_str() + 4;
        const long v = std::strtol(num, &end, 10);
        if (end == num || *end != '\0' || v < 0 || v > 11) return false;
        spec.kind = CaseSpec::icosahedral;
        spec.level = int(v);
        spec.n = 10 * (int64_t(1) << (2 * v)) + 2;
        return true;
    }
    if (text.rfind("grid-", 0) == 0) {
        const char *num = text.c_str() + 5;
        const double v = std::strtod(num, &end);
        if (end == num || *end != '\0' || !(v >= 0.05) || v > 90) return false;
        const double rows = 180.0 / v;  // the step must divide 180 (and so 360)
        if (std::fabs(rows - std::round(rows)) > 1e-9 * rows) return false;
        spec.kind = CaseSpec::grid;
        spec.step = v;
        spec.n = 2 * std::llround(rows) * (std::llround(rows) - 1) + 2;
        return true;
    }
    return false;
}

// The points of a case, unit vectors and degrees; false with a message if
// the grid's counts came out wrong.
inline bool make_points(const CaseSpec &spec, PointSet &ps, std::string &error) {
    switch (spec.kind) {
    case CaseSpec::random:
        ps.xyz = random_points(spec.n, kSeed);
        fill_lonlat(ps);
        return true;
    case CaseSpec::icosahedral:
        if (!icosahedral_points(spec.level, ps.xyz, error)) return false;
        fill_lonlat(ps);
        return true;
    case CaseSpec::grid:
        lonlat_grid(spec.step, ps);
        if (ps.size() != spec.n) {
            error = "grid of " + std::to_string(spec.step) + " degrees has " + std::to_string(ps.size()) +
                    " points, expected " + std::to_string(spec.n);
            return false;
        }
        return true;
    }
    return false;
}

}  // namespace bench
