// The costs the optimisation decides with (paper section 6.1, DESIGN.md
// section 5), evaluated on one triangle from its three lifted points. They
// are the reported metrics (quality/metrics.hpp) with chords for arcs and
// the planar chord triangle for the spherical one: the two agree to O(h^2)
// relative (1e-5 at 30 km), and chords need no atan2 in the hot loop.
#pragma once

#include <cmath>

#include "geom/sphere.hpp"

namespace um::optim {

using geom::Vec3;

// A generator as the sweeps hold it: unit direction x and lifted length s
// (q = s x, s = 1 / (1 - w/2)), so that neither is recomputed per visit.
struct Generator {
    Vec3 x;
    double s = 1;
    Vec3 lifted() const { return s * x; }
};

struct TriangleCost {
    double area_length;  // Q^T: 4 sqrt(3) A / (l1^2 + l2^2 + l3^2)
    double primal_dual;  // Q^P, eq. 1
};

// Q^T and Q^P of the triangle (a, b, c), counter-clockwise seen from outside.
// Q^T is negative when the triangle is inverted.
TriangleCost triangle_cost(const Generator &a, const Generator &b, const Generator &c);
// Each of the two alone (what a vertex move and a weight update look at).
double area_length_ratio(const Vec3 &a, const Vec3 &b, const Vec3 &c);
double primal_dual(const Generator &a, const Generator &b, const Generator &c);
// The cosine of the spherical triangle's largest angle (between the great
// arcs, as the quality report measures it: obtuse when negative).
double largest_angle_cosine(const Vec3 &a, const Vec3 &b, const Vec3 &c);

// The score a vertex move improves: Q^T, capped by kObtuseOffset + cos of
// the largest angle, so that a triangle near or past a right angle scores
// by its angle (Q^T barely tells 85 from 95 degrees; MPAS needs acute
// triangles), while for acute ones it is Q^T alone.
constexpr double kObtuseOffset = 0.8;
// Inline: the line searches call it for every triangle of every trial.
inline double shape_score(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    const Vec3 ab = b - a, bc = c - b, ca = a - c;
    const double lab = geom::dot(ab, ab), lbc = geom::dot(bc, bc), lca = geom::dot(ca, ca);
    // The chord triangle's area signed against a (unit): off by O(l^2)
    // relative, far below what separates two trial positions.
    const double area = 0.5 * geom::dot(geom::cross(ab, c - a), a);
    const double q = 4 * std::sqrt(3.0) * area / (lab + lbc + lca);
    // The largest angle is opposite the longest edge: cos = d / sqrt(p).
    double d, p;
    if (lab >= lbc && lab >= lca) d = -geom::dot(bc, ca), p = lbc * lca;
    else if (lbc >= lca) d = -geom::dot(ca, ab), p = lca * lab;
    else d = -geom::dot(ab, bc), p = lab * lbc;
    // The cap binds only when kObtuseOffset + d / sqrt(p) < q; tell without
    // the square root first (most triangles are well clear of it).
    const double t = q - kObtuseOffset;
    const bool binds = t > 0 ? (d < 0 || d * d < t * t * p) : (d < 0 && d * d > t * t * p);
    return binds ? kObtuseOffset + d / std::sqrt(p) : q;
}

// The score a weight update improves: Q^P, less kOutsidePenalty when the
// triangle does not contain its orthocentre, so that the worst triangle of
// a star is one that is not well-centred whenever there is one (MPAS needs
// them well-centred; Q^P alone can rank such a triangle above a
// well-centred one).
constexpr double kOutsidePenalty = 1.0;
// primal_dual_out (may be null) receives the plain Q^P.
double staggering_score(const Generator &a, const Generator &b, const Generator &c,
                        double *primal_dual_out = nullptr);


// dQ^P / dw_a: the derivative of the triangle's Q^P in the weight of its
// first vertex (analytic; eq. 5's ascent direction), with Q^P itself.
double primal_dual_weight_derivative(const Generator &a, const Generator &b, const Generator &c,
                                     double *primal_dual_out = nullptr);

// Where the dual arc of the primal edge (i, j) crosses it, as the share of
// the way from x_i: the edge orthocentre is p ~ alpha x_i + beta x_j with
// alpha = s_j - s_i cos d, beta = s_i - s_j cos d; this returns
// beta / (alpha + beta), in (0, 1) exactly when the crossing lies between
// the two generators (each generator inside its own power cell, as seen
// from the other: neither can be hidden by the other).
double edge_crossing_share(const Generator &i, const Generator &j);

}  // namespace um::optim
