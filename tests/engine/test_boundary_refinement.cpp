// Engine tests: boundary refinement along Gamma (paper section 5.1), then
// surface refinement that does not encroach Gamma.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <vector>

#include "refine/boundary.hpp"
#include "features/network.hpp"
#include "refine/restricted.hpp"
#include "refine/sides.hpp"
#include "refine/surface.hpp"
#include "tri/validate.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;

namespace {

constexpr double kRadiusKm = 6371.22;

// A closed "coastline": the circle of latitude 30 degrees with a wiggle of
// amplitude `wiggle_deg` and `waves` periods, sampled every `step_deg`.
std::vector<geom::ArcTree::Arc> wavy_ring(double wiggle_deg, int waves, double step_deg) {
    std::vector<Vec3> pts;
    for (double lon = 0; lon < 360 - 1e-9; lon += step_deg)
        pts.push_back(geom::unit_from_lonlat_deg(
            lon, 30 + wiggle_deg * std::sin(waves * lon * M_PI / 180)));
    std::vector<geom::ArcTree::Arc> arcs;
    for (size_t i = 0; i < pts.size(); ++i) arcs.push_back({pts[i], pts[(i + 1) % pts.size()]});
    return arcs;
}

struct Mesh {
    tri::Triangulation tri;
    std::vector<int32_t> on_gamma;
};

Mesh build(const geom::ArcTree &gamma, double hkm) {
    Context ctx;
    Mesh m{refine::icosahedron(ctx), {}};
    auto h = [&](const Vec3 &) { return hkm / kRadiusKm; };
    int32_t next_id = 12;
    refine::refine_boundary(ctx, m.tri, h, gamma, {}, next_id, m.on_gamma);
    refine::SurfaceOptions so;
    so.gamma = &gamma;
    so.on_gamma = &m.on_gamma;
    refine::refine_surface(ctx, m.tri, h, so, next_id);
    m.on_gamma.resize(static_cast<size_t>(m.tri.vertex_slots()), -1);
    std::string problem = tri::check_triangulation(m.tri);
    if (!problem.empty()) fail_msg("%s", problem.c_str());
    return m;
}

void smooth_coast_is_followed(void **) {
    geom::ArcTree gamma(wavy_ring(0.0, 1, 0.25));  // a plain small circle, fine samples
    const double hkm = 240;
    Mesh m = build(gamma, hkm);
    Context ctx;
    auto edges = refine::restricted_edges(ctx, m.tri, gamma);
    auto h = [&](const Vec3 &) { return hkm / kRadiusKm; };
    // The restricted edges form the ring: about circumference / h of them,
    // each short and close to Gamma.
    double circumference = 2 * M_PI * kRadiusKm * std::cos(30 * M_PI / 180);
    assert_true(edges.size() > 0.7 * circumference / hkm && edges.size() < 1.6 * circumference / hkm);
    for (auto &e : edges) {
        refine::EdgeMeasure em = refine::measure(m.tri, e, h);
        assert_true(em.length < 4.0 / 3.0 * em.h);
        assert_true(em.eps < 0.2 * em.h);
    }
    // Vertices inserted on Gamma lie on it.
    int on = 0;
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v) {
        if (!m.tri.in_triangulation(v) || m.on_gamma[v] < 0) continue;
        auto &arc = gamma.arc(m.on_gamma[v]);
        assert_true(geom::distance_to_arc(m.tri.direction(v), arc.a, arc.b) < 1e-12);
        ++on;
    }
    assert_true(on > 0.7 * circumference / hkm);
}

void features_below_the_spacing_are_filtered(void **) {
    // Wiggles of 0.3 degrees (~33 km) every 2 degrees: far below h = 240 km.
    geom::ArcTree gamma(wavy_ring(0.3, 180, 0.05));
    const double hkm = 240;
    Mesh m = build(gamma, hkm);
    // No edge anywhere shorter than h / 2: the wiggles were not followed.
    double shortest = 1e300;
    for (int32_t t = 0; t < m.tri.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k)
            shortest = std::min(shortest, geom::arc_length(m.tri.direction(m.tri.vertex(t, (k + 1) % 3)),
                                                           m.tri.direction(m.tri.vertex(t, (k + 2) % 3))));
    assert_true(shortest * kRadiusKm > 0.5 * hkm);
}

