// Engine tests: the weighted primal-dual optimisation (paper section 6).
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "optim/chord_bounds.hpp"
#include "optim/local_quality.hpp"
#include "optim/mesh_state.hpp"
#include "optim/optimise.hpp"
#include "optim/shape_sweeps.hpp"
#include "optim/slide.hpp"
#include "optim/star_graph.hpp"
#include "optim/topology.hpp"
#include "optim/weight_sweeps.hpp"
#include "refine/surface.hpp"
#include "support/feature_parts.hpp"
#include "tri/validate.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;
using optim::Generator;

namespace {

Generator generator(const Vec3 &x, double w) { return {geom::normalized(x), tri::lifted_scale(w)}; }

// dQ^P/dw_a against central differences, on small random triangles with
// random weights of the size the optimisation gives them (|w| ~ 0.1 h^2).
void weight_derivative_matches_finite_differences(void **) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    int checked = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec3 c = geom::normalized({u(rng), u(rng), u(rng)});
        const double h = 1e-3 * (1 + 20 * std::abs(u(rng)));  // 6 to 130 km
        Vec3 e1 = geom::normalized(geom::cross(c, {0.3, 0.5, 0.7})), e2 = geom::cross(c, e1);
        auto around = [&](double angle, double r) {
            return c + (h * r * std::cos(angle)) * e1 + (h * r * std::sin(angle)) * e2;
        };
        const double t0 = u(rng);
        Generator a = generator(around(t0, 0.6 + 0.2 * u(rng)), 0.1 * h * h * u(rng));
        Generator b = generator(around(t0 + 2.1 + 0.3 * u(rng), 0.6 + 0.2 * u(rng)), 0.1 * h * h * u(rng));
        Generator d = generator(around(t0 + 4.2 + 0.3 * u(rng), 0.6 + 0.2 * u(rng)), 0.1 * h * h * u(rng));
        const double w = 2 * (1 - 1 / a.s);
        double q = 0;
        const double analytic = optim::primal_dual_weight_derivative(a, b, d, &q);
        const double dw = 1e-4 * h * h;
        Generator plus = a, minus = a;
        plus.s = tri::lifted_scale(w + dw), minus.s = tri::lifted_scale(w - dw);
        const double numeric = (optim::triangle_cost(plus, b, d).primal_dual -
                                optim::triangle_cost(minus, b, d).primal_dual) / (2 * dw);
        // Relative to the derivative's natural scale 1/h^2.
        if (std::abs(analytic - numeric) * h * h > 1e-5)
            fail_msg("trial %d: analytic %.10g, numeric %.10g (h = %g)", trial, analytic, numeric, h);
        assert_true(std::abs(q - optim::triangle_cost(a, b, d).primal_dual) < 1e-15);
        ++checked;
    }
    assert_int_equal(checked, 2000);
}

// An equilateral triangle with equal weights staggers perfectly: Q^T = Q^P = 1.
void equilateral_triangle_scores_one(void **) {
    const Vec3 c = geom::normalized({1, 2, 3});
    Vec3 e1 = geom::normalized(geom::cross(c, {0, 0, 1})), e2 = geom::cross(c, e1);
    Generator g[3];
    for (int k = 0; k < 3; ++k) {
        const double angle = 2 * M_PI * k / 3;
        g[k] = generator(c + 0.01 * std::cos(angle) * e1 + 0.01 * std::sin(angle) * e2, 0.0);
    }
    const optim::TriangleCost q = optim::triangle_cost(g[0], g[1], g[2]);
    assert_true(std::abs(q.area_length - 1) < 1e-9);
    assert_true(std::abs(q.primal_dual - 1) < 1e-9);
    // Inverted: Q^T negative.
    assert_true(optim::triangle_cost(g[0], g[2], g[1]).area_length < 0);
    // A heavier vertex pulls the crossing of its edges away from itself.
    Generator heavy = g[0];
    heavy.s = tri::lifted_scale(2e-5);
    assert_true(optim::edge_crossing_share(heavy, g[1]) > 0.5);
    assert_true(std::abs(optim::edge_crossing_share(g[0], g[1]) - 0.5) < 1e-9);
}

