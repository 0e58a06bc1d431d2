#include "quality/geodesic.hpp"

#include <algorithm>
#include <limits>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>

namespace um::quality {

namespace {

// Items per block: each block's sums are made in order and added in block
// order, so the totals do not depend on the threads.
constexpr int64_t kBlock = 4096;

struct Partial {
    int64_t count = 0;
    double sum = 0, min = std::numeric_limits<double>::infinity(), max = 0;
    void add(double x) { ++count, sum += x, min = std::min(min, x), max = std::max(max, x); }
    void add(const Partial &p) {
        count += p.count, sum += p.sum, min = std::min(min, p.min), max = std::max(max, p.max);
    }
};

// fn(i, partial) for i in [0, n), in fixed blocks; the partials added in
// order. With a heartbeat between runs of blocks (as the rest of the
// report): the geodesics take seconds at a million cells, and cancel must
// get in.
template <class Fn>
Partial in_blocks(Context &ctx, int64_t n, Fn fn) {
    const int64_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<Partial> partial(static_cast<size_t>(blocks));
    ctx.parallel_for_with_heartbeat("quality", blocks, 1, [&](int64_t b, int64_t e) {
        for (int64_t k = b; k < e; ++k)
            for (int64_t i = k * kBlock; i < std::min(n, (k + 1) * kBlock); ++i) fn(i, partial[k]);
    });
    Partial total;
    for (const Partial &p : partial) total.add(p);
    return total;
}

}  // namespace

Report::Geodesic measure_geodesic(Context &ctx, const tri::Triangulation &tri, const geom::Surface &surface,
                                  const refine::SpacingRadians &h, const std::vector<uint8_t> *cells) {
    const GeographicLib::Geodesic geodesic(surface.a(), surface.f());
    auto kept = [&](int32_t v) { return !cells || (*cells)[v] != 0; };
    auto lonlat = [&](const geom::Vec3 &u, double &lon, double &lat) { surface.geodetic(u, lon, lat); };

    const Partial edges = in_blocks(ctx, 3 * int64_t(tri.triangle_slots()), [&](int64_t i, Partial &p) {
        const int32_t t = static_cast<int32_t>(i / 3);
        const int k = static_cast<int>(i % 3);
        if (tri.is_free(t) || tri.neighbour(t, k) < t) return;
        const int32_t a = tri.vertex(t, (k + 1) % 3), b = tri.vertex(t, (k + 2) % 3);
        if (!kept(a) || !kept(b)) return;
        const geom::Vec3 ua = tri.direction(a), ub = tri.direction(b), mid = geom::normalized(ua + ub);
        double lon1, lat1, lon2, lat2, length;
        lonlat(ua, lon1, lat1), lonlat(ub, lon2, lat2);
        geodesic.Inverse(lat1, lon1, lat2, lon2, length);
        p.add(length / (h(mid) * surface.radius_along(mid)));
    });
    const Partial areas = in_blocks(ctx, tri.vertex_slots(), [&](int64_t i, Partial &p) {
        const int32_t v = static_cast<int32_t>(i);
        if (!tri.in_triangulation(v) || !kept(v)) return;
        GeographicLib::PolygonArea polygon(geodesic);
        for (const geom::Vec3 &corner : tri.power_cell(v)) {
            double lon, lat;
            lonlat(corner, lon, lat);
            polygon.AddPoint(lat, lon);
        }
        double perimeter, area;
        polygon.Compute(false, true, perimeter, area);  // counter-clockwise from outside: > 0
        p.add(area);
    });

    Report::Geodesic g;
    g.measured = true;
    g.a_m = surface.a(), g.f = surface.f();
    g.edges = edges.count, g.cells = areas.count;
    if (edges.count > 0) {
        g.length_over_h_min = edges.min, g.length_over_h_max = edges.max;
        g.length_over_h_mean = edges.sum / static_cast<double>(edges.count);
    }
    g.cell_area_m2 = areas.sum;
    g.surface_area_m2 = surface.area_m2();
    return g;
}

}  // namespace um::quality
