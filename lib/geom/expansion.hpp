// Floating-point expansions: a real number held exactly as a sum of
// non-overlapping doubles, with error-free transformations (Knuth's two-sum,
// FMA-based two-product). Used only by the exact fallback of the predicates,
// which degenerate input (grids: cocircular cells) calls often; fixed-capacity
// storage avoids the heap.
#pragma once

#include <cassert>
#include <cmath>

namespace um::geom {

// x = a + b exactly as hi + lo.
inline void two_sum(double a, double b, double &hi, double &lo) {
    hi = a + b;
    double bv = hi - a;
    double av = hi - bv;
    lo = (a - av) + (b - bv);
}

// x = a * b exactly as hi + lo (needs a correctly rounded fma).
inline void two_product(double a, double b, double &hi, double &lo) {
    hi = a * b;
    lo = std::fma(a, b, -hi);
}

template <int Capacity>
struct Expansion {
    double c[Capacity];  // increasing magnitude, no zeros; c[n..] unwritten
    int n = 0;

    Expansion() = default;
    // Copies the n components only: the capacities run to 192 doubles while
    // the exact predicates' expansions mostly hold a few, and copying whole
    // arrays was most of the cost of an exact sign.
    Expansion(const Expansion &other) : n(other.n) {
        for (int i = 0; i < n; ++i) c[i] = other.c[i];
    }
    Expansion &operator=(const Expansion &other) {
        n = other.n;
        for (int i = 0; i < n; ++i) c[i] = other.c[i];
        return *this;
    }

    static Expansion of(double v) {
        Expansion e;
        if (v != 0) e.c[e.n++] = v;
        return e;
    }
    // a - b exactly.
    static Expansion difference(double a, double b) {
        Expansion e;
        double hi, lo;
        two_sum(a, -b, hi, lo);
        if (lo != 0) e.c[e.n++] = lo;
        if (hi != 0) e.c[e.n++] = hi;
        return e;
    }
    // a b exactly.
    static Expansion product(double a, double b) {
        Expansion e;
        double hi, lo;
        two_product(a, b, hi, lo);
        if (lo != 0) e.c[e.n++] = lo;
        if (hi != 0) e.c[e.n++] = hi;
        return e;
    }
    int sign() const { return n == 0 ? 0 : (c[n - 1] > 0 ? 1 : -1); }
};

namespace detail {
// a + sign b for sign 1 or -1 (negation is exact): Shewchuk's
// fast-expansion-sum with zero elimination - the components of both merged
// by magnitude, then summed in one pass of two-sums, O(a.n + b.n). It needs
// strongly nonoverlapping inputs and round-to-nearest-even (Shewchuk 1997,
// Theorem 13); every expansion here is (two-sum and two-product pairs are
// nonadjacent, and this sum and scale keep the property), and IEEE
// arithmetic rounds to even.
template <int C, int A, int B>
Expansion<C> signed_sum(const Expansion<A> &a, const Expansion<B> &b, double sign) {
    assert(a.n + b.n <= C);
    Expansion<C> out;
    int i = 0, j = 0;
    // The next component, the one of smaller magnitude first.
    auto next = [&]() -> double {
        if (j < b.n) {
            const double bj = sign * b.c[j];
            if (i == a.n || (bj > a.c[i]) != (bj > -a.c[i])) return ++j, bj;
        }
        return a.c[i++];
    };
    if (a.n + b.n == 0) return out;
    double q = next();
    while (i < a.n || j < b.n) {
        double hi, lo;
        two_sum(q, next(), hi, lo);
        if (lo != 0) out.c[out.n++] = lo;
        q = hi;
    }
    if (q != 0) out.c[out.n++] = q;
    return out;
}
}  // namespace detail

// a + b exactly; at most a.n + b.n components: callers size C for that.
template <int C, int A, int B>
Expansion<C> add(const Expansion<A> &a, const Expansion<B> &b) {
    return detail::signed_sum<C>(a, b, 1.0);
}

// a - b exactly, the same way.
template <int C, int A, int B>
Expansion<C> subtract(const Expansion<A> &a, const Expansion<B> &b) {
    return detail::signed_sum<C>(a, b, -1.0);
}

// An expansion times a double, exactly (scale-expansion, zero-eliminating).
template <int C, int A>
Expansion<C> scale(const Expansion<A> &a, double s) {
    static_assert(C >= 2 * A, "expansion capacity");
    Expansion<C> out;
    if (a.n == 0 || s == 0) return out;
    double q, lo;
    two_product(a.c[0], s, q, lo);
    if (lo != 0) out.c[out.n++] = lo;
    for (int i = 1; i < a.n; ++i) {
        double p_hi, p_lo, s_hi, s_lo;
        two_product(a.c[i], s, p_hi, p_lo);
        two_sum(q, p_lo, s_hi, s_lo);
        if (s_lo != 0) out.c[out.n++] = s_lo;
        double t_hi, t_lo;
        two_sum(p_hi, s_hi, t_hi, t_lo);  // p_hi and s_hi may overlap: full two-sum
        if (t_lo != 0) out.c[out.n++] = t_lo;
        q = t_hi;
    }
    if (q != 0) out.c[out.n++] = q;
    return out;
}

// Product of two expansions: sum of a scaled by each component of b.
template <int C, int A, int B>
Expansion<C> multiply(const Expansion<A> &a, const Expansion<B> &b) {
    static_assert(C >= 2 * A * B, "expansion capacity");
    Expansion<C> out;
    // After j terms out has at most 2 * A * j components, within C.
    for (int j = 0; j < b.n; ++j) out = add<C>(out, scale<2 * A>(a, b.c[j]));
    return out;
}

}  // namespace um::geom
