// Engine tests of the Laguerre triangulation on the hard inputs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <random>
#include <set>
#include <string>
#include <cstring>

#include "core/error.hpp"
#include "support/point_sets.hpp"
#include "tri/cell_walk.hpp"
#include "tri/triangulation.hpp"
#include "tri/validate.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;

namespace {

tri::Triangulation build(const std::vector<Vec3> &pts, const std::vector<double> *weights = nullptr,
                         int threads = 1) {
    Context ctx;
    ctx.set_threads(threads);
    tri::Triangulation t;
    t.build(ctx, static_cast<int64_t>(pts.size()), [&](int64_t i) { return pts[i]; },
            weights ? weights->data() : nullptr);
    return t;
}

void expect_valid(const tri::Triangulation &t) {
    std::string problem = tri::check_triangulation(t);
    if (!problem.empty()) fail_msg("%s", problem.c_str());
}

// Every input is a vertex and the counts are those of a triangulated sphere.
void expect_complete(const tri::Triangulation &t, size_t n) {
    expect_valid(t);
    assert_int_equal(t.vertex_count(), static_cast<int64_t>(n));
    assert_int_equal(t.triangle_count(), 2 * static_cast<int64_t>(n) - 4);
}

void expect_identical(const tri::Triangulation &a, const tri::Triangulation &b) {
    assert_int_equal(a.triangle_count(), b.triangle_count());
    assert_int_equal(a.vertex_slots(), b.vertex_slots());
    for (int32_t f = 0; f < a.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            assert_int_equal(a.id(a.vertex(f, k)), b.id(b.vertex(f, k)));
            assert_int_equal(a.neighbour(f, k), b.neighbour(f, k));
        }
}

// The live triangles by input ids (after updates, free slots lie among them).
std::set<std::array<int32_t, 3>> triangle_set(const tri::Triangulation &t) {
    std::set<std::array<int32_t, 3>> out;
    for (int32_t f = 0; f < t.triangle_slots(); ++f) {
        if (t.is_free(f)) continue;
        std::array<int32_t, 3> ids = {t.id(t.vertex(f, 0)), t.id(t.vertex(f, 1)),
                                      t.id(t.vertex(f, 2))};
        std::rotate(ids.begin(), std::min_element(ids.begin(), ids.end()), ids.end());
        out.insert(ids);
    }
    return out;
}

void random_points_small_and_large(void **) {
    // The smallest spheres: a tetrahedron and an octahedron.
    std::vector<Vec3> tetra = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (auto &p : tetra) p = geom::normalized(p);
    expect_complete(build(tetra), 4);
    std::vector<Vec3> octa = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    expect_complete(build(octa), 6);  // every quadruple around the equators is cocircular
    for (int64_t n : {100, 1000, 100000}) {
        auto pts = test::random_points(n, 7 + n);
        expect_complete(build(pts), pts.size());
    }
}

// Also the one case whose last BRIO round is cut into 16 regions (those of
// same_result_for_any_thread_count stop at 8): the same for one thread.
void a_million_random_points(void **) {
    auto pts = test::random_points(1000000, 11);
    auto two = build(pts, nullptr, 2);
    expect_complete(two, pts.size());
    expect_identical(two, build(pts, nullptr, 1));
}

void icosahedral_grids_to_level_8(void **) {
    for (int level : {0, 1, 2, 5, 8}) {
        auto pts = test::icosahedral_points(level);
        assert_int_equal(pts.size(), 10 * (size_t(1) << (2 * level)) + 2);
        expect_complete(build(pts), pts.size());
    }
}

void cocircular_latitude_circles_and_poles(void **) {
    auto pts = test::latitude_circles({-60, -30, 0, 30, 60}, 360);
    expect_complete(build(pts), pts.size());
    // Two points only besides the poles: the smallest octahedron-like case.
    auto few = test::latitude_circles({0}, 4);
    expect_complete(build(few), few.size());
}

void points_on_three_great_circles(void **) {
    auto pts = test::great_circles(1000);
    expect_complete(build(pts), pts.size());
}

void antipodal_pairs(void **) {
    auto half = test::random_points(500, 3);
    std::vector<Vec3> pts = half;
    for (auto p : half) pts.push_back(-1.0 * p);
    expect_complete(build(pts), pts.size());
}

void near_duplicates_are_distinct_vertices(void **) {
    auto pts = test::random_points(2000, 5);
    for (int i = 0; i < 200; ++i) {  // the next double up in x, renormalised or not
        Vec3 p = pts[i];
        p.x = std::nextafter(p.x, 2.0);
        pts.push_back(p);
    }
    tri::Triangulation t = build(pts);
    expect_valid(t);
    // A point one ulp away may be buried by rounding (it lies inside the hull
    // by less than an ulp): it is then reported hidden, never lost.
    assert_int_equal(t.vertex_count() + static_cast<int64_t>(t.hidden_ids().size()),
                     static_cast<int64_t>(pts.size()));
}

void exact_duplicates_are_named(void **) {
    auto pts = test::random_points(1000, 9);
    pts[700] = pts[123];
    try {
        build(pts);
        fail_msg("duplicates accepted");
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_DUPLICATE_POINTS);
        assert_non_null(strstr(e.what(), "123"));
        assert_non_null(strstr(e.what(), "700"));
    }
}

// Duplicates among the big rounds (those go the parallel way, the pair is
// found by the serial fallback): the same smallest pair for any thread count.
void exact_duplicates_in_parallel_rounds_are_named(void **) {
    auto pts = test::random_points(100000, 31);
    pts[90000] = pts[4321];
    pts[77777] = pts[50000];
    for (int threads : {1, 2}) {
        try {
            build(pts, nullptr, threads);
            fail_msg("duplicates accepted");
        } catch (const Error &e) {
            assert_int_equal(e.status(), UM_ERR_DUPLICATE_POINTS);
            assert_non_null(strstr(e.what(), "points 4321 and 90000"));
        }
    }
}

