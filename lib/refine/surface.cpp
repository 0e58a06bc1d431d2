#include "refine/surface.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "core/error.hpp"
#include "refine/restricted.hpp"

namespace um::refine {

using geom::Vec3;

namespace {

// A queued bad triangle: its vertices identify it (slots are reused).
struct Candidate {
    int32_t t;
    int32_t v0, v1, v2;
};

bool still_there(const tri::Triangulation &tri, const Candidate &c) {
    return !tri.is_free(c.t) && tri.vertex(c.t, 0) == c.v0 && tri.vertex(c.t, 1) == c.v1 &&
           tri.vertex(c.t, 2) == c.v2;
}

// The point at arc distance d from m towards c along their great circle.
Vec3 towards(const Vec3 &m, const Vec3 &c, double d) {
    Vec3 t = c - geom::dot(c, m) * m;  // tangent at m pointing to c
    double tl = geom::norm(t);
    if (tl == 0) return m;
    t = (1.0 / tl) * t;
    return geom::normalized(std::cos(d) * m + std::sin(d) * t);
}

// Whether any Gamma arc comes within (about) `reach` of p: a surface ball
// holding p has its centre on Gamma within its radius, below ~h, so farther
// candidates need no encroachment search.
bool near_gamma(const geom::ArcTree &gamma, const Vec3 &p, double reach) {
    geom::Box box;
    box.add(p);
    box.grow(reach);
    bool any = false;
    gamma.query(box, [&](int32_t) { any = true; });
    return any;
}


// A restricted edge near p whose surface ball holds p: such an edge has a
// triangle whose circumcircle holds p, so the triangle containing p and its
// neighbours are searched (p's cavity in a well-shaped mesh).
bool encroached_edge(const tri::Triangulation &tri, const Vec3 &p, int32_t hint,
                     const geom::ArcTree &gamma, RestrictedEdge *out) {
    int32_t t0 = tri.locate(p, hint);
    const Vec3 c0 = tri.orthocentre(t0);
    for (int k0 = 0; k0 < 3; ++k0) {
        // Edge k0 of t0, then the two other edges of its neighbour t1.
        const int32_t t1 = tri.neighbour(t0, k0);
        const Vec3 c1 = tri.orthocentre(t1);
        RestrictedEdge e;
        if (restricted_crossing(tri, t0, k0, c0, c1, gamma, &e) && geom::arc_length(p, e.centre) < e.radius)
            return *out = e, true;
        for (int k1 = 0; k1 < 3; ++k1) {
            const int32_t t2 = tri.neighbour(t1, k1);
            if (t2 == t0) continue;
            if (restricted_crossing(tri, t1, k1, c1, tri.orthocentre(t2), gamma, &e) &&
                geom::arc_length(p, e.centre) < e.radius)
                return *out = e, true;
        }
    }
    return false;
}

}  // namespace

// Chords compared, one asin.
double nearest_neighbour(const tri::Triangulation &tri, int32_t v) {
    double d2 = 1e300;
    const Vec3 x = tri.direction(v);
    for (int32_t t : tri.star(v))
        for (int k = 0; k < 3; ++k)
            if (tri.vertex(t, k) != v) {
                Vec3 d = x - tri.direction(tri.vertex(t, k));
                d2 = std::min(d2, geom::dot(d, d));
            }
    return 2 * std::asin(std::min(1.0, 0.5 * std::sqrt(d2)));
}

void triangle_size(const tri::Triangulation &tri, int32_t t, double *radius, double *shortest) {
    // Chords first, one arc conversion each (2 asin(chord / 2)): this runs
    // for every new triangle of the refinement.
    Vec3 a = tri.direction(tri.vertex(t, 0)), b = tri.direction(tri.vertex(t, 1)),
         c = tri.direction(tri.vertex(t, 2));
    double e2 = std::min({geom::dot(a - b, a - b), geom::dot(b - c, b - c), geom::dot(c - a, c - a)});
    Vec3 centre = tri.orthocentre(t);
    double r2 = geom::dot(centre - a, centre - a);
    *radius = 2 * std::asin(std::min(1.0, 0.5 * std::sqrt(r2)));
    *shortest = 2 * std::asin(std::min(1.0, 0.5 * std::sqrt(e2)));
}

tri::Triangulation icosahedron(Context &ctx) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    const Vec3 v[12] = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                        {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    tri::Triangulation tri;
    tri.build(ctx, 12, [&](int64_t i) { return geom::normalized(v[i]); }, nullptr);
    return tri;
}

SurfaceStats refine_surface(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                            const SurfaceOptions &options, int32_t next_id,
                            const std::vector<int32_t> *around) {
    SurfaceStats stats;
    std::deque<Candidate> queue;  // first in, first out: deterministic and cache-friendly
    auto consider = [&](int32_t t) {
        double r, e;
        triangle_size(tri, t, &r, &e);
        double ht = h(tri.orthocentre(t));
        if (!(ht > 0) || !std::isfinite(ht))
            fail(UM_ERR_NUMERICAL, "the spacing is ", ht, " (not a positive length) at a "
                 "triangle's circumcentre");
        bool too_big = std::sqrt(3.0) * r >= options.alpha * ht;
        bool badly_shaped = r / e >= options.rho;
        if (too_big || badly_shaped)
            queue.push_back({t, tri.vertex(t, 0), tri.vertex(t, 1), tri.vertex(t, 2)});
    };
    if (around) {
        for (int32_t t : tri.triangles_around(*around)) consider(t);
    } else {
        for (int32_t t = 0; t < tri.triangle_slots(); ++t)
            if (!tri.is_free(t)) consider(t);
    }

    int64_t steps = 0;
    while (!queue.empty()) {
        Candidate c = queue.front();
        queue.pop_front();
        if (!still_there(tri, c)) continue;
        if (++steps % 65536 == 0) ctx.progress("refine surface", 0.0);
        // The shortest edge (a, b) and its bisector towards the circumcentre.
        int k_short = 0;
        double e_short = 1e300;
        for (int k = 0; k < 3; ++k) {
            double e = geom::arc_length(tri.direction(tri.vertex(c.t, (k + 1) % 3)),
                                        tri.direction(tri.vertex(c.t, (k + 2) % 3)));
            if (e < e_short) e_short = e, k_short = k;
        }
        Vec3 a = tri.direction(tri.vertex(c.t, (k_short + 1) % 3));
        Vec3 b = tri.direction(tri.vertex(c.t, (k_short + 2) % 3));
        Vec3 m = geom::normalized(a + b);
        Vec3 centre = tri.orthocentre(c.t);
        double d_centre = geom::arc_length(m, centre);
        double half = 0.5 * e_short;
        double off = e_short * std::sqrt(options.rho * options.rho - 0.25);
        double target = h(m);
        // Spherical right triangle: cos(target) = cos(half) cos(d).
        double d_front = target > half ? std::acos(std::min(1.0, std::cos(target) / std::cos(half)))
                                       : 0.0;
        double d = std::min({d_centre, off, d_front});
        if (d <= 1e-3 * e_short) d = d_centre;
        Vec3 p = towards(m, centre, d);
        int32_t arc = -1;
        RestrictedEdge enc;
        const bool near = options.gamma && near_gamma(*options.gamma, p, 3 * target);
        if (near && encroached_edge(tri, p, c.t, *options.gamma, &enc)) {
            if (enc.radius < options.filter * h(enc.centre)) {
                ++stats.rejected;  // left as it is: refining would over-refine Gamma
                continue;
            }
            p = enc.centre, arc = enc.arc;
        }
        std::vector<int32_t> buried;
        int32_t v = tri.insert(p, 0.0, next_id++, &buried, c.t);
        if (!tri.in_triangulation(v)) {
            ++stats.rejected;
            continue;
        }
        // A point this close to an existing vertex (one on Gamma, placed
        // where the front did not expect it) would over-refine: take it back.
        if (nearest_neighbour(tri, v) < options.filter * h(p)) {
            tri.remove(v);
            ++stats.rejected;
            continue;
        }
        if (options.on_gamma) {
            options.on_gamma->resize(static_cast<size_t>(tri.vertex_slots()), -1);
            (*options.on_gamma)[v] = arc;
        }
        ++stats.inserted;
        // Its cavity's dual edges lie within about 2 r < 2 alpha h / sqrt(3)
        // of it (1.54 h by default): only then may it have changed Tri|Gamma.
        if (near && near_gamma(*options.gamma, p, 1.2 * options.alpha * target)) stats.near_gamma.push_back(v);
        for (int32_t t : tri.star(v)) consider(t);  // only the new fan changed
    }
    stats.next_id = next_id;
    return stats;
}

}  // namespace um::refine