// Sliding keeps the point on the polyline and finds the nearest point along
// it, many segments away, around corners and across the end of a ring.
void slide_stays_on_the_polyline(void **) {
    features::Network net;
    std::vector<double> lon, lat;
    // East along the equator to lon -0.1, then north along that meridian.
    for (int i = 0; i < 200; ++i)
        lon.push_back(i < 100 ? -10 + 0.1 * i : -0.1), lat.push_back(i < 100 ? 0 : 0.1 * (i - 99));
    std::vector<int64_t> offsets = {0, 200};
    std::vector<int32_t> closed = {0}, kind = {3};
    features::PartsInput in;
    in.n_points = 200, in.lon_deg = lon.data(), in.lat_deg = lat.data();
    in.n_parts = 1, in.part_offsets = offsets.data(), in.closed = closed.data(), in.kind = kind.data();
    net.add(in);
    // From segment 5, a target beside the northward leg, 30 segments up it.
    const Vec3 target = geom::unit_from_lonlat_deg(-0.05, 3.0);
    optim::PointOnGamma p = optim::slide_along(net, 5, target);
    double lo, la;
    geom::lonlat_deg_from_unit(p.x, lo, la);
    assert_true(p.segment > 100);
    assert_true(geom::distance_to_arc(p.x, net.segment_a(p.segment), net.segment_b(p.segment)) < 1e-14);
    assert_true(std::abs(lo - -0.1) < 1e-6);
    assert_true(std::abs(la - 3.0) < 1e-3);
    // The open end: beyond the first point it stays at the first point.
    p = optim::slide_along(net, 3, geom::unit_from_lonlat_deg(-20, 0));
    assert_int_equal(p.segment, 0);
    assert_true(geom::norm(p.x - net.point(0)) < 1e-15);
}

tri::Triangulation uniform_mesh(Context &ctx, double h) {
    tri::Triangulation tri = refine::icosahedron(ctx);
    refine::SurfaceOptions so;
    refine::refine_surface(ctx, tri, [h](const Vec3 &) { return h; }, so, 12);
    tri.compact();
    return tri;
}

// The colouring is proper: no two neighbours share a colour.
void colouring_separates_neighbours(void **) {
    Context ctx;
    tri::Triangulation tri = uniform_mesh(ctx, 0.06);
    optim::StarGraph g(ctx, tri);
    std::vector<int> colour(static_cast<size_t>(g.vertex_slots()), -1);
    for (size_t c = 0; c < g.colours().size(); ++c)
        for (int32_t v : g.colours()[c]) colour[v] = static_cast<int>(c);
    int64_t coloured = 0;
    for (int32_t v = 0; v < g.vertex_slots(); ++v) {
        if (g.degree(v) == 0) continue;
        ++coloured;
        assert_true(colour[v] >= 0);
        for (int k = 0; k < g.degree(v); ++k) assert_int_not_equal(colour[v], colour[g.link(v)[k]]);
    }
    assert_int_equal(coloured, tri.vertex_count());
    assert_true(g.colours().size() <= 12);
}

// After optimising, the triangulation is still the exact regular
// triangulation of its points, every triangle holds its orthocentre, and
// the worst triangle is better than before.
void optimised_mesh_is_regular_and_better(void **) {
    Context ctx;
    ctx.set_threads(2);
    const double h = 0.04;  // 255 km
    tri::Triangulation tri = uniform_mesh(ctx, h);
    auto worst = [](const tri::Triangulation &t) {
        double qt = 2;
        int64_t bad = 0;
        for (int32_t f = 0; f < t.triangle_slots(); ++f) {
            if (t.is_free(f)) continue;
            Generator g[3];
            for (int k = 0; k < 3; ++k) g[k] = {t.direction(t.vertex(f, k)), geom::norm(t.lifted(t.vertex(f, k)))};
            qt = std::min(qt, optim::triangle_cost(g[0], g[1], g[2]).area_length);
            const Vec3 o = t.orthocentre(f);
            for (int k = 0; k < 3; ++k)
                if (geom::dot(geom::cross(g[(k + 1) % 3].x, g[(k + 2) % 3].x), o) < 0) { ++bad; break; }
        }
        return std::make_pair(qt, bad);
    };
    auto before = worst(tri);
    std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
    optim::OptimiseOptions o;
    optim::OptimiseStats stats =
        optim::optimise(ctx, tri, on_segment, nullptr, [h](const Vec3 &) { return h; }, o);
    tri.compact();
    const std::string problem = tri::check_triangulation(tri);
    if (!problem.empty()) fail_msg("%s", problem.c_str());
    auto after = worst(tri);
    assert_true(before.second > 0);
    assert_int_equal(after.second, 0);
    assert_true(after.first > before.first + 0.05);
    assert_true(stats.moves > 0);
    assert_true(stats.outer_iterations >= 1 && stats.outer_iterations <= o.outer_iterations);
}