// Two points on one direction with different weights: their lifted points
// differ, so they are not duplicates (exact_duplicates_are_named has equal
// ones); the lighter one lies under the facets around the heavier and is
// hidden, whichever comes first. Serial rounds only, then parallel rounds
// too; the same for any thread count. (A point on a vertex's direction ends
// the parallel rounds' filtered walk beside two undecided edges, so the
// exact path takes it; the filtered starts that bury vertices are met in
// test_triangulation_api's weighted grid.)
void coincident_points_with_other_weights(void **) {
    for (int64_t n : {3000, 100000}) {
        auto pts = test::random_points(n, 37);
        std::vector<double> w(pts.size(), 0.0);
        const int64_t a = n / 3, b = n - 7, c = n / 2, d = n - 3;
        // Weights far below the spacing squared: no neighbour is hidden.
        pts[b] = pts[a], w[b] = 1e-9;   // the later point heavier
        pts[d] = pts[c], w[d] = -1e-9;  // the later point lighter
        // And at the north pole, where the lifted points are exactly
        // parallel (0, 0, s): the exact walk meets the vertex there.
        const int64_t e = n / 5, f = n - 11;
        pts[e] = pts[f] = Vec3{0, 0, 1}, w[e] = 2e-9, w[f] = 0;
        auto one = build(pts, &w, 1);
        expect_valid(one);
        auto hidden = one.hidden_ids();
        std::vector<int32_t> lighter = {int32_t(a), int32_t(d), int32_t(f)};
        std::sort(lighter.begin(), lighter.end());
        assert_true(hidden == lighter);
        assert_int_equal(one.vertex_count(), n - 3);
        expect_identical(one, build(pts, &w, 2));
    }
}

// Points crowded into a small cap (plus the six axis directions to surround
// the centre): the early hull keeps virtual vertices for long, and the
// regions of the parallel rounds are tiny and meet everywhere.
void clustered_points_in_parallel_rounds(void **) {
    std::vector<Vec3> pts;
    std::mt19937_64 rng(41);
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    for (int i = 0; i < 60000; ++i) pts.push_back(geom::normalized({1.0, u(rng), u(rng)}));
    for (Vec3 a : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}})
        pts.push_back(geom::normalized(a + Vec3{1e-3, 2e-3, 3e-3}));
    auto one = build(pts, nullptr, 1);
    expect_complete(one, pts.size());
    expect_identical(one, build(pts, nullptr, 2));
}

// A third of the points crowded around the axis of the bands that take the
// points the regions defer (parallel_insertion.cpp): most of those fall in
// the top bin of the bands' histogram, whose cut is the end of the keys.
void points_crowded_at_the_band_axis(void **) {
    auto pts = test::random_points(280000, 43);
    const Vec3 axis = geom::normalized({1, 2, 3});
    const Vec3 e1 = geom::normalized(geom::cross(axis, {0, 0, 1})), e2 = geom::cross(axis, e1);
    std::mt19937_64 rng(47);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    for (int i = 0; i < 120000; ++i) pts.push_back(geom::normalized(axis + u(rng) * e1 + u(rng) * e2));
    auto one = build(pts, nullptr, 1);
    expect_complete(one, pts.size());
    expect_identical(one, build(pts, nullptr, 2));
}

void one_hemisphere_or_great_circle_is_rejected(void **) {
    auto pts = test::random_points(1000, 13);
    for (auto &p : pts) p.z = std::fabs(p.z) + 1e-3, p = geom::normalized(p);
    try {
        build(pts);
        fail_msg("hemisphere accepted");
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_DEGENERATE_INPUT);
    }
    auto ring = test::latitude_circles({0}, 100);
    ring.erase(ring.begin(), ring.begin() + 2);  // drop the poles: one great circle
    try {
        build(ring);
        fail_msg("great circle accepted");
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_DEGENERATE_INPUT);
    }
}

void weights_hide_points(void **) {
    auto pts = test::random_points(20000, 17);
    std::vector<double> w(pts.size());
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-2e-3, 2e-3);  // ~ spacing^2 scale
    for (auto &x : w) x = u(rng);
    for (size_t i = 0; i < 50; ++i) w[i * 7] = -0.5;  // far too light: buried
    tri::Triangulation t = build(pts, &w);
    expect_valid(t);
    auto hidden = t.hidden_ids();
    for (size_t i = 0; i < 50; ++i)
        assert_true(std::binary_search(hidden.begin(), hidden.end(), int32_t(i * 7)));
    assert_int_equal(t.vertex_count() + static_cast<int64_t>(hidden.size()),
                     static_cast<int64_t>(pts.size()));
}

// The big BRIO rounds are inserted by regions in parallel: the same
// triangles in the same slots for any thread count, also with weights that
// bury vertices and with the many exact ties of an icosahedral grid.
void same_result_for_any_thread_count(void **) {
    auto pts = test::random_points(200000, 19);
    auto one = build(pts, nullptr, 1);
    expect_identical(one, build(pts, nullptr, 2));
    expect_identical(one, build(pts, nullptr, 4));

    auto wpts = test::random_points(60000, 29);
    std::vector<double> w(wpts.size());
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-4e-3, 4e-3);
    for (auto &x : w) x = u(rng);
    auto wone = build(wpts, &w, 1);
    expect_valid(wone);
    assert_true(!wone.hidden_ids().empty());
    expect_identical(wone, build(wpts, &w, 3));
    // Heavy weights: most insertions bury vertices, regions empty slots and
    // the deferred points start from emptied regions.
    std::uniform_real_distribution<double> heavy(-3e-2, 3e-2);
    for (auto &x : w) x = heavy(rng);
    auto hone = build(wpts, &w, 1);
    expect_valid(hone);
    assert_true(hone.hidden_ids().size() > wpts.size() / 10);
    expect_identical(hone, build(wpts, &w, 2));

    auto ico = test::icosahedral_points(7);
    auto ione = build(ico, nullptr, 1);
    expect_complete(ione, ico.size());
    expect_identical(ione, build(ico, nullptr, 2));
}

