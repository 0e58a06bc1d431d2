// Engine tests: exact predicates, great-arc primitives, the Hilbert order.
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <random>
#include <set>
#include <algorithm>
#include <cstring>
#include <string>

#include <sys/mman.h>
#include <unistd.h>

#include "core/radix_sort.hpp"
#include "core/uninit_vector.hpp"
#include "geom/expansion.hpp"
#include "geom/predicates.hpp"
#include "geom/sphere.hpp"
#include "support/point_sets.hpp"
#include "tri/spatial_order.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;

namespace {

void orient3d_signs_on_exact_configurations(void **) {
    const double a[3] = {0, 0, 1}, b[3] = {1, 0, 1}, c[3] = {0, 1, 1};
    double d[3] = {0.25, 0.25, 1};
    assert_int_equal(geom::orient3d(a, b, c, d), 0);  // coplanar
    d[2] = std::nextafter(1.0, 2.0);                   // one ulp above the plane
    assert_int_equal(geom::orient3d(a, b, c, d), 1);
    d[2] = std::nextafter(1.0, 0.0);  // one ulp below
    assert_int_equal(geom::orient3d(a, b, c, d), -1);
    // Far from the origin with a tiny offset: the filter must not decide wrongly.
    const double big = 1e15;
    const double A[3] = {big, big, 1}, B[3] = {big + 1, big, 1}, C[3] = {big, big + 1, 1};
    double D[3] = {big + 0.5, big + 0.5, 1};
    assert_int_equal(geom::orient3d(A, B, C, D), 0);
    D[2] = 1 + 0x1p-52;
    assert_int_equal(geom::orient3d(A, B, C, D), 1);
}

// The filtered predicate agrees with the exact evaluation on nearly
// degenerate input (points on a plane through rounding).
void filter_agrees_with_exact(void **) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    int decided_by_exact = 0;
    for (int i = 0; i < 200000; ++i) {
        double p[4][3];
        double nx = u(rng), ny = u(rng), off = u(rng);
        for (auto &q : p) {
            q[0] = u(rng), q[1] = u(rng);
            q[2] = off + nx * q[0] + ny * q[1];  // on a plane up to rounding
        }
        int s = geom::orient3d(p[0], p[1], p[2], p[3]);
        int e = geom::orient3d_exact(p[0], p[1], p[2], p[3]);
        assert_int_equal(s, e);
        decided_by_exact += e == 0;
    }
    (void)decided_by_exact;
}

// The sum by growing (Shewchuk's grow-expansion, one component of b at a
// time): quadratic, and correct for any nonoverlapping inputs - the
// reference for geom::add and subtract, which merge.
template <int C, int A, int B>
geom::Expansion<C> sum_by_growing(const geom::Expansion<A> &a, const geom::Expansion<B> &b) {
    geom::Expansion<C> out;
    for (int i = 0; i < a.n; ++i) out.c[out.n++] = a.c[i];
    for (int j = 0; j < b.n; ++j) {
        double q = b.c[j];
        int m = 0;
        for (int i = 0; i < out.n; ++i) {
            double hi, lo;
            geom::two_sum(q, out.c[i], hi, lo);
            q = hi;
            if (lo != 0) out.c[m++] = lo;
        }
        if (q != 0) out.c[m++] = q;
        out.n = m;
    }
    return out;
}

// The value of the lowest set bit of x (x != 0).
double lowest_bit(double x) {
    int exponent;
    const double mantissa = std::frexp(std::fabs(x), &exponent);  // [0.5, 1)
    auto bits = static_cast<uint64_t>(std::ldexp(mantissa, 53));
    int shift = 0;
    while (!(bits & 1)) bits >>= 1, ++shift;
    return std::ldexp(1.0, exponent - 53 + shift);
}

