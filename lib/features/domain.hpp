// The region of a regional mesh: the closed Kind::domain rings of Gamma. A
// point is inside when an odd number of rings enclose it: a ring inside
// another is a hole, and a ring may cross the antimeridian or hold a pole.
// A ring encloses what it encloses drawn in longitude and latitude, as its
// edges are (a ring through a pole does not go round it); a ring round a
// pole, the smaller of the two regions it bounds (the rule the land/ocean
// sides use for coastlines, refine/sides.hpp), or for the equator the side
// on its left. Rings must not cross themselves or each other.
//
// Inside tests are local: the side of the nearest ring segment, which the
// region holds on one side all along a ring (found once per ring by the
// parity rule), so a test costs one nearest-arc query.
#pragma once

#include <algorithm>
#include <atomic>
#include <memory>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "features/network.hpp"
#include "geom/arc_tree.hpp"

namespace um::features {

// Domain rings are drawn as GeoJSON draws lines: straight in longitude and
// latitude, so that a box of longitudes and latitudes is that box. Each edge
// goes the shorter way round in longitude (160 to -160 crosses the
// antimeridian, as 160 to 200 does): an edge of 180 degrees or more of
// longitude needs points between. net with each domain ring's
// segments longer than kDomainStepDeg (in either coordinate) divided along
// those lines; the other parts as they are (the same part indices).
constexpr double kDomainStepDeg = 0.25;
Network with_domain_rings_traced(const Network &net);

// Whether closed part p of net encloses x: x lies in the smaller of the two
// regions the ring bounds (a closed coastline's land). O(segments of p).
// (A domain ring holds what it encloses drawn in longitude and latitude:
// Domain.)
bool ring_encloses(const Network &net, int64_t p, const Vec3 &x);

class Domain {
public:
    // The domain of net's Kind::domain parts (none: empty(), the whole
    // sphere). Throws UM_ERR_INPUT naming the parts and segments where two
    // segments of the rings cross (touching at a shared point included),
    // other than consecutive segments of one ring at their shared point;
    // `origin`, when given, names where part p came from (a file and JSON
    // path, say; empty: unknown) for that message.
    using Origin = std::function<std::string(int64_t part)>;
    explicit Domain(const Network &net, const Origin &origin = {});

    bool empty() const { return arcs_.size() == 0; }
    // Whether unit point x is inside (always, when empty). A point on a ring
    // may be either.
    bool contains(const Vec3 &x) const;
    // contains(x), and the arc distance (radians) from x to the nearest ring
    // into *distance (when not null), with one search for the nearest segment.
    // A point with no direction (NaN, infinite) is outside, at NaN.
    bool locate(const Vec3 &x, double *distance) const;
    // Which side of the rings x is on, when the memo knows without a search:
    // inside or outside when x lies in a memo cell wholly on that side,
    // farther from the rings than its half-diagonal; near otherwise
    // ("search"). The cells are those of a cube's faces cut into squares
    // (gnomonic: no trigonometry to find one) at five levels, 512 to 32 a
    // side, the coarsest asked first, so that points far from the rings,
    // however sparse (the cover of a regional mesh), are answered by a few
    // large cells; each cell's answer is found on first use and kept, a pure
    // function of the cell, so the same on every thread.
    enum class Side : uint8_t { near, inside, outside };
    Side side(const Vec3 &x) const;
    // The distance (radians) from x to the rings simplified within
    // rough_error() (Douglas-Peucker): a cheap stand-in for the exact one,
    // within rough_error() of it.
    double rough_distance(const Vec3 &x) const;
    static constexpr double rough_error() { return kRoughError; }
    // The centre and radius (radians) of a cap holding every ring (and the
    // domain, when the radius is below pi / 2).
    const Vec3 &cap_centre() const { return cap_centre_; }
    double cap_radius() const { return cap_radius_; }
    // A lower bound of distance(x) from the cap around the rings (no
    // search): 0 when the rings do not fit in a cap smaller than a hemisphere.
    // Points well within the cap (most of those a regional mesh asks about)
    // are told by one dot product, without the arc's atan2: the same answer.
    double distance_at_least(const Vec3 &x) const {
        if (cap_radius_ >= M_PI / 2) return 0.0;
        const double along = geom::dot(x, cap_centre_);
        if (along > 0 && along * along > within_cos2_ * geom::dot(x, x)) return 0.0;
        return std::max(0.0, geom::arc_length(x, cap_centre_) - cap_radius_);
    }
    // The domain's area (steradians, the unit sphere's 4 pi when empty).
    double area() const { return area_; }
    // Whether segment s of net is of a domain ring.
    bool is_ring_segment(int64_t s) const {
        return s >= 0 && static_cast<size_t>(s) < ring_segment_.size() && ring_segment_[s];
    }
    // Whether a vertex at x, placed on segment s of net (-1: none), is of the
    // cover around a regional mesh: outside the domain and off its rings.
    bool in_cover(const Vec3 &x, int64_t s) const { return !is_ring_segment(s) && !contains(x); }

private:
    // Whether x is on the left of ring arc i (seen from outside the sphere),
    // judged at the point of the arc nearest to x: an end shared with the
    // next or previous arc is judged by both, as the corner turns.
    bool left_of(int32_t i, const Vec3 &x) const;

    geom::ArcTree arcs_;                 // the domain segments, in network order
    std::vector<int32_t> ring_of_arc_;   // per arc: its ring (index among the domain rings)
    std::vector<int32_t> next_, prev_;   // per arc: the arcs after and before it on its ring
    std::vector<uint8_t> inside_on_left_;  // per ring: the domain lies on its left
    std::vector<uint8_t> ring_segment_;    // per network segment
    double area_ = 4 * M_PI;
    // The memo of side(): per level (kMemoCells >> level cells a side on
    // each face), per cell 0 not known, else 1 + the Side.
    static constexpr int kMemoLevels = 5;
    static constexpr int kMemoCells = 512;  // at level 0: 25 km at a face's centre, 13 at its corners
    Side memo_side(int level, int face, int i, int j) const;
    std::vector<std::unique_ptr<std::atomic<uint8_t>[]>> memo_;
    // The rings simplified (rough_distance): tolerance kRoughTolerance, an
    // error of at most kRoughError (the traced rings' arcs are at most
    // kDomainStepDeg long, so that they bend from the simplified ones by far
    // less than the margin).
    static constexpr double kRoughTolerance = 0.05 * M_PI / 180;  // 5.6 km
    static constexpr double kRoughError = 1.25 * kRoughTolerance;
    geom::ArcTree rough_;
    // A cap holding every ring (and so the domain, when it is smaller than a hemisphere).
    Vec3 cap_centre_{0, 0, 1};
    double cap_radius_ = M_PI;
    // The squared cosine of an angle short of cap_radius_ by far more than
    // rounding (distance_at_least): a point whose cosine to the centre
    // exceeds it is inside the cap; above 1 (never) for a cap too small to tell.
    double within_cos2_ = 2;
};

}  // namespace um::features
