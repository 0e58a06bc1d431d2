// Polyarc networks Gamma (paper section 5.1): coastlines, lake shores, rivers,
// watersheds as polylines on the sphere. Each edge ("segment") is the minor
// great-circle arc between consecutive vertices, plus last -> first for a
// closed part. Vertices are kept as unit vectors (what the geometry uses) and
// as the longitude/latitude the caller gave (what goes back out).
//
// What adding accepts and what it changes:
//   - rejected (um::Error, nothing added): NaN/Inf coordinates
//     (UM_ERR_NONFINITE_INPUT), |lat| > 90 (UM_ERR_COORDINATE_RANGE), a part
//     with fewer than 2 distinct points (UM_ERR_TOO_FEW_POINTS, in the
//     UM_ERR_INPUT band), exactly antipodal consecutive points, whose arc is
//     undefined (UM_ERR_DEGENERATE_INPUT), kinds outside UM_FEATURE_*, closed
//     flags other than 0/1 and inconsistent offsets (UM_ERR_INVALID_ARGUMENT);
//   - cleaned: consecutive duplicate points are dropped (the first is kept),
//     and so is the closing duplicate of a closed part (a ring given with
//     first == last stores that point once);
//   - kept as given: self-intersecting, self-touching and overlapping lines
//     (restricted meshing filters them), lines across the antimeridian (an
//     edge is always the short arc, whatever the longitudes).
// Two points are the same point when their unit vectors are equal, or their
// latitudes are equal and their longitudes differ by a multiple of 360
// degrees (so lon 180 and lon -180 are one point).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "geom/arc_tree.hpp"
#include "geom/sphere.hpp"

namespace um::features {

using geom::Vec3;

// The values of UM_FEATURE_* in unimesh.h.
// A passage is not part of Gamma: a line (or a point: a part of one point)
// across which the ocean mesh is kept open (split off before refinement).
// A domain ring is a closed ring bounding a regional mesh (features/domain.hpp):
// part of Gamma (the mesh's boundary conforms to it), and nothing is kept
// outside the region its rings enclose.
enum class Kind : int32_t { coastline = 1, lake = 2, river = 3, watershed = 4, other = 5, passage = 6, domain = 7 };

bool is_kind(int32_t value);
// "coastline", "lake", "river", "watershed", "other", "passage", "domain".
const char *kind_name(Kind kind);
// The kind of one of those names (ASCII case-insensitive); false if none.
bool kind_from_name(std::string_view name, Kind &kind);

// Whether (lon1, lat1) and (lon2, lat2), degrees, are the same point on the
// sphere in the sense above (the unit vectors are those of the positions).
bool same_point(double lon1, double lat1, const Vec3 &u1, double lon2, double lat2,
                const Vec3 &u2);

// A batch of parts in the layout of um_features_add (names match its
// arguments, and so do the error messages).
struct PartsInput {
    int64_t n_points = 0;
    const double *lon_deg = nullptr;  // n_points
    const double *lat_deg = nullptr;  // n_points
    int64_t n_parts = 0;
    const int64_t *part_offsets = nullptr;  // n_parts + 1: part p is points [off[p], off[p+1])
    const int32_t *closed = nullptr;        // n_parts, 0 or 1
    const int32_t *kind = nullptr;          // n_parts, UM_FEATURE_*
    const int32_t *part_id = nullptr;       // n_parts; nullptr: the part's index in the network
};

// Names a place of the caller's input in error messages: part p of the batch,
// point i of that part as given (before cleaning; -1 for the part as a
// whole), coordinate c (0 longitude, 1 latitude, -1 the point as a whole).
using Locator = std::function<std::string(int64_t part, int64_t point, int coordinate)>;

// One stored part.
struct Part {
    int64_t first_point = 0;    // its points are [first_point, first_point + n_points)
    int64_t n_points = 0;       // distinct consecutive points, >= 2 (>= 1 for an open passage)
    int64_t first_segment = 0;  // its segments are [first_segment, first_segment + n_segments)
    int64_t n_segments = 0;     // n_points - 1 when open, n_points when closed
    bool closed = false;
    Kind kind = Kind::other;
    int32_t id = 0;
};

class Network {
public:
    // Limits that keep every index of a network within int32 (what the later
    // stages store per triangle and per arc).
    static constexpr int64_t kMaxPoints = 2147483647 - 1;
    static constexpr int64_t kMaxParts = 2147483647 - 1;