// The big arrays of a construction from many points (HugePageVector, set
// by reset_on_huge_pages) start on a huge page from 2 MiB on, through every
// way a vector gets a new buffer, and free them as they were allocated
// (AddressSanitizer checks the pairing); the setting moves with the buffer,
// and copies are ordinary vectors.
void big_arrays_start_on_huge_pages(void **) {
    constexpr size_t kBig = kHugePageMinBytes / sizeof(Vec3) + 1, kSmall = 1000;
    auto on_huge_page = [](const void *p) { return reinterpret_cast<uintptr_t>(p) % kHugePageBytes == 0; };
    auto placed = [](const auto &v) { return v.get_allocator().on_huge_pages; };
    HugePageVector<Vec3> big;
    assert_false(placed(big));
    reset_on_huge_pages(big, true);
    big.assign(kBig, Vec3{1, 2, 3});
    assert_true(on_huge_page(big.data()));
    HugePageVector<Vec3> grown;  // by push_back, through both sizes
    reset_on_huge_pages(grown, true);
    for (size_t i = 0; i < 2 * kBig; ++i) grown.push_back(Vec3{double(i), 0, 0});
    assert_true(on_huge_page(grown.data()));
    assert_true(grown[kBig].x == double(kBig));
    HugePageVector<Vec3> copy = grown;
    assert_false(placed(copy));
    assert_true(copy[kBig].x == double(kBig));
    grown.resize(kSmall);  // shrunk below the threshold
    grown.shrink_to_fit();
    assert_int_equal(grown.capacity(), kSmall);
    assert_true(grown[kSmall - 1].x == double(kSmall - 1));
    copy.swap(big);  // the setting goes with the buffer
    assert_true(placed(copy) && on_huge_page(copy.data()));
    assert_false(placed(big));
    big = std::move(copy);
    assert_true(placed(big) && on_huge_page(big.data()));
    HugePageVector<Vec3> assigned;
    assigned = big;  // keeps its own setting
    assert_false(placed(assigned));
    assert_int_equal(assigned.size(), kBig);
    assert_true(assigned[kBig - 1].z == 3);
    reset_on_huge_pages(big, false);
    assert_true(big.empty() && !placed(big));
}

// A caller's temporaries in the build's room (as the C API's unit vectors
// from lon/lat are) leave the triangulation as build() makes it; the room
// is bounded, and ends with prepare().
void build_room_holds_a_callers_temporaries(void **) {
    auto pts = test::random_points(150000, 41);
    const int64_t n = static_cast<int64_t>(pts.size());
    for (int threads : {1, 2}) {
        Context ctx;
        ctx.set_threads(threads);
        tri::Triangulation t;
        for (int again = 0; again < 2; ++again) {  // a second build in the same object
            Vec3 *unit = t.reserve_build(n).take<Vec3>(pts.size());
            std::copy(pts.begin(), pts.end(), unit);
            auto direction = [unit](int64_t i) { return unit[i]; };
            t.prepare(ctx, n, direction, nullptr, direction);
            t.finish_build(ctx);
            expect_complete(t, pts.size());
            expect_identical(t, build(pts));
        }
    }
    auto expect_status = [](um_status status, auto &&call) {
        try {
            call();
            fail_msg("no error where status %d was due", int(status));
        } catch (const Error &e) {
            assert_int_equal(e.status(), status);
        }
    };
    Context ctx;
    auto few = test::random_points(1000, 43);
    auto few_direction = [&](int64_t i) { return few[i]; };
    {  // bounded: 2 (1000 + 6) triangles of 24 bytes
        tri::Triangulation t;
        tri::Triangulation::BuildRoom &room = t.reserve_build(1000);
        (void)room.take<double>(6000);
        expect_status(UM_ERR_INTERNAL, [&] { (void)room.take<double>(37); });
        // A copy has no room (one pointing into t's storage would fail its
        // build), and t's stays as it was.
        tri::Triangulation copy = t;
        copy.build(ctx, 1000, few_direction, nullptr);
        expect_complete(copy, few.size());
        (void)room.take<double>(36);
    }
    {  // ended by the build
        tri::Triangulation t;
        tri::Triangulation::BuildRoom &room = t.reserve_build(1000);
        t.build(ctx, 1000, few_direction, nullptr);
        expect_complete(t, few.size());
        expect_status(UM_ERR_INTERNAL, [&] { (void)room.take<double>(1); });
    }
    {  // made for another build
        tri::Triangulation t;
        (void)t.reserve_build(999);
        expect_status(UM_ERR_INTERNAL, [&] { t.build(ctx, 1000, few_direction, nullptr); });
        t.build(ctx, 1000, few_direction, nullptr);  // the failed prepare() ended it
        expect_complete(t, few.size());
    }
    tri::Triangulation t;
    expect_status(UM_ERR_LIMIT, [&] { (void)t.reserve_build(-1); });
    expect_status(UM_ERR_LIMIT, [&] { (void)t.reserve_build((int64_t(1) << 28) + 1); });
}

void insertion_order_does_not_change_the_triangles(void **) {
    // Same points, permuted ids: the symbolic perturbation follows the ids,
    // so compare a non-degenerate input (no ties) across orders.
    auto pts = test::random_points(5000, 23);
    auto a = triangle_set(build(pts));
    std::vector<Vec3> rev(pts.rbegin(), pts.rend());
    auto b_tri = build(rev);
    std::set<std::array<int32_t, 3>> b;
    const int32_t n = static_cast<int32_t>(pts.size());
    for (auto f : triangle_set(b_tri)) {
        std::array<int32_t, 3> ids = {n - 1 - f[0], n - 1 - f[1], n - 1 - f[2]};
        std::rotate(ids.begin(), std::min_element(ids.begin(), ids.end()), ids.end());
        b.insert(ids);
    }
    assert_true(a == b);
}

