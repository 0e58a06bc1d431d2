// Engine tests: the streamed quality report (quality/metrics) against every
// value computed and sorted.
#include <algorithm>
#include <cfenv>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <random>
#include <vector>

#include <string>

#include "dual/spherical.hpp"
#include "quality/metrics.hpp"
#include "refine/surface.hpp"
#include "support/point_sets.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;

namespace {

void check(const quality::Summary &s, std::vector<double> values) {
    std::sort(values.begin(), values.end());
    assert_true(s.min == values.front());
    assert_true(s.max == values.back());
    assert_true(s.p1 == values[values.size() / 100]);  // exactly the sorted list's entry
    double sum = 0;
    for (double v : values) sum += v;
    assert_true(std::fabs(s.mean - sum / double(values.size())) < 1e-12 * std::fabs(s.mean) + 1e-15);
    int64_t counted = 0;
    for (int64_t c : s.histogram) counted += c;
    assert_int_equal(counted, static_cast<int64_t>(values.size()));
    // rms and the standard deviation, against the two-pass forms.
    double sum_sq = 0, dev_sq = 0;
    for (double v : values) sum_sq += v * v, dev_sq += (v - sum / double(values.size())) * (v - sum / double(values.size()));
    assert_true(std::fabs(s.rms - std::sqrt(sum_sq / double(values.size()))) < 1e-12 * s.rms + 1e-15);
    assert_true(std::fabs(s.std - std::sqrt(dev_sq / double(values.size()))) < 1e-9 * s.std + 1e-15);
}

// The operator diagnostics of every live edge (once) and cell, computed one
// by one: dual-edge offsets, primal-edge offsets, dcEdge / h(xEdge),
// centroid offsets.
void operator_values(const tri::Triangulation &tri, const refine::SpacingRadians &h, std::vector<double> v[4]) {
    for (int32_t t = 0; t < tri.triangle_slots(); ++t)
        for (int k = 0; k < 3 && !tri.is_free(t); ++k) {
            if (tri.neighbour(t, k) < t) continue;
            const quality::EdgeOffsets e = quality::edge_offsets(tri, t, k);
            v[0].push_back(e.dual), v[1].push_back(e.primal), v[2].push_back(e.dc_edge / h(e.x_edge));
        }
    for (int32_t c = 0; c < tri.vertex_slots(); ++c)
        if (tri.in_triangulation(c)) v[3].push_back(quality::centroid_offset(tri, c));
}

void streamed_report_matches_sorted_values(void **) {
    for (int threads : {1, 3}) {
        Context ctx;
        ctx.set_threads(threads);
        tri::Triangulation tri = refine::icosahedron(ctx);
        refine::SurfaceOptions so;
        // Spacing from 60 to 180 km: a spread of edge ratios and shapes, and
        // more triangles than two of the report's blocks (32768 each), so
        // that the blocks' results are merged.
        auto h = [](const Vec3 &x) { return (60.0 + 120.0 * x.z * x.z) / 6371.22; };
        refine::refine_surface(ctx, tri, h, so, 12);
        assert_true(tri.triangle_slots() > 2 * 32768);
        for (int i = 0; i < 40; ++i) tri.remove(100 + 37 * i);  // free slots, odd shapes
        const quality::Report r = quality::measure(ctx, tri, h);
        std::vector<double> v[5];
        int64_t triangles = 0, obtuse = 0, not_well_centred = 0;
        for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
            if (tri.is_free(t)) continue;
            const quality::TriangleQuality q = quality::triangle_quality(tri, t);
            v[0].push_back(q.area_length), v[1].push_back(q.primal_dual);
            v[2].push_back(q.angle_min), v[3].push_back(q.angle_max);
            ++triangles, obtuse += q.angle_max > 90, not_well_centred += !q.well_centred;
            for (int k = 0; k < 3; ++k) {
                if (tri.neighbour(t, k) < t) continue;
                const Vec3 a = tri.direction(tri.vertex(t, (k + 1) % 3)), c = tri.direction(tri.vertex(t, (k + 2) % 3));
                v[4].push_back(quality::arc(a, c) / h(geom::normalized(a + c)));
            }
        }
        assert_int_equal(r.triangles, triangles);
        assert_int_equal(r.obtuse, obtuse);
        assert_int_equal(r.not_well_centred, not_well_centred);
        assert_int_equal(r.not_well_centred_off_gamma, not_well_centred);  // no Gamma: every vertex is off it
        assert_true(obtuse > 0 && not_well_centred > 0);
        // A made-up Gamma holding most vertices: the off-Gamma count is of
        // the triangles with a vertex that is not on it.
        std::vector<int32_t> on_segment(static_cast<size_t>(tri.vertex_slots()), 0);
        for (size_t v = 0; v < on_segment.size(); v += 7) on_segment[v] = -1;
        int64_t off = 0;
        for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
            if (tri.is_free(t) || quality::triangle_quality(tri, t).well_centred) continue;
            bool any_off = false;
            for (int k = 0; k < 3; ++k) any_off |= on_segment[tri.vertex(t, k)] < 0;
            off += any_off;
        }
        const quality::Report with_gamma = quality::measure(ctx, tri, h, &on_segment);
        assert_int_equal(with_gamma.not_well_centred, not_well_centred);
        assert_int_equal(with_gamma.not_well_centred_off_gamma, off);
        assert_true(off > 0 && off < not_well_centred);
        check(r.area_length, v[0]), check(r.primal_dual, v[1]);
        check(r.angle_min, v[2]), check(r.angle_max, v[3]), check(r.spacing_ratio, v[4]);
        if (threads == 1) continue;  // the blocks, and so the report, are those of 3 threads
        std::vector<double> o[4];
        operator_values(tri, h, o);
        assert_int_equal(static_cast<int64_t>(o[0].size()), r.edges);
        check(r.dual_edge_offset, o[0]), check(r.primal_edge_offset, o[1]);
        check(r.cell_spacing_ratio, o[2]), check(r.centroid_offset, o[3]);
    }
}