// The near-Gamma flags kept between calls equal flags found anew after a
// vertex moved onto Gamma (stamped), and another was taken out and a new
// one put into its slot (nothing stamped: the id tells).
void kept_near_gamma_flags_equal_flags_found_anew(void **) {
    Context ctx;
    ctx.set_threads(2);
    const double h = 0.02;
    tri::Triangulation tri = uniform_mesh(ctx, h);
    features::Network net;  // a closed coastline round a 30 x 30 degree island
    assert_int_equal(testing::add(net, {{{-20, 10, 10, -20}, {-10, -10, 20, 20}, 1, UM_FEATURE_COASTLINE}}), UM_OK);
    std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
    const refine::SpacingRadians spacing = [h](const Vec3 &) { return h; };
    const optim::OptimiseOptions o;
    optim::detail::MeshState kept(ctx, tri, on_segment, &net, spacing, o);
    kept.load_spacing();
    ++kept.clock;  // (the slots' first stamps, older than the first call)
    kept.flag_near_gamma();
    auto flagged = [](const std::vector<uint8_t> &f) { return std::count(f.begin(), f.end(), 1); };
    const auto before = flagged(kept.near_gamma);
    ++kept.clock;
    // The vertex nearest (lon 90, lat 0), far from the island, and the one
    // nearest (lon 150, lat 0): the first moves onto the island's coast, the
    // second's slot gets a new vertex beside the coast.
    auto nearest = [&](const Vec3 &x) {
        int32_t best = -1;
        for (int32_t v = 0; v < tri.vertex_slots(); ++v)
            if (tri.in_triangulation(v) && (best < 0 || geom::dot(tri.direction(v), x) > geom::dot(tri.direction(best), x)))
                best = v;
        return best;
    };
    const int32_t far = nearest(geom::unit_from_lonlat_deg(150, 0));
    const int32_t near_slot = tri.remove(far);
    int32_t next_id = 0;
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) next_id = std::max(next_id, tri.id(v) + 1);
    const int32_t added = tri.insert_into_removed(far, geom::unit_from_lonlat_deg(-5, -10.2), 0.0, next_id, nullptr, near_slot);
    assert_int_equal(added, far);
    kept.load_spacing();
    const int32_t moved = nearest(geom::unit_from_lonlat_deg(90, 0));
    kept.set_generator(moved, generator(geom::unit_from_lonlat_deg(10.2, 5), 0.0));
    kept.changed_at[moved] = kept.clock;
    kept.load_spacing();
    kept.flag_near_gamma();
    optim::detail::MeshState anew(ctx, tri, on_segment, &net, spacing, o);
    anew.load_spacing();
    anew.flag_near_gamma();
    assert_true(kept.near_gamma == anew.near_gamma);
    assert_true(kept.near_gamma[far] && kept.near_gamma[moved]);
    assert_int_equal(flagged(kept.near_gamma), before + 2);
}

// The root-free chord bounds of the edge scans never contradict the chord
// between the two directions as the scans compute it, and decide most
// edges away from the limit (random weights of the optimisation's size,
// limits from 0.3 to 1.5 times the chord, and at the chord itself).
void chord_bounds_agree_with_the_chord(void **) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    int decided = 0, tried = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double h = 1e-4 * (1 + 100 * std::abs(u(rng)));
        const Vec3 a = geom::normalized({u(rng), u(rng), u(rng)});
        const Vec3 b = geom::normalized(a + h * Vec3{u(rng), u(rng), u(rng)});
        const Generator ga = generator(a, 0.1 * h * h * u(rng)), gb = generator(b, 0.1 * h * h * u(rng));
        const optim::ChordBounds bounds(ga.lifted(), gb.lifted());
        const double chord = geom::norm(geom::normalized(ga.lifted()) - geom::normalized(gb.lifted()));
        for (double limit : {0.3 * chord, 0.9 * chord, chord, std::nextafter(chord, 2.0), 1.1 * chord, 1.5 * chord}) {
            ++tried;
            if (bounds.surely_at_least(limit)) assert_true(chord >= limit), ++decided;
            if (bounds.surely_below(limit)) assert_true(chord < limit), ++decided;
        }
    }
    assert_true(decided > tried / 2);
    // Limits no chord can be below, or above: the answers stay safe.
    const double kInf = std::numeric_limits<double>::infinity(), kNaN = std::numeric_limits<double>::quiet_NaN();
    const optim::ChordBounds bounds(Vec3{1, 0, 0}, Vec3{0, 1, 0});
    for (double limit : {0.0, -1.0, -kInf, kNaN}) assert_true(bounds.surely_at_least(limit));
    for (double limit : {0.0, -1.0, kNaN}) assert_false(bounds.surely_below(limit));
    assert_false(bounds.surely_at_least(kInf));
    assert_true(bounds.surely_below(kInf));
}

