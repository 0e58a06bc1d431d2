#include "quality/metrics.hpp"

#include <algorithm>
#include <cmath>

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

Summary summarise(std::vector<double> values, double lo, double hi) {
    Summary s;
    s.lo = lo, s.hi = hi;
    s.histogram.assign(kBins, 0);
    if (values.empty()) return s;
    double sum = 0;
    s.min = s.max = values.front();
    for (double v : values) {
        sum += v;
        s.min = std::min(s.min, v), s.max = std::max(s.max, v);
        int b = static_cast<int>((v - lo) / (hi - lo) * kBins);
        ++s.histogram[std::clamp(b, 0, kBins - 1)];
    }
    s.mean = sum / double(values.size());  // summed in index order: deterministic
    // The 1st percentile: the value a full sort would put at size/100.
    auto p1 = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 100);
    std::nth_element(values.begin(), p1, values.end());
    s.p1 = *p1;
    return s;
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

Report measure(Context &ctx, const tri::Triangulation &tri, const refine::SpacingRadians &h) {
    const int32_t n = tri.triangle_slots();
    std::vector<TriangleQuality> q(static_cast<size_t>(n));
    std::vector<double> ratio(3 * static_cast<size_t>(n), -1.0);
    ctx.parallel_for(n, 2048, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t) {
            const int32_t ti = static_cast<int32_t>(t);
            if (tri.is_free(ti)) continue;
            q[t] = triangle_quality(tri, ti);
            if (!h) continue;
            for (int k = 0; k < 3; ++k) {
                if (tri.neighbour(ti, k) < ti) continue;  // each edge once
                Vec3 a = tri.direction(tri.vertex(ti, (k + 1) % 3)), c = tri.direction(tri.vertex(ti, (k + 2) % 3));
                ratio[3 * t + k] = geom::arc_length(a, c) / h(geom::normalized(a + c));
            }
        }
    });
    Report r;
    for (int32_t t = 0; t < n; ++t) {
        if (tri.is_free(t)) continue;
        ++r.triangles;
        r.obtuse += q[t].angle_max > 90;
        r.not_well_centred += !q[t].well_centred;
    }
    r.edges = 3 * r.triangles / 2;
    // One metric at a time, so that only one list of values is alive.
    auto over_triangles = [&](double TriangleQuality::*field) {
        std::vector<double> values;
        values.reserve(static_cast<size_t>(r.triangles));
        for (int32_t t = 0; t < n; ++t)
            if (!tri.is_free(t)) values.push_back(q[t].*field);
        return values;
    };
    r.area_length = summarise(over_triangles(&TriangleQuality::area_length), 0, 1);
    r.primal_dual = summarise(over_triangles(&TriangleQuality::primal_dual), 0, 1);
    r.angle_min = summarise(over_triangles(&TriangleQuality::angle_min), 0, 180);
    r.angle_max = summarise(over_triangles(&TriangleQuality::angle_max), 0, 180);
    std::vector<double> hr;
    if (h) hr.reserve(static_cast<size_t>(r.edges));
    for (double x : ratio)
        if (x >= 0) hr.push_back(x);
    r.spacing_ratio = summarise(std::move(hr), 0, 2);
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
                  ",", nl, "\"not_well_centred\": ", r.not_well_centred);
    if (!extra_members.empty()) text += concat(",", nl, extra_members);
    return text + concat("\n", indent, "}", indent.empty() ? "\n" : "");
}

}  // namespace um::quality