tri::Triangulation build(Context &ctx, const std::vector<Vec3> &pts, const std::vector<double> *weights = nullptr) {
    tri::Triangulation tri;
    tri.build(ctx, static_cast<int64_t>(pts.size()), [&](int64_t i) { return pts[i]; },
              weights ? weights->data() : nullptr);
    return tri;
}

// The Voronoi mesh of the icosahedral grid of level 6 (40962 cells; each
// triangle split in four by its normalised edge midpoints), whose
// diagnostics are known: xEdge is the edge midpoint (primal-edge offset 0),
// centroid offsets rms 0.0092, dual-edge offsets rms 0.013. The report is
// the same, to the bit, for any thread count.
void icosahedral_operator_diagnostics(void **) {
    const std::vector<Vec3> pts = test::icosahedral_points(6);
    assert_int_equal(static_cast<int64_t>(pts.size()), 40962);
    const double spacing = 0.0189;  // about the mean edge (radians)
    const refine::SpacingRadians h = [&](const Vec3 &) { return spacing; };
    std::string json[2];
    for (int threads : {1, 3}) {
        Context ctx;
        ctx.set_threads(threads);
        const tri::Triangulation tri = build(ctx, pts);
        const quality::Report r = quality::measure(ctx, tri, h);
        assert_true(r.primal_edge_offset.max < 1e-9);
        assert_true(std::fabs(r.centroid_offset.rms / 0.0092 - 1) < 0.1);
        assert_true(std::fabs(r.dual_edge_offset.rms / 0.013 - 1) < 0.1);
        assert_true(r.centroid_offset.max < 0.05 && r.dual_edge_offset.max < 0.1);
        // dcEdge / h: h is constant, so its spread is that of the edge lengths.
        std::vector<double> o[4];
        operator_values(tri, h, o);
        check(r.cell_spacing_ratio, o[2]);
        assert_true(r.cell_spacing_ratio.std > 0.01 && r.cell_spacing_ratio.std < 0.1);
        assert_true(std::fabs(r.cell_spacing_ratio.mean - 1) < 0.1);
        json[threads == 1 ? 0 : 1] = quality::to_json(r);
    }
    assert_string_equal(json[0].c_str(), json[1].c_str());
}

