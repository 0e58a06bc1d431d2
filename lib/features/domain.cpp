#include "features/domain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "features/lonlat_ring.hpp"
#include "geom/predicates.hpp"
#include "geom/surface.hpp"

namespace um::features {

using geom::Vec3;

namespace {

// +1 when c is on the left of the great circle a -> b, -1 on the right, 0 on
// it: exactly (the sign of det(a, b, c)).
int orientation(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
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

// Where two rings cross, in messages: degrees to 1e-7 (about a centimetre);
// the intersection's last bits are rounding.
constexpr int kPlaceDecimals = 7;

// The apex of a fan over closed part p: its first point, unless a point of
// the part is near that point's antipode (a ring wider than a hemisphere):
// a fan triangle through the antipode has no defined area, and near it its
// area is ill-conditioned. Then the one of the six axis directions farthest
// from every point's antipode.
constexpr double kApexClearance = 1e-2;  // chord
Vec3 fan_apex(const Network &net, const Part &part) {
    auto clearance = [&](const Vec3 &apex) {
        double least = 2;
        for (int64_t s = part.first_segment; s < part.first_segment + part.n_segments; ++s)
            least = std::min(least, geom::norm(apex + net.segment_a(s)));
        return least;
    };
    const Vec3 first = net.segment_a(part.first_segment);
    if (clearance(first) > kApexClearance) return first;
    Vec3 best = first;
    double best_clearance = -1;
    for (int axis = 0; axis < 6; ++axis) {
        const double sign = axis % 2 == 0 ? 1.0 : -1.0;
        const Vec3 candidate{axis / 2 == 0 ? sign : 0.0, axis / 2 == 1 ? sign : 0.0, axis / 2 == 2 ? sign : 0.0};
        const double c = clearance(candidate);
        if (c > best_clearance) best = candidate, best_clearance = c;
    }
    return best;
}

// The area of the region on the left of closed part p: the fan of signed
// triangles from an apex (fan_apex), modulo 4 pi, in [0, 4 pi).
double left_area(const Network &net, int64_t p) {
    const Part &part = net.part(p);
    const Vec3 apex = fan_apex(net, part);
    double sum = 0;
    for (int64_t s = part.first_segment; s < part.first_segment + part.n_segments; ++s)
        sum += geom::signed_triangle_area(apex, net.segment_a(s), net.segment_b(s));
    sum = std::fmod(sum, 4 * M_PI);
    return sum < 0 ? sum + 4 * M_PI : sum;
}

bool is_domain_ring(const Part &p) { return p.closed && p.kind == Kind::domain; }

// Douglas-Peucker on the sphere: the points of the closed ring (its first
// and its farthest point kept, then between each two kept ones the one
// farthest from their arc, while farther than tolerance) as arcs.
void simplify_ring(const std::vector<Vec3> &ring, double tolerance, std::vector<geom::ArcTree::Arc> &out) {
    const size_t n = ring.size();
    size_t far = 0;
    for (size_t k = 1; k < n; ++k)
        if (geom::arc_length(ring[0], ring[k]) > geom::arc_length(ring[0], ring[far])) far = k;
    std::vector<uint8_t> keep(n, 0);
    keep[0] = keep[far] = 1;
    // Spans (first, last) of the ring's points, last taken modulo n.
    std::vector<std::pair<size_t, size_t>> spans{{0, far}, {far, n}};
    while (!spans.empty()) {
        const auto [first, last] = spans.back();
        spans.pop_back();
        const Vec3 &a = ring[first], &b = ring[last % n];
        size_t worst = first;
        double worst_d = tolerance;
        for (size_t k = first + 1; k < last; ++k) {
            const double d = geom::distance_to_arc(ring[k], a, b);
            if (d > worst_d) worst_d = d, worst = k;
        }
        if (worst == first) continue;
        keep[worst] = 1;
        spans.push_back({first, worst});
        spans.push_back({worst, last});
    }
    size_t previous = 0;
    for (size_t k = 1; k <= n; ++k)
        if (k == n || keep[k]) {
            out.push_back({ring[previous], ring[k % n]});
            previous = k;
        }
}

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
            // A pole has no longitude: an edge to or from one runs along the
            // other end's meridian. (A box up to lat 90 has two corners
            // there, one point on the sphere: the edges beside them are
            // its meridians, not a diagonal to the one kept.)
            const bool from_pole = std::fabs(net.lat_deg(i)) == 90, to_pole = std::fabs(net.lat_deg(j)) == 90;
            const double lon_i = from_pole && !to_pole ? net.lon_deg(j) : net.lon_deg(i);
            const double lon_j = to_pole && !from_pole ? net.lon_deg(i) : net.lon_deg(j);
            const double dlon = std::remainder(lon_j - lon_i, 360.0);  // in [-180, 180]
            const double dlat = net.lat_deg(j) - net.lat_deg(i);
            const int64_t steps = static_cast<int64_t>(std::ceil(std::max(std::fabs(dlon), std::fabs(dlat)) / kDomainStepDeg));
            for (int64_t s = 1; s < steps; ++s) {
                const double t = static_cast<double>(s) / static_cast<double>(steps);
                copy.add_point(lon_i + t * dlon, net.lat_deg(i) + t * dlat);
            }
        }
        copy.end_part(p);
    }
    return copy.network(net.flattening());
}

