#include "features/domain.hpp"

#include <cmath>

#include "core/error.hpp"
#include "geom/predicates.hpp"
#include "geom/surface.hpp"

namespace um::features {

using geom::Vec3;

namespace {

// +1 when c is on the left of the great circle a -> b, -1 on the right, 0 on
// it: exactly (the sign of det(a, b, c)).
int side(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    return geom::orient_origin_exact(a.data(), b.data(), c.data());
}

// A point a thousandth of the segment's length to the left of the middle of
// segment s: on the left side of the ring at s, off any other ring.
Vec3 just_left_of(const Network &net, int64_t s) {
    const Vec3 a = net.segment_a(s), b = net.segment_b(s);
    const Vec3 mid = geom::normalized(a + b), left = geom::normalized(geom::cross(a, b));
    const double offset = 1e-3 * geom::arc_length(a, b);
    return geom::normalized(std::cos(offset) * mid + std::sin(offset) * left);
}

// The area of the region on the left of closed part p: the fan of signed
// triangles from its first point, modulo 4 pi, in [0, 4 pi).
double left_area(const Network &net, int64_t p) {
    const Part &part = net.part(p);
    const Vec3 apex = net.segment_a(part.first_segment);
    double sum = 0;
    for (int64_t s = part.first_segment; s < part.first_segment + part.n_segments; ++s)
        sum += geom::signed_triangle_area(apex, net.segment_a(s), net.segment_b(s));
    sum = std::fmod(sum, 4 * M_PI);
    return sum < 0 ? sum + 4 * M_PI : sum;
}

bool is_domain_ring(const Part &p) { return p.closed && p.kind == Kind::domain; }

}  // namespace

Network with_domain_rings_traced(const Network &net) {
    PartsCopy copy;
    for (int64_t index = 0; index < net.part_count(); ++index) {
        const Part &p = net.part(index);
        for (int64_t k = 0; k < p.n_points; ++k) {
            const int64_t i = p.first_point + k;
            copy.add_point(net.lon_deg(i), net.lat_deg(i));
            if (!is_domain_ring(p)) continue;
            const int64_t j = p.first_point + (k + 1) % p.n_points;
            const double dlon = std::remainder(net.lon_deg(j) - net.lon_deg(i), 360.0);  // in [-180, 180]
            const double dlat = net.lat_deg(j) - net.lat_deg(i);
            const int64_t steps = static_cast<int64_t>(std::ceil(std::max(std::fabs(dlon), std::fabs(dlat)) / kDomainStepDeg));
            for (int64_t s = 1; s < steps; ++s) {
                const double t = static_cast<double>(s) / static_cast<double>(steps);
                copy.add_point(net.lon_deg(i) + t * dlon, net.lat_deg(i) + t * dlat);
            }
        }
        copy.end_part(p);
    }
    return copy.network(net.flattening());
}

bool ring_encloses(const Network &net, int64_t p, const Vec3 &x) {
    const Part &part = net.part(p);
    const int64_t s0 = part.first_segment, s1 = s0 + part.n_segments;
    const double left = left_area(net, p);
    const bool left_is_smaller = left > 0 && left < 2 * M_PI;
    // x is on the left when the arc from x to a point just left of the first
    // segment crosses the ring an even number of times.
    const Vec3 r = just_left_of(net, s0);
    int crossings = 0;
    for (int64_t s = s0; s < s1; ++s) {
        Vec3 c;
        if (geom::arc_intersection(x, r, net.segment_a(s), net.segment_b(s), c, 0.0)) ++crossings;
    }
    return (crossings % 2 == 0) == left_is_smaller;
}

Domain::Domain(const Network &net) {
    std::vector<int64_t> rings;
    std::vector<geom::ArcTree::Arc> arcs;
    ring_segment_.assign(static_cast<size_t>(net.segment_count()), 0);
    for (int64_t p = 0; p < net.part_count(); ++p) {
        const Part &part = net.part(p);
        if (!is_domain_ring(part)) continue;
        const int32_t ring = static_cast<int32_t>(rings.size());
        const int32_t first = static_cast<int32_t>(arcs.size()), n = static_cast<int32_t>(part.n_segments);
        rings.push_back(p);
        for (int32_t k = 0; k < n; ++k) {
            const int64_t s = part.first_segment + k;
            arcs.push_back({net.segment_a(s), net.segment_b(s)});
            ring_of_arc_.push_back(ring);
            next_.push_back(first + (k + 1) % n);
            prev_.push_back(first + (k + n - 1) % n);
            ring_segment_[static_cast<size_t>(s)] = 1;
        }
    }
    if (arcs.empty()) return;
    arcs_ = geom::ArcTree(std::move(arcs));
    memo_.reset(new std::atomic<uint8_t>[static_cast<size_t>(kMemoLon) * kMemoLat]);
    for (size_t k = 0; k < static_cast<size_t>(kMemoLon) * kMemoLat; ++k) memo_[k].store(0, std::memory_order_relaxed);

    // No two segments may cross: the inside would not be one side of each ring.
    for (int32_t i = 0; i < static_cast<int32_t>(arcs_.size()); ++i) {
        const auto &a = arcs_.arc(i);
        arcs_.query(geom::arc_box(a.a, a.b), [&](int32_t j) {
            if (j <= i || j == next_[i] || j == prev_[i]) return;
            const auto &b = arcs_.arc(j);
            Vec3 c;
            if (!geom::arc_intersection(a.a, a.b, b.a, b.b, c, 0.0)) return;
            const int64_t pi = rings[ring_of_arc_[i]], pj = rings[ring_of_arc_[j]];
            double lon, lat;
            geom::Surface::ellipsoid(1.0, net.flattening()).geodetic(c, lon, lat);
            fail(UM_ERR_INPUT, "domain ring ", pi, " (id ", net.part(pi).id, ")",
                 pi == pj ? std::string(" crosses itself") : concat(" crosses domain ring ", pj, " (id ", net.part(pj).id, ")"),
                 " at lon ", lon, ", lat ", lat, ": domain rings must not cross themselves or each other");
        });
    }

    // The cap: about the mean of the ring points, out to the farthest arc.
    Vec3 sum{0, 0, 0};
    for (size_t i = 0; i < arcs_.size(); ++i) sum = sum + arcs_.arc(static_cast<int32_t>(i)).a;
    if (geom::norm(sum) > 1e-9) {
        cap_centre_ = geom::normalized(sum);
        cap_radius_ = 0;
        for (size_t i = 0; i < arcs_.size(); ++i) {
            const auto &arc = arcs_.arc(static_cast<int32_t>(i));
            // An arc of a cap smaller than a hemisphere stays in it; its
            // length bounds how far it reaches beyond its ends otherwise.
            cap_radius_ = std::max(cap_radius_, geom::arc_length(cap_centre_, arc.a) + geom::arc_length(arc.a, arc.b));
        }
    }

    // Which side of each ring is inside: the parity rule at a point just left of it.
    area_ = 0;
    for (size_t r = 0; r < rings.size(); ++r) {
        const int64_t p = rings[r];
        const Vec3 probe = just_left_of(net, net.part(p).first_segment);
        bool inside = false;
        for (int64_t q : rings) inside ^= ring_encloses(net, q, probe);
        inside_on_left_.push_back(inside);
        const double left = left_area(net, p), smaller = std::min(left, 4 * M_PI - left);
        const bool smaller_on_left = left < 2 * M_PI;
        area_ += inside == smaller_on_left ? smaller : -smaller;
    }
}

bool Domain::left_of(int32_t i, const Vec3 &x) const {
    const auto &arc = arcs_.arc(i);
    const Vec3 n = geom::cross(arc.a, arc.b);
    // The nearest point of the arc's great circle lies between its ends:
    // judged by this arc alone.
    const bool past_a = geom::dot(geom::cross(arc.a, x), n) >= 0, before_b = geom::dot(geom::cross(x, arc.b), n) >= 0;
    if (past_a && before_b) return side(arc.a, arc.b, x) > 0;
    // Else at the nearer end, where the ring turns: on the left of a corner
    // that turns left when on the left of both arcs, of one when it turns right.
    const bool at_b = geom::dot(x, arc.b) >= geom::dot(x, arc.a);
    const auto &other = arcs_.arc(at_b ? next_[i] : prev_[i]);
    const Vec3 u = at_b ? arc.a : other.a, v = at_b ? arc.b : arc.a, w = at_b ? other.b : arc.b;
    const bool left1 = side(u, v, x) > 0, left2 = side(v, w, x) > 0;
    return side(u, v, w) > 0 ? left1 && left2 : left1 || left2;
}

bool Domain::locate(const Vec3 &x, double *distance) const {
    double d = 0;
    if (empty()) {
        if (distance) *distance = 0;
        return true;
    }
    const int32_t i = arcs_.nearest(x, &d);
    if (distance) *distance = d;
    return left_of(i, x) == (inside_on_left_[ring_of_arc_[i]] != 0);
}

bool Domain::contains(const Vec3 &x) const {
    if (distance_at_least(x) > 0) return false;  // beyond the cap holding the domain
    return deep_inside(x) || locate(x, nullptr);
}

bool Domain::deep_inside(const Vec3 &x) const {
    if (empty()) return true;
    double lon, lat;
    geom::lonlat_deg_from_unit(x, lon, lat);
    const int i = std::min(kMemoLon - 1, std::max(0, static_cast<int>((lon + 180) / kMemoDeg)));
    const int j = std::min(kMemoLat - 1, std::max(0, static_cast<int>((lat + 90) / kMemoDeg)));
    std::atomic<uint8_t> &known = memo_[static_cast<size_t>(j) * kMemoLon + i];
    uint8_t state = known.load(std::memory_order_relaxed);
    if (state == 0) {
        // Every point of the cell is within its half-diagonal of the centre.
        const double half_diagonal = kMemoDeg * M_SQRT1_2 * M_PI / 180 * (1 + 1e-6);
        double d = 0;
        const bool inside = locate(geom::unit_from_lonlat_deg(-180 + (i + 0.5) * kMemoDeg, -90 + (j + 0.5) * kMemoDeg), &d);
        state = inside && d > half_diagonal ? 1 : 2;
        known.store(state, std::memory_order_relaxed);
    }
    return state == 1;
}

}  // namespace um::features
