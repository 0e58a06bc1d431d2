// Exact geometric predicates: the only code that decides combinatorics.
//
// Every predicate first evaluates in double precision with a forward error
// bound (a "filter"); only when the result is within the bound does it
// recompute exactly with floating-point expansions (error-free sums and
// products), so the sign returned is always the sign of the exact value for
// the stored doubles.
//
// Tie rule (symbolic perturbation). Lifted points are perturbed radially,
// q_i -> q_i (1 + eps_i), with eps_i infinitesimal and eps_i >> eps_j when
// id_i < id_j (smaller id = larger perturbation). When the exact determinant
// is zero, the sign is that of the first non-zero first-order term, taken in
// id order. Four coplanar lifted points on a plane that misses the origin
// always have a non-zero first-order term (three distinct points on a sphere
// are never collinear), which is every case a triangulated sphere around the
// origin meets; should all terms vanish the predicate returns -1 ("not
// beyond"), a fixed, documented choice.
#pragma once

#include <cstdint>

#include <cfloat>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace um::geom {

// Exact signs for the rare inputs the filters cannot decide (predicates.cpp).
int orient3d_exact(const double *a, const double *b, const double *c, const double *d);
// orient3d_exact without its fast path for exact differences (the tests'
// reference for it).
int orient3d_exact_general(const double *a, const double *b, const double *c, const double *d);
int orient_origin_exact(const double *a, const double *b, const double *c);
int orient3d_tie_break(const double *a, const double *b, const double *c, const double *d,
                       int64_t id_a, int64_t id_b, int64_t id_c, int64_t id_d);

namespace detail {
constexpr double kUnitRoundoff = DBL_EPSILON / 2;  // u = 2^-53
// Forward error bounds relative to the "permanent" (the same expression with
// every term replaced by its absolute value); a little looser than the
// tightest known ones (Shewchuk: (7 + 56u)u for orient3d).
constexpr double kOrient3dBound = 8 * kUnitRoundoff;
constexpr double kOrientOriginBound = 6 * kUnitRoundoff;

// orient3d_static's determinant, rounded as orient3d's expression is: the
// same products and sums in the same order, with the x and y coordinates
// side by side in one SSE2 register (fewer instructions in the cavity
// search's test; the walk's orient_origin gained nothing so). Products
// commute, x - y == -(y - x) and x + (-y) == x - y, so the value is the
// same but for the sign of a zero (x - y for x == y); where a compiler fuses
// multiplications and additions (FMA contraction) the two may differ in the
// last bits. Neither matters: the static filter's bound holds for either
// rounding, and what it cannot decide, orient3d decides exactly.
#if defined(__SSE2__)
inline double swapped_difference(__m128d t) {  // t[0] - t[1]
    return _mm_cvtsd_f64(t) - _mm_cvtsd_f64(_mm_unpackhi_pd(t, t));
}
// det[b - a, c - a, d - a] = ux (vy wz - vz wy) + uy (vz wx - vx wz) + uz (vx wy - vy wx).
inline double orient3d_det(const double *a, const double *b, const double *c, const double *d) {
    const __m128d a_xy = _mm_loadu_pd(a);
    const __m128d u = _mm_sub_pd(_mm_loadu_pd(b), a_xy), v = _mm_sub_pd(_mm_loadu_pd(c), a_xy),
                  w = _mm_sub_pd(_mm_loadu_pd(d), a_xy);
    const double uz = b[2] - a[2], vz = c[2] - a[2], wz = d[2] - a[2];
    const __m128d v_yx = _mm_shuffle_pd(v, v, 1), w_yx = _mm_shuffle_pd(w, w, 1);
    // (vy wz - vz wy, vx wz - vz wx): the first two minors, the second negated.
    const __m128d minors = _mm_sub_pd(_mm_mul_pd(v_yx, _mm_set1_pd(wz)), _mm_mul_pd(_mm_set1_pd(vz), w_yx));
    return swapped_difference(_mm_mul_pd(u, minors)) + uz * swapped_difference(_mm_mul_pd(v, w_yx));
}
#else
inline double orient3d_det(const double *a, const double *b, const double *c, const double *d) {
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    return ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
}
#endif
}  // namespace detail

