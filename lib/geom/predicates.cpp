#include "geom/predicates.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "geom/expansion.hpp"

// Error-free transformations (two-sum, two-product), the filters' error
// bounds and sincos_deg's reduction (geom/sphere.cpp) assume IEEE arithmetic
// as written: this stops a build of the library with -ffast-math.
#if defined(__FAST_MATH__)
#error "unimesh needs IEEE arithmetic: build without -ffast-math / -Ofast"
#endif

namespace um::geom {

namespace {
using E2 = Expansion<2>;


// Exact sign of det[u, v, w] for coordinates given as exact expansions.
template <int N>
int det3_exact_sign(const Expansion<N> u[3], const Expansion<N> v[3], const Expansion<N> w[3]) {
    constexpr int P = 2 * N * N;  // product of two N-expansions
    constexpr int M = 2 * P;      // difference of two products
    constexpr int T = 2 * M * N;  // times an N-expansion
    auto minor = [&](int i, int j) {  // v_i w_j - v_j w_i
        return subtract<M>(multiply<P>(v[i], w[j]), multiply<P>(v[j], w[i]));
    };
    auto t0 = multiply<T>(minor(1, 2), u[0]);
    auto t1 = multiply<T>(minor(2, 0), u[1]);
    auto t2 = multiply<T>(minor(0, 1), u[2]);
    return add<3 * T>(add<2 * T>(t0, t1), t2).sign();
}

// The fast path of the exact orient3d, for rows that are doubles (the
// differences of nearby points are exact: Sterbenz). Expansions as raw
// arrays of increasing magnitude without zeros, summed by merging
// (Shewchuk's fast-expansion-sum: linear, where Expansion's sum by growing
// is quadratic), in straight-line code: the general path spent some 5,000
// instructions on a sign, and a longitude-latitude grid asks for one in
// about a fifth of its insertions (every cell's corners are cocircular).
// The merge needs strongly nonoverlapping inputs and round-to-even (1997,
// Theorem 13): two-sum's and two-product's pairs are, and the merge and
// scale keep it.

// h = e + f; returns h's length (at most ne + nf).
int merge_sum(const double *e, int ne, const double *f, int nf, double *h) {
    int i = 0, j = 0, nh = 0;
    // The next component, the one of smaller magnitude first.
    auto next = [&]() -> double {
        if (j < nf && (i == ne || (f[j] > e[i]) != (f[j] > -e[i]))) return f[j++];
        return e[i++];
    };
    if (ne + nf == 0) return 0;
    double q = next();
    while (i < ne || j < nf) {
        double hi, lo;
        two_sum(q, next(), hi, lo);
        if (lo != 0) h[nh++] = lo;
        q = hi;
    }
    if (q != 0) h[nh++] = q;
    return nh;
}

// h = e b, as geom::scale; returns h's length (at most 2 ne).
int scale_into(const double *e, int ne, double b, double *h) {
    int nh = 0;
    if (ne == 0 || b == 0) return 0;
    double q, lo;
    two_product(e[0], b, q, lo);
    if (lo != 0) h[nh++] = lo;
    for (int i = 1; i < ne; ++i) {
        double p_hi, p_lo, s_hi, s_lo, t_hi, t_lo;
        two_product(e[i], b, p_hi, p_lo);
        two_sum(q, p_lo, s_hi, s_lo);
        if (s_lo != 0) h[nh++] = s_lo;
        two_sum(p_hi, s_hi, t_hi, t_lo);
        if (t_lo != 0) h[nh++] = t_lo;
        q = t_hi;
    }
    if (q != 0) h[nh++] = q;
    return nh;
}

// The pair of x y exactly (lo, hi), zeros dropped; returns its length.
int product_pair(double x, double y, double sign, double *h) {
    double hi, lo;
    two_product(sign * x, y, hi, lo);
    int n = 0;
    if (lo != 0) h[n++] = lo;
    if (hi != 0) h[n++] = hi;
    return n;
}

// r (x0 y1 - x1 y0), a term of the determinant, exactly; h holds up to 8.
int minor_term(double r, double x0, double y1, double x1, double y0, double *h) {
    double plus[2], minus[2], minor[4];
    const int np = product_pair(x0, y1, 1.0, plus), nm = product_pair(x1, y0, -1.0, minus);
    return scale_into(minor, merge_sum(plus, np, minus, nm, minor), r, h);
}

// Exact sign of det[u, v, w] = u . (v x w) for rows of doubles.
int det3_sign_of_doubles(const double u[3], const double v[3], const double w[3]) {
    double t0[8], t1[8], t2[8], t01[16], sum[24];
    const int n0 = minor_term(u[0], v[1], w[2], v[2], w[1], t0);
    const int n1 = minor_term(u[1], v[2], w[0], v[0], w[2], t1);
    const int n2 = minor_term(u[2], v[0], w[1], v[1], w[0], t2);
    const int n = merge_sum(t01, merge_sum(t0, n0, t1, n1, t01), t2, n2, sum);
    return n == 0 ? 0 : (sum[n - 1] > 0 ? 1 : -1);
}

}  // namespace

int orient3d_exact(const double *a, const double *b, const double *c, const double *d) {
    double rows[3][3];
    bool exact = true;  // every difference a double
    for (int k = 0; k < 3; ++k) {
        const double *p[3] = {b, c, d};
        for (int r = 0; r < 3; ++r) {
            double lo;
            two_sum(p[r][k], -a[k], rows[r][k], lo);
            exact &= lo == 0;
        }
    }
    if (exact) return det3_sign_of_doubles(rows[0], rows[1], rows[2]);
    return orient3d_exact_general(a, b, c, d);
}

int orient3d_exact_general(const double *a, const double *b, const double *c, const double *d) {
    E2 u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = E2::difference(b[k], a[k]);
        v[k] = E2::difference(c[k], a[k]);
        w[k] = E2::difference(d[k], a[k]);
    }
    // det[u, v, w] = u . (v x w)
    return det3_exact_sign<2>(u, v, w);
}

