#include "quality/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/growth.hpp"
#include "core/text.hpp"
#include "core/uninit_vector.hpp"
#include "dual/spherical.hpp"
#include "geom/predicates.hpp"
#include "refine/boundary.hpp"

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

// JSON has no inf or nan: null stands for them.
std::string json_number(double v) { return std::isfinite(v) ? to_text(v) : "null"; }

// The ocean regions as [[cells, lon, lat], ...] and the closed passages as
// [[lon, lat, land cells], ...], at most kListed of each (the largest
// regions, the thinnest closures; the counts are always whole).
constexpr size_t kListed = 100;
std::string json_connectivity(const OceanConnectivity &c) {
    std::string regions, closed;
    for (size_t i = 0; i < std::min(c.regions.size(), kListed); ++i)
        regions += concat(i ? ", " : "", "[", c.regions[i].cells, ", ", c.regions[i].lon, ", ", c.regions[i].lat, "]");
    for (size_t i = 0; i < std::min(c.closed_passages.size(), kListed); ++i) {
        const OceanConnectivity::ClosedPassage &p = c.closed_passages[i];
        closed += concat(i ? ", " : "", "[", p.lon, ", ", p.lat, ", ", p.land_cells, "]");
    }
    return concat("\"regions\": {\"count\": ", c.regions.size(), ", \"largest\": [", regions,
                  "]}, \"water_bodies\": ", c.water_bodies, ", \"closed_passages\": {\"count\": ",
                  c.closed_passages.size(), ", \"thinnest\": [", closed, "]}");
}

std::string json_offset(const Summary &s) {
    return concat("{\"rms\": ", json_number(s.rms), ", \"max\": ", json_number(s.max), "}");
}

// The operator diagnostics, one line each after `nl`: what certifies a mesh
// for the MPAS operators (metrics.hpp).
std::string json_operator_diagnostics(const Report &r, const std::string &nl) {
    const std::string in = nl + "  ";
    const Summary &c = r.cell_spacing_ratio;
    return concat("{", in, "\"centroid_offset\": ", json_offset(r.centroid_offset),
                  ",", in, "\"dual_edge_offset\": ", json_offset(r.dual_edge_offset),
                  ",", in, "\"primal_edge_offset\": ", json_offset(r.primal_edge_offset),
                  ",", in, "\"cell_spacing_ratio\": {\"min\": ", json_number(c.min), ", \"max\": ",
                  json_number(c.max), ", \"mean\": ", json_number(c.mean), ", \"std\": ", json_number(c.std),
                  "}", nl, "}");
}

}  // namespace

// The chord's arc below a quarter circle (a chord below sqrt 2), where it is
// as accurate as atan2(|a x b|, a . b): both err by the rounding of the
// vectors' differences, ~1e-16 absolute. Beyond, the arcsine loses digits.
double arc(const Vec3 &a, const Vec3 &b) {
    const double chord_sq = geom::dot(a - b, a - b);
    return chord_sq < 2.0 ? geom::arc_of_chord(std::sqrt(chord_sq)) : dual::arc(a, b);
}

// Eriksson's tan(E/2) = det / (1 + a.b + b.c + c.a), as dual::signed_area;
// for |tan(E/2)| up to 1e-2 (triangles to about 1,000 km on the Earth) its
// arctangent's series to the 7th power, whose next term is below 1.2e-17 of
// the value. (Tested before dividing: a den of 0 must raise no
// floating-point exception, which a host may trap.)
double signed_area(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    const dual::HalfExcessTangent tangent(a, b, c);
    const double det = tangent.det, den = tangent.den;
    if (den > 0 && std::fabs(det) <= 1e-2 * den) {
        const double t = det / den, t2 = t * t;
        return 2.0 * t * (1.0 - t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 / 7.0)));
    }
    return 2.0 * std::atan2(det, den);
}

