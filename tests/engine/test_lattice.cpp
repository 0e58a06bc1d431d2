// Engine tests: the geodesic lattice (refine/lattice) and the refinement that
// starts from it when the spacing is uniform (mesh/refined_mesh).
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <limits>
#include <vector>

#include "core/options.hpp"
#include "hfun/spacing.hpp"
#include "mesh/refined_mesh.hpp"
#include "optim/star_graph.hpp"
#include "refine/lattice.hpp"
#include "tri/validate.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;

namespace {

constexpr double kRadiusKm = 6371.22;

struct Degrees {
    int64_t five = 0, six = 0, other = 0;
};

Degrees count_degrees(Context &ctx, const tri::Triangulation &tri) {
    const std::vector<int32_t> degree = optim::vertex_degrees(ctx, tri);
    Degrees d;
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) {
        if (!tri.in_triangulation(v)) continue;
        if (degree[v] == 5) ++d.five;
        else if (degree[v] == 6) ++d.six;
        else ++d.other;
    }
    return d;
}

// The edges of a lattice's triangulation, relative to their mean.
struct EdgeSpread {
    double mean = 0, lo = 0, hi = 0, std = 0;
};

// The triangulation of `points`, checked, with none hidden.
tri::Triangulation triangulated(Context &ctx, const std::vector<Vec3> &points) {
    for (const Vec3 &p : points) assert_true(std::fabs(geom::norm(p) - 1) < 1e-14);
    tri::Triangulation tri;
    tri.build(ctx, static_cast<int64_t>(points.size()), [&](int64_t i) { return points[i]; }, nullptr);
    assert_string_equal(tri::check_triangulation(tri).c_str(), "");
    assert_int_equal(tri.vertex_count(), points.size());  // none hidden: all distinct
    return tri;
}

bool within(const Vec3 &p, const refine::Cap *cap) { return !cap || geom::arc_length(p, cap->centre) < cap->radius; }

// The spread of the edges of the triangles within `cap` (all without one).
EdgeSpread edge_spread(const tri::Triangulation &tri, const refine::Cap *cap) {
    std::vector<double> lengths;
    for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
        if (tri.is_free(t)) continue;
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && within(tri.direction(tri.vertex(t, k)), cap);
        for (int k = 0; k < 3 && inside; ++k)
            lengths.push_back(geom::arc_length(tri.direction(tri.vertex(t, k)), tri.direction(tri.vertex(t, (k + 1) % 3))));
    }
    EdgeSpread s;
    for (double e : lengths) s.mean += e / static_cast<double>(lengths.size());
    s.lo = *std::min_element(lengths.begin(), lengths.end()) / s.mean;
    s.hi = *std::max_element(lengths.begin(), lengths.end()) / s.mean;
    for (double e : lengths) s.std += (e / s.mean - 1) * (e / s.mean - 1) / static_cast<double>(lengths.size());
    s.std = std::sqrt(s.std);
    return s;
}

// Checks that `points` are the frequency-n lattice: 10 n^2 + 2 distinct unit
// points whose triangulation has 12 five-valent vertices, the rest
// six-valent. Returns its edges' spread (of the triangles within `cap`
// only, when given).
EdgeSpread check_lattice(const std::vector<Vec3> &points, int64_t n, const refine::Cap *cap = nullptr) {
    assert_int_equal(points.size(), 10 * n * n + 2);
    Context ctx;
    const tri::Triangulation tri = triangulated(ctx, points);
    const Degrees d = count_degrees(ctx, tri);
    assert_int_equal(d.five, 12);
    assert_int_equal(d.other, 0);
    return edge_spread(tri, cap);
}

// The lattice of every frequency, with edges within 12 % of their mean.
void lattice_points_and_degrees(void **) {
    for (int64_t n : {1, 2, 3, 7, 32}) {
        const EdgeSpread s = check_lattice(refine::geodesic_lattice(n), n);
        print_message("frequency %lld: edges %.4f..%.4f of their mean\n", static_cast<long long>(n), s.lo, s.hi);
        assert_true(s.lo > 0.88 && s.hi < 1.12);
        // The frequency that spacing gives back is n.
        assert_int_equal(refine::lattice_frequency(s.mean, int64_t{1} << 31), n);
    }
}