// Vertices with three or more restricted edges (all arcs are one part).
int64_t folded_vertices(const tri::Triangulation &tri, const geom::ArcTree &gamma) {
    Context ctx;
    std::vector<int> degree(static_cast<size_t>(tri.vertex_slots()), 0);
    for (const auto &e : refine::restricted_edges(ctx, tri, gamma))
        for (int end = 1; end <= 2; ++end) ++degree[tri.vertex(e.triangle, (e.edge + end) % 3)];
    return std::count_if(degree.begin(), degree.end(), [](int d) { return d >= 3; });
}

// A small island ringing one vertex of a uniform mesh at 0.51 h, just
// outside the middle of its spokes: every dual edge of the vertex crosses it
// (about 0.1 h from the spoke's midpoint), so Tri|Gamma is the vertex's whole
// star - no curve - while each of those restricted edges is short and close
// to the ring (eps ~ 0.1 h < beta h), so the size and distance criteria see
// nothing wrong. The topology check refines it into a ring of edges.
void topology_check_mends_a_star_shaped_tri_gamma(void **) {
    const double hkm = 240, h = hkm / kRadiusKm;
    int64_t folded[2], added[2], degree = 0;
    for (int check = 0; check <= 1; ++check) {
        Context ctx;
        tri::Triangulation tri = refine::icosahedron(ctx);
        refine::refine_surface(ctx, tri, [&](const Vec3 &) { return h; }, {}, 12);
        // A vertex whose spokes are all about h (the premise above), from
        // the middle of the slots on.
        int32_t v = -1;
        for (int32_t t = tri.triangle_count() / 2; v < 0 && t < tri.triangle_count(); ++t) {
            const int32_t u = tri.vertex(t, 0);
            bool regular = true;
            for (int32_t s : tri.star(u)) {
                const int32_t w = tri.vertex(s, (tri.local_index(s, u) + 1) % 3);
                const double l = geom::arc_length(tri.direction(u), tri.direction(w));
                regular = regular && l > 0.9 * h && l < 1.1 * h;
            }
            if (regular) v = u;
        }
        assert_true(v >= 0);
        const Vec3 c = tri.direction(v);
        const Vec3 e1 = geom::normalized(geom::cross(c, Vec3{0, 0, 1})), e2 = geom::cross(c, e1);
        std::vector<geom::ArcTree::Arc> ring;
        const double r = 0.51 * h;
        for (int i = 0; i < 90; ++i) {
            auto at = [&](int j) {
                const double a = 2 * M_PI * j / 90;
                return geom::normalized(c + std::tan(r) * (std::cos(a) * e1 + std::sin(a) * e2));
            };
            ring.push_back({at(i), at(i + 1)});
        }
        geom::ArcTree gamma(ring);
        const std::vector<int64_t> part_of_arc(gamma.size(), 0);
        refine::BoundaryOptions bo;
        if (check) bo.part_of_arc = &part_of_arc;
        std::vector<int32_t> on_gamma;
        int32_t next_id = tri.vertex_slots();
        const int64_t vertices_before = tri.vertex_count();
        refine::refine_boundary(ctx, tri, [&](const Vec3 &) { return h; }, gamma, bo, next_id, on_gamma);
        folded[check] = folded_vertices(tri, gamma);
        added[check] = tri.vertex_count() - vertices_before;
        degree = static_cast<int64_t>(tri.star(v).size());
        std::string problem = tri::check_triangulation(tri);
        if (!problem.empty()) fail_msg("%s", problem.c_str());
    }
    print_message("star-shaped Tri|Gamma: %lld folded vertices without the topology check, %lld with it\n",
                  (long long)folded[0], (long long)folded[1]);
    assert_true(folded[0] > 0);
    assert_int_equal(folded[1], 0);
    // The ring is sampled, not the mesh refined wholesale: about one point
    // per spoke of the centre, at most twice that.
    assert_true(added[1] > added[0] && added[1] - added[0] <= 2 * degree + 2);
}