// The stopping test's summary, kept in blocks between calls, equals one
// made anew (bit for bit) after vertices moved and were weighted (with
// their change stamped, as every pass does) and edges flipped (nothing
// stamped: the slots' vertices tell).
void a_kept_summary_equals_one_made_anew(void **) {
    Context ctx;
    ctx.set_threads(3);
    const double h = 0.02;
    tri::Triangulation tri = uniform_mesh(ctx, h);
    std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
    const refine::SpacingRadians spacing = [h](const Vec3 &) { return h; };
    const optim::OptimiseOptions o;
    optim::detail::MeshState kept(ctx, tri, on_segment, nullptr, spacing, o);
    kept.load_spacing();
    auto same = [](const optim::detail::Summary &a, const optim::detail::Summary &b) {
        return a.qt_min == b.qt_min && a.qt_mean == b.qt_mean && a.qp_min == b.qp_min && a.qp_mean == b.qp_mean &&
               a.largest_angle_cosine == b.largest_angle_cosine;
    };
    ++kept.clock;  // (the slots' first stamps, older than the first call)
    const optim::detail::Summary first = kept.summarise();
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int round = 0; round < 3; ++round) {
        ++kept.clock;
        for (int i = 0; i < 40; ++i) {  // moves and weights, stamped
            const int32_t v = static_cast<int32_t>(rng() % static_cast<uint64_t>(tri.vertex_slots()));
            if (!tri.in_triangulation(v)) continue;
            const Vec3 x = tri.direction(v) + 0.1 * h * Vec3{u(rng), u(rng), u(rng)};
            kept.set_generator(v, generator(x, 0.05 * h * h * u(rng)));
            kept.changed_at[v] = kept.clock;
        }
        int flipped = 0;
        for (int32_t t = static_cast<int32_t>(rng() % 997); t < tri.triangle_slots() && flipped < 10; t += 1500)
            flipped += !tri.is_free(t) && tri.flip(t, 0);  // not stamped
        assert_true(flipped > 0);
        for (bool angle : {false, true}) {
            optim::detail::MeshState anew(ctx, tri, on_segment, nullptr, spacing, o);
            anew.load_spacing();
            const optim::detail::Summary a = kept.summarise(angle), b = anew.summarise(angle);
            assert_true(same(a, b));
            assert_false(same(a, first));
        }
    }
}

