#include "optim/slide.hpp"

namespace um::optim {

using geom::Vec3;

namespace {

struct Closest {
    Vec3 x;
    double distance2 = 0;  // squared chord to p
    int clamped = 0;       // -1 at the start point, +1 at the end point, 0 inside
};

// Nearest point of the minor arc (a, b) to p.
Closest closest_on_arc(const Vec3 &a, const Vec3 &b, const Vec3 &p) {
    const Vec3 n = geom::cross(a, b);
    Closest c;
    const double nn = geom::dot(n, n);
    Vec3 foot = nn > 0 ? p - (geom::dot(p, n) / nn) * n : a;
    const double len = geom::norm(foot);
    if (len == 0) foot = a;
    else foot = (1.0 / len) * foot;
    if (nn > 0 && geom::dot(geom::cross(a, foot), n) < 0) c.x = a, c.clamped = -1;
    else if (nn > 0 && geom::dot(geom::cross(foot, b), n) < 0) c.x = b, c.clamped = +1;
    else c.x = foot;
    const Vec3 d = c.x - p;
    c.distance2 = geom::dot(d, d);
    return c;
}

// The segment after (step +1) or before (step -1) s in its part; -1 at an
// open end.
int64_t neighbour_segment(const features::Network &g, int64_t s, int step) {
    const features::Part &part = g.part(g.segment_part(s));
    int64_t k = s - part.first_segment + step;
    if (k < 0 || k >= part.n_segments) {
        if (!part.closed) return -1;
        k = (k + part.n_segments) % part.n_segments;
    }
    return part.first_segment + k;
}

}  // namespace

PointOnGamma slide_along(const features::Network &gamma, int64_t segment, const Vec3 &p,
                         int max_steps) {
    Closest best = closest_on_arc(gamma.segment_a(segment), gamma.segment_b(segment), p);
    PointOnGamma out{best.x, segment};
    const Closest start = best;
    for (int step : {+1, -1}) {
        if (start.clamped != step) continue;  // the nearest point is not beyond this end
        int64_t s = segment;
        for (int i = 0; i < max_steps; ++i) {
            s = neighbour_segment(gamma, s, step);
            if (s < 0 || s == segment) break;
            Closest c = closest_on_arc(gamma.segment_a(s), gamma.segment_b(s), p);
            if (c.distance2 >= best.distance2) break;
            best = c, out = {c.x, s};
            if (c.clamped != step) break;
        }
    }
    return out;
}

}  // namespace um::optim