namespace {

// A triangle's corners and its edges' arc lengths, l[k] opposite corner k:
// what its metrics and its edges' spacing ratios share.
struct Corners {
    Vec3 x[3];
    double l[3];
    Corners(const tri::Triangulation &tri, int32_t t) {
        for (int k = 0; k < 3; ++k) x[k] = tri.direction(tri.vertex(t, k));
        for (int k = 0; k < 3; ++k) l[k] = arc(x[(k + 1) % 3], x[(k + 2) % 3]);
    }
};

TriangleQuality triangle_quality(const tri::Triangulation &tri, int32_t t, const Corners &corners) {
    const Vec3 *x = corners.x;
    const double *l = corners.l;
    double l2 = 0, lsum = 0;
    for (int k = 0; k < 3; ++k) l2 += l[k] * l[k], lsum += l[k];
    const double area = signed_area(x[0], x[1], x[2]);
    TriangleQuality q;
    q.area_length = 4 * std::sqrt(3.0) * area / l2;
    const Vec3 ortho = tri.orthocentre(t);
    const Vec3 centroid = geom::normalized(x[0] + x[1] + x[2]);
    const double d_f = arc(ortho, centroid);
    double edge_term = 0;
    for (int k = 0; k < 3; ++k) {
        Vec3 mid = geom::normalized(x[(k + 1) % 3] + x[(k + 2) % 3]);
        double d_e = arc(tri.edge_orthocentre(t, k), mid);
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

}  // namespace

TriangleQuality triangle_quality(const tri::Triangulation &tri, int32_t t) {
    return triangle_quality(tri, t, Corners(tri, t));
}

namespace {

// Lengths below the rounding of unit vectors count as that long: a dual
// edge of no length (four cocircular generators) or a cell of no area gets
// a finite offset, ~1e16, which flags it, and no floating-point exception
// (hosts may trap them).
constexpr double kRoundingArc = 0x1p-52;

// Of edge k of t, dcEdge and xEdge (all that its spacing ratio needs), and
// its ends.
struct EdgeSpan {
    Vec3 xi, xj, x_edge;
    double dc_edge;
    EdgeSpan(const tri::Triangulation &tri, int32_t t, int k) {
        const int32_t i = tri.vertex(t, (k + 1) % 3), j = tri.vertex(t, (k + 2) % 3);
        xi = tri.direction(i), xj = tri.direction(j);
        // The edge orthocentre as the MPAS writer places it, accurate on small cells.
        x_edge = dual::edge_point(tri.lifted(i), tri.lifted(j));
        dc_edge = arc(xi, xj);
    }
};

// edge_offsets, given o1, the orthocentre of t (a pass over the triangles
// computes it once for their three edges).
EdgeOffsets edge_offsets(const tri::Triangulation &tri, int32_t t, int k, const Vec3 &o1) {
    const EdgeSpan span(tri, t, k);
    const Vec3 &xi = span.xi, &xj = span.xj, o2 = tri.orthocentre(tri.neighbour(t, k));
    EdgeOffsets e;
    e.x_edge = span.x_edge;
    e.dc_edge = span.dc_edge;
    e.primal = arc(e.x_edge, geom::normalized(xi + xj)) / e.dc_edge;
    const double dv_edge = arc(o1, o2);
    e.dual = arc(e.x_edge, geom::normalized(o1 + o2)) / std::max(dv_edge, kRoundingArc);
    return e;
}

}  // namespace

EdgeOffsets edge_offsets(const tri::Triangulation &tri, int32_t t, int k) {
    return edge_offsets(tri, t, k, tri.orthocentre(t));
}

// The polygon of the power cell is the orthocentres of v's star,
// counter-clockwise. The centroid direction is exact: the integral of x
// over the cell is half the sum, over the polygon's edges (p, q), of
// arc(p, q) times the unit normal of p x q (a signed sum, right even for a
// cell that does not hold its generator); the area is the fan of signed
// triangles from the generator.
double centroid_offset(const tri::Triangulation &tri, int32_t v) {
    const Vec3 x = tri.direction(v);
    Vec3 moment, first, prev;
    double area = 0;
    bool started = false;
    auto edge = [&](const Vec3 &p, const Vec3 &q) {
        area += signed_area(x, p, q);
        const Vec3 normal = dual::arc_normal(p, q);  // p x q, accurate on short arcs
        const double length = geom::norm(normal);
        if (length > 0) moment = moment + (arc(p, q) / length) * normal;
    };
    tri.for_each_in_star(v, [&](int32_t t) {
        const Vec3 o = tri.orthocentre(t);
        if (started) edge(prev, o);
        else first = o, started = true;
        prev = o;
    });
    edge(prev, first);
    const double length = geom::norm(moment);  // 0 only for a cell shrunk to a point
    const Vec3 centroid = length > 0 ? (1.0 / length) * moment : prev;
    return arc(x, centroid) / std::max(std::sqrt(std::max(area, 0.0)), kRoundingArc);
}

namespace {

// The metrics of a report: four per triangle and one per edge (Figure 10),
// then the operator diagnostics, three per edge and one per cell.
enum Metric {
    kAreaLength, kPrimalDual, kAngleMin, kAngleMax, kSpacingRatio,
    kDualEdgeOffset, kPrimalEdgeOffset, kCellSpacingRatio, kCentroidOffset, kMetrics
};
constexpr uint16_t kNoBin = 0xffff;
// Histogram ranges. An offset past 1/2 puts xEdge off its dual (or primal)
// arc; centroid offsets of usable cells are a few hundredths.
constexpr double kLo[kMetrics] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
constexpr double kHi[kMetrics] = {1, 1, 180, 180, 2, 0.5, 0.5, 2, 0.25};

// One metric streamed over a block: min, max, sum, sum of squares, the
// report's histogram, and a finer one (with a bin below lo and one above
// hi) that tells which fine bin holds the 1st percentile, so that a second
// pass need keep only the values in that bin (and, from the bins measure()
// notes per item, recompute only the items that have one). Keeping every
// value instead would hold ~150 bytes per cell on top of the mesh while the
// report is made; the bins are 14 to 18 bytes per triangle.
constexpr int kFine = 2048;
struct Stream {
    double min = HUGE_VAL, max = -HUGE_VAL, sum = 0, sum_sq = 0;
    // Welford's running mean and sum of squared deviations: the standard
    // deviation without the cancellation of sum_sq / n - mean^2 when the
    // spread is small against the mean (dcEdge / h is 1 give or take 1e-3).
    double centre = 0, m2 = 0;
    int64_t n = 0;
    std::vector<int64_t> coarse = std::vector<int64_t>(kBins, 0), fine = std::vector<int64_t>(kFine + 2, 0);
};

// Offsets crowd near 0 (a Voronoi mesh's primal-edge offsets are all about
// 1e-13): their fine bins are logarithmic from kLogFloor to hi, so that the
// 1st percentile's bin stays small (linear, it would hold every value, and
// the second pass recompute every edge). Logarithmic by the bits of the
// double: those of a positive double grow with it, by an octave per
// exponent step, and cost no log() (two per edge). Any bins that grow with
// the value give the same percentile; these only decide how few values
// the second pass keeps.
constexpr bool kLogFine[kMetrics] = {false, false, false, false, false, true, true, false, true};
constexpr double kLogFloor = 1e-16;

double bits_of(double v) {
    int64_t bits;  // (v > 0: below 2^63)
    std::memcpy(&bits, &v, sizeof bits);
    return static_cast<double>(bits);
}

int fine_bin(double v, Metric m) {
    if (kLogFine[m] && !(v > kLogFloor)) return 0;  // (and NaN)
    const double x = kLogFine[m] ? (bits_of(v) - bits_of(kLogFloor)) / (bits_of(kHi[m]) - bits_of(kLogFloor))
                                 : (v - kLo[m]) / (kHi[m] - kLo[m]);
    if (!(x >= 0)) return 0;  // below lo (or NaN)
    if (x >= 1) return kFine + 1;
    return 1 + std::min(kFine - 1, static_cast<int>(x * kFine));
}

void add(Stream &s, double v, Metric m) {
    s.min = std::min(s.min, v), s.max = std::max(s.max, v), s.sum += v, s.sum_sq += v * v, ++s.n;
    const double d = v - s.centre;
    s.centre += d / double(s.n), s.m2 += d * (v - s.centre);
    const double x = (v - kLo[m]) / (kHi[m] - kLo[m]) * kBins;  // clamped before the cast: v may be ~1e16
    ++s.coarse[x >= 0 ? static_cast<size_t>(std::min(x, double(kBins - 1))) : 0];
    ++s.fine[fine_bin(v, m)];
}

// s into the total a (Chan, Golub and LeVeque's update for the deviations),
// block after block in a fixed order.
void merge(Stream &a, const Stream &s) {
    if (s.n == 0) return;
    const double n = double(a.n + s.n), d = s.centre - a.centre;
    a.m2 += s.m2 + d * d * double(a.n) * double(s.n) / n;
    a.centre += d * double(s.n) / n;
    a.min = std::min(a.min, s.min), a.max = std::max(a.max, s.max);
    a.sum += s.sum, a.sum_sq += s.sum_sq, a.n += s.n;
    for (int i = 0; i < kBins; ++i) a.coarse[i] += s.coarse[i];
    for (int i = 0; i < kFine + 2; ++i) a.fine[i] += s.fine[i];
}

// What the triangle pass counts besides its metrics.
struct Counts {
    int64_t triangles = 0, edges = 0, obtuse = 0, not_well_centred = 0, not_well_centred_off_gamma = 0;
    void operator+=(const Counts &c) {
        triangles += c.triangles, edges += c.edges, obtuse += c.obtuse, not_well_centred += c.not_well_centred;
        not_well_centred_off_gamma += c.not_well_centred_off_gamma;
    }
};

// The summary of a metric from its total stream and the values of its
// 1st-percentile fine bin (rank: the 1st percentile's rank in that bin).
void finish(Summary &s, Metric m, const Stream &all, std::vector<double> &in_bin, int64_t rank) {
    s.lo = kLo[m], s.hi = kHi[m];
    s.histogram = all.coarse;
    if (all.n == 0) return;  // an empty mesh (or no h): zeros
    const double n = double(all.n);
    s.min = all.min, s.max = all.max, s.mean = all.sum / n;
    s.rms = std::sqrt(all.sum_sq / n), s.std = std::sqrt(all.m2 / n);
    // The two passes see the same values unless h is not reproducible
    // (a user callback): then the nearest the bin allows.
    if (in_bin.empty()) {
        s.p1 = s.min;
        return;
    }
    auto at = in_bin.begin() + static_cast<std::ptrdiff_t>(std::min<int64_t>(rank, in_bin.size() - 1));
    std::nth_element(in_bin.begin(), at, in_bin.end());
    s.p1 = *at;
}

// The summaries of the metrics of items 0..n-1 (triangles, or vertex
// slots): values(i, counts, emit) calls emit(slot, value) for every value
// of item i, each slot (< kSlots) at most once, the value being of metric
// slot_metric[slot]; those metrics are consecutive. Fixed blocks, combined
// in block order: the same summaries for any thread count.
template <size_t kSlots, class Values>
Counts summarise(Context &ctx, int64_t n, const std::array<Metric, kSlots> &slot_metric, Values &&values,
                 Summary *const summary[kMetrics]) {
    constexpr int64_t kBlock = 32768;
    const int first = *std::min_element(slot_metric.begin(), slot_metric.end());
    const int count = *std::max_element(slot_metric.begin(), slot_metric.end()) + 1 - first;
    const int64_t n_blocks = (n + kBlock - 1) / kBlock;
    struct Block {
        std::vector<Stream> metric;
        Counts counts;
    };
    std::vector<Block> blocks(static_cast<size_t>(n_blocks));
    // Each value's fine bin, per item and slot: the second pass then
    // recomputes only the items with a value in a 1st-percentile bin.
    // (Written first by the parallel pass: zeroed here, on one thread, its
    // 14 to 18 bytes a triangle would take every page fault.)
    UninitVector<std::array<uint16_t, kSlots>> bins(static_cast<size_t>(n));
    // With a heartbeat between runs of blocks: the values may call a slow
    // spacing callback, and cancel must get in.
    ctx.parallel_for_with_heartbeat("quality", n_blocks, 1, [&](int64_t b0, int64_t b1) {
        for (int64_t blk = b0; blk < b1; ++blk) {
            Block &bl = blocks[blk];
            bl.metric.resize(static_cast<size_t>(count));
            for (int64_t i = blk * kBlock; i < std::min(n, (blk + 1) * kBlock); ++i) {
                auto &bin = bins[i];
                bin.fill(kNoBin);
                values(i, bl.counts, [&](int slot, double v) {
                    const Metric m = slot_metric[slot];
                    add(bl.metric[m - first], v, m);
                    bin[slot] = static_cast<uint16_t>(fine_bin(v, m));
                });
            }
        }
    });
    Counts counts;
    std::vector<Stream> all(static_cast<size_t>(count));
    for (const Block &bl : blocks) {
        counts += bl.counts;
        for (int m = 0; m < count; ++m) merge(all[m], bl.metric[m]);
    }
    release(blocks);
    // The 1st percentile (the value a full sort puts at n / 100): its fine
    // bin and rank there, then the values of that bin only.
    std::vector<int> p1_bin(static_cast<size_t>(count));
    std::vector<int64_t> p1_rank(static_cast<size_t>(count));
    for (int m = 0; m < count; ++m) {
        int64_t rank = all[m].n / 100, i = 0;
        while (i < kFine + 1 && rank >= all[m].fine[i]) rank -= all[m].fine[i++];
        p1_bin[m] = static_cast<int>(i), p1_rank[m] = rank;
    }
    std::array<uint16_t, kSlots> wanted_bin;
    for (size_t s = 0; s < kSlots; ++s) wanted_bin[s] = static_cast<uint16_t>(p1_bin[slot_metric[s] - first]);
    std::vector<std::vector<std::vector<double>>> in_bin(
        static_cast<size_t>(count), std::vector<std::vector<double>>(static_cast<size_t>(n_blocks)));
    ctx.parallel_for_with_heartbeat("quality", n_blocks, 1, [&](int64_t b0, int64_t b1) {
        Counts again;  // counted in the first pass
        for (int64_t blk = b0; blk < b1; ++blk)
            for (int64_t i = blk * kBlock; i < std::min(n, (blk + 1) * kBlock); ++i) {
                bool wanted = false;
                for (size_t s = 0; s < kSlots && !wanted; ++s) wanted = bins[i][s] == wanted_bin[s];
                if (!wanted) continue;
                values(i, again, [&](int slot, double v) {
                    const Metric m = slot_metric[slot];
                    if (fine_bin(v, m) == p1_bin[m - first]) in_bin[m - first][blk].push_back(v);
                });
            }
    });
    release(bins);
    for (int m = 0; m < count; ++m) {
        std::vector<double> joined;
        for (const auto &v : in_bin[m]) joined.insert(joined.end(), v.begin(), v.end());
        finish(*summary[first + m], Metric(first + m), all[m], joined, p1_rank[m]);
    }
    return counts;
}

// The slots of a triangle's values: its four metrics, then the spacing
// ratio of edge k at 4 + k.
constexpr std::array<Metric, 7> kTriangleSlots = {kAreaLength, kPrimalDual, kAngleMin, kAngleMax,
                                                  kSpacingRatio, kSpacingRatio, kSpacingRatio};
// Of the operator diagnostics of a triangle's edges: those of edge k at 3k.
constexpr std::array<Metric, 9> kEdgeSlots = {
    kDualEdgeOffset, kPrimalEdgeOffset, kCellSpacingRatio, kDualEdgeOffset, kPrimalEdgeOffset,
    kCellSpacingRatio, kDualEdgeOffset, kPrimalEdgeOffset, kCellSpacingRatio};

}  // namespace

Report measure(Context &ctx, const tri::Triangulation &tri, const refine::SpacingRadians &h,
               const std::vector<int32_t> *on_segment, const std::vector<uint8_t> *cells) {
    Report r;
    Summary *const summary[kMetrics] = {&r.area_length,      &r.primal_dual,        &r.angle_min,
                                        &r.angle_max,        &r.spacing_ratio,      &r.dual_edge_offset,
                                        &r.primal_edge_offset, &r.cell_spacing_ratio, &r.centroid_offset};
    auto off_gamma = [&](int32_t t) {
        for (int k = 0; k < 3; ++k) {
            const size_t v = static_cast<size_t>(tri.vertex(t, k));
            if (!on_segment || v >= on_segment->size() || (*on_segment)[v] < 0) return true;
        }
        return false;
    };
    auto kept = [&](int32_t v) { return !cells || (*cells)[v] != 0; };
    auto kept_triangle = [&](int32_t t) {
        return !tri.is_free(t) && kept(tri.vertex(t, 0)) && kept(tri.vertex(t, 1)) && kept(tri.vertex(t, 2));
    };
    // Every edge once, from its triangle of the smaller number.
    auto counted = [&](int32_t t, int k) {
        return tri.neighbour(t, k) > t && kept(tri.vertex(t, (k + 1) % 3)) && kept(tri.vertex(t, (k + 2) % 3));
    };
    const int32_t n = tri.triangle_slots();
    auto triangle_values = [&](int64_t i, Counts &c, auto &&emit) {
        const int32_t t = static_cast<int32_t>(i);
        if (tri.is_free(t)) return;
        const Corners corners(tri, t);
        // Every edge between kept cells, whichever of its triangles is kept.
        for (int k = 0; k < 3 && h; ++k) {
            if (!counted(t, k)) continue;
            const Vec3 &a = corners.x[(k + 1) % 3], &b = corners.x[(k + 2) % 3];
            emit(kSpacingRatio + k, corners.l[k] / h(geom::normalized(a + b)));
        }
        for (int k = 0; k < 3; ++k) c.edges += counted(t, k);
        if (!kept_triangle(t)) return;
        const TriangleQuality q = triangle_quality(tri, t, corners);
        emit(kAreaLength, q.area_length), emit(kPrimalDual, q.primal_dual);
        emit(kAngleMin, q.angle_min), emit(kAngleMax, q.angle_max);
        ++c.triangles, c.obtuse += q.angle_max > 90, c.not_well_centred += !q.well_centred;
        c.not_well_centred_off_gamma += !q.well_centred && off_gamma(t);
    };
    const Counts c = summarise(ctx, n, kTriangleSlots, triangle_values, summary);
    r.triangles = c.triangles, r.obtuse = c.obtuse, r.not_well_centred = c.not_well_centred;
    r.not_well_centred_off_gamma = c.not_well_centred_off_gamma;
    r.edges = c.edges;
    auto edge_values = [&](int64_t i, Counts &, auto &&emit) {
        const int32_t t = static_cast<int32_t>(i);
        if (tri.is_free(t)) return;
        const Vec3 o1 = tri.orthocentre(t);
        for (int k = 0; k < 3; ++k) {
            if (!counted(t, k)) continue;
            const EdgeOffsets e = edge_offsets(tri, t, k, o1);
            emit(3 * k, e.dual), emit(3 * k + 1, e.primal);
            if (h) emit(3 * k + 2, e.dc_edge / h(e.x_edge));
        }
    };
    summarise(ctx, n, kEdgeSlots, edge_values, summary);
    auto cell_values = [&](int64_t v, Counts &, auto &&emit) {
        if (tri.in_triangulation(static_cast<int32_t>(v)) && kept(static_cast<int32_t>(v)))
            emit(0, centroid_offset(tri, static_cast<int32_t>(v)));
    };
    summarise(ctx, tri.vertex_slots(), std::array<Metric, 1>{kCentroidOffset}, cell_values, summary);
    return r;
}

Report::OceanEdges measure_ocean_edges(Context &ctx, const tri::Triangulation &tri, const refine::SpacingRadians &h,
                                       const std::vector<uint8_t> &ocean_cell, double floor,
                                       const std::vector<std::pair<int32_t, int32_t>> &contacts,
                                       const geom::Surface &surface) {
    constexpr int64_t kBlock = 16384;
    const int64_t n = tri.triangle_slots(), n_blocks = (n + kBlock - 1) / kBlock;
    std::vector<Report::OceanEdges> part(static_cast<size_t>(n_blocks));
    auto ocean = [&](int32_t v) { return static_cast<size_t>(v) < ocean_cell.size() && ocean_cell[v] != 0; };
    auto kept_open = [&](int32_t v) { return ocean_cell[v] == 2; };
    ctx.parallel_for_with_heartbeat("quality", n_blocks, 1, [&](int64_t b0, int64_t b1) {
        for (int64_t blk = b0; blk < b1; ++blk) {
            Report::OceanEdges &o = part[static_cast<size_t>(blk)];
            o.min_ratio = std::numeric_limits<double>::infinity();
            for (int64_t i = blk * kBlock; i < std::min(n, (blk + 1) * kBlock); ++i) {
                const int32_t t = static_cast<int32_t>(i);
                if (tri.is_free(t)) continue;
                for (int k = 0; k < 3; ++k) {
                    if (tri.neighbour(t, k) < t) continue;  // each edge once
                    const int32_t a = tri.vertex(t, (k + 1) % 3), b = tri.vertex(t, (k + 2) % 3);
                    if (!ocean(a) || !ocean(b)) continue;
                    const EdgeSpan e(tri, t, k);
                    const double ratio = e.dc_edge / h(e.x_edge);
                    ++o.edges;
                    if (kept_open(a) || kept_open(b)) {
                        o.kept_open_below_floor += ratio < floor;
                        continue;
                    }
                    o.below_floor += ratio < floor;
                    o.min_ratio = std::min(o.min_ratio, ratio);
                }
            }
        }
    });
    Report::OceanEdges all;
    all.measured = true, all.floor = floor, all.min_ratio = std::numeric_limits<double>::infinity();
    for (const Report::OceanEdges &o : part) {
        all.edges += o.edges, all.below_floor += o.below_floor, all.kept_open_below_floor += o.kept_open_below_floor;
        all.min_ratio = std::min(all.min_ratio, o.min_ratio);
    }
    for (int32_t v = 0; v < tri.vertex_slots(); ++v) all.kept_open_cells += tri.in_triangulation(v) && kept_open(v);
    all.connectivity = ocean_connectivity(tri, ocean_cell, contacts, surface);
    return all;
}

Report::CoastlineFidelity measure_coastline_fidelity(const tri::Triangulation &tri,
                                                     const std::vector<refine::RestrictedEdge> &restricted,
                                                     const std::vector<uint8_t> &coast_arc,
                                                     const refine::SpacingRadians &h, double beta) {
    Report::CoastlineFidelity f;
    f.measured = true, f.beta = beta;
    double sum = 0;
    for (const refine::RestrictedEdge &e : restricted) {
        if (!coast_arc[static_cast<size_t>(e.arc)]) continue;
        const refine::EdgeMeasure m = refine::measure(tri, e, h);
        const double ratio = m.eps / (beta * m.h);
        ++f.restricted_edges, f.beyond_beta += ratio >= 1;
        sum += ratio, f.eps_max = std::max(f.eps_max, ratio);
    }
    f.eps_mean = f.restricted_edges ? sum / double(f.restricted_edges) : 0;
    return f;
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
                  ",", nl, "\"not_well_centred_off_gamma\": ", r.not_well_centred_off_gamma,
                  ",", nl, "\"operator_diagnostics\": ", json_operator_diagnostics(r, nl));
    if (r.ocean.measured)
        text += concat(",", nl, "\"ocean_floor\": {\"floor\": ", r.ocean.floor, ", \"ocean_edges\": ", r.ocean.edges,
                       ", \"min_ratio\": ", json_number(r.ocean.min_ratio),
                       ", \"all_edges_min_ratio\": ", json_number(r.cell_spacing_ratio.min),
                       ", \"below_floor\": ", r.ocean.below_floor, ", \"kept_open\": {\"cells\": ",
                       r.ocean.kept_open_cells, ", \"below_floor\": ", r.ocean.kept_open_below_floor, "}, ",
                       json_connectivity(r.ocean.connectivity), "}");
    if (r.coastline.measured)
        text += concat(",", nl, "\"coastline_fidelity\": {\"beta\": ", r.coastline.beta,
                       ", \"restricted_edges\": ", r.coastline.restricted_edges, ", \"eps_over_beta_h\": {\"mean\": ",
                       r.coastline.eps_mean, ", \"max\": ", r.coastline.eps_max, "}, \"beyond_beta\": ",
                       r.coastline.beyond_beta, "}");
    if (r.geodesic.measured)
        text += concat(",", nl, "\"geodesic\": {\"ellipsoid\": {\"semi_major_axis_m\": ", r.geodesic.a_m,
                       ", \"flattening\": ", r.geodesic.f, "}, \"edges\": ", r.geodesic.edges,
                       ", \"length_over_h\": {\"min\": ", r.geodesic.length_over_h_min, ", \"mean\": ",
                       r.geodesic.length_over_h_mean, ", \"max\": ", r.geodesic.length_over_h_max,
                       "}, \"cells\": ", r.geodesic.cells, ", \"cell_area_m2\": ", r.geodesic.cell_area_m2,
                       ", \"ellipsoid_area_m2\": ", r.geodesic.surface_area_m2, "}");
    if (!extra_members.empty()) text += concat(",", nl, extra_members);
    return text + concat("\n", indent, "}", indent.empty() ? "\n" : "");
}

}  // namespace um::quality