// geom::add and subtract give the exact sum and difference of expansions
// made as the predicates make them (differences, their products), with
// components nonzero, of increasing magnitude and nonoverlapping: minus the
// growing sum's, exactly zero. Exponents over 2^-60 .. 2^60, and every third
// case shares values so that terms cancel exactly.
void expansion_sums_are_exact(void **) {
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> exponent(-60, 60);
    auto draw = [&] { return std::ldexp(u(rng), exponent(rng)); };
    using E2 = geom::Expansion<2>;
    auto negated = [](auto e) {
        for (int k = 0; k < e.n; ++k) e.c[k] = -e.c[k];
        return e;
    };
    for (int i = 0; i < 200000; ++i) {
        const double x = draw(), y = draw(), z = draw(), w = draw();
        const E2 d1 = E2::difference(x, y), d2 = E2::difference(z, i % 3 ? w : x);
        const auto p1 = geom::multiply<8>(d1, d2);
        const auto p2 = geom::multiply<8>(d2, i % 3 == 1 ? d1 : E2::difference(w, y));
        const geom::Expansion<16> sums[2][2] = {{geom::add<16>(p1, p2), sum_by_growing<16>(p1, p2)},
                                                {geom::subtract<16>(p1, p2), sum_by_growing<16>(p1, negated(p2))}};
        for (const auto &pair : sums) {
            const geom::Expansion<16> &s = pair[0];
            assert_int_equal(sum_by_growing<32>(s, negated(pair[1])).sign(), 0);
            for (int k = 0; k < s.n; ++k) {
                assert_true(s.c[k] != 0);
                if (k + 1 < s.n) assert_true(std::fabs(s.c[k]) < lowest_bit(s.c[k + 1]));
            }
        }
    }
}

// orient3d_exact's fast path (differences that are doubles) against the
// general expansion path, and against integer arithmetic: nearby points
// on a plane up to rounding, exactly coplanar ones (zeros), corners of
// longitude-latitude cells (cocircular up to rounding), and integers below
// 2^20 scaled by a power of two, whose determinant __int128 holds exactly.
void exact_fast_path_agrees(void **) {
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int64_t> small(-(1 << 20), 1 << 20);
    int fast = 0, zeros = 0;
    auto check = [&](const double p[4][3]) {
        const int s = geom::orient3d_exact(p[0], p[1], p[2], p[3]);
        assert_int_equal(s, geom::orient3d_exact_general(p[0], p[1], p[2], p[3]));
        bool exact = true;
        for (int r = 1; r < 4; ++r)
            for (int k = 0; k < 3; ++k) {
                double hi, lo;
                geom::two_sum(p[r][k], -p[0][k], hi, lo);
                exact &= lo == 0;
            }
        fast += exact, zeros += s == 0;
    };
    for (int i = 0; i < 100000; ++i) {
        double p[4][3];
        const double cx = u(rng), cy = u(rng), nx = u(rng) / 3, ny = u(rng) / 3, off = u(rng) / 3;
        for (auto &q : p) {
            q[0] = cx + 1e-3 * u(rng), q[1] = cy + 1e-3 * u(rng);
            q[2] = off + nx * q[0] + ny * q[1];
        }
        check(p);
        // A longitude-latitude cell's corners on the unit sphere.
        const double lat0 = 80 * u(rng), lon0 = 180 * u(rng), step = 0.25;
        for (int k = 0; k < 4; ++k) {
            const double lat = (lat0 + step * (k / 2)) * M_PI / 180, lon = (lon0 + step * (k % 2)) * M_PI / 180;
            p[k][0] = std::cos(lat) * std::cos(lon), p[k][1] = std::cos(lat) * std::sin(lon), p[k][2] = std::sin(lat);
        }
        check(p);
        // Integers (exactly coplanar every other time), scaled by 2^-20.
        int64_t m[4][3];
        for (auto &row : m)
            for (int64_t &x : row) x = small(rng);
        if (i % 2)
            for (int k = 0; k < 3; ++k) m[3][k] = m[1][k] + m[2][k] - m[0][k];  // a parallelogram
        __int128 d[3][3];
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) d[r][k] = m[r + 1][k] - m[0][k];
        const __int128 det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                             d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                             d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 3; ++k) p[r][k] = std::ldexp(double(m[r][k]), -20);
        check(p);
        assert_int_equal(geom::orient3d_exact(p[0], p[1], p[2], p[3]), (det > 0) - (det < 0));
    }
    assert_true(fast > 200000 && zeros > 40000);  // both paths and many zeros were met
}

// Calls check(draw, largest, bound) 100000 times for each largest coordinate
// magnitude, 1 (unit vectors) and 3 (lifted points of weights up to 4/3),
// with bound = bound_of(largest); draw() is uniform in [-1, 1].
template <class BoundFn, class CheckFn>
void for_static_bounds(uint64_t seed, BoundFn bound_of, CheckFn check) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    auto draw = [&] { return u(rng); };
    for (double largest : {1.0, 3.0})
        for (int i = 0; i < 100000; ++i) check(draw, largest, bound_of(largest));
}

