// Engine tests: the AABB tree over great arcs and the restricted edges Tri|Gamma.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <cstring>
#include <random>
#include <set>

#include "geom/arc_tree.hpp"
#include "refine/restricted.hpp"
#include "support/point_sets.hpp"
#include "tri/triangulation.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;

namespace {

// Short random arcs (length up to max_len radians) and a closed small circle.
std::vector<geom::ArcTree::Arc> sample_arcs(int n, double max_len, uint64_t seed) {
    auto starts = test::random_points(n, seed);
    auto dirs = test::random_points(n, seed + 1);
    std::mt19937_64 rng(seed + 2);
    std::uniform_real_distribution<double> u(1e-6, max_len);
    std::vector<geom::ArcTree::Arc> arcs;
    for (int i = 0; i < n; ++i) {
        Vec3 a = starts[i];
        Vec3 t = geom::normalized(geom::cross(a, dirs[i]));  // a tangent at a
        double len = u(rng);
        arcs.push_back({a, geom::normalized(std::cos(len) * a + std::sin(len) * t)});
    }
    const int m = 720;  // the circle of latitude 30 degrees
    for (int i = 0; i < m; ++i)
        arcs.push_back({geom::unit_from_lonlat_deg(360.0 * i / m, 30),
                        geom::unit_from_lonlat_deg(360.0 * (i + 1) / m, 30)});
    return arcs;
}

void arc_boxes_contain_their_arcs(void **) {
    for (auto &arc : sample_arcs(2000, 1.5, 1)) {
        geom::Box box = geom::arc_box(arc.a, arc.b);
        for (int s = 0; s <= 64; ++s) {
            double f = s / 64.0;
            Vec3 p = geom::normalized((1 - f) * arc.a + f * arc.b);
            assert_true(box.distance2(p) == 0);
        }
    }
}

void tree_queries_match_brute_force(void **) {
    auto arcs = sample_arcs(5000, 0.05, 3);
    geom::ArcTree tree(arcs);
    auto probes = sample_arcs(500, 0.2, 7);
    for (auto &probe : probes) {
        geom::Box box = geom::arc_box(probe.a, probe.b);
        std::set<int32_t> got, want;
        tree.query(box, [&](int32_t i) { got.insert(i); });
        for (size_t i = 0; i < arcs.size(); ++i)
            if (geom::arc_box(arcs[i].a, arcs[i].b).overlaps(box)) want.insert(int32_t(i));
        assert_true(got == want);
    }
}

void nearest_matches_brute_force(void **) {
    auto arcs = sample_arcs(3000, 0.05, 11);
    geom::ArcTree tree(arcs);
    for (auto &p : test::random_points(300, 13)) {
        double d = 0;
        int32_t i = tree.nearest(p, &d);
        double best = 1e300;
        for (auto &arc : arcs) best = std::min(best, geom::distance_to_arc(p, arc.a, arc.b));
        assert_true(i >= 0);
        assert_true(std::fabs(d - best) <= 1e-15);
    }
    double d = 0;
    assert_int_equal(geom::ArcTree().nearest({1, 0, 0}, &d), -1);
}

tri::Triangulation triangulate(int n, uint64_t seed) {
    auto pts = test::random_points(n, seed);
    Context ctx;
    tri::Triangulation t;
    t.build(ctx, n, [&](int64_t i) { return pts[i]; }, nullptr);
    return t;
}

// The crossing query (a box and the probe's great-circle plane) visits every
// arc that arc_intersection finds crossing or touching the probe, with its
// default tolerance and with none: for short and long probes, and for arcs
// that end on the probe or touch its great circle from one side. On long
// probes it visits far fewer arcs than the box query.
void crossing_queries_find_every_crossing(void **) {
    auto arcs = sample_arcs(5000, 0.05, 3);
    auto probes = sample_arcs(300, 0.2, 7);
    const auto long_probes = sample_arcs(100, 2.5, 11);  // (100 long arcs, then a circle's 720 short ones)
    const size_t long_first = probes.size();
    probes.insert(probes.end(), long_probes.begin(), long_probes.end());
    for (size_t k = 0; k < 50; ++k) {  // arcs from a point of a probe, or grazing its circle
        const Vec3 on = geom::normalized(probes[k].a + probes[k].b);
        const Vec3 n = geom::normalized(geom::cross(probes[k].a, probes[k].b));
        const Vec3 along = geom::normalized(geom::cross(n, on));
        arcs.push_back({on, geom::normalized(on + 0.01 * n)});
        const Vec3 above = on + 0.01 * n, grazing = on + 1e-13 * n;
        arcs.push_back({geom::normalized(above + 0.01 * along), geom::normalized(above - 0.01 * along)});
        arcs.push_back({geom::normalized(grazing - 0.01 * along), geom::normalized(grazing + 0.01 * along)});
    }
    // A probe in the plane z = 0 and a short arc 5e-13 above it, over the
    // probe: its box lies wholly on one side of the plane, yet the arc
    // touches the probe within the default tolerance.
    probes.push_back({Vec3{1, 0, 0}, geom::normalized(Vec3{1, 1, 0})});
    arcs.push_back({geom::normalized(Vec3{0.9, 0.3, 5e-13}), geom::normalized(Vec3{0.9, 0.3 + 1e-7, 5e-13})});
    geom::ArcTree tree(arcs);
    size_t visited_long = 0, boxed_long = 0;
    for (size_t p = 0; p < probes.size(); ++p) {
        const Vec3 a = probes[p].a, b = probes[p].b;
        std::set<int32_t> visited, boxed;
        tree.query_crossing(a, b, [&](int32_t i) { visited.insert(i); });
        tree.query(geom::arc_box(a, b), [&](int32_t i) { boxed.insert(i); });
        for (size_t i = 0; i < arcs.size(); ++i) {
            Vec3 x;
            if (geom::arc_intersection(a, b, arcs[i].a, arcs[i].b, x) ||
                geom::arc_intersection(a, b, arcs[i].a, arcs[i].b, x, 0.0))
                assert_true(visited.count(static_cast<int32_t>(i)) == 1);
        }
        assert_true(std::includes(boxed.begin(), boxed.end(), visited.begin(), visited.end()));
        const int32_t stop = visited.empty() ? -1 : *visited.begin();
        assert_true(tree.query_crossing_until(a, b, [&](int32_t i) { return i == stop; }) == !visited.empty());
        if (p >= long_first && p < long_first + 100) visited_long += visited.size(), boxed_long += boxed.size();
    }
    print_message("long probes: %zu arcs visited, %zu in their boxes\n", visited_long, boxed_long);
    assert_true(visited_long * 4 < boxed_long);
}

void restricted_edges_match_brute_force(void **) {
    tri::Triangulation t = triangulate(20000, 17);
    auto arcs = sample_arcs(3000, 0.03, 19);
    geom::ArcTree tree(arcs);
    Context ctx;
    auto edges = refine::restricted_edges(ctx, t, tree);
    assert_true(edges.size() > 100);
    std::set<std::pair<int32_t, int>> got;
    for (auto &e : edges) got.insert({e.triangle, e.edge});
    // Brute force over every arc (a box test first only to keep it quick).
    std::vector<geom::Box> boxes;
    for (auto &arc : arcs) boxes.push_back(geom::arc_box(arc.a, arc.b));
    std::set<std::pair<int32_t, int>> want;
    for (int32_t f = 0; f < t.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            if (t.neighbour(f, k) < f) continue;
            Vec3 c0 = t.orthocentre(f), c1 = t.orthocentre(t.neighbour(f, k)), x;
            geom::Box dual = geom::arc_box(c0, c1);
            for (size_t i = 0; i < arcs.size(); ++i)
                if (boxes[i].overlaps(dual) && geom::arc_intersection(c0, c1, arcs[i].a, arcs[i].b, x)) {
                    want.insert({f, k});
                    break;
                }
        }
    assert_true(got == want);
    // Each surface ball centre lies on its arc and on the dual edge's great circle.
    for (auto &e : edges) {
        auto &arc = tree.arc(e.arc);
        assert_true(geom::distance_to_arc(e.centre, arc.a, arc.b) < 1e-12);
        Vec3 qi = t.lifted(t.vertex(e.triangle, (e.edge + 1) % 3));
        Vec3 qj = t.lifted(t.vertex(e.triangle, (e.edge + 2) % 3));
        assert_true(std::fabs(geom::dot(e.centre, qi - qj)) < 1e-12);
    }
}

// Among the edges of a list of triangles (the boundary pass's later rounds):
// exactly the full scan's edges that have a listed triangle on a side, each
// once and from its smaller triangle, with the same crossings.
void restricted_edges_of_a_triangle_list(void **) {
    tri::Triangulation t = triangulate(20000, 37);
    geom::ArcTree tree(sample_arcs(3000, 0.03, 41));
    Context ctx;
    const auto all = refine::restricted_edges(ctx, t, tree);
    std::vector<int32_t> vertices;
    for (int32_t v = 0; v < t.vertex_slots(); v += 7) vertices.push_back(v);
    const std::vector<int32_t> listed = t.triangles_around(vertices);
    const auto some = refine::restricted_edges(ctx, t, tree, listed);
    auto is_listed = [&](int32_t f) { return std::binary_search(listed.begin(), listed.end(), f); };
    std::set<std::pair<int32_t, int>> want, got;
    for (const auto &e : all)
        if (is_listed(e.triangle) || is_listed(t.neighbour(e.triangle, e.edge))) want.insert({e.triangle, e.edge});
    for (const auto &e : some) {
        assert_true(e.triangle < t.neighbour(e.triangle, e.edge));
        assert_true(got.insert({e.triangle, e.edge}).second);  // each once
        auto same = std::find_if(all.begin(), all.end(), [&](const refine::RestrictedEdge &a) {
            return a.triangle == e.triangle && a.edge == e.edge;
        });
        assert_true(same != all.end() && same->arc == e.arc && same->radius == e.radius);
    }
    assert_true(want.size() > 20);
    assert_true(got == want);
}

void restricted_edges_same_for_any_thread_count(void **) {
    tri::Triangulation t = triangulate(50000, 23);
    geom::ArcTree tree(sample_arcs(2000, 0.05, 29));
    Context one, two;
    one.set_threads(1);
    two.set_threads(2);
    auto a = refine::restricted_edges(one, t, tree), b = refine::restricted_edges(two, t, tree);
    assert_int_equal(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
        assert_int_equal(a[i].triangle, b[i].triangle);
        assert_int_equal(a[i].arc, b[i].arc);
        assert_memory_equal(&a[i].centre, &b[i].centre, sizeof(Vec3));
    }
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(arc_boxes_contain_their_arcs),
        cmocka_unit_test(tree_queries_match_brute_force),
        cmocka_unit_test(crossing_queries_find_every_crossing),
        cmocka_unit_test(nearest_matches_brute_force),
        cmocka_unit_test(restricted_edges_match_brute_force),
        cmocka_unit_test(restricted_edges_of_a_triangle_list),
        cmocka_unit_test(restricted_edges_same_for_any_thread_count),
    };
    return cmocka_run_group_tests_name("restricted", tests, nullptr, nullptr);
}
