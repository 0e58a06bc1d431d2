#include "quality/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/growth.hpp"
#include "core/text.hpp"
#include "geom/predicates.hpp"

namespace um::quality {

using geom::Vec3;

namespace {

constexpr double kDegree = 180.0 / M_PI;

// Interior angle at b of the spherical triangle (a, b, c), radians.
double angle_at(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    Vec3 ta = geom::cross(geom::cross(b, a), b), tc = geom::cross(geom::cross(b, c), b);
    return std::atan2(geom::norm(geom::cross(ta, tc)), geom::dot(ta, tc));
}

std::string json_summary(const Summary &s) {
    std::string h = "[";
    for (size_t i = 0; i < s.histogram.size(); ++i) h += (i ? "," : "") + to_text(s.histogram[i]);
    return concat("{\"min\": ", s.min, ", \"p1\": ", s.p1, ", \"mean\": ", s.mean, ", \"max\": ", s.max,
                  ", \"histogram\": {\"lo\": ", s.lo, ", \"hi\": ", s.hi, ", \"counts\": ", h, "]}}");
}

}  // namespace

TriangleQuality triangle_quality(const tri::Triangulation &tri, int32_t t) {
    Vec3 x[3];
    for (int k = 0; k < 3; ++k) x[k] = tri.direction(tri.vertex(t, k));
    double l[3], l2 = 0, lsum = 0;
    for (int k = 0; k < 3; ++k) {
        l[k] = geom::arc_length(x[(k + 1) % 3], x[(k + 2) % 3]);  // opposite vertex k
        l2 += l[k] * l[k], lsum += l[k];
    }
    const double area = geom::signed_triangle_area(x[0], x[1], x[2]);
    TriangleQuality q;
    q.area_length = 4 * std::sqrt(3.0) * area / l2;
    const Vec3 ortho = tri.orthocentre(t);
    const Vec3 centroid = geom::normalized(x[0] + x[1] + x[2]);
    const double d_f = geom::arc_length(ortho, centroid);
    double edge_term = 0;
    for (int k = 0; k < 3; ++k) {
        Vec3 mid = geom::normalized(x[(k + 1) % 3] + x[(k + 2) % 3]);
        double d_e = geom::arc_length(tri.edge_orthocentre(t, k), mid);
        edge_term += 1 - (d_e / l[k]) * (d_e / l[k]);
    }
    const double l_mean = lsum / 3;
    q.primal_dual = 2.0 / 3.0 * (1 - (d_f / l_mean) * (d_f / l_mean)) + 1.0 / 3.0 * edge_term / 3;
    double angles[3];
    for (int k = 0; k < 3; ++k) angles[k] = angle_at(x[(k + 2) % 3], x[k], x[(k + 1) % 3]) * kDegree;
    q.angle_min = std::min({angles[0], angles[1], angles[2]});
    q.angle_max = std::max({angles[0], angles[1], angles[2]});
    // Inside (or on) the triangle: on the left of (or on) every edge, exactly.
    q.well_centred = true;
    for (int k = 0; k < 3; ++k)
        q.well_centred &= geom::orient_origin(x[(k + 1) % 3].data(), x[(k + 2) % 3].data(), ortho.data()) >= 0;
    return q;
}

namespace {

// The five metrics of a report: four per triangle, one per edge.
enum Metric { kAreaLength, kPrimalDual, kAngleMin, kAngleMax, kSpacingRatio, kMetrics };
constexpr int kValuesPerTriangle = kSpacingRatio + 3;  // the spacing ratio of up to 3 edges
constexpr uint16_t kNoBin = 0xffff;
constexpr double kLo[kMetrics] = {0, 0, 0, 0, 0}, kHi[kMetrics] = {1, 1, 180, 180, 2};

// One metric streamed over a block: min, max, sum, the report's histogram,
// and a finer one (with a bin below lo and one above hi) that tells which
// fine bin holds the 1st percentile, so that a second pass need keep only
// the values in that bin (and, from the bins measure() notes per triangle,
// recompute only the triangles that have one). Keeping every value instead
// would hold ~150 bytes per cell on top of the mesh while the report is
// made; the bins are 14.
constexpr int kFine = 2048;
struct Stream {
    double min = HUGE_VAL, max = -HUGE_VAL, sum = 0;
    int64_t n = 0;
    std::vector<int64_t> coarse = std::vector<int64_t>(kBins, 0), fine = std::vector<int64_t>(kFine + 2, 0);
};

int fine_bin(double v, Metric m) {
    const double x = (v - kLo[m]) / (kHi[m] - kLo[m]);
    if (!(x >= 0)) return 0;  // below lo (or NaN)
    if (x >= 1) return kFine + 1;
    return 1 + std::min(kFine - 1, static_cast<int>(x * kFine));
}

void add(Stream &s, double v, Metric m) {
    s.min = std::min(s.min, v), s.max = std::max(s.max, v), s.sum += v, ++s.n;
    const int b = static_cast<int>((v - kLo[m]) / (kHi[m] - kLo[m]) * kBins);
    ++s.coarse[std::clamp(b, 0, kBins - 1)];
    ++s.fine[fine_bin(v, m)];
}

// Calls fn(metric, value) for every value of triangle t (each edge once).
template <class Fn>
void for_each_value(const tri::Triangulation &tri, const refine::SpacingRadians &h, int32_t t,
                    TriangleQuality &q, Fn &&fn) {
    q = triangle_quality(tri, t);
    fn(kAreaLength, q.area_length), fn(kPrimalDual, q.primal_dual);
    fn(kAngleMin, q.angle_min), fn(kAngleMax, q.angle_max);
    if (!h) return;
    for (int k = 0; k < 3; ++k) {
        if (tri.neighbour(t, k) < t) continue;
        const Vec3 a = tri.direction(tri.vertex(t, (k + 1) % 3)), c = tri.direction(tri.vertex(t, (k + 2) % 3));
        fn(kSpacingRatio, geom::arc_length(a, c) / h(geom::normalized(a + c)));
    }
}

}  // namespace

Report measure(Context &ctx, const tri::Triangulation &tri, const refine::SpacingRadians &h,
               const std::vector<int32_t> *on_segment) {
    // Fixed blocks, combined in block order: the same report for any
    // thread count.
    constexpr int64_t kBlock = 32768;
    const int32_t n = tri.triangle_slots();
    const int64_t n_blocks = (n + kBlock - 1) / kBlock;
    struct Block {
        Stream metric[kMetrics];
        int64_t triangles = 0, obtuse = 0, not_well_centred = 0, not_well_centred_off_gamma = 0;
    };
    auto off_gamma = [&](int32_t t) {
        for (int k = 0; k < 3; ++k) {
            const size_t v = static_cast<size_t>(tri.vertex(t, k));
            if (!on_segment || v >= on_segment->size() || (*on_segment)[v] < 0) return true;
        }
        return false;
    };
    std::vector<Block> blocks(static_cast<size_t>(n_blocks));
    // Each value's fine bin, per triangle (its four metrics, then the
    // spacing ratios of the edges it counts): the second pass then
    // recomputes only the triangles with a value in a 1st-percentile bin.
    // 14 bytes per triangle, for as long as the report is being made.
    std::vector<std::array<uint16_t, kValuesPerTriangle>> bins(static_cast<size_t>(n));
    ctx.parallel_for(n_blocks, 1, [&](int64_t b0, int64_t b1) {
        for (int64_t blk = b0; blk < b1; ++blk) {
            Block &bl = blocks[blk];
            for (int64_t t = blk * kBlock; t < std::min<int64_t>(n, (blk + 1) * kBlock); ++t) {
                auto &bin = bins[t];
                bin.fill(kNoBin);
                if (tri.is_free(static_cast<int32_t>(t))) continue;
                TriangleQuality q;
                int edge = 0;
                for_each_value(tri, h, static_cast<int32_t>(t), q, [&](Metric m, double v) {
                    add(bl.metric[m], v, m);
                    bin[m == kSpacingRatio ? kSpacingRatio + edge++ : m] = static_cast<uint16_t>(fine_bin(v, m));
                });
                ++bl.triangles, bl.obtuse += q.angle_max > 90, bl.not_well_centred += !q.well_centred;
                bl.not_well_centred_off_gamma += !q.well_centred && off_gamma(static_cast<int32_t>(t));
            }
        }
    });
    Report r;
    Summary *summary[kMetrics] = {&r.area_length, &r.primal_dual, &r.angle_min, &r.angle_max, &r.spacing_ratio};
    Stream all[kMetrics];
    for (const Block &bl : blocks) {
        r.triangles += bl.triangles, r.obtuse += bl.obtuse, r.not_well_centred += bl.not_well_centred;
        r.not_well_centred_off_gamma += bl.not_well_centred_off_gamma;
        for (int m = 0; m < kMetrics; ++m) {
            const Stream &s = bl.metric[m];
            Stream &a = all[m];
            a.min = std::min(a.min, s.min), a.max = std::max(a.max, s.max), a.sum += s.sum, a.n += s.n;
            for (int i = 0; i < kBins; ++i) a.coarse[i] += s.coarse[i];
            for (int i = 0; i < kFine + 2; ++i) a.fine[i] += s.fine[i];
        }
    }
    release(blocks);
    r.edges = 3 * r.triangles / 2;
    // The 1st percentile (the value a full sort puts at n / 100): its fine
    // bin and rank there, then the values of that bin only.
    int p1_bin[kMetrics];
    int64_t p1_rank[kMetrics];
    for (int m = 0; m < kMetrics; ++m) {
        int64_t rank = all[m].n / 100, i = 0;
        while (i < kFine + 1 && rank >= all[m].fine[i]) rank -= all[m].fine[i++];
        p1_bin[m] = static_cast<int>(i), p1_rank[m] = rank;
    }
    std::vector<std::vector<double>> in_bin[kMetrics];
    for (auto &v : in_bin) v.resize(static_cast<size_t>(n_blocks));
    ctx.parallel_for(n_blocks, 1, [&](int64_t b0, int64_t b1) {
        for (int64_t blk = b0; blk < b1; ++blk)
            for (int64_t t = blk * kBlock; t < std::min<int64_t>(n, (blk + 1) * kBlock); ++t) {
                bool wanted = false;
                for (int i = 0; i < kValuesPerTriangle && !wanted; ++i)
                    wanted = bins[t][i] == p1_bin[std::min(i, int(kSpacingRatio))];
                if (!wanted) continue;
                TriangleQuality q;
                for_each_value(tri, h, static_cast<int32_t>(t), q, [&](Metric m, double v) {
                    if (fine_bin(v, m) == p1_bin[m]) in_bin[m][blk].push_back(v);
                });
            }
    });
    release(bins);
    for (int m = 0; m < kMetrics; ++m) {
        Summary &s = *summary[m];
        s.lo = kLo[m], s.hi = kHi[m];
        s.histogram = all[m].coarse;
        if (all[m].n == 0) continue;  // an empty mesh: zeros
        s.min = all[m].min, s.max = all[m].max, s.mean = all[m].sum / double(all[m].n);
        std::vector<double> values;
        for (const auto &v : in_bin[m]) values.insert(values.end(), v.begin(), v.end());
        // The two passes see the same values unless h is not reproducible
        // (a user callback): then the nearest the bin allows.
        if (values.empty()) {
            s.p1 = s.min;
            continue;
        }
        auto at = values.begin() + static_cast<std::ptrdiff_t>(std::min<int64_t>(p1_rank[m], values.size() - 1));
        std::nth_element(values.begin(), at, values.end());
        s.p1 = *at;
    }
    return r;
}

std::string to_json(const Report &r, const std::string &indent,
                    const std::string &extra_members) {
    const std::string nl = "\n" + indent + "  ";
    std::string text = concat("{", nl, "\"triangles\": ", r.triangles, ",", nl, "\"edges\": ", r.edges,
                  ",", nl, "\"area_length_ratio\": ", json_summary(r.area_length),
                  ",", nl, "\"primal_dual\": ", json_summary(r.primal_dual),
                  ",", nl, "\"angle_min_deg\": ", json_summary(r.angle_min),
                  ",", nl, "\"angle_max_deg\": ", json_summary(r.angle_max),
                  ",", nl, "\"edge_spacing_ratio\": ", json_summary(r.spacing_ratio),
                  ",", nl, "\"obtuse_triangles\": ", r.obtuse,
                  ",", nl, "\"not_well_centred\": ", r.not_well_centred,
                  ",", nl, "\"not_well_centred_off_gamma\": ", r.not_well_centred_off_gamma);
    if (!extra_members.empty()) text += concat(",", nl, extra_members);
    return text + concat("\n", indent, "}", indent.empty() ? "\n" : "");
}

}  // namespace um::quality