// The static filter's determinant (SSE2 where the compiler has it) equals
// orient3d's expression evaluated as written, but for the sign of a zero:
// on random points, and on points sharing coordinates (where a difference
// is an exact zero). Where the compiler may fuse multiplications and
// additions (FMA) the two may round differently, which the filter's bound
// allows (static_filter_agrees_with_exact), so there it is not asked.
void static_determinant_is_the_scalar_expression(void **) {
#if defined(__FMA__)
    skip();
#endif
    auto scalar = [](const double *a, const double *b, const double *c, const double *d) {
        const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
        const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
        const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
        return ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
    };
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> pick(0, 11);
    for (int i = 0; i < 200000; ++i) {
        double p[4][3];
        for (auto &q : p)
            for (double &x : q) x = u(rng) * (i % 3 == 0 ? 1e-3 : 1.0);
        if (i % 2) p[pick(rng) / 3][pick(rng) % 3] = p[pick(rng) / 3][pick(rng) % 3];  // a shared coordinate
        const double det = geom::detail::orient3d_det(p[0], p[1], p[2], p[3]);
        const double expected = scalar(p[0], p[1], p[2], p[3]);
        assert_true(det == expected);  // (+0 == -0)
    }
}

// orient3d_static agrees with the exact sign on nearly coplanar points, on
// points off such planes by 1e-16 .. 1e-2 (mostly decided by the bound), and
// on four points of a small circle of the unit sphere, nudged by a few units
// in the last place.
void static_filter_agrees_with_exact(void **) {
    auto agrees = [](const double p[4][3], double bound) {
        assert_int_equal(geom::orient3d_static(p[0], p[1], p[2], p[3], bound),
                         geom::orient3d_exact(p[0], p[1], p[2], p[3]));
    };
    for_static_bounds(2, geom::orient3d_static_bound, [&](auto &draw, double largest, double bound) {
        double p[4][3];
        const double nx = draw() / 3, ny = draw() / 3, off = draw() / 3;
        for (auto &q : p) {
            q[0] = largest * draw(), q[1] = largest * draw();
            q[2] = largest * off + nx * q[0] + ny * q[1];
        }
        agrees(p, bound);
        p[3][2] += largest * std::pow(10.0, -16 + 7 * (draw() + 1)) * (draw() > 0 ? 1 : -1);
        agrees(p, bound);
    });
    for_static_bounds(4, geom::orient3d_static_bound, [&](auto &draw, double largest, double bound) {
        if (largest != 1.0) return;
        const double z = draw(), r = std::sqrt(1 - z * z), t0 = 3 * draw();
        double p[4][3];
        for (int k = 0; k < 4; ++k) {
            const double t = t0 + 1e-3 * k * (1 + draw());
            p[k][0] = r * std::cos(t) * (1 + 4e-16 * draw()), p[k][1] = r * std::sin(t), p[k][2] = z;
        }
        agrees(p, bound);
    });
}

// orient_origin_static agrees with the exact sign for points on and near
// the great circle of two others.
void static_origin_filter_agrees_with_exact(void **) {
    for_static_bounds(3, geom::orient_origin_static_bound, [](auto &draw, double largest, double bound) {
        const geom::Vec3 a = largest * geom::normalized({draw(), draw(), draw()});
        const geom::Vec3 b = geom::normalized({draw(), draw(), draw()});
        const double off = std::pow(10.0, -17 + 7.5 * (draw() + 1)) * draw();
        const geom::Vec3 c = ((draw() + 1) / 2 * largest) *
                             geom::normalized(draw() * a + draw() * b + off * geom::cross(a, b));
        assert_int_equal(geom::orient_origin_static(a.data(), b.data(), c.data(), bound),
                         geom::orient_origin_exact(a.data(), b.data(), c.data()));
    });
}

void orient_origin_is_exact(void **) {
    const double a[3] = {1, 0, 0}, b[3] = {0, 1, 0};
    double c[3] = {0.5, 0.5, 0};
    assert_int_equal(geom::orient_origin(a, b, c), 0);
    c[2] = 1e-300;
    assert_int_equal(geom::orient_origin(a, b, c), 1);
    c[2] = -1e-300;
    assert_int_equal(geom::orient_origin(a, b, c), -1);
}

