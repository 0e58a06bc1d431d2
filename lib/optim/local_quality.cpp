#include "optim/local_quality.hpp"

#include <cmath>

namespace um::optim {

namespace {

constexpr double kBetaFace = 2.0 / 3.0, kBetaEdge = 1.0 / 3.0;

inline double norm2(Vec3 a) { return geom::dot(a, a); }

// Edge orthocentre of (i, j) before normalisation: alpha x_i + beta x_j,
// with 1 - cos d written as |x_i - x_j|^2 / 2 so equal weights do not cancel.
inline Vec3 edge_orthocentre_raw(const Generator &i, const Generator &j, double chord2) {
    const double one_minus_cos = 0.5 * chord2;
    const double alpha = (j.s - i.s) + i.s * one_minus_cos;
    const double beta = (i.s - j.s) + j.s * one_minus_cos;
    return alpha * i.x + beta * j.x;
}

// The part of Q^P that an edge contributes: 1 - (delta_e / l_e)^2, with the
// squared distance from its orthocentre to its midpoint.
inline double edge_defect(const Generator &i, const Generator &j, double chord2) {
    const Vec3 p = geom::normalized(edge_orthocentre_raw(i, j, chord2));
    const Vec3 mid = geom::normalized(i.x + j.x);
    return norm2(p - mid) / chord2;
}

}  // namespace

double area_length_ratio(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    const Vec3 n = geom::cross(b - a, c - a);
    // Signed area of the chord triangle: its normal against the outward direction.
    const Vec3 outward = a + b + c;
    const double area = 0.5 * geom::dot(n, outward) / geom::norm(outward);
    return 4 * std::sqrt(3.0) * area / (norm2(a - b) + norm2(b - c) + norm2(c - a));
}

double largest_angle_cosine(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    // The largest angle is opposite the longest side (on the sphere too).
    const double lab = norm2(b - a), lbc = norm2(c - b), lca = norm2(a - c);
    auto corner = [](const Vec3 &p, const Vec3 &q, const Vec3 &r) {  // the angle at p
        const Vec3 u = q - geom::dot(p, q) * p, w = r - geom::dot(p, r) * p;  // tangents at p
        return geom::dot(u, w) / std::sqrt(geom::dot(u, u) * geom::dot(w, w));
    };
    if (lab >= lbc && lab >= lca) return corner(c, a, b);
    if (lbc >= lca) return corner(a, b, c);
    return corner(b, c, a);
}

namespace {

// The orthocentre's direction (not normalised) of the triangle.
inline Vec3 orthocentre_raw(const Generator &a, const Generator &b, const Generator &c) {
    return geom::cross(b.lifted() - a.lifted(), c.lifted() - a.lifted());
}

inline bool inside(const Generator &a, const Generator &b, const Generator &c, const Vec3 &ortho) {
    return geom::dot(geom::cross(a.x, b.x), ortho) >= 0 && geom::dot(geom::cross(b.x, c.x), ortho) >= 0 &&
           geom::dot(geom::cross(c.x, a.x), ortho) >= 0;
}

// Q^P from the orthocentre's direction, so that a caller needing both it
// and the inside test computes it once.
double primal_dual_from(const Generator &a, const Generator &b, const Generator &c, const Vec3 &ortho_raw) {
    const double lab = norm2(a.x - b.x), lbc = norm2(b.x - c.x), lca = norm2(c.x - a.x);
    const Vec3 ortho = geom::normalized(ortho_raw);
    const Vec3 centroid = geom::normalized(a.x + b.x + c.x);
    const double l_mean = (std::sqrt(lab) + std::sqrt(lbc) + std::sqrt(lca)) / 3;
    const double face = 1 - norm2(ortho - centroid) / (l_mean * l_mean);
    const double edges = 3 - edge_defect(a, b, lab) - edge_defect(b, c, lbc) - edge_defect(c, a, lca);
    return kBetaFace * face + kBetaEdge * edges / 3;
}

}  // namespace

double primal_dual(const Generator &a, const Generator &b, const Generator &c) {
    return primal_dual_from(a, b, c, orthocentre_raw(a, b, c));
}

double staggering_score(const Generator &a, const Generator &b, const Generator &c, double *primal_dual_out) {
    const Vec3 ortho = orthocentre_raw(a, b, c);
    const double q = primal_dual_from(a, b, c, ortho);
    if (primal_dual_out) *primal_dual_out = q;
    return q - (inside(a, b, c, ortho) ? 0.0 : kOutsidePenalty);
}

TriangleCost triangle_cost(const Generator &a, const Generator &b, const Generator &c) {
    return {area_length_ratio(a.x, b.x, c.x), primal_dual(a, b, c)};
}

double edge_crossing_share(const Generator &i, const Generator &j) {
    const double one_minus_cos = 0.5 * norm2(i.x - j.x);
    const double alpha = (j.s - i.s) + i.s * one_minus_cos;
    const double beta = (i.s - j.s) + j.s * one_minus_cos;
    return beta / (alpha + beta);
}

namespace {

// d/ds_i of |normalize(u) - m|^2 where du/ds_i = du.
inline double d_distance2(Vec3 u, Vec3 du, Vec3 m) {
    const double len = geom::norm(u);
    const Vec3 p = (1.0 / len) * u;
    // d p = (du - p (p . du)) / |u|
    const Vec3 dp = (1.0 / len) * (du - geom::dot(p, du) * p);
    return 2 * geom::dot(p - m, dp);
}

// d/ds_i of the edge defect of (i, j) (delta_e^2 / l_e^2; l_e does not
// depend on the weights).
inline double d_edge_defect(const Generator &i, const Generator &j) {
    const double chord2 = norm2(i.x - j.x);
    const Vec3 u = edge_orthocentre_raw(i, j, chord2);
    // alpha = s_j - s_i cos d, beta = s_i - s_j cos d: d alpha = -cos d, d beta = 1.
    const double cos_d = 1 - 0.5 * chord2;
    const Vec3 du = (-cos_d) * i.x + j.x;
    return d_distance2(u, du, geom::normalized(i.x + j.x)) / chord2;
}

}  // namespace

double primal_dual_weight_derivative(const Generator &a, const Generator &b, const Generator &c,
                                     double *primal_dual_out) {
    if (primal_dual_out) *primal_dual_out = primal_dual(a, b, c);
    const Vec3 qa = a.lifted(), qb = b.lifted(), qc = c.lifted();
    // n = (q_b - q_a) x (q_c - q_a) = q_a x q_b + q_b x q_c + q_c x q_a,
    // so dn/ds_a = x_a x (q_b - q_c).
    const Vec3 n = geom::cross(qb - qa, qc - qa);
    const Vec3 dn = geom::cross(a.x, qb - qc);
    const Vec3 centroid = geom::normalized(a.x + b.x + c.x);
    const double l_mean =
        (geom::norm(a.x - b.x) + geom::norm(b.x - c.x) + geom::norm(c.x - a.x)) / 3;
    const double d_face = -d_distance2(n, dn, centroid) / (l_mean * l_mean);
    // Only the two edges at a move with s_a.
    const double d_edges = -d_edge_defect(a, b) - d_edge_defect(a, c);
    const double dq_ds = kBetaFace * d_face + kBetaEdge * d_edges / 3;
    // s = 1 / (1 - w/2): ds/dw = s^2 / 2.
    return dq_ds * 0.5 * a.s * a.s;
}

}  // namespace um::optim