namespace {

// Whether x is on the left of closed part p: the arc from x to a point just
// left of its first segment crosses it an even number of times.
bool on_left_of_ring(const Network &net, int64_t p, const Vec3 &x) {
    const Part &part = net.part(p);
    const int64_t s0 = part.first_segment, s1 = s0 + part.n_segments;
    const Vec3 r = just_left_of(net, s0);
    int crossings = 0;
    for (int64_t s = s0; s < s1; ++s) {
        Vec3 c;
        if (geom::arc_intersection(x, r, net.segment_a(s), net.segment_b(s), c, 0.0)) ++crossings;
    }
    return crossings % 2 == 0;
}

bool smaller_side_on_left(const Network &net, int64_t p) {
    const double left = left_area(net, p);
    return left > 0 && left < 2 * M_PI;
}

// Whether domain ring p holds the region on its left. A ring that does not
// go round a pole holds what it encloses drawn in longitude and latitude
// (as its edges are): on its left when it runs counter-clockwise there. So
// a box wider than a hemisphere is that box, not the rest of the sphere. A
// ring round a pole encloses nothing in that plane: it holds the smaller of
// its two sides (the pole it is nearer), or, halving the sphere (the
// equator), the side on its left, not the one the rounding makes smaller.
constexpr double kHalvesWithin = 1e-9;  // steradians
bool domain_ring_holds_left(const Network &net, int64_t p) {
    const Part &part = net.part(p);
    std::vector<double> lon, lat;
    for (int64_t i = part.first_point; i < part.first_point + part.n_points; ++i)
        lon.push_back(net.lon_deg(i)), lat.push_back(net.lat_deg(i));
    const LonLatRing ring(lon.data(), lat.data(), part.n_points);
    const double twice_area = ring.twice_area();
    if (!ring.round_a_pole() && twice_area != 0) return twice_area > 0;
    return std::fabs(left_area(net, p) - 2 * M_PI) <= kHalvesWithin || smaller_side_on_left(net, p);
}

}  // namespace

bool ring_encloses(const Network &net, int64_t p, const Vec3 &x) {
    return on_left_of_ring(net, p, x) == smaller_side_on_left(net, p);
}

Domain::Domain(const Network &net, const Origin &origin) {
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
    std::vector<geom::ArcTree::Arc> rough;
    for (int64_t p : rings) {
        const Part &part = net.part(p);
        std::vector<Vec3> points;
        for (int64_t s = part.first_segment; s < part.first_segment + part.n_segments; ++s) points.push_back(net.segment_a(s));
        simplify_ring(points, kRoughTolerance, rough);
    }
    rough_ = geom::ArcTree(std::move(rough));
    arcs_ = geom::ArcTree(std::move(arcs));
    for (int level = 0; level < kMemoLevels; ++level) {
        const size_t side_cells = static_cast<size_t>(kMemoCells >> level), cells = 6 * side_cells * side_cells;
        memo_.emplace_back(new std::atomic<uint8_t>[cells]);
        for (size_t k = 0; k < cells; ++k) memo_.back()[k].store(0, std::memory_order_relaxed);
    }

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
            auto ring = [&](int64_t p) {
                const std::string from = origin ? origin(p) : std::string();
                return concat("domain ring ", p, " (id ", net.part(p).id, from.empty() ? "" : ", ", from, ")");
            };
            fail(UM_ERR_INPUT, ring(pi), pi == pj ? std::string(" crosses itself") : concat(" crosses ", ring(pj)),
                 " at lon ", rounded_text(lon, kPlaceDecimals), ", lat ", rounded_text(lat, kPlaceDecimals),
                 ": domain rings must not cross themselves or each other");
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
        // The margin keeps the cosine's gap (about margin * sin(radius))
        // above 1e-14, a hundred times the dot product's rounding.
        const double margin = 1e-9 + 1e-6 * cap_radius_;
        if (cap_radius_ > 1e-5 && cap_radius_ < M_PI / 2) within_cos2_ = std::pow(std::cos(cap_radius_ - margin), 2);
    }

    // Which side of each ring is inside: the parity rule at a point just left of it.
    std::vector<bool> holds_left;
    for (int64_t p : rings) holds_left.push_back(domain_ring_holds_left(net, p));
    area_ = 0;
    for (size_t r = 0; r < rings.size(); ++r) {
        const int64_t p = rings[r];
        const Vec3 probe = just_left_of(net, net.part(p).first_segment);
        bool inside = false;
        for (size_t q = 0; q < rings.size(); ++q) inside ^= on_left_of_ring(net, rings[q], probe) == holds_left[q];
        inside_on_left_.push_back(inside);
        // The area of what the ring holds, added where the domain is on that
        // side of it (taken away for a hole).
        const double left = left_area(net, p), held = holds_left[r] ? left : 4 * M_PI - left;
        area_ += inside == holds_left[r] ? held : -held;
    }
}