// Territories insert what they own in parallel (two layouts), the rest goes
// one by one; the result is the triangulation of all the points with the
// ids the territories gave (their ids keep the insertion order), the same
// for 1 and 2 threads. The extra points are an icosahedral grid (cocircular
// quadruples, points on the base's edges are not) over a random base.
tri::Triangulation insert_by_territories(const std::vector<Vec3> &base, const std::vector<Vec3> &extra,
                                         int threads, std::vector<Vec3> *point_of_id, int64_t *in_territories) {
    Context ctx;
    ctx.set_threads(threads);
    tri::Triangulation t;
    t.build(ctx, static_cast<int64_t>(base.size()), [&](int64_t i) { return base[i]; }, nullptr);
    *point_of_id = base;
    *in_territories = 0;
    std::vector<int32_t> left(extra.size());
    for (size_t i = 0; i < extra.size(); ++i) left[i] = static_cast<int32_t>(i);
    int32_t next_id = static_cast<int32_t>(base.size());
    for (int layout = 0; layout < 2; ++layout) {
        // 16 territories of equal counts of the points left.
        std::vector<uint32_t> keys;
        for (int32_t i : left) keys.push_back(tri::Triangulation::territory_key(extra[i], layout));
        std::sort(keys.begin(), keys.end());
        std::vector<uint32_t> cuts;
        for (int g = 1; g < 16; ++g) cuts.push_back(keys[keys.size() * g / 16]);
        cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
        std::vector<int32_t> budget(cuts.size() + 1, static_cast<int32_t>(left.size()));
        auto territories = t.open_territories(ctx, cuts, budget, next_id, layout);
        std::vector<std::vector<int32_t>> inserted(territories.size()), slot(territories.size()),
            deferred(territories.size());
        // A start for each: any triangle it owns, found before they work (a
        // scan of all triangles while they work would read theirs).
        std::vector<int32_t> start(territories.size(), -1);
        for (int32_t f = 0; f < t.triangle_slots(); ++f)
            for (size_t g = 0; g < territories.size(); ++g)
                if (start[g] < 0 && !t.is_free(f) && t.owns(territories[g], f)) start[g] = f;
        ctx.parallel_for(static_cast<int64_t>(territories.size()), 1, [&](int64_t b, int64_t e) {
            for (int64_t g = b; g < e; ++g) {
                int32_t hint = start[g];  // then the last insertion's fan
                for (int32_t i : left) {
                    if (!t.owns_point(territories[g], extra[i])) continue;
                    if (hint < 0) {
                        deferred[g].push_back(i);
                        continue;
                    }
                    int32_t v = -1;
                    const auto r = t.insert_in(territories[g], extra[i], hint, 0.0, &v);
                    if (r == tri::Triangulation::TerritoryInsert::inserted) {
                        inserted[g].push_back(i), slot[g].push_back(v);
                        t.for_each_in_star(v, [&](int32_t f) { hint = f; });
                    } else {
                        deferred[g].push_back(i);
                    }
                }
            }
        });
        const auto moved = t.close_territories(ctx, territories);
        point_of_id->resize(static_cast<size_t>(moved.next_id));
        std::vector<int32_t> still;
        for (size_t g = 0; g < inserted.size(); ++g) {
            for (size_t j = 0; j < inserted[g].size(); ++j) {
                const int32_t v = moved.new_slot[slot[g][j] - moved.first_slot];
                (*point_of_id)[t.id(v)] = extra[inserted[g][j]];
            }
            *in_territories += static_cast<int64_t>(inserted[g].size());
            still.insert(still.end(), deferred[g].begin(), deferred[g].end());
        }
        // Points owned by no territory (keys at a cut are owned: none here).
        std::sort(still.begin(), still.end());
        left.swap(still);
        next_id = moved.next_id;
    }
    for (int32_t i : left) {
        t.insert(extra[i], 0.0, next_id++);
        point_of_id->push_back(extra[i]);
    }
    return t;
}

void territories_insert_as_the_serial_path_would(void **) {
    const std::vector<Vec3> base = test::random_points(3000, 41);
    const std::vector<Vec3> extra = test::icosahedral_points(5);
    std::vector<Vec3> point_of_id, point_of_id_2;
    int64_t in_territories = 0, in_territories_2 = 0;
    tri::Triangulation t = insert_by_territories(base, extra, 1, &point_of_id, &in_territories);
    print_message("territories inserted %lld of %zu points\n", (long long)in_territories, extra.size());
    assert_true(in_territories > static_cast<int64_t>(extra.size()) / 2);
    t.compact();
    assert_int_equal(t.triangle_count(), t.triangle_slots());  // compact() leaves no free slot
    expect_complete(t, base.size() + extra.size());
    assert_true(triangle_set(t) == triangle_set(build(point_of_id)));
    tri::Triangulation t2 = insert_by_territories(base, extra, 2, &point_of_id_2, &in_territories_2);
    t2.compact();
    assert_int_equal(t2.triangle_count(), t2.triangle_slots());  // compact() leaves no free slot
    assert_int_equal(point_of_id.size(), point_of_id_2.size());
    for (size_t i = 0; i < point_of_id.size(); ++i)
        assert_true(std::memcmp(&point_of_id[i], &point_of_id_2[i], sizeof(Vec3)) == 0);
    expect_identical(t, t2);
}

// A territory's insertion that would put a vertex too close to its link
// leaves everything as it was; one beyond its keys is deferred.
void territory_insertion_refuses_without_changes(void **) {
    Context ctx;
    tri::Triangulation t = build(test::random_points(4000, 5));
    const auto before = triangle_set(t);
    const Vec3 p = geom::normalized(Vec3{0.3, 0.2, 0.9});
    const uint32_t key = tri::Triangulation::territory_key(p, 0);
    auto g = t.open_territories(ctx, {key, key + 1}, {4, 4, 4}, t.vertex_slots(), 0);
    int32_t hint = -1;
    for (int32_t f = 0; f < t.triangle_slots() && hint < 0; ++f)
        if (!t.is_free(f) && t.owns(g[1], f)) hint = f;
    int32_t v = -1;
    // Territory 1 owns only the key of p: no triangle, so nothing to start from.
    assert_true(hint < 0);
    assert_true(t.insert_in(g[0], p, 0, 0.0, &v) == tri::Triangulation::TerritoryInsert::deferred);
    t.close_territories(ctx, g);
    auto one = t.open_territories(ctx, {}, {4}, t.vertex_slots(), 0);
    const int32_t start = t.locate_in(one[0], p, 0);
    assert_true(start >= 0);
    assert_true(t.insert_in(one[0], p, start, 2.0, &v) == tri::Triangulation::TerritoryInsert::too_close);
    const auto moved = t.close_territories(ctx, one);
    assert_true(moved.new_slot.size() == 4 && moved.new_slot[0] < 0);
    t.compact();
    assert_int_equal(t.triangle_count(), t.triangle_slots());  // compact() leaves no free slot
    expect_valid(t);
    assert_true(triangle_set(t) == before);
    // A budget of one vertex: the second insertion is deferred.
    const int32_t id = t.vertex_slots();
    auto small = t.open_territories(ctx, {}, {1}, id, 0);
    const Vec3 q = geom::normalized(Vec3{0.31, 0.2, 0.9});
    assert_true(t.insert_in(small[0], p, t.locate_in(small[0], p, 0), 0.0, &v) ==
                tri::Triangulation::TerritoryInsert::inserted);
    int32_t w = -1;
    assert_true(t.insert_in(small[0], q, t.locate_in(small[0], q, 0), 0.0, &w) ==
                tri::Triangulation::TerritoryInsert::deferred);
    const auto closed = t.close_territories(ctx, small);
    assert_int_equal(closed.next_id, id + 1);
    assert_int_equal(t.id(closed.new_slot[0]), id);
    t.compact();
    assert_int_equal(t.triangle_count(), t.triangle_slots());  // compact() leaves no free slot
    expect_complete(t, 4001);
}