// The relaxed lattice: the same points in number and topology, its edges
// more even than the placed lattice's (smaller spread; none shorter than
// 0.84 of the mean, where the springs alone would squeeze the pentagons'
// spokes to 0.77 at this size), the same bits for any thread count, and the
// icosahedron's symmetry kept: a fifth of a turn about a corner maps it onto
// itself.
void relaxed_lattice_is_even_and_symmetric(void **) {
    for (int64_t n : {2, 3, 9, 17, 40, 128}) {
        Context one, three;
        three.set_threads(3);
        const std::vector<Vec3> points = refine::relaxed_geodesic_lattice(one, n);
        const std::vector<Vec3> again = refine::relaxed_geodesic_lattice(three, n);
        for (size_t i = 0; i < points.size(); ++i)
            assert_true(points[i].x == again[i].x && points[i].y == again[i].y && points[i].z == again[i].z);
        const EdgeSpread placed = check_lattice(refine::geodesic_lattice(n), n);
        const EdgeSpread relaxed = check_lattice(points, n);
        print_message("frequency %lld: placed %.4f..%.4f std %.4f, relaxed %.4f..%.4f std %.4f\n",
                      static_cast<long long>(n), placed.lo, placed.hi, placed.std, relaxed.lo, relaxed.hi, relaxed.std);
        if (n > 2) assert_true(relaxed.std < placed.std);
        assert_true(relaxed.lo > 0.84 && relaxed.hi < 1.1);
        if (n > 40) continue;  // the symmetry by brute force
        const Vec3 axis = points[0];
        const double c = std::cos(2 * M_PI / 5), s = std::sin(2 * M_PI / 5);
        for (const Vec3 &p : points) {
            const Vec3 along = geom::dot(p, axis) * axis, across = p - along;
            const Vec3 turned = along + c * across + s * geom::cross(axis, across);
            double nearest = 1e300;
            for (const Vec3 &q : points) nearest = std::min(nearest, geom::norm(q - turned));
            assert_true(nearest < 1e-9);
        }
    }
}

