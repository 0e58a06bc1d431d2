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

// Exact sign of det[u, v, w] = u . (v x w) for rows of doubles: what
// det3_exact_sign<1> computes, without multiply's loops over one-component
// factors (through them, a 0.25-degree grid took 1.03-1.05x the time:
// bench_ab).
// orient3d_exact takes it when the differences of its points are doubles
// (nearby points: Sterbenz), which a grid - every cell's corners
// cocircular - asks for in about a fifth of its insertions.
int det3_sign_of_doubles(const double u[3], const double v[3], const double w[3]) {
    auto term = [&](int r, int i, int j) {  // u_r (v_i w_j - v_j w_i)
        return scale<8>(subtract<4>(E2::product(v[i], w[j]), E2::product(v[j], w[i])), u[r]);
    };
    return add<24>(add<16>(term(0, 1, 2), term(1, 2, 0)), term(2, 0, 1)).sign();
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
    return exact ? det3_sign_of_doubles(rows[0], rows[1], rows[2]) : orient3d_exact_general(a, b, c, d);
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