bool Domain::left_of(int32_t i, const Vec3 &x) const {
    const auto &arc = arcs_.arc(i);
    const Vec3 n = geom::cross(arc.a, arc.b);
    // The nearest point of the arc's great circle lies between its ends:
    // judged by this arc alone.
    const bool past_a = geom::dot(geom::cross(arc.a, x), n) >= 0, before_b = geom::dot(geom::cross(x, arc.b), n) >= 0;
    if (past_a && before_b) return orientation(arc.a, arc.b, x) > 0;
    // Else at the nearer end, where the ring turns: on the left of a corner
    // that turns left when on the left of both arcs, of one when it turns right.
    const bool at_b = geom::dot(x, arc.b) >= geom::dot(x, arc.a);
    const auto &other = arcs_.arc(at_b ? next_[i] : prev_[i]);
    const Vec3 u = at_b ? arc.a : other.a, v = at_b ? arc.b : arc.a, w = at_b ? other.b : arc.b;
    const bool left1 = orientation(u, v, x) > 0, left2 = orientation(v, w, x) > 0;
    return orientation(u, v, w) > 0 ? left1 && left2 : left1 || left2;
}

bool Domain::locate(const Vec3 &x, double *distance) const {
    double d = 0;
    if (empty()) {
        if (distance) *distance = 0;
        return true;
    }
    const int32_t i = arcs_.nearest(x, &d);
    if (i < 0) {  // no distance to any arc: x is no direction (NaN, infinite)
        if (distance) *distance = std::numeric_limits<double>::quiet_NaN();
        return false;
    }
    if (distance) *distance = d;
    return left_of(i, x) == (inside_on_left_[ring_of_arc_[i]] != 0);
}

bool Domain::contains(const Vec3 &x) const {
    if (distance_at_least(x) > 0) return false;  // beyond the cap holding the domain
    const Side known = side(x);
    return known == Side::near ? locate(x, nullptr) : known == Side::inside;
}

namespace {

// The cube's face holding x (the axis of its largest coordinate, and the
// sign) and x's gnomonic coordinates on it, in [-1, 1].
struct CubePoint {
    int face;
    double u, v;
};
CubePoint cube_point(const Vec3 &x) {
    const double ax = std::fabs(x.x), ay = std::fabs(x.y), az = std::fabs(x.z);
    if (ax >= ay && ax >= az) return {x.x >= 0 ? 0 : 1, x.y / ax, x.z / ax};
    if (ay >= az) return {x.y >= 0 ? 2 : 3, x.z / ay, x.x / ay};
    return {x.z >= 0 ? 4 : 5, x.x / az, x.y / az};
}
Vec3 from_cube(int face, double u, double v) {
    const double s = face % 2 == 0 ? 1 : -1;
    switch (face / 2) {
    case 0: return geom::normalized(Vec3{s, u, v});
    case 1: return geom::normalized(Vec3{v, s, u});
    default: return geom::normalized(Vec3{u, v, s});
    }
}

}  // namespace

Domain::Side Domain::side(const Vec3 &x) const {
    if (empty()) return Side::inside;
    const double size = std::fabs(x.x) + std::fabs(x.y) + std::fabs(x.z);
    if (!(size > 0) || !std::isfinite(size)) return Side::near;  // (no direction: searched)
    const CubePoint c = cube_point(x);
    for (int level = kMemoLevels - 1; level >= 0; --level) {
        const int n = kMemoCells >> level;
        const int i = std::min(n - 1, std::max(0, static_cast<int>((c.u + 1) * 0.5 * n)));
        const int j = std::min(n - 1, std::max(0, static_cast<int>((c.v + 1) * 0.5 * n)));
        const Side known = memo_side(level, c.face, i, j);
        if (known != Side::near) return known;
    }
    return Side::near;
}

Domain::Side Domain::memo_side(int level, int face, int i, int j) const {
    const int n = kMemoCells >> level;
    std::atomic<uint8_t> &known = memo_[level][(static_cast<size_t>(face) * n + j) * n + i];
    const uint8_t state = known.load(std::memory_order_relaxed);
    if (state != 0) return static_cast<Side>(state - 1);
    // Every point of the cell is within its half-diagonal of the centre: the
    // gnomonic map onto the sphere shortens every distance, so the
    // half-diagonal on the face bounds it.
    const double size = 2.0 / n, half_diagonal = size * M_SQRT1_2 * (1 + 1e-6);
    double d = 0;
    const bool inside = locate(from_cube(face, -1 + (i + 0.5) * size, -1 + (j + 0.5) * size), &d);
    const Side side = d <= half_diagonal ? Side::near : inside ? Side::inside : Side::outside;
    known.store(static_cast<uint8_t>(static_cast<uint8_t>(side) + 1), std::memory_order_relaxed);
    return side;
}

double Domain::rough_distance(const Vec3 &x) const {
    double d = 0;
    rough_.nearest(x, &d);
    return d;
}

}  // namespace um::features