// Renumbering along the Hilbert curve keeps the triangulation (same
// triangles by input id, every vertex where it was), puts hidden slots last,
// sorts triangles by their smallest vertex, and brings the vertices of an
// edge closer in memory than the insertion order did.
void spatial_reordering_keeps_the_triangulation(void **) {
    auto pts = test::random_points(20000, 29);
    std::vector<double> w(pts.size(), 0.0);
    for (size_t i = 0; i < 20; ++i) w[i * 11] = -0.5;  // hidden
    tri::Triangulation t = build(pts, &w);
    // Shuffle the slots first (by removing and re-inserting), so the test
    // does not start from an order that is already spatial.
    std::mt19937_64 rng(5);
    for (int i = 0; i < 3000; ++i) {
        int32_t v = static_cast<int32_t>(rng() % static_cast<uint64_t>(t.vertex_slots()));
        if (!t.in_triangulation(v)) continue;
        const Vec3 x = t.direction(v);
        const int32_t id = t.id(v);
        t.remove(v);
        t.insert(x, 0.0, id + 1000000);
    }
    t.compact();
    assert_int_equal(t.triangle_count(), t.triangle_slots());  // compact() leaves no free slot
    auto mean_edge_gap = [](const tri::Triangulation &m) {
        double sum = 0;
        for (int32_t f = 0; f < m.triangle_count(); ++f)
            for (int k = 0; k < 3; ++k) sum += std::abs(m.vertex(f, k) - m.vertex(f, (k + 1) % 3));
        return sum / (3.0 * m.triangle_count());
    };
    const auto before = triangle_set(t);
    std::vector<Vec3> where(static_cast<size_t>(t.vertex_slots()));
    for (int32_t v = 0; v < t.vertex_slots(); ++v) where[v] = t.lifted(v);
    const double gap_before = mean_edge_gap(t);
    // The copy gathered on several threads and the moves in place give the
    // same slots, triangles, neighbours and incident triangles.
    tri::Triangulation in_place = t;
    Context serial;
    serial.set_threads(1);
    const std::vector<int32_t> old_slot_in_place = in_place.reorder_spatially(serial, tri::Triangulation::Reorder::in_place);
    Context ctx;
    ctx.set_threads(3);
    const std::vector<int32_t> old_slot = t.reorder_spatially(ctx);
    assert_true(old_slot == old_slot_in_place);
    assert_int_equal(t.triangle_slots(), in_place.triangle_slots());
    assert_int_equal(t.vertex_slots(), in_place.vertex_slots());
    for (int32_t f = 0; f < t.triangle_slots(); ++f)
        for (int k = 0; k < 3; ++k) {
            assert_int_equal(t.vertex(f, k), in_place.vertex(f, k));
            assert_int_equal(t.neighbour(f, k), in_place.neighbour(f, k));
        }
    for (int32_t v = 0; v < t.vertex_slots(); ++v) {
        assert_int_equal(t.id(v), in_place.id(v));
        assert_int_equal(t.incident_triangle(v), in_place.incident_triangle(v));
        assert_memory_equal(t.lifted(v).data(), in_place.lifted(v).data(), sizeof(Vec3));
    }
    expect_valid(t);
    assert_true(triangle_set(t) == before);
    assert_int_equal(static_cast<int64_t>(old_slot.size()), t.vertex_slots());
    bool seen_outside = false;
    for (int32_t v = 0; v < t.vertex_slots(); ++v) {
        assert_memory_equal(t.lifted(v).data(), where[old_slot[v]].data(), sizeof(Vec3));
        if (!t.in_triangulation(v)) seen_outside = true;
        else assert_false(seen_outside);  // slots outside the triangulation come last
    }
    assert_true(seen_outside);
    int32_t last = -1;
    for (int32_t f = 0; f < t.triangle_count(); ++f) {
        const int32_t lo = std::min({t.vertex(f, 0), t.vertex(f, 1), t.vertex(f, 2)});
        assert_true(lo >= last);
        last = lo;
    }
    assert_true(mean_edge_gap(t) < 0.1 * gap_before);
}

// A snapshot puts the triangulation back exactly: the same slots, triangles,
// neighbours and incident triangles (star order), after moves, insertions
// and removals; taken on several threads (a mesh of more than two of its
// copying chunks).
// Slot for slot the same triangles, neighbours, ids and lifted points.
bool same_slots(const tri::Triangulation &a, const tri::Triangulation &b) {
    if (a.triangle_slots() != b.triangle_slots() || a.vertex_slots() != b.vertex_slots()) return false;
    for (int32_t f = 0; f < a.triangle_slots(); ++f)
        for (int k = 0; k < 3; ++k)
            if (a.vertex(f, k) != b.vertex(f, k) || (!a.is_free(f) && a.neighbour(f, k) != b.neighbour(f, k)))
                return false;
    for (int32_t v = 0; v < a.vertex_slots(); ++v)
        if (a.id(v) != b.id(v) || std::memcmp(a.lifted(v).data(), b.lifted(v).data(), sizeof(Vec3)) != 0 ||
            a.star(v) != b.star(v))
            return false;
    return true;
}

void snapshot_restores_exactly(void **) {
    tri::Triangulation t = build(test::random_points(40000, 31));
    auto same = same_slots;
    const tri::Triangulation original = t;
    Context ctx;
    ctx.set_threads(3);
    tri::Triangulation::Snapshot s = t.snapshot(ctx);
    std::mt19937_64 rng(9);
    for (int i = 0; i < 500; ++i) {
        const int32_t v = static_cast<int32_t>(rng() % 5000);
        if (!t.in_triangulation(v)) continue;
        if (i % 3 == 0) t.remove(v);
        else t.move(v, geom::normalized(t.direction(v) + Vec3{1e-3, -2e-3, 1e-3}));
        if (i % 5 == 0) t.insert(geom::normalized(Vec3{double(i), 1.0, -3.0}), 0.0, 10000 + i);
    }
    assert_false(same(t, original));
    t.restore(std::move(s));
    expect_valid(t);
    assert_true(same(t, original));
}

// The room reserve_extra makes (copied on three threads) holds the
// triangulation as it was, and takes the vertices it was made for without
// another reallocation.
void reserved_room_keeps_the_triangulation(void **) {
    tri::Triangulation t = build(test::random_points(40000, 33));
    const tri::Triangulation original = t;
    Context ctx;
    ctx.set_threads(3);
    t.reserve_extra(ctx, 0.05, 0.02);
    assert_true(t.vertex_capacity() >= static_cast<size_t>(1.05 * original.vertex_slots()));
    assert_true(same_slots(t, original));
    expect_valid(t);
    const size_t room = t.vertex_capacity();
    for (int i = 0; i < 1000; ++i)
        t.insert(geom::normalized(Vec3{std::sin(i), std::cos(3.0 * i), 0.1 * i - 50}), 0.0, 50000 + i);
    expect_valid(t);
    assert_int_equal(t.vertex_capacity(), room);
    t.reserve_extra(ctx, 0.0, 0.0);  // room enough already: nothing moves
    assert_int_equal(t.vertex_capacity(), room);
}