    // Points are the directions of their geodetic lon/lat on an ellipsoid of
    // this flattening (geom/surface.hpp; 0, the default: a sphere).
    Network() = default;
    explicit Network(double flattening) : flattening_(flattening) {}
    double flattening() const { return flattening_; }

    // Validates and cleans the batch and appends it. All-or-nothing: if it
    // throws, the network is unchanged. `where` names places in messages
    // (default: "part p", "part p, point i", "... longitude/latitude").
    void add(const PartsInput &in, const Locator &where = {});

    int64_t part_count() const { return static_cast<int64_t>(parts_.size()); }
    int64_t point_count() const { return static_cast<int64_t>(points_.size()); }
    int64_t segment_count() const { return static_cast<int64_t>(segment_part_.size()); }

    const Part &part(int64_t p) const { return parts_[p]; }
    const std::vector<Part> &parts() const { return parts_; }
    // Where domain part p came from, as add's `where` named it ("file:
    // JSON path" for a file); empty when add had no `where` or p is of
    // another kind. (Kept for the domain rings only: their errors come
    // later, when the rings are seen together.)
    std::string domain_origin(int64_t p) const;

    Vec3 point(int64_t i) const { return points_[i]; }
    const std::vector<Vec3> &points() const { return points_; }
    double lon_deg(int64_t i) const { return lon_deg_[i]; }
    double lat_deg(int64_t i) const { return lat_deg_[i]; }

    // Segment s runs from point segment_start(s) to point segment_end(s).
    int64_t segment_part(int64_t s) const { return segment_part_[s]; }
    int64_t segment_start(int64_t s) const {
        const Part &p = parts_[segment_part_[s]];
        return p.first_point + (s - p.first_segment);
    }
    int64_t segment_end(int64_t s) const {
        const Part &p = parts_[segment_part_[s]];
        int64_t k = s - p.first_segment + 1;
        return p.first_point + (k == p.n_points ? 0 : k);
    }
    Vec3 segment_a(int64_t s) const { return points_[segment_start(s)]; }
    Vec3 segment_b(int64_t s) const { return points_[segment_end(s)]; }
    Kind segment_kind(int64_t s) const { return parts_[segment_part_[s]].kind; }
    int32_t segment_id(int64_t s) const { return parts_[segment_part_[s]].id; }

    // Lengths in radians (on the unit sphere: multiply by the radius).
    double segment_length(int64_t s) const;
    double part_length(int64_t p) const { return part_length_[p]; }
    // Sum of the part lengths, in part order (the same bits for the same adds).
    double total_length() const { return total_length_; }

private:
    double flattening_ = 0;
    std::vector<Vec3> points_;
    std::vector<double> lon_deg_, lat_deg_;
    std::vector<Part> parts_;
    std::vector<double> part_length_;
    std::vector<int32_t> segment_part_;
    double total_length_ = 0;
    std::vector<std::pair<int64_t, std::string>> domain_origin_;  // (part, place), ascending parts
};

// A network made from parts of others (checked and cleaned already): points
// appended one at a time, each part ended with the kind, closure and id it
// keeps.
struct PartsCopy {
    std::vector<double> lon, lat;
    std::vector<int64_t> offsets{0};
    std::vector<int32_t> closed, kinds, ids;
    void add_point(double lon_deg, double lat_deg) { lon.push_back(lon_deg), lat.push_back(lat_deg); }
    void end_part(const Part &like) {
        offsets.push_back(static_cast<int64_t>(lon.size()));
        closed.push_back(like.closed), kinds.push_back(static_cast<int32_t>(like.kind)), ids.push_back(like.id);
    }
    Network network(double flattening = 0) const;
};

// The same parts (ids, kinds, order) with their points on an ellipsoid of
// this flattening.
Network on_ellipsoid(const Network &net, double flattening);

// The parts of `net` of kind `kind` (keep) or every other part (!keep), as a
// network of their own, ids kept; source_parts (when given) gets the index in
// net of each.
Network parts_of_kind(const Network &net, Kind kind, bool keep, std::vector<int64_t> *source_parts = nullptr);

// The arc tree of every segment of `net` (arc i = segment i); empty for a
// null or empty network.
geom::ArcTree segment_arc_tree(const Network *net);

}  // namespace um::features