// Section 6.4 on its own (no sweeps, no weights, one outer iteration, so
// no valence repair): vertices planted 0.2 h from others make edges much
// shorter than h, and removed vertices leave holes with edges much longer;
// each short edge is collapsed and each hole gets a vertex, and the mesh
// stays a valid regular triangulation with every edge within the options'
// band.
void short_edges_collapse_and_long_ones_split(void **) {
    Context ctx;
    const double h = 0.05;  // 320 km
    tri::Triangulation tri = uniform_mesh(ctx, h);
    const int64_t before = tri.vertex_count();
    constexpr int kEach = 8;
    const int32_t n = tri.vertex_slots();
    int32_t next_id = 0;
    for (int32_t v = 0; v < n; ++v) next_id = std::max(next_id, tri.id(v) + 1);
    for (int i = 0; i < kEach; ++i) {
        // Far apart: vertices a sixteenth of the slots from each other.
        const int32_t planted_next_to = (2 * i) * n / (2 * kEach), removed = (2 * i + 1) * n / (2 * kEach);
        tri.remove(removed);
        const Vec3 x = tri.direction(planted_next_to);
        const Vec3 side = geom::normalized(geom::cross(x, {0.3, 0.5, 0.7}));
        tri.insert(geom::normalized(x + (0.2 * h) * side), 0.0, next_id++);
    }
    assert_int_equal(tri.vertex_count(), before);
    std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
    optim::OptimiseOptions o;
    o.outer_iterations = 1, o.inner_iterations = 0, o.weights = false;
    o.ocean_floor = 0;  // (no Gamma: all ocean, and the floor would take the short edges out too)
    optim::OptimiseStats stats =
        optim::optimise(ctx, tri, on_segment, nullptr, [h](const Vec3 &) { return h; }, o);
    tri.compact();
    const std::string problem = tri::check_triangulation(tri);
    if (!problem.empty()) fail_msg("%s", problem.c_str());
    assert_int_equal(stats.collapses, kEach);
    assert_int_equal(stats.splits, kEach);
    assert_int_equal(tri.vertex_count(), before);
    double shortest = 1e9, longest = 0;
    for (int32_t t = 0; t < tri.triangle_slots(); ++t)
        for (int k = 0; k < 3; ++k) {
            const double l = geom::norm(tri.direction(tri.vertex(t, k)) - tri.direction(tri.vertex(t, (k + 1) % 3)));
            shortest = std::min(shortest, l / h), longest = std::max(longest, l / h);
        }
    if (shortest < o.collapse_ratio || longest > o.split_ratio)
        fail_msg("edges from %.3f h to %.3f h", shortest, longest);
}


// A sweep after the first visits only the vertices changed_near the last
// one's start (and the links of the updates it takes, for the colours
// after them): it takes the same updates, bit for bit, as sweeps that look
// at every vertex (a fresh pass each time, with no last sweep). Both
// meshes get the same 60 stamped moves and weights before each of three
// rounds of three sweeps, after six sweeps to settle.
void sweeps_skipping_the_unchanged_take_the_same_updates(void **) {
    const double h = 0.02;  // 130 km
    const refine::SpacingRadians spacing = [h](const Vec3 &) { return h; };
    optim::OptimiseOptions o;
    o.ocean_floor = 0;
    for (const bool weights : {false, true}) {
        Context ctx;
        ctx.set_threads(2);
        tri::Triangulation tri_kept = uniform_mesh(ctx, h), tri_anew = uniform_mesh(ctx, h);
        std::vector<int32_t> on_kept(static_cast<size_t>(tri_kept.vertex_slots()), -1), on_anew = on_kept;
        optim::detail::MeshState kept(ctx, tri_kept, on_kept, nullptr, spacing, o),
            anew(ctx, tri_anew, on_anew, nullptr, spacing, o);
        for (optim::detail::MeshState *s : {&kept, &anew}) {
            s->load_spacing();
            s->weighing = weights;
            s->grow_slots();
        }
        const optim::StarGraph g_kept(ctx, tri_kept), g_anew(ctx, tri_anew);
        optim::detail::ShapeSweeps shape_kept(kept);
        optim::detail::WeightSweeps weight_kept(kept);
        auto sweep_both = [&](bool forward) {
            const int64_t a = weights ? weight_kept.sweep(g_kept, forward) : shape_kept.sweep(g_kept, forward);
            const int64_t b = weights ? optim::detail::WeightSweeps(anew).sweep(g_anew, forward)
                                      : optim::detail::ShapeSweeps(anew).sweep(g_anew, forward);
            assert_int_equal(a, b);
            return a;
        };
        for (int k = 0; k < 6; ++k) sweep_both(k % 2 == 0);
        std::mt19937_64 rng(17);
        std::uniform_real_distribution<double> u(-1, 1);
        int64_t late = 0;
        for (int round = 0; round < 3; ++round) {
            ++kept.clock, ++anew.clock;
            for (int i = 0; i < 60; ++i) {
                const int32_t v = static_cast<int32_t>(rng() % static_cast<uint64_t>(tri_kept.vertex_slots()));
                const Vec3 x = tri_kept.direction(v) + 0.05 * h * Vec3{u(rng), u(rng), u(rng)};
                const double w = weights ? 0.02 * h * h * u(rng) : 0.0;
                for (optim::detail::MeshState *s : {&kept, &anew}) {
                    s->set_generator(v, generator(x, w));
                    s->changed_at[v] = s->clock;
                }
            }
            for (int k = 0; k < 3; ++k) late += sweep_both(k % 2 == 0);
        }
        print_message("%s sweeps: %lld updates after the perturbations\n", weights ? "weight" : "shape", (long long)late);
        assert_true(late > 0);
        for (int32_t v = 0; v < tri_kept.vertex_slots(); ++v)
            if (geom::norm(tri_kept.lifted(v) - tri_anew.lifted(v)) != 0)
                fail_msg("%s sweeps: vertex %d differs", weights ? "weight" : "shape", v);
    }
}