// The tie rule: never 0, antisymmetric under a swap of the facet's vertices,
// and a point is beyond a facet exactly when the facet is not beyond it in
// the reversed test (consistency of the perturbation).
void perturbed_orientation_breaks_ties_consistently(void **) {
    auto pts = test::latitude_circles({30}, 8);  // 8 cocircular points + poles
    const double *p[6];
    for (int i = 0; i < 6; ++i) p[i] = pts[2 + i].data();
    for (int i = 0; i < 4; ++i) {
        int s = geom::orient3d_perturbed(p[0], p[1], p[2], p[3], 0, 1, 2, 3);
        assert_true(s == 1 || s == -1);
        int swapped = geom::orient3d_perturbed(p[1], p[0], p[2], p[3], 1, 0, 2, 3);
        assert_int_equal(swapped, -s);
        int rotated = geom::orient3d_perturbed(p[1], p[2], p[0], p[3], 1, 2, 0, 3);
        assert_int_equal(rotated, s);
    }
    // Exactly coplanar integer points: the highest-priority point decides.
    const double a[3] = {0, 0, 1}, b[3] = {1, 0, 1}, c[3] = {0, 1, 1}, d[3] = {1, 1, 1};
    int s1 = geom::orient3d_perturbed(a, b, c, d, 1, 2, 3, 0);  // d first: pushed out => beyond
    assert_int_equal(s1, 1);
    int s2 = geom::orient3d_perturbed(a, b, c, d, 0, 1, 2, 3);
    assert_true(s2 == 1 || s2 == -1);
}

void arc_length_and_areas(void **) {
    Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    assert_true(std::fabs(geom::arc_length(x, y) - M_PI / 2) < 1e-15);
    assert_true(std::fabs(geom::arc_length(x, -1.0 * x) - M_PI) < 1e-15);
    Vec3 near = geom::normalized({1, 1e-12, 0});
    assert_true(std::fabs(geom::arc_length(x, near) - 1e-12) < 1e-24);
    assert_true(std::fabs(geom::signed_triangle_area(x, y, z) - M_PI / 2) < 1e-15);
    assert_true(std::fabs(geom::signed_triangle_area(x, z, y) + M_PI / 2) < 1e-15);
}

void lonlat_round_trip_and_poles(void **) {
    Vec3 n1 = geom::unit_from_lonlat_deg(10, 90), n2 = geom::unit_from_lonlat_deg(-170, 90);
    assert_true(n1.x == n2.x && n1.y == n2.y && n1.z == n2.z);
    double lon, lat;
    geom::lonlat_deg_from_unit(geom::unit_from_lonlat_deg(-179.5, -45.25), lon, lat);
    assert_true(std::fabs(lon + 179.5) < 1e-12 && std::fabs(lat + 45.25) < 1e-12);
    geom::lonlat_deg_from_unit(geom::unit_from_lonlat_deg(180, 0), lon, lat);
    assert_true(std::fabs(lon - 180) < 1e-12);
}

// sincos_deg against long double (64-bit significand) sin and cos of the
// angle reduced exactly: within 2 units of 2^-53 (1.69 the worst found over
// 10^9 angles, about 1.75 by a rough analysis; glibc's sin(deg * pi / 180)
// is up to 5 off within +-360, 10 within +-720), exact at the multiples of
// 90, odd and even (==, so up to the sign of a zero), any finite angle.
void sincos_in_degrees(void **) {
    const long double kRadiansPerDegree = 3.14159265358979323846264338327950288L / 180.0L;
    auto check = [&](double deg) {
        double s, c;
        geom::sincos_deg(deg, s, c);
        const long double x = std::fmod(static_cast<long double>(deg), 360.0L) * kRadiansPerDegree;
        const long double bound = 2.0L * 0x1p-53L;
        if (std::fabs(s - std::sin(x)) > bound || std::fabs(c - std::cos(x)) > bound)
            fail_msg("sincos_deg(%.17g) = %.17g, %.17g", deg, s, c);
        double s_neg, c_neg;
        geom::sincos_deg(-deg, s_neg, c_neg);
        assert_true(s_neg == -s && c_neg == c);
    };
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> turn(-720.0, 720.0), tiny(-1e-9, 1e-9);
    for (int i = 0; i < 200000; ++i) check(turn(rng));
    for (int k = -16; k <= 16; ++k)  // next to the ends of the reduced range
        for (double d : {tiny(rng), tiny(rng), 1e-300}) check(45.0 * k + d);
    for (double deg : {1e10, -3.3e12, 1e20, 7e300}) check(deg);
    for (int k = -12; k <= 12; ++k) {
        double s, c;
        geom::sincos_deg(90.0 * k, s, c);
        const int m = ((k % 4) + 4) % 4;
        assert_true(s == (m == 1 ? 1.0 : m == 3 ? -1.0 : 0.0));
        assert_true(c == (m == 0 ? 1.0 : m == 2 ? -1.0 : 0.0));
    }
    // Axes from lon/lat multiples of 90 are exact.
    const Vec3 e = geom::unit_from_lonlat_deg(-270, 0), w = geom::unit_from_lonlat_deg(180, 0);
    assert_true(e.x == 0 && e.y == 1 && e.z == 0 && w.x == -1 && w.y == 0 && w.z == 0);
}