int orient_origin_exact(const double *a, const double *b, const double *c) {
    Expansion<1> u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = Expansion<1>::of(a[k]);
        v[k] = Expansion<1>::of(b[k]);
        w[k] = Expansion<1>::of(c[k]);
    }
    // det[a, b, c] = a . (b x c) = (a x b) . c
    return det3_exact_sign<1>(u, v, w);
}

namespace {
// First-order coefficient of the perturbed orient3d for the point at row k of
// (a, b, c, d): (-1)^(k+1) * p_k . ((r - q) x (s - q)) with (q, r, s) the
// other rows in order (see the derivation in predicates.hpp's tie rule).
int first_order_sign(const double *const rows[4], int k) {
    const double *others[3];
    for (int i = 0, m = 0; i < 4; ++i)
        if (i != k) others[m++] = rows[i];
    // det[p, r - q, s - q] = p . ((r - q) x (s - q)), exactly.
    E2 p[3], r[3], s[3];
    for (int j = 0; j < 3; ++j) {
        p[j] = E2::of(rows[k][j]);
        r[j] = E2::difference(others[1][j], others[0][j]);
        s[j] = E2::difference(others[2][j], others[0][j]);
    }
    int sign = det3_exact_sign<2>(p, r, s);
    return (k % 2 == 0) ? -sign : sign;
}

}  // namespace

int orient3d_tie_break(const double *a, const double *b, const double *c, const double *d,
                       int64_t id_a, int64_t id_b, int64_t id_c, int64_t id_d) {
    const double *rows[4] = {a, b, c, d};
    int64_t ids[4] = {id_a, id_b, id_c, id_d};
    int order[4] = {0, 1, 2, 3};
    std::sort(order, order + 4, [&](int i, int j) { return ids[i] < ids[j]; });
    for (int k : order) {
        int t = first_order_sign(rows, k);
        if (t != 0) return t;
    }
    return -1;
}

}  // namespace um::geom