// A smooth coast has no folds: the check changes nothing there.
void topology_check_leaves_a_smooth_coast_alone(void **) {
    geom::ArcTree gamma(wavy_ring(0.0, 1, 0.25));
    const std::vector<int64_t> part_of_arc(gamma.size(), 0);
    int64_t vertices[2];
    for (int check = 0; check <= 1; ++check) {
        Context ctx;
        tri::Triangulation tri = refine::icosahedron(ctx);
        std::vector<int32_t> on_gamma;
        int32_t next_id = 12;
        refine::BoundaryOptions bo;
        if (check) bo.part_of_arc = &part_of_arc;
        refine::refine_boundary(ctx, tri, [](const Vec3 &) { return 240.0 / kRadiusKm; }, gamma, bo, next_id,
                                on_gamma);
        vertices[check] = tri.vertex_count();
    }
    assert_int_equal(vertices[1], vertices[0]);
}

// A network of one closed coastline part: the circle of latitude `lat`.
features::Network ring_network(double lat, int n) {
    std::vector<double> lon, la;
    for (int i = 0; i < n; ++i) lon.push_back(360.0 * i / n - 180), la.push_back(lat);
    int64_t offsets[2] = {0, n};
    int32_t closed = 1, kind = UM_FEATURE_COASTLINE;
    features::PartsInput in;
    in.n_points = n, in.lon_deg = lon.data(), in.lat_deg = la.data();
    in.n_parts = 1, in.part_offsets = offsets, in.closed = &closed, in.kind = &kind;
    features::Network net;
    net.add(in);
    return net;
}

void land_and_ocean_sides(void **) {
    features::Network net = ring_network(30, 1440);
    std::vector<geom::ArcTree::Arc> arcs;
    for (int64_t s = 0; s < net.segment_count(); ++s) arcs.push_back({net.segment_a(s), net.segment_b(s)});
    geom::ArcTree gamma(arcs);
    Mesh m = build(gamma, 300);
    // The cap north of 30 degrees is the smaller region: land.
    assert_true(refine::is_land(net, geom::unit_from_lonlat_deg(10, 60)));
    assert_false(refine::is_land(net, geom::unit_from_lonlat_deg(10, 0)));
    auto sides = refine::triangle_sides(m.tri, net);
    // Testing only the restricted dual edges (what the pipeline does) gives
    // the same sides: the others cross no coastline.
    Context ctx;
    const std::vector<refine::RestrictedEdge> restricted = refine::restricted_edges(ctx, m.tri, gamma);
    assert_true(restricted.size() > 100);
    assert_true(refine::triangle_sides(m.tri, net, &restricted) == sides);
    int land = 0, ocean = 0;
    for (int32_t t = 0; t < m.tri.triangle_slots(); ++t) {
        if (m.tri.is_free(t)) continue;
        double lon, lat;
        geom::lonlat_deg_from_unit(m.tri.orthocentre(t), lon, lat);
        if (lat > 33) assert_int_equal(int(sides[t]), int(refine::Side::land)), ++land;
        if (lat < 27) assert_int_equal(int(sides[t]), int(refine::Side::ocean)), ++ocean;
    }
    assert_true(land > 100 && ocean > 1000);
    auto vsides = refine::vertex_sides(m.tri, sides, m.on_gamma, net);
    int coastal = 0;
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v) {
        if (!m.tri.in_triangulation(v)) continue;
        double lon, lat;
        geom::lonlat_deg_from_unit(m.tri.direction(v), lon, lat);
        if (vsides[v] == refine::Side::coastal) {
            ++coastal;
            assert_true(std::fabs(lat - 30) < 3);
        } else {
            assert_int_equal(int(vsides[v]), int(lat > 30 ? refine::Side::land : refine::Side::ocean));
        }
    }
    assert_true(coastal > 50);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(smooth_coast_is_followed),
        cmocka_unit_test(features_below_the_spacing_are_filtered),
        cmocka_unit_test(topology_check_mends_a_star_shaped_tri_gamma),
        cmocka_unit_test(topology_check_leaves_a_smooth_coast_alone),
        cmocka_unit_test(land_and_ocean_sides),
    };
    return cmocka_run_group_tests_name("boundary_refinement", tests, nullptr, nullptr);
}