void power_cells_and_orthocentres(void **) {
    auto pts = test::random_points(3000, 29);
    tri::Triangulation t = build(pts);
    double total = 0;
    for (int32_t v = 0; v < t.vertex_slots(); ++v) {
        auto cell = t.power_cell(v);
        Vec3 x = t.direction(v);
        // Fan area around the generator; with zero weights every generator lies in its cell.
        for (size_t i = 0; i < cell.size(); ++i) {
            double a = geom::signed_triangle_area(x, cell[i], cell[(i + 1) % cell.size()]);
            assert_true(a > 0);  // counter-clockwise and convex around x
            total += a;
        }
    }
    assert_true(std::fabs(total - 4 * M_PI) < 1e-9);
    // Orthocentres are equidistant from the triangle's vertices when weights are 0,
    // and edge orthocentres are midpoints.
    for (int32_t f = 0; f < t.triangle_count(); f += 7) {
        Vec3 c = t.orthocentre(f);
        double d0 = geom::arc_length(c, t.direction(t.vertex(f, 0)));
        for (int k = 1; k < 3; ++k)
            assert_true(std::fabs(geom::arc_length(c, t.direction(t.vertex(f, k))) - d0) < 1e-12);
        Vec3 m = t.edge_orthocentre(f, 0);
        double l1 = geom::arc_length(m, t.direction(t.vertex(f, 1)));
        double l2 = geom::arc_length(m, t.direction(t.vertex(f, 2)));
        assert_true(std::fabs(l1 - l2) < 1e-12);
    }
}

void weighted_edge_orthocentre_is_on_the_bisector(void **) {
    auto pts = test::random_points(2000, 31);
    std::vector<double> w(pts.size());
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3);
    for (auto &x : w) x = u(rng);
    tri::Triangulation t = build(pts, &w);
    for (int32_t f = 0; f < t.triangle_count(); ++f) {
        for (int k = 0; k < 3; ++k) {
            Vec3 p = t.edge_orthocentre(f, k);
            const Vec3 &qi = t.lifted(t.vertex(f, (k + 1) % 3)), &qj = t.lifted(t.vertex(f, (k + 2) % 3));
            assert_true(std::fabs(geom::dot(p, qi - qj)) < 1e-14);  // on the bisector plane
            // and on the primal arc: coplanar with the two generators
            assert_true(std::fabs(geom::dot(p, geom::cross(qi, qj))) < 1e-14);
        }
        // The orthocentre lies on all three bisector planes.
        Vec3 c = t.orthocentre(f);
        for (int k = 0; k < 3; ++k) {
            const Vec3 &qi = t.lifted(t.vertex(f, k)), &qj = t.lifted(t.vertex(f, (k + 1) % 3));
            assert_true(std::fabs(geom::dot(c, qi - qj)) < 1e-14);
        }
    }
}

void insert_remove_move_and_reweight(void **) {
    auto pts = test::random_points(3000, 37);
    tri::Triangulation t = build(pts);
    std::mt19937_64 rng(41);
    // Insert more points.
    auto extra = test::random_points(500, 43);
    for (size_t i = 0; i < extra.size(); ++i) t.insert(extra[i], 0.0, int32_t(pts.size() + i));
    expect_valid(t);
    assert_int_equal(t.vertex_count(), 3500);
    // Remove every fifth vertex.
    for (int32_t v = 0; v < t.vertex_slots(); v += 5) t.remove(v);
    expect_valid(t);
    assert_int_equal(t.vertex_count(), 3500 - 700);
    // Move vertices by small random amounts.
    std::normal_distribution<double> g(0, 0.01);
    for (int32_t v = 1; v < t.vertex_slots(); v += 3) {
        if (!t.in_triangulation(v)) continue;
        Vec3 d = t.direction(v);
        t.move(v, geom::normalized(d + Vec3{g(rng), g(rng), g(rng)}));
    }
    expect_valid(t);
    // Reweight: small changes keep everything; a large negative weight buries.
    for (int32_t v = 2; v < t.vertex_slots(); v += 7)
        if (t.in_triangulation(v)) t.set_weight(v, 1e-4);
    expect_valid(t);
    int32_t victim = 3;
    while (!t.in_triangulation(victim)) ++victim;
    auto buried = t.set_weight(victim, -0.5);
    assert_int_equal(buried.size(), 1);
    assert_int_equal(buried[0], victim);
    assert_false(t.in_triangulation(victim));
    expect_valid(t);
    // A heavy vertex buries neighbours, and says which.
    int32_t heavy = 4;
    while (!t.in_triangulation(heavy)) ++heavy;
    auto around = t.set_weight(heavy, 0.5);
    assert_true(!around.empty());
    for (int32_t u : around) assert_false(t.in_triangulation(u));
    expect_valid(t);
}