// A lattice relaxed only around a cap (a regional mesh's): placed only
// there (every point within the cap, none beyond the margins), within the
// cap the lattice still (six neighbours each) and as even as the whole
// sphere's relaxed lattice (the same spread of edges to a few thousandths),
// its points within a small fraction of an edge of that lattice's (a
// corner's strain reaches farthest: 0.11 edges there), about as many as
// lattice_region_points estimates; the same
// bits for any thread count. One cap holds a corner of the icosahedron
// (five neighbours there), one crosses the antimeridian.
void lattice_relaxed_within_a_cap(void **) {
    const refine::Cap caps[] = {{geom::unit_from_lonlat_deg(-40, 35), 0.5},
                                {geom::unit_from_lonlat_deg(180, -5), 0.3},
                                {geom::normalized(Vec3{0, 1, 1.618033988749895}), 0.2}};
    for (int64_t n : {64, 128}) {
        Context one, three;
        three.set_threads(3);
        const std::vector<Vec3> whole = refine::relaxed_geodesic_lattice(one, n);
        check_lattice(whole, n);
        const tri::Triangulation whole_tri = triangulated(one, whole);
        for (const refine::Cap &cap : caps) {
            const EdgeSpread w = edge_spread(whole_tri, &cap);
            const refine::LatticeRegion region = refine::relaxed_lattice_region(one, n, cap);
            const refine::LatticeRegion again = refine::relaxed_lattice_region(three, n, cap);
            assert_true(region.index == again.index);
            for (size_t i = 0; i < region.points.size(); ++i)
                assert_true(region.points[i].x == again.points[i].x && region.points[i].y == again.points[i].y &&
                            region.points[i].z == again.points[i].z);
            assert_true(std::is_sorted(region.index.begin(), region.index.end()));
            const double estimate = refine::lattice_region_points(n, cap);  // (what the lattice's limit reads)
            assert_true(std::fabs(static_cast<double>(region.points.size()) - estimate) < 0.05 * estimate);
            for (int64_t c = 0; c < 12; ++c) assert_int_equal(region.index[c], c);
            const double reach = cap.radius + (refine::kCapMargin + refine::kHeldMargin + 1) * w.mean;
            double moved = 0;
            for (size_t i = 12; i < region.points.size(); ++i) {
                assert_true(geom::arc_length(region.points[i], cap.centre) < reach);
                if (within(whole[region.index[i]], &cap))
                    moved = std::max(moved, geom::arc_length(whole[region.index[i]], region.points[i]));
            }
            int64_t inside = 0;
            for (int64_t p = 0; p < static_cast<int64_t>(whole.size()); ++p)
                if (within(whole[p], &cap)) {
                    ++inside;
                    assert_true(std::binary_search(region.index.begin(), region.index.end(), p));
                }
            const tri::Triangulation tri = triangulated(one, region.points);
            const std::vector<int32_t> degree = optim::vertex_degrees(one, tri);
            for (int32_t v = 0; v < tri.vertex_slots(); ++v)
                if (tri.in_triangulation(v) && within(tri.direction(v), &cap))
                    assert_int_equal(degree[v], region.index[tri.id(v)] < 12 ? 5 : 6);
            const EdgeSpread c = edge_spread(tri, &cap);
            print_message("frequency %lld, cap of %.2f: %zu points placed for %lld within; edges whole std %.5f, "
                          "capped %.4f..%.4f std %.5f; points at most %.4f edges apart\n",
                          static_cast<long long>(n), cap.radius, region.points.size(), static_cast<long long>(inside),
                          w.std, c.lo, c.hi, c.std, moved / w.mean);
            assert_true(std::fabs(c.std - w.std) < 0.003 && c.lo > w.lo - 0.02 && c.hi < w.hi + 0.02);
            assert_true(moved < 0.15 * w.mean);  // 0.11 around the corner at 128 (0.05 elsewhere)
        }
    }
}

void frequency_of_degenerate_spacings(void **) {
    const int64_t cap = int64_t{1} << 31;
    assert_int_equal(refine::lattice_frequency(0.0, cap), 0);
    assert_int_equal(refine::lattice_frequency(-1.0, cap), 0);
    assert_int_equal(refine::lattice_frequency(std::numeric_limits<double>::quiet_NaN(), cap), 0);
    assert_int_equal(refine::lattice_frequency(std::numeric_limits<double>::infinity(), cap), 1);
    assert_int_equal(refine::lattice_frequency(10.0, cap), 1);  // wider than the sphere: the icosahedron
    assert_int_equal(refine::lattice_frequency(1e-6, cap), 0);  // more points than the cap
    assert_int_equal(refine::lattice_frequency(100.0 / kRadiusKm, 1000), 0);
}

// Bit for bit the same lifted point in every slot of `a` (b has as many).
void assert_same_points(const tri::Triangulation &a, const tri::Triangulation &b) {
    for (int32_t v = 0; v < a.vertex_slots(); ++v) {
        const Vec3 p = a.lifted(v), q = b.lifted(v);
        assert_true(p.x == q.x && p.y == q.y && p.z == q.z);
    }
}

struct Built {
    mesh::RefinedMesh m;
    Degrees refined, optimised;
};

Built build(hfun::SpacingPtr h, int lattice, int threads) {
    Context ctx;
    ctx.set_threads(threads);
    Options options;
    options.set_int(UM_OPT_REFINE_LATTICE, lattice);
    Built b{mesh::refine_mesh(ctx, std::move(h), nullptr, options), {}, {}};
    b.refined = count_degrees(ctx, b.m.tri);
    mesh::optimise_mesh(ctx, b.m, options);
    b.optimised = count_degrees(ctx, b.m.tri);
    return b;
}