void arc_intersections(void **) {
    Vec3 c;
    auto ll = geom::unit_from_lonlat_deg;
    // Crossing at the origin of lon/lat.
    assert_true(geom::arc_intersection(ll(-1, 0), ll(1, 0), ll(0, -1), ll(0, 1), c));
    assert_true(std::fabs(c.x - 1) < 1e-15);
    // Disjoint arcs.
    assert_false(geom::arc_intersection(ll(-1, 0), ll(1, 0), ll(5, -1), ll(5, 1), c));
    // Antipodal crossing point is not on either arc.
    assert_false(geom::arc_intersection(ll(179, 0), ll(178, 0), ll(0, -1), ll(0, 1), c));
    // Across the dateline: the short arc from 179.5 to -179.5 crosses the meridian 180.
    assert_true(geom::arc_intersection(ll(179.5, 0.5), ll(-179.5, -0.5), ll(180, -1), ll(180, 1), c));
    double lon, lat;
    geom::lonlat_deg_from_unit(c, lon, lat);
    assert_true(std::fabs(std::fabs(lon) - 180) < 1e-9 && std::fabs(lat) < 1e-9);
    // Touching at an end point (T junction) counts within the tolerance.
    assert_true(geom::arc_intersection(ll(-1, 0), ll(1, 0), ll(0, 0), ll(0, 1), c));
    // Overlapping collinear arcs.
    assert_true(geom::arc_intersection(ll(0, 0), ll(2, 0), ll(1, 0), ll(3, 0), c));
}

// Consecutive cells along the Hilbert curve of one cube face are neighbours.
void hilbert_order_is_continuous(void **) {
    const int n = 64;  // sample a 64 x 64 grid of face (+x) cell centres
    std::vector<std::pair<uint64_t, std::pair<int, int>>> cells;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double u = -1 + (2.0 * i + 1) / n, v = -1 + (2.0 * j + 1) / n;
            cells.push_back({tri::hilbert_key({1, u, v}), {i, j}});
        }
    std::sort(cells.begin(), cells.end());
    for (size_t k = 1; k < cells.size(); ++k) {
        auto [i0, j0] = cells[k - 1].second;
        auto [i1, j1] = cells[k].second;
        assert_int_equal(std::abs(i1 - i0) + std::abs(j1 - j0), 1);
    }
}

void brio_order_is_a_permutation_and_deterministic(void **) {
    auto pts = test::random_points(100000, 3);
    Context one, two;
    one.set_threads(1);
    two.set_threads(2);
    // The insertion order: the points of the sorted words.
    auto order = [&](Context &ctx) {
        const auto words = tri::brio_words(ctx, 100000, [&](int64_t i) { return pts[i]; });
        std::vector<int32_t> out;
        for (uint64_t w : words) out.push_back(tri::brio_point(w));
        return out;
    };
    const std::vector<int32_t> a = order(one), b = order(two);
    assert_true(a == b);
    std::vector<int32_t> sorted = a;
    std::sort(sorted.begin(), sorted.end());
    for (int32_t i = 0; i < 100000; ++i) assert_int_equal(sorted[i], i);
    // The same words in a caller's room of 2n words, and the room only
    // (the words past it keep their values).
    std::vector<uint64_t> room(200000 + 64, 0x5eed5eed5eed5eedull);
    const auto words = tri::brio_words(two, 100000, [&](int64_t i) { return pts[i]; }, room.data());
    assert_true(words.data() == room.data() || words.data() == room.data() + 100000);
    for (int32_t i = 0; i < 100000; ++i) assert_int_equal(tri::brio_point(words[i]), a[i]);
    for (size_t i = 200000; i < room.size(); ++i) assert_true(room[i] == 0x5eed5eed5eed5eedull);
}