// A point tried and taken out again leaves the triangulation as it was
// (the same triangles, every other vertex where it was): how the
// optimisation undoes a vertex it put at an obtuse corner and moved a few
// steps (optim/gamma_corners.cpp, try_corner_vertex). On an icosahedral grid,
// where the triangles across cocircular quadruples are those of the tie
// rule, and on random points; tried at circumcentres (cocircular with the
// triangle's corners), on edges' chords and near vertices.
void a_point_tried_and_removed_leaves_the_triangulation(void **) {
    for (int input = 0; input < 2; ++input) {
        const std::vector<Vec3> pts = input == 0 ? test::icosahedral_points(4) : test::random_points(3000, 53);
        tri::Triangulation t = build(pts);
        const auto before = triangle_set(t);
        std::vector<Vec3> where(static_cast<size_t>(t.vertex_slots()));
        for (int32_t v = 0; v < t.vertex_slots(); ++v) where[v] = t.lifted(v);
        std::mt19937_64 rng(61);
        std::uniform_real_distribution<double> share(0.0, 1.0);
        int tried = 0;
        for (int i = 0; i < 300; ++i) {
            const int32_t f = static_cast<int32_t>(rng() % static_cast<uint64_t>(t.triangle_slots()));
            if (t.is_free(f)) continue;
            const Vec3 a = t.direction(t.vertex(f, 0)), b = t.direction(t.vertex(f, 1)), c = t.direction(t.vertex(f, 2));
            Vec3 at;
            switch (i % 3) {
            case 0: at = geom::normalized(geom::cross(b - a, c - a)); break;      // circumcentre
            case 1: at = geom::normalized(a + share(rng) * (b - a)); break;        // on an edge's chord
            default: at = geom::normalized(a + 1e-3 * (b + c - 2.0 * a)); break;  // near a vertex
            }
            std::vector<int32_t> buried;
            const int32_t v = t.insert(at, 0.0, 1000000 + i, &buried, f);
            assert_true(buried.empty());
            assert_true(t.in_triangulation(v));
            for (int step = 0; step < 3; ++step) {
                const Vec3 to = geom::normalized(t.direction(v) + 0.3 * share(rng) * (b - a) + 0.2 * share(rng) * (c - a));
                assert_true(t.move(v, to).empty());
            }
            t.remove(v);
            expect_valid(t);
            ++tried;
        }
        assert_true(tried > 200);
        assert_true(triangle_set(t) == before);
        for (size_t v = 0; v < where.size(); ++v)
            assert_memory_equal(t.lifted(static_cast<int32_t>(v)).data(), where[v].data(), sizeof(Vec3));
    }
}

// A point that hid vertices, taken out again with them put back
// (restore_hidden), and a vertex removed to make room for a point and put
// back after it (restore_removed): the triangulation as it was. How the
// optimisation undoes a vertex at an obtuse corner among weighted vertices,
// and one that took the place of a vertex too near it (try_corner_vertex,
// try_corner_relocation). Weighted random points, the point tried heavy
// enough to hide its neighbours.
void hidden_and_removed_vertices_put_back(void **) {
    const std::vector<Vec3> pts = test::random_points(3000, 59);
    std::vector<double> w(pts.size());
    std::mt19937_64 rng(67);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3), share(0.0, 1.0);
    for (auto &x : w) x = u(rng);
    tri::Triangulation t = build(pts, &w);
    const auto before = triangle_set(t);
    std::vector<Vec3> where(static_cast<size_t>(t.vertex_slots()));
    for (int32_t v = 0; v < t.vertex_slots(); ++v) where[v] = t.lifted(v);
    int64_t hid = 0, replaced = 0;
    for (int i = 0; i < 200; ++i) {
        const int32_t f = static_cast<int32_t>(rng() % static_cast<uint64_t>(t.triangle_slots()));
        if (t.is_free(f)) continue;
        const int32_t a = t.vertex(f, 0);
        const Vec3 at = geom::normalized(t.direction(a) + 0.3 * (t.direction(t.vertex(f, 1)) - t.direction(a)) +
                                         0.3 * share(rng) * (t.direction(t.vertex(f, 2)) - t.direction(a)));
        const bool make_room = i % 2 == 1;  // remove a first, as try_corner_relocation does
        const int32_t near_a = make_room ? t.remove(a) : f;
        std::vector<int32_t> buried;
        const int32_t v = t.insert(at, make_room ? 0.0 : 0.02, 2000000 + i, &buried, near_a);
        hid += static_cast<int64_t>(buried.size());
        const int32_t near = t.remove(v);
        for (int32_t b : buried) t.restore_hidden(b, near);
        if (make_room) t.restore_removed(a, near), ++replaced;
        expect_valid(t);
    }
    assert_true(hid > 100 && replaced > 50);
    assert_true(triangle_set(t) == before);
    for (size_t v = 0; v < where.size(); ++v)
        assert_memory_equal(t.lifted(static_cast<int32_t>(v)).data(), where[v].data(), sizeof(Vec3));
}

// Points inserted into the slots of removed vertices (the re-seeding of
// defects): the same triangles as fresh slots would give, the slot count
// unchanged, each slot with its new point and id; a slot that is not
// removed is refused, leaving the triangulation as it was.
void insertion_into_removed_slots(void **) {
    const std::vector<Vec3> pts = test::random_points(2000, 71);
    tri::Triangulation reused = build(pts), fresh = build(pts);
    std::vector<int32_t> slots;
    for (int32_t v = 0; v < reused.vertex_slots() && slots.size() < 300; v += 5) {
        reused.remove(v), fresh.remove(v);
        slots.push_back(v);
    }
    const std::vector<Vec3> more = test::random_points(300, 79);
    const int32_t n_slots = reused.vertex_slots();
    for (size_t i = 0; i < more.size(); ++i) {
        const int32_t id = 5000 + static_cast<int32_t>(i);
        const int32_t v = reused.insert_into_removed(slots[i], more[i], 0.0, id);
        assert_int_equal(v, slots[i]);
        assert_int_equal(reused.id(v), id);
        assert_true(reused.in_triangulation(v));
        fresh.insert(more[i], 0.0, id);
    }
    expect_valid(reused);
    assert_int_equal(reused.vertex_slots(), n_slots);
    assert_int_equal(reused.vertex_count(), fresh.vertex_count());
    // The same triangles, by the ids of their vertices.
    auto by_ids = [](const tri::Triangulation &t) {
        std::set<std::array<int32_t, 3>> out;
        for (int32_t f = 0; f < t.triangle_slots(); ++f) {
            if (t.is_free(f)) continue;
            std::array<int32_t, 3> k{t.id(t.vertex(f, 0)), t.id(t.vertex(f, 1)), t.id(t.vertex(f, 2))};
            std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
            out.insert(k);
        }
        return out;
    };
    assert_true(by_ids(reused) == by_ids(fresh));
    const auto before = triangle_set(reused);
    int32_t live = 0;
    while (!reused.in_triangulation(live)) ++live;
    bool refused = false;
    try {
        reused.insert_into_removed(live, more[0], 0.0, 9999);
    } catch (const Error &) {
        refused = true;
    }
    assert_true(refused);
    assert_true(triangle_set(reused) == before);
}