// The centroid against quadrature: each fan triangle (generator, o_k,
// o_k+1) of a power cell cut into m^2 small ones, each of its (signed)
// area at its normalised vertex mean. Power cells of weighted random
// points, some of which do not hold their generator.
void centroid_offset_is_exact(void **) {
    Context ctx;
    const std::vector<Vec3> pts = test::random_points(200, 7);
    std::vector<double> w(pts.size());
    for (size_t i = 0; i < w.size(); ++i) w[i] = 0.004 * double((i * 37) % 11);  // up to ~2 cell areas
    const tri::Triangulation tri = build(ctx, pts, &w);
    constexpr int m = 48;
    int checked = 0;
    for (int32_t v = 0; v < tri.vertex_slots() && checked < 40; ++v) {
        if (!tri.in_triangulation(v)) continue;
        const Vec3 x = tri.direction(v);
        const std::vector<Vec3> cell = tri.power_cell(v);
        Vec3 moment;
        double area = 0;
        for (size_t k = 0; k < cell.size(); ++k) {
            const Vec3 p = cell[k], q = cell[(k + 1) % cell.size()];
            auto at = [&](int i, int j) {  // barycentric (i, j) / m of (x, p, q)
                return geom::normalized(double(m - i - j) * x + double(i) * p + double(j) * q);
            };
            for (int i = 0; i < m; ++i)
                for (int j = 0; i + j < m; ++j) {
                    const Vec3 a = at(i, j), b = at(i + 1, j), c = at(i, j + 1);
                    double da = dual::signed_area(a, b, c);
                    moment = moment + da * geom::normalized(a + b + c), area += da;
                    if (i + j + 1 < m) {
                        const Vec3 d = at(i + 1, j + 1);
                        da = dual::signed_area(b, d, c);
                        moment = moment + da * geom::normalized(b + d + c), area += da;
                    }
                }
        }
        const double expected = dual::arc(x, geom::normalized(moment)) / std::sqrt(area);
        const double got = quality::centroid_offset(tri, v);
        if (std::fabs(got - expected) > 1e-6 * (1 + expected))
            fail_msg("cell %d: centroid offset %.10g, quadrature %.10g", v, got, expected);
        ++checked;
    }
    assert_int_equal(checked, 40);
}

// quality.json's operator diagnostics, and null for what JSON cannot hold.
void json_has_operator_diagnostics(void **) {
    quality::Report r;
    r.dual_edge_offset.rms = 0.25, r.dual_edge_offset.max = HUGE_VAL, r.cell_spacing_ratio.std = 0.125;
    const std::string json = quality::to_json(r);
    for (const char *key : {"\"operator_diagnostics\": {", "\"centroid_offset\": {\"rms\": 0, \"max\": 0}",
                            "\"dual_edge_offset\": {\"rms\": 0.25, \"max\": null}",
                            "\"primal_edge_offset\": {\"rms\": 0, \"max\": 0}",
                            "\"cell_spacing_ratio\": {\"min\": 0, \"max\": 0, \"mean\": 0, \"std\": 0.125}"})
        if (json.find(key) == std::string::npos) fail_msg("no %s in\n%s", key, json.c_str());
}

}  // namespace

