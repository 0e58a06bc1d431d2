// Engine tests: the streamed quality report (quality/metrics) against every
// value computed and sorted.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <vector>

#include "quality/metrics.hpp"
#include "refine/surface.hpp"

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
                v[4].push_back(geom::arc_length(a, c) / h(geom::normalized(a + c)));
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
    }
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(streamed_report_matches_sorted_values),
    };
    return cmocka_run_group_tests_name("quality", tests, nullptr, nullptr);
}