// Removing vertices whose links lie along one great circle (a meridian
// through the pole, a latitude-free grid of meridians): every hull ear of
// such a link can be flat, and removal must still leave the exact regular
// triangulation of what is left.
void removal_with_links_on_one_great_circle(void **) {
    std::vector<Vec3> pts;
    for (int m = 0; m < 24; ++m)          // 24 meridians, every 10 degrees of latitude
        for (int k = -8; k <= 8; ++k) pts.push_back(geom::unit_from_lonlat_deg(15.0 * m, 10.0 * k));
    pts.push_back(geom::unit_from_lonlat_deg(0, 90));
    pts.push_back(geom::unit_from_lonlat_deg(0, -90));
    const size_t n = pts.size();
    tri::Triangulation t = build(pts);
    expect_complete(t, n);
    // The poles (links: 24 points on one latitude circle, each on a meridian
    // great circle with the pole), then a whole meridian, vertex by vertex.
    int64_t removed = 0;
    for (int32_t v = 0; v < t.vertex_slots(); ++v) {
        const int32_t id = t.id(v);
        if (id < 0 || !t.in_triangulation(v)) continue;
        if (size_t(id) >= n - 2 || id < 17) {
            t.remove(v);
            ++removed;
            expect_valid(t);
        }
    }
    assert_int_equal(removed, 19);
    assert_int_equal(t.vertex_count(), static_cast<int64_t>(n) - 19);
    assert_int_equal(t.triangle_count(), 2 * (static_cast<int64_t>(n) - 19) - 4);
}

void flips_keep_a_valid_sphere(void **) {
    auto pts = test::random_points(500, 47);
    tri::Triangulation t = build(pts);
    int flipped = 0;
    for (int32_t f = 0; f < t.triangle_count(); f += 3)
        if (t.flip(f, 0)) ++flipped;
    assert_true(flipped > 0);
    // Flipped edges are no longer regular: the sphere stays valid, regularity goes.
    int irregular = 0;
    for (int32_t f = 0; f < t.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) irregular += !t.is_locally_regular(f, k);
    assert_true(irregular > 0);
}

// The vertex whose power cell holds x, by brute force: the lifted hull's
// vertex furthest along x. Its height along x.
double furthest_along(const tri::Triangulation &t, const Vec3 &x) {
    double best = -HUGE_VAL;
    for (int32_t v = 0; v < t.vertex_slots(); ++v)
        if (t.in_triangulation(v)) best = std::max(best, geom::dot(t.lifted(v), x));
    return best;
}

bool neighbours(const tri::Triangulation &t, int32_t a, int32_t b) {
    bool found = false;
    t.for_each_neighbour(a, [&](int32_t u) { found = found || u == b; });
    return found;
}

// cell_holding against brute force on a weighted triangulation (some
// points hidden), from every kind of start; cells_along_arc from a's cell
// to b's through neighbours, holding every point of the arc sampled.
void cell_walks_find_the_power_cells(void **) {
    const auto pts = test::random_points(4000, 91);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> weight(-2e-4, 2e-4);  // about the spacing squared
    std::vector<double> w(pts.size());
    for (double &x : w) x = weight(rng);
    const tri::Triangulation t = build(pts, &w);
    const auto probes = test::random_points(500, 92);
    int32_t start = -1;
    for (const Vec3 &x : probes) {
        const int32_t v = tri::cell_holding(t, x, start);
        assert_true(t.in_triangulation(v));
        assert_true(geom::dot(t.lifted(v), x) >= furthest_along(t, x) - 1e-14);
        start = v;  // (the next walk starts where this one ended)
    }
    for (size_t i = 0; i + 1 < probes.size(); i += 25) {
        const Vec3 &a = probes[i], &b = probes[i + 1];
        if (geom::dot(a, b) < -0.9) continue;  // (a minor arc of nearly half the sphere is ill defined)
        const std::vector<int32_t> cells = tri::cells_along_arc(t, a, b);
        assert_true(!cells.empty());
        assert_true(geom::dot(t.lifted(cells.front()), a) >= furthest_along(t, a) - 1e-14);
        assert_true(geom::dot(t.lifted(cells.back()), b) >= furthest_along(t, b) - 1e-14);
        for (size_t k = 1; k < cells.size(); ++k) assert_true(neighbours(t, cells[k - 1], cells[k]));
        for (int k = 0; k <= 200; ++k) {
            const double f = k / 200.0;
            const Vec3 p = geom::normalized((1 - f) * a + f * b);
            const double top = furthest_along(t, p);
            // A cell holding p is on the list (on a cell boundary, either).
            bool listed = false;
            for (int32_t c : cells) listed = listed || geom::dot(t.lifted(c), p) >= top - 1e-14;
            assert_true(listed);
        }
    }
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cell_walks_find_the_power_cells),
        cmocka_unit_test(random_points_small_and_large),
        cmocka_unit_test(a_million_random_points),
        cmocka_unit_test(icosahedral_grids_to_level_8),
        cmocka_unit_test(cocircular_latitude_circles_and_poles),
        cmocka_unit_test(points_on_three_great_circles),
        cmocka_unit_test(antipodal_pairs),
        cmocka_unit_test(near_duplicates_are_distinct_vertices),
        cmocka_unit_test(exact_duplicates_are_named),
        cmocka_unit_test(exact_duplicates_in_parallel_rounds_are_named),
        cmocka_unit_test(coincident_points_with_other_weights),
        cmocka_unit_test(clustered_points_in_parallel_rounds),
        cmocka_unit_test(one_hemisphere_or_great_circle_is_rejected),
        cmocka_unit_test(points_crowded_at_the_band_axis),
        cmocka_unit_test(weights_hide_points),
        cmocka_unit_test(same_result_for_any_thread_count),
        cmocka_unit_test(build_room_holds_a_callers_temporaries),
        cmocka_unit_test(big_arrays_start_on_huge_pages),
        cmocka_unit_test(insertion_order_does_not_change_the_triangles),
        cmocka_unit_test(territories_insert_as_the_serial_path_would),
        cmocka_unit_test(territory_insertion_refuses_without_changes),
        cmocka_unit_test(removal_with_links_on_one_great_circle),
        cmocka_unit_test(spatial_reordering_keeps_the_triangulation),
        cmocka_unit_test(snapshot_restores_exactly),
        cmocka_unit_test(reserved_room_keeps_the_triangulation),
        cmocka_unit_test(power_cells_and_orthocentres),
        cmocka_unit_test(weighted_edge_orthocentre_is_on_the_bisector),
        cmocka_unit_test(insert_remove_move_and_reweight),
        cmocka_unit_test(a_point_tried_and_removed_leaves_the_triangulation),
        cmocka_unit_test(hidden_and_removed_vertices_put_back),
        cmocka_unit_test(insertion_into_removed_slots),
        cmocka_unit_test(flips_keep_a_valid_sphere),
    };
    return cmocka_run_group_tests_name("triangulation", tests, nullptr, nullptr);
}