// The report's arcs and areas against the same measures in long double
// (atan2 of |a x b| and a . b; Eriksson's formula) on the same vectors:
// within twice dual::arc's and dual::signed_area's error and 4 units in the
// last place, from arcs of 1e-8 to nearly a half circle (past the quarter
// where quality::arc takes atan2) and triangles up to a few thousand km.
void report_arcs_and_areas_are_accurate(void **) {
    std::mt19937_64 rng(41);
    std::normal_distribution<double> normal;
    auto unit = [&] { return geom::normalized(Vec3{normal(rng), normal(rng), normal(rng)}); };
    auto near = [&](const Vec3 &a, double s) {
        return geom::normalized(a + s * Vec3{normal(rng), normal(rng), normal(rng)});
    };
    auto reference_arc = [](const Vec3 &a, const Vec3 &b) {
        const long double cx = (long double)a.y * b.z - (long double)a.z * b.y;
        const long double cy = (long double)a.z * b.x - (long double)a.x * b.z;
        const long double cz = (long double)a.x * b.y - (long double)a.y * b.x;
        const long double dot = (long double)a.x * b.x + (long double)a.y * b.y + (long double)a.z * b.z;
        return static_cast<double>(std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot));
    };
    auto reference_area = [](const Vec3 &a, const Vec3 &b, const Vec3 &c) {
        auto d = [](const Vec3 &p, const Vec3 &q) {
            return (long double)p.x * q.x + (long double)p.y * q.y + (long double)p.z * q.z;
        };
        const long double ux = (long double)b.x - a.x, uy = (long double)b.y - a.y, uz = (long double)b.z - a.z;
        const long double wx = (long double)c.x - a.x, wy = (long double)c.y - a.y, wz = (long double)c.z - a.z;
        const long double det = a.x * (uy * wz - uz * wy) + a.y * (uz * wx - ux * wz) + a.z * (ux * wy - uy * wx);
        return static_cast<double>(2 * std::atan2(det, 1 + d(a, b) + d(b, c) + d(c, a)));
    };
    auto within = [](double got, double old, double ref) {
        const double ulp = std::nextafter(std::fabs(ref), HUGE_VAL) - std::fabs(ref);
        return std::fabs(got - ref) <= 2 * std::fabs(old - ref) + 4 * ulp;
    };
    int fallbacks = 0;
    for (int i = 0; i < 200000; ++i) {
        const Vec3 a = unit();
        const double s = std::pow(10.0, -8.0 + 8.5 * double(i % 1000) / 1000.0);  // 1e-8 .. 3
        const Vec3 b = near(a, s), c = near(a, s);
        const double ref = reference_arc(a, b);
        fallbacks += geom::dot(a - b, a - b) >= 2.0;
        if (!within(quality::arc(a, b), dual::arc(a, b), ref))
            fail_msg("arc %.17g: report %.17g, dual %.17g", ref, quality::arc(a, b), dual::arc(a, b));
        const double area = reference_area(a, b, c);
        if (!within(quality::signed_area(a, b, c), dual::signed_area(a, b, c), area))
            fail_msg("area %.17g: report %.17g, dual %.17g", area, quality::signed_area(a, b, c),
                     dual::signed_area(a, b, c));
    }
    assert_true(fallbacks > 1000);  // the arcs past a quarter circle were met
    // Exact cases: no arc, a quarter circle, an octant of the sphere.
    const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    assert_true(quality::arc(x, x) == 0.0);
    assert_true(std::fabs(quality::arc(x, y) - M_PI / 2) <= 4e-16);
    assert_true(std::fabs(quality::signed_area(x, y, z) - M_PI / 2) <= 4e-16);
    assert_true(std::fabs(quality::signed_area(x, z, y) + M_PI / 2) <= 4e-16);
    // A triangle whose Eriksson denominator is exactly 0 (E = pi): no
    // division by zero, which a host trapping floating-point exceptions
    // would die of.
    const Vec3 w{-0.5, -0.5, std::sqrt(0.5)};
    std::feclearexcept(FE_ALL_EXCEPT);
    const double e = quality::signed_area(x, y, w);
    assert_false(std::fetestexcept(FE_DIVBYZERO | FE_INVALID | FE_OVERFLOW));
    assert_true(std::fabs(std::fabs(e) - M_PI) <= 1e-15);
}

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(report_arcs_and_areas_are_accurate),
        cmocka_unit_test(streamed_report_matches_sorted_values),
        cmocka_unit_test(icosahedral_operator_diagnostics),
        cmocka_unit_test(centroid_offset_is_exact),
        cmocka_unit_test(json_has_operator_diagnostics),
    };
    return cmocka_run_group_tests_name("quality", tests, nullptr, nullptr);
}