// The edges of t shorter than `ratio` h (the chord, as the passes' guards
// measure it; no Gamma: every vertex is off the land).
int64_t edges_below(const tri::Triangulation &t, double ratio, double h) {
    int64_t below = 0;
    for (int32_t f = 0; f < t.triangle_slots(); ++f)
        if (!t.is_free(f))
            for (int k = 0; k < 3; ++k)
                if (t.neighbour(f, k) > f)
                    below += geom::norm(t.direction(t.vertex(f, (k + 1) % 3)) - t.direction(t.vertex(f, (k + 2) % 3))) <
                             ratio * h;
    return below;
}

// The repair of vertex degrees splits a vertex of degree 8 or more in two,
// but not where the two would have more edges below the floor the floor
// pass lifts than the vertex had: that pass would take one out again and
// the next repair split it again, every outer iteration. Pairs of
// neighbours taken out of a uniform mesh leave vertices of degree 8 or
// more around their holes: without a floor their splits make edges below
// it; with one, the pass makes none (and its undone splits leave a valid
// triangulation).
void valence_splits_keep_the_floor(void **) {
    const double h = 0.05;  // 320 km
    const double lifted = 0.77;  // the floor pass's floor in the shape phase, for a floor of 0.7
    constexpr int kHoles = 24;
    int64_t splits_without = 0;
    for (const double floor : {0.0, 0.7}) {
        Context ctx;
        tri::Triangulation tri = uniform_mesh(ctx, h);
        for (int i = 0; i < kHoles; ++i) {
            const int32_t v = 12 + i * (tri.vertex_slots() - 12) / kHoles;  // far apart, past the corners
            const int32_t u = tri.link(v).front();
            tri.remove(v);
            tri.remove(u);
        }
        std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
        optim::OptimiseOptions o;
        o.ocean_floor = floor;
        const refine::SpacingRadians spacing = [h](const Vec3 &) { return h; };  // (held by reference)
        optim::detail::MeshState s(ctx, tri, on_segment, nullptr, spacing, o);
        s.load_spacing();
        s.refresh_sides();
        if (floor > 0) assert_true(std::abs(s.floor_to_lift() - lifted) < 1e-12);
        const int64_t below = edges_below(tri, lifted, h);
        std::vector<Vec3> was;
        for (int32_t v = 0; v < tri.vertex_slots(); ++v) was.push_back(tri.lifted(v));
        const int64_t vertices = tri.vertex_count();
        const int64_t changes = optim::detail::Topology(s).improve_valence();
        const std::string problem = tri::check_triangulation(tri);
        if (!problem.empty()) fail_msg("floor %.1f: %s", floor, problem.c_str());
        const int64_t below_after = edges_below(tri, lifted, h);
        print_message("floor %.1f: %lld splits, edges below %.2f h %lld -> %lld\n", floor,
                      (long long)s.stats.splits, lifted, (long long)below, (long long)below_after);
        if (floor == 0) {
            splits_without = s.stats.splits;
            assert_true(below_after > below);  // the case in point: such splits happen
        } else {
            assert_true(below_after <= below);
            assert_true(s.stats.splits < splits_without);
            // Every split refused: the only changes are removals of vertices
            // of low degree, and every vertex left is where it was.
            assert_int_equal(tri.vertex_count(), vertices - changes);
            for (int32_t v = 0; v < static_cast<int32_t>(was.size()); ++v)
                if (tri.in_triangulation(v) && geom::norm(tri.lifted(v) - was[static_cast<size_t>(v)]) != 0)
                    fail_msg("vertex %d moved", v);
        }
    }
}