// The radix sort with its buffer given: sorted and stable for an odd number
// of passes too, when the result ends in that buffer.
void radix_sort_with_a_given_buffer(void **) {
    std::mt19937_64 rng(11);
    std::vector<uint64_t> input(50000);
    for (size_t i = 0; i < input.size(); ++i) input[i] = (rng() & ~uint64_t(0xfffff)) | i;  // index below
    for (int high_bit : {29, 38, 47}) {  // 1, 2 and 3 passes of at most 9 bits above bit 20
        Context ctx;
        ctx.set_threads(2);
        std::vector<uint64_t> own(input), scratch(input.size());
        Buffer<uint64_t> keys = Buffer<uint64_t>::over(own.data(), own.size());
        radix_sort(ctx, keys, 20, high_bit, scratch.data());
        assert_true(keys.data() == own.data() || keys.data() == scratch.data());
        std::vector<uint64_t> expected(input);
        const uint64_t mask = ((uint64_t(1) << high_bit) - 1) & ~uint64_t(0xfffff);
        std::stable_sort(expected.begin(), expected.end(),
                         [&](uint64_t x, uint64_t y) { return (x & mask) < (y & mask); });
        for (size_t i = 0; i < expected.size(); ++i) assert_true(keys[i] == expected[i]);
    }
}

// UninitVector::resize leaves plain values unwritten, Vec3 (whose members
// have default initialisers, and which opts in: LeftUnwritten) included: the
// construction sizes its arrays so and writes them in parallel, where their
// pages are first touched. Seen by the pages of a fresh 64 MB buffer that are
// resident after the resize (mincore): a written buffer has them all. (This
// relies on glibc's malloc mapping a fresh 64 MB block, above its largest
// mmap threshold; an allocator preloaded to reuse resident memory would fail
// it.) Other values are constructed, member initialisers kept.
void uninit_vector_leaves_plain_values_unwritten(void **) {
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    auto resident_share = [page](const void *data, size_t bytes) {
        const uintptr_t begin = reinterpret_cast<uintptr_t>(data) / page * page;
        const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) / page * page;
        std::vector<unsigned char> in_core((end - begin) / page);
        assert_int_equal(mincore(reinterpret_cast<void *>(begin), end - begin, in_core.data()), 0);
        size_t resident = 0;
        for (unsigned char c : in_core) resident += c & 1;
        return double(resident) / double(in_core.size());
    };
    const size_t n = (size_t(64) << 20) / sizeof(Vec3);
    UninitVector<Vec3> points;
    points.reserve(n);
    points.resize(n);
    assert_true(resident_share(points.data(), n * sizeof(Vec3)) < 0.25);
    // What std::vector writes (the check's control).
    std::vector<Vec3> written(n);
    assert_true(resident_share(written.data(), n * sizeof(Vec3)) > 0.75);
    UninitVector<std::string> names;
    names.resize(3);
    for (const std::string &name : names) assert_true(name.empty());
    struct Tagged {  // trivially copyable, but its initialiser matters
        int32_t tag = -7;
    };
    UninitVector<Tagged> tagged;
    tagged.resize(5);
    for (const Tagged &t : tagged) assert_int_equal(t.tag, -7);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(orient3d_signs_on_exact_configurations),
        cmocka_unit_test(static_determinant_is_the_scalar_expression),
        cmocka_unit_test(static_filter_agrees_with_exact),
        cmocka_unit_test(static_origin_filter_agrees_with_exact),
        cmocka_unit_test(filter_agrees_with_exact),
        cmocka_unit_test(expansion_sums_are_exact),
        cmocka_unit_test(exact_fast_path_agrees),
        cmocka_unit_test(orient_origin_is_exact),
        cmocka_unit_test(perturbed_orientation_breaks_ties_consistently),
        cmocka_unit_test(arc_length_and_areas),
        cmocka_unit_test(lonlat_round_trip_and_poles),
        cmocka_unit_test(sincos_in_degrees),
        cmocka_unit_test(arc_intersections),
        cmocka_unit_test(hilbert_order_is_continuous),
        cmocka_unit_test(brio_order_is_a_permutation_and_deterministic),
        cmocka_unit_test(radix_sort_with_a_given_buffer),
        cmocka_unit_test(uninit_vector_leaves_plain_values_unwritten),
    };
    return cmocka_run_group_tests_name("geometry", tests, nullptr, nullptr);
}