// A uniform spacing's mesh is the lattice of that spacing, and stays one
// through the optimisation (the re-seeding leaves the lone pentagons alone),
// the same for any thread count; the frontal refinement (refine_lattice 0)
// leaves hundreds of 5-7 defects.
void uniform_spacing_meshes_from_the_lattice(void **) {
    const double km = 240;
    const int64_t n = refine::lattice_frequency(km / kRadiusKm, int64_t{1} << 31);
    const Built one = build(hfun::make_constant(km), 1, 1);
    assert_int_equal(one.m.vertex_count(), 10 * n * n + 2);
    assert_int_equal(one.refined.five, 12);
    assert_int_equal(one.refined.other, 0);
    assert_int_equal(one.optimised.five, 12);
    assert_int_equal(one.optimised.other, 0);
    const Built three = build(hfun::make_constant(km), 1, 3);
    assert_int_equal(three.m.vertex_count(), one.m.vertex_count());
    assert_same_points(one.m.tri, three.m.tri);
    const Built frontal = build(hfun::make_constant(km), 0, 1);
    print_message("240 km: lattice %lld cells, 12 pentagons; frontal %lld cells, %lld + %lld defects\n",
                  static_cast<long long>(one.m.vertex_count()), static_cast<long long>(frontal.m.vertex_count()),
                  static_cast<long long>(frontal.optimised.five), static_cast<long long>(frontal.optimised.other));
    assert_true(frontal.optimised.five + frontal.optimised.other > 100);
}

// A graded spacing - 240 km over the northern hemisphere, finer towards the
// south pole - has the lattice where it is flat: north of 15 degrees every
// vertex but the four lattice corners there is six-valent, before and after
// the optimisation; the south, refined frontally, has the 5-7 defects. The
// same mesh on 1 and 3 threads.
double graded_km(void *, double, double lat_deg) {
    return lat_deg >= 0 ? 240.0 : 240.0 * (1.0 - 0.5 * std::sin(-lat_deg * M_PI / 180));
}
struct Hemispheres {
    int64_t north = 0, south = 0;  // vertices of degree other than 6
};
Hemispheres defects_by_hemisphere(const tri::Triangulation &tri) {
    Context ctx;
    const std::vector<int32_t> degree = optim::vertex_degrees(ctx, tri);
    Hemispheres d;
    const double z15 = std::sin(15 * M_PI / 180);
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) {
        if (!tri.in_triangulation(v) || degree[v] == 6) continue;
        const double z = tri.direction(v).z;
        d.north += z > z15, d.south += z < 0;
    }
    return d;
}
void graded_spacing_has_the_lattice_where_it_is_flat(void **) {
    Context ctx;
    Options options;
    mesh::RefinedMesh m = mesh::refine_mesh(ctx, hfun::make_callback(graded_km, nullptr), nullptr, options);
    const Hemispheres refined = defects_by_hemisphere(m.tri);
    mesh::optimise_mesh(ctx, m, options);
    const Hemispheres optimised = defects_by_hemisphere(m.tri);
    const Built three = build(hfun::make_callback(graded_km, nullptr), 1, 3);
    assert_int_equal(three.m.tri.vertex_slots(), m.tri.vertex_slots());
    assert_same_points(m.tri, three.m.tri);
    print_message("graded: defects north of 15 degrees %lld -> %lld, south of the equator %lld -> %lld\n",
                  static_cast<long long>(refined.north), static_cast<long long>(optimised.north),
                  static_cast<long long>(refined.south), static_cast<long long>(optimised.south));
    assert_int_equal(refined.north, 4);
    assert_int_equal(optimised.north, 4);
    assert_true(optimised.south > 100);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lattice_points_and_degrees),
        cmocka_unit_test(relaxed_lattice_is_even_and_symmetric),
        cmocka_unit_test(lattice_relaxed_within_a_cap),
        cmocka_unit_test(frequency_of_degenerate_spacings),
        cmocka_unit_test(uniform_spacing_meshes_from_the_lattice),
        cmocka_unit_test(graded_spacing_has_the_lattice_where_it_is_flat),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