// Every pass switched off (optimise.hpp): the schedule still runs its outer
// iterations, but no vertex moves, no weight changes and the topology stays
// as it was (the uniform mesh is regular already: no flip either).
void passes_switched_off_change_nothing(void **) {
    Context ctx;
    const double h = 0.05;  // 320 km
    tri::Triangulation tri = uniform_mesh(ctx, h);
    std::vector<Vec3> lifted;
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) lifted.push_back(tri.lifted(v));
    std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
    optim::OptimiseOptions o;
    o.moves = false, o.polish_poor_stars = false, o.weights = false, o.collapse_and_split = false;
    o.valence_repair = false, o.mends = false, o.corner_vertices = false, o.centroidal_sweeps = 0;
    o.reseed_rounds = 0, o.ocean_floor = 0;
    const optim::OptimiseStats stats =
        optim::optimise(ctx, tri, on_segment, nullptr, [h](const Vec3 &) { return h; }, o);
    assert_true(stats.outer_iterations >= 1);
    assert_int_equal(stats.moves + stats.weight_updates + stats.flips, 0);
    assert_int_equal(stats.collapses + stats.splits + stats.corner_vertices, 0);
    assert_int_equal(tri.vertex_slots(), static_cast<int32_t>(lifted.size()));
    for (int32_t v = 0; v < tri.vertex_slots(); ++v)
        if (geom::norm(tri.lifted(v) - lifted[v]) != 0) fail_msg("vertex %d moved", v);
}

// The rms over the vertices of arc(generator, centroid of its power cell) /
// sqrt(cell area): the centroid by the vector-area identity over the cell's
// edges (the orthocentres of the star, in star order), the area by fanning.
double centroid_offset_rms(const tri::Triangulation &t) {
    double sum = 0;
    int64_t n = 0;
    for (int32_t v = 0; v < t.vertex_slots(); ++v) {
        if (!t.in_triangulation(v)) continue;
        std::vector<Vec3> corner;
        t.for_each_in_star(v, [&](int32_t f) { corner.push_back(t.orthocentre(f)); });
        const Vec3 x = t.direction(v);
        Vec3 moment{};
        double area = 0;
        for (size_t k = 0; k < corner.size(); ++k) {
            const Vec3 &a = corner[k], &b = corner[(k + 1) % corner.size()];
            const Vec3 n = geom::cross(a, b);
            moment = moment + (std::atan2(geom::norm(n), geom::dot(a, b)) / geom::norm(n)) * n;
            area += 2 * std::atan2(std::abs(geom::dot(x, n)), 1 + geom::dot(x, a) + geom::dot(a, b) + geom::dot(b, x));
        }
        if (geom::dot(moment, x) < 0) moment = -1.0 * moment;  // the star's order may be clockwise
        sum += geom::arc_length(x, geom::normalized(moment)) * geom::arc_length(x, geom::normalized(moment)) / area;
        ++n;
    }
    return std::sqrt(sum / double(n));
}

// The least area-length ratio Q^T of the mesh's triangles.
double qt_min(const tri::Triangulation &t) {
    double qt = 2;
    for (int32_t f = 0; f < t.triangle_slots(); ++f)
        if (!t.is_free(f))
            qt = std::min(qt, optim::area_length_ratio(t.direction(t.vertex(f, 0)), t.direction(t.vertex(f, 1)),
                                                       t.direction(t.vertex(f, 2))));
    return qt;
}

// A uniform mesh of spacing h, optimised with `o` on `threads` threads.
tri::Triangulation optimised_uniform(double h, int threads, const optim::OptimiseOptions &o,
                                     optim::OptimiseStats *stats = nullptr) {
    Context ctx;
    ctx.set_threads(threads);
    tri::Triangulation tri = uniform_mesh(ctx, h);
    std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), -1);
    const optim::OptimiseStats s = optim::optimise(ctx, tri, on_segment, nullptr, [h](const Vec3 &) { return h; }, o);
    if (stats) *stats = s;
    return tri;
}

void expect_same_bits(const tri::Triangulation &a, const tri::Triangulation &b) {
    assert_int_equal(a.vertex_slots(), b.vertex_slots());
    for (int32_t v = 0; v < a.vertex_slots(); ++v) {
        const Vec3 p = a.lifted(v), q = b.lifted(v);
        if (p.x != q.x || p.y != q.y || p.z != q.z) fail_msg("vertex %d differs between 1 and 2 threads", v);
    }
}