// Sign of det[b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a):
// +1 when d lies beyond the plane of (a, b, c) on the side its normal
// (b - a) x (c - a) points to, -1 on the other side, 0 when coplanar.
inline int orient3d(const double *a, const double *b, const double *c, const double *d) {
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    const double m0 = vy * wz, m1 = vz * wy;
    const double m2 = vz * wx, m3 = vx * wz;
    const double m4 = vx * wy, m5 = vy * wx;
    const double det = ux * (m0 - m1) + uy * (m2 - m3) + uz * (m4 - m5);
    const double permanent = std::fabs(ux) * (std::fabs(m0) + std::fabs(m1)) +
                             std::fabs(uy) * (std::fabs(m2) + std::fabs(m3)) +
                             std::fabs(uz) * (std::fabs(m4) + std::fabs(m5));
    const double bound = detail::kOrient3dBound * permanent;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient3d_exact(a, b, c, d);
}

// orient3d with a static filter first: `bound` must bound the rounding error
// of the determinant for every input it is used with; orient3d_static_bound()
// gives one for points with coordinates of at most `largest` in magnitude.
// Decided by that one comparison in most calls, else by orient3d.
inline int orient3d_static(const double *a, const double *b, const double *c, const double *d,
                           double bound) {
    const double det = detail::orient3d_det(a, b, c, d);
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient3d(a, b, c, d);
}

// The error bound of orient3d for coordinates of magnitude <= largest: the
// differences are at most 2 largest (1 + u), and each of the permanent's six
// products has one x, one y and one z of them, so the permanent is at most
// 6 (2 largest)^3 (1 + u)^3; the factor 1.001 covers that (1 + u)^3 and the
// rounding of this product itself.
inline double orient3d_static_bound(double largest) {
    return detail::kOrient3dBound * 48.0 * largest * largest * largest * 1.001;
}

// orient3d with the symbolic-perturbation tie rule above: never 0. The ids
// are read only on an exact tie.
template <class IdFn>
inline int orient3d_perturbed(const double *a, const double *b, const double *c,
                              const double *d, IdFn ids) {
    int s = orient3d(a, b, c, d);
    if (s != 0) return s;
    int64_t i[4];
    ids(i);
    return orient3d_tie_break(a, b, c, d, i[0], i[1], i[2], i[3]);
}

inline int orient3d_perturbed(const double *a, const double *b, const double *c,
                              const double *d, int64_t id_a, int64_t id_b, int64_t id_c,
                              int64_t id_d) {
    int s = orient3d(a, b, c, d);
    return s != 0 ? s : orient3d_tie_break(a, b, c, d, id_a, id_b, id_c, id_d);
}

// Sign of det[a, b, c] = (a x b) . c: +1 when c is to the left of the great
// circle through a then b (seen from outside the sphere), 0 on it.
inline int orient_origin(const double *a, const double *b, const double *c) {
    const double m0 = a[1] * b[2], m1 = a[2] * b[1];
    const double m2 = a[2] * b[0], m3 = a[0] * b[2];
    const double m4 = a[0] * b[1], m5 = a[1] * b[0];
    const double det = c[0] * (m0 - m1) + c[1] * (m2 - m3) + c[2] * (m4 - m5);
    const double permanent = std::fabs(c[0]) * (std::fabs(m0) + std::fabs(m1)) +
                             std::fabs(c[1]) * (std::fabs(m2) + std::fabs(m3)) +
                             std::fabs(c[2]) * (std::fabs(m4) + std::fabs(m5));
    const double bound = detail::kOrientOriginBound * permanent;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient_origin_exact(a, b, c);
}

// The static filter of orient_origin alone: the sign of det[a, b, c] when
// the bound decides it, 0 when it cannot (the exact sign may be any).
inline int orient_origin_static_filter(const double *a, const double *b, const double *c, double bound) {
    const double det = c[0] * (a[1] * b[2] - a[2] * b[1]) + c[1] * (a[2] * b[0] - a[0] * b[2]) +
                       c[2] * (a[0] * b[1] - a[1] * b[0]);
    return det > bound ? 1 : (det < -bound ? -1 : 0);
}

// orient_origin with a static filter first, as orient3d_static; the bound
// from orient_origin_static_bound(largest coordinate magnitude).
inline int orient_origin_static(const double *a, const double *b, const double *c, double bound) {
    const int s = orient_origin_static_filter(a, b, c, bound);
    return s != 0 ? s : orient_origin(a, b, c);
}

// Its permanent has six products of one x, one y and one z coordinate:
// at most 6 largest^3; 1.001 covers the rounding of this product.
inline double orient_origin_static_bound(double largest) {
    return detail::kOrientOriginBound * 6.0 * largest * largest * largest * 1.001;
}

}  // namespace um::geom