// The centroidal pass (Lloyd sweeps after the shape phase) takes the
// generators much closer to their cells' centroids than the shape sweeps
// alone, keeps every triangle's area-length ratio above its floor (0.925, or
// what the mesh had), and the result is the same for one and two threads.
void centroidal_pass_centres_the_cells(void **) {
    const double h = 0.04;  // 255 km
    auto optimised = [&](int sweeps, int threads) {
        optim::OptimiseOptions o;
        o.centroidal_sweeps = sweeps;
        tri::Triangulation tri = optimised_uniform(h, threads, o);
        tri.compact();
        return tri;
    };
    const tri::Triangulation shaped = optimised(0, 2), centred = optimised(8, 2), one_thread = optimised(8, 1);
    const double before = centroid_offset_rms(shaped), after = centroid_offset_rms(centred);
    print_message("centroid offset rms: shape sweeps only %.4f, with the centroidal pass %.4f; Q^T min %.3f, %.3f\n",
                  before, after, qt_min(shaped), qt_min(centred));
    assert_true(after < 0.6 * before);
    assert_true(qt_min(centred) >= std::min(qt_min(shaped), 0.925) - 1e-3);
    const std::string problem = tri::check_triangulation(centred);
    if (!problem.empty()) fail_msg("%s", problem.c_str());
    expect_same_bits(centred, one_thread);
}

// Vertices of degree other than 6.
int64_t defects(Context &ctx, const tri::Triangulation &t) {
    const std::vector<int32_t> degree = optim::vertex_degrees(ctx, t);
    int64_t n = 0;
    for (int32_t v = 0; v < t.vertex_slots(); ++v) n += t.in_triangulation(v) && degree[v] != 6;
    return n;
}

// The re-seeding rounds leave far fewer 5-7 defects than the sweeps alone,
// keep the triangles' floors, reuse the slots they empty (the slot count
// stays within the few per cent the splits add) and give the same mesh for
// one and two threads.
void reseeding_lowers_the_defects(void **) {
    const double h = 0.04;  // 255 km
    auto optimised = [&](int rounds, int threads) {
        optim::OptimiseOptions o;
        o.reseed_rounds = rounds;
        optim::OptimiseStats stats;
        tri::Triangulation tri = optimised_uniform(h, threads, o, &stats);
        assert_true(rounds == 0 ? stats.reseed_rounds == 0 : stats.reseed_rounds >= 2);
        return tri;
    };
    Context ctx;
    const int32_t slots_refined = uniform_mesh(ctx, h).vertex_slots();
    const tri::Triangulation plain = optimised(0, 2), reseeded = optimised(7, 2), one_thread = optimised(7, 1);
    const int64_t without = defects(ctx, plain), with = defects(ctx, reseeded);
    print_message("vertices of degree other than 6: %lld without re-seeding, %lld with; slots %d -> %d\n",
                  (long long)without, (long long)with, slots_refined, reseeded.vertex_slots());
    assert_true(with < 0.6 * static_cast<double>(without));
    assert_true(reseeded.vertex_slots() < 1.05 * slots_refined);
    const std::string problem = tri::check_triangulation(reseeded);
    if (!problem.empty()) fail_msg("%s", problem.c_str());
    assert_true(qt_min(reseeded) >= 0.92);
    expect_same_bits(reseeded, one_thread);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(weight_derivative_matches_finite_differences),
        cmocka_unit_test(equilateral_triangle_scores_one),
        cmocka_unit_test(slide_stays_on_the_polyline),
        cmocka_unit_test(colouring_separates_neighbours),
        cmocka_unit_test(optimised_mesh_is_regular_and_better),
        cmocka_unit_test(short_edges_collapse_and_long_ones_split),
        cmocka_unit_test(centroidal_pass_centres_the_cells),
        cmocka_unit_test(reseeding_lowers_the_defects),
        cmocka_unit_test(passes_switched_off_change_nothing),
        cmocka_unit_test(a_kept_summary_equals_one_made_anew),
        cmocka_unit_test(chord_bounds_agree_with_the_chord),
        cmocka_unit_test(kept_near_gamma_flags_equal_flags_found_anew),
        cmocka_unit_test(valence_splits_keep_the_floor),
        cmocka_unit_test(sweeps_skipping_the_unchanged_take_the_same_updates),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
