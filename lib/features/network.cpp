#include "features/network.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "core/error.hpp"
#include "features/lonlat_ring.hpp"
#include "geom/surface.hpp"

namespace um::features {

namespace {

constexpr const char *kKindNames[] = {"coastline", "lake", "river", "watershed", "other", "passage", "domain"};

bool equal_ascii_nocase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

bool equal(const Vec3 &a, const Vec3 &b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// A multiple of 360 degrees (lon - lon' for the same meridian). fmod is exact.
bool whole_turns(double degrees) { return std::fmod(degrees, 360.0) == 0.0; }

// Exactly opposite points: the minor arc between them is not defined. Checked
// on the unit vectors (poles, exact negatives, or a cross product that rounds
// to zero) and on the degrees (lat' = -lat, lon' = lon + 180 + k 360), which
// catches (0, 0) / (180, 0) although sin(pi) rounds to 1.2e-16.
bool antipodal(double lon1, double lat1, const Vec3 &u1, double lon2, double lat2,
               const Vec3 &u2) {
    if (u1.x == -u2.x && u1.y == -u2.y && u1.z == -u2.z) return true;
    if (lat1 == -lat2 && whole_turns(lon1 - lon2 - 180.0)) return true;
    Vec3 n = geom::cross(u1, u2);
    return n.x == 0 && n.y == 0 && n.z == 0 && geom::dot(u1, u2) < 0;
}

// The default locator: positions within the batch.
std::string default_place(int64_t part, int64_t point, int coordinate) {
    std::string s = concat("part ", part);
    if (point >= 0) s += concat(", point ", point);
    if (coordinate == 0) s += " longitude";
    if (coordinate == 1) s += " latitude";
    return s;
}

// One batch, checked and cleaned, before it joins the network.
struct Staged {
    std::vector<Vec3> points;
    std::vector<double> lon, lat;
    std::vector<Part> parts;
    std::vector<double> length;
    std::vector<int32_t> segment_part;
};

class BatchChecker {
public:
    BatchChecker(const PartsInput &in, const Locator &where, int64_t first_part, double flattening)
        : in_(in), where_(where), first_part_(first_part), surface_(geom::Surface::ellipsoid(1.0, flattening)) {}

    void check_counts(int64_t points_before, int64_t parts_before) const {
        if (in_.n_points < 0)
            fail(UM_ERR_INVALID_ARGUMENT, "n_points = ", in_.n_points, " is negative");
        if (in_.n_parts < 0)
            fail(UM_ERR_INVALID_ARGUMENT, "n_parts = ", in_.n_parts, " is negative");
        if (in_.n_points > Network::kMaxPoints - points_before)
            fail(UM_ERR_LIMIT, "n_points = ", in_.n_points,
                 " would bring the network to more than ", Network::kMaxPoints, " points");
        if (in_.n_parts > Network::kMaxParts - parts_before)
            fail(UM_ERR_LIMIT, "n_parts = ", in_.n_parts, " would bring the network to more than ",
                 Network::kMaxParts, " parts");
    }

    void check_layout() const {
        if (!in_.part_offsets) fail(UM_ERR_NULL_ARGUMENT, "part_offsets is NULL");
        if (in_.n_points > 0 && !in_.lon_deg)
            fail(UM_ERR_NULL_ARGUMENT, "lon_deg is NULL but n_points = ", in_.n_points);
        if (in_.n_points > 0 && !in_.lat_deg)
            fail(UM_ERR_NULL_ARGUMENT, "lat_deg is NULL but n_points = ", in_.n_points);
        if (in_.n_parts > 0 && !in_.closed)
            fail(UM_ERR_NULL_ARGUMENT, "closed is NULL but n_parts = ", in_.n_parts);
        if (in_.n_parts > 0 && !in_.kind)
            fail(UM_ERR_NULL_ARGUMENT, "kind is NULL but n_parts = ", in_.n_parts);
        const int64_t *off = in_.part_offsets;
        if (off[0] != 0) fail(UM_ERR_INVALID_ARGUMENT, "part_offsets[0] = ", off[0], " is not 0");
        for (int64_t p = 0; p < in_.n_parts; ++p)
            if (off[p + 1] < off[p] || off[p + 1] > in_.n_points)
                fail(UM_ERR_INVALID_ARGUMENT, "part_offsets[", p + 1, "] = ", off[p + 1],
                     off[p + 1] < off[p] ? " is below part_offsets[" : " exceeds n_points = ",
                     off[p + 1] < off[p] ? concat(p, "] = ", off[p]) : to_text(in_.n_points));
        if (off[in_.n_parts] != in_.n_points)
            fail(UM_ERR_INVALID_ARGUMENT, "part_offsets[n_parts = ", in_.n_parts, "] = ",
                 off[in_.n_parts], " is not n_points = ", in_.n_points);
        for (int64_t p = 0; p < in_.n_parts; ++p) {
            if (in_.closed[p] != 0 && in_.closed[p] != 1)
                fail(UM_ERR_INVALID_ARGUMENT, "closed[", p, "] = ", in_.closed[p],
                     " is not 0 or 1");
            if (!is_kind(in_.kind[p]))
                fail(UM_ERR_INVALID_ARGUMENT, "kind[", p, "] = ", in_.kind[p],
                     " is not a feature kind (UM_FEATURE_COASTLINE = 1 to UM_FEATURE_DOMAIN = 7)");
        }
    }

    // Checks and cleans part p into `out`.
    void add_part(int64_t p, Staged &out) const {
        const int64_t first = in_.part_offsets[p];
        int64_t n = in_.part_offsets[p + 1] - first;  // (a polar cap's ring below: its rewritten points)
        const double *lon = in_.lon_deg + first, *lat = in_.lat_deg + first;
        for (int64_t i = 0; i < n; ++i) {
            if (!std::isfinite(lon[i]))
                fail(UM_ERR_NONFINITE_INPUT, place(p, i, 0), " = ", lon[i], " is not finite");
            if (!std::isfinite(lat[i]))
                fail(UM_ERR_NONFINITE_INPUT, place(p, i, 1), " = ", lat[i], " is not finite");
            if (std::fabs(lat[i]) > 90.0)
                fail(UM_ERR_COORDINATE_RANGE, place(p, i, 1), " = ", lat[i],
                     " is outside [-90, 90] degrees");
        }
        const bool closed = in_.closed[p] == 1;
        // A domain ring drawn as GIS tools draw a polar cap: the ring round
        // the pole it stands for (lonlat_ring.hpp).
        PolarCapRing cap;
        const int64_t *input_point = nullptr;  // per point read: the input point it comes from (null: itself)
        if (in_.kind[p] == static_cast<int32_t>(Kind::domain) && closed && runs_round_the_sphere(lon, n)) {
            cap = polar_cap_ring(lon, lat, n);
            if (!cap.error.empty())
                fail(UM_ERR_INPUT, place(p, -1, -1), " is a domain ring with an edge 360 degrees of longitude "
                     "long, read as a polar cap drawn in the plane of longitude and latitude, but it ", cap.error);
            lon = cap.lon.data(), lat = cap.lat.data(), n = static_cast<int64_t>(cap.lon.size());
            input_point = cap.source.data();
        }
        // Drop consecutive duplicates; remember which input point each kept one was.
        const size_t start = out.points.size();
        std::vector<int64_t> source;
        source.reserve(static_cast<size_t>(n));
        for (int64_t i = 0; i < n; ++i) {
            Vec3 u = surface_.direction(lon[i], lat[i]);
            if (!source.empty() &&
                same_point(lon[i], lat[i], u, out.lon.back(), out.lat.back(), out.points.back()))
                continue;
            out.points.push_back(u), out.lon.push_back(lon[i]), out.lat.push_back(lat[i]);
            source.push_back(input_point ? input_point[i] : i);
        }
        if (closed && source.size() >= 2 &&
            same_point(out.lon.back(), out.lat.back(), out.points.back(), out.lon[start],
                       out.lat[start], out.points[start])) {
            out.points.pop_back(), out.lon.pop_back(), out.lat.pop_back(), source.pop_back();
        }
        const int64_t kept = static_cast<int64_t>(source.size());
        // A passage may be one point (open: a ring of one point has no arc).
        const bool point_allowed = in_.kind[p] == static_cast<int32_t>(Kind::passage) && !closed;
        if (kept < (point_allowed ? 1 : 2))
            fail(UM_ERR_TOO_FEW_POINTS, place(p, -1, -1), " has ", kept,
                 " distinct point", kept == 1 ? "" : "s", " (", in_.part_offsets[p + 1] - first, " given); ",
                 point_allowed ? "a passage needs at least 1"
                 : in_.kind[p] == static_cast<int32_t>(Kind::passage) ? "a closed passage needs at least 2"
                                                                        : "a line needs at least 2");
        if (in_.kind[p] == static_cast<int32_t>(Kind::domain) && (!closed || kept < 3))
            fail(UM_ERR_INPUT, place(p, -1, -1), " is a domain ring but ",
                 closed ? concat("has ", kept, " distinct points: a ring needs at least 3")
                        : std::string("is open: a domain is bounded by closed rings"));
        for (int64_t k = 1; k < kept; ++k) {
            size_t a = start + k - 1, b = start + k;
            if (antipodal(out.lon[a], out.lat[a], out.points[a], out.lon[b], out.lat[b],
                          out.points[b]))
                fail(UM_ERR_DEGENERATE_INPUT, place(p, source[k], -1), " = (", out.lon[b], ", ",
                     out.lat[b], ") is antipodal to the point before it (point ",
                     source[k - 1], " of the part): the great-circle arc between them is undefined");
        }
        if (closed && antipodal(out.lon.back(), out.lat.back(), out.points.back(),
                                out.lon[start], out.lat[start], out.points[start]))
            fail(UM_ERR_DEGENERATE_INPUT, place(p, -1, -1), " is closed but its last point ",
                 source.back(), " is antipodal to its first point ", source.front(),
                 ": the closing great-circle arc is undefined");

        Part part;
        part.first_point = static_cast<int64_t>(start);  // relative to the batch for now
        part.n_points = kept;
        part.first_segment = static_cast<int64_t>(out.segment_part.size());
        part.n_segments = closed ? kept : kept - 1;
        part.closed = closed;
        part.kind = static_cast<Kind>(in_.kind[p]);
        part.id = in_.part_id ? in_.part_id[p] : static_cast<int32_t>(first_part_ + p);
        double length = 0;
        for (int64_t k = 0; k < part.n_segments; ++k) {
            size_t a = start + k, b = start + (k + 1 == kept ? 0 : k + 1);
            length += geom::arc_length(out.points[a], out.points[b]);
        }
        const int32_t index = static_cast<int32_t>(first_part_ + p);
        out.segment_part.insert(out.segment_part.end(), static_cast<size_t>(part.n_segments),
                                index);
        out.parts.push_back(part);
        out.length.push_back(length);
    }

    // Refuses a closed part of the batch that repeats a closed ring of the
    // network or of the batch (the same points, from any start, either way
    // round): the side of a point (refine/sides.cpp) counts the rings
    // around it, so a coastline given twice (a file read twice) turned all
    // land into ocean.
    void refuse_repeated_rings(const Network &net, const Staged &staged) const {
        std::unordered_map<uint64_t, std::vector<int64_t>> seen;  // hash -> parts (batch ones after the network's)
        auto ring = [&](int64_t q) {
            if (q < net.part_count()) {
                const Part &part = net.part(q);
                std::vector<Vec3> points(static_cast<size_t>(part.n_points));
                for (int64_t i = 0; i < part.n_points; ++i) points[i] = net.point(part.first_point + i);
                return canonical_ring(points);
            }
            const Part &part = staged.parts[static_cast<size_t>(q - net.part_count())];
            return canonical_ring(std::vector<Vec3>(staged.points.begin() + part.first_point,
                                                    staged.points.begin() + part.first_point + part.n_points));
        };
        const int64_t total = net.part_count() + static_cast<int64_t>(staged.parts.size());
        for (int64_t q = 0; q < total; ++q) {
            const bool closed = q < net.part_count() ? net.part(q).closed : staged.parts[q - net.part_count()].closed;
            if (!closed) continue;
            const std::vector<Vec3> canonical = ring(q);
            std::vector<int64_t> &same_hash = seen[hash_of(canonical)];
            for (int64_t other : same_hash)
                if (q >= net.part_count() && same_ring(ring(other), canonical))
                    fail(UM_ERR_INPUT, place(q - net.part_count(), -1, -1), " is the same closed ring as ",
                         other < net.part_count() ? concat("part ", other, " read before")
                                                  : place(other - net.part_count(), -1, -1),
                         ": a ring given twice (a file read twice?) would cancel itself in the land and "
                         "ocean sides");
            same_hash.push_back(q);
        }
    }

private:
    // The ring from its least point on (by x, y, z), in the direction whose
    // sequence is the lesser: the same for the same ring from any start,
    // either way round.
    static std::vector<Vec3> canonical_ring(const std::vector<Vec3> &p) {
        auto less = [](const Vec3 &a, const Vec3 &b) {
            return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
        };
        const size_t n = p.size();
        const size_t m = static_cast<size_t>(std::min_element(p.begin(), p.end(), less) - p.begin());
        std::vector<Vec3> forward(n), backward(n);
        for (size_t i = 0; i < n; ++i) forward[i] = p[(m + i) % n], backward[i] = p[(m + n - i) % n];
        return std::lexicographical_compare(backward.begin(), backward.end(), forward.begin(), forward.end(), less)
                   ? backward
                   : forward;
    }
    static bool same_ring(const std::vector<Vec3> &a, const std::vector<Vec3> &b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const Vec3 &u, const Vec3 &v) {
                   return u.x == v.x && u.y == v.y && u.z == v.z;
               });
    }
    static uint64_t hash_of(const std::vector<Vec3> &ring) {
        uint64_t h = 1469598103934665603ull;
        for (const Vec3 &v : ring)
            for (double c : {v.x, v.y, v.z}) {
                uint64_t bits;
                std::memcpy(&bits, &c, sizeof bits);
                h = (h ^ bits) * 1099511628211ull;
            }
        return h;
    }

    std::string place(int64_t part, int64_t point, int coordinate) const {
        return where_ ? where_(part, point, coordinate) : default_place(part, point, coordinate);
    }

    const PartsInput &in_;
    const Locator &where_;
    int64_t first_part_;
    geom::Surface surface_;
};

template <class T>
void append(std::vector<T> &to, const std::vector<T> &from) {
    to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

bool is_kind(int32_t value) {
    return value >= static_cast<int32_t>(Kind::coastline) && value <= static_cast<int32_t>(Kind::domain);
}

const char *kind_name(Kind kind) {
    int32_t k = static_cast<int32_t>(kind);
    return is_kind(k) ? kKindNames[k - 1] : "unknown";
}

bool kind_from_name(std::string_view name, Kind &kind) {
    for (int32_t k = 1; k <= static_cast<int32_t>(Kind::domain); ++k)
        if (equal_ascii_nocase(name, kKindNames[k - 1])) {
            kind = static_cast<Kind>(k);
            return true;
        }
    return false;
}

bool same_point(double lon1, double lat1, const Vec3 &u1, double lon2, double lat2,
                const Vec3 &u2) {
    return equal(u1, u2) || (lat1 == lat2 && whole_turns(lon1 - lon2));
}

void Network::add(const PartsInput &in, const Locator &where) {
    BatchChecker checker(in, where, part_count(), flattening_);
    checker.check_counts(point_count(), part_count());
    checker.check_layout();

    Staged staged;
    staged.points.reserve(static_cast<size_t>(in.n_points));
    staged.lon.reserve(static_cast<size_t>(in.n_points));
    staged.lat.reserve(static_cast<size_t>(in.n_points));
    staged.parts.reserve(static_cast<size_t>(in.n_parts));
    staged.length.reserve(static_cast<size_t>(in.n_parts));
    staged.segment_part.reserve(static_cast<size_t>(in.n_points));
    for (int64_t p = 0; p < in.n_parts; ++p) checker.add_part(p, staged);
    checker.refuse_repeated_rings(*this, staged);
    std::vector<std::pair<int64_t, std::string>> origins;
    if (where)
        for (int64_t p = 0; p < in.n_parts; ++p)
            if (staged.parts[static_cast<size_t>(p)].kind == Kind::domain) origins.push_back({part_count() + p, where(p, -1, -1)});

    // Commit: reserve everything first (the only step that can throw, and
    // reserve leaves a vector as it was when it throws), then append.
    points_.reserve(points_.size() + staged.points.size());
    lon_deg_.reserve(lon_deg_.size() + staged.lon.size());
    lat_deg_.reserve(lat_deg_.size() + staged.lat.size());
    parts_.reserve(parts_.size() + staged.parts.size());
    part_length_.reserve(part_length_.size() + staged.length.size());
    segment_part_.reserve(segment_part_.size() + staged.segment_part.size());
    domain_origin_.reserve(domain_origin_.size() + origins.size());

    const int64_t point_base = point_count(), segment_base = segment_count();
    for (Part &part : staged.parts) {
        part.first_point += point_base;
        part.first_segment += segment_base;
    }
    append(points_, staged.points);
    append(lon_deg_, staged.lon);
    append(lat_deg_, staged.lat);
    append(parts_, staged.parts);
    append(part_length_, staged.length);
    append(segment_part_, staged.segment_part);
    for (auto &origin : origins) domain_origin_.push_back(std::move(origin));
    for (double length : staged.length) total_length_ += length;
}

std::string Network::domain_origin(int64_t p) const {
    auto it = std::lower_bound(domain_origin_.begin(), domain_origin_.end(), p,
                               [](const std::pair<int64_t, std::string> &o, int64_t q) { return o.first < q; });
    return it != domain_origin_.end() && it->first == p ? it->second : std::string();
}

double Network::segment_length(int64_t s) const {
    return geom::arc_length(segment_a(s), segment_b(s));
}

Network PartsCopy::network(double flattening) const {
    Network out(flattening);
    if (closed.empty()) return out;
    PartsInput in;
    in.n_points = static_cast<int64_t>(lon.size()), in.lon_deg = lon.data(), in.lat_deg = lat.data();
    in.n_parts = static_cast<int64_t>(closed.size()), in.part_offsets = offsets.data();
    in.closed = closed.data(), in.kind = kinds.data(), in.part_id = ids.data();
    out.add(in);  // checked and cleaned already: the same parts again
    return out;
}

Network parts_of_kind(const Network &net, Kind kind, bool keep, std::vector<int64_t> *source_parts) {
    PartsCopy copy;
    if (source_parts) source_parts->clear();
    for (int64_t index = 0; index < net.part_count(); ++index) {
        const Part &p = net.part(index);
        if ((p.kind == kind) != keep) continue;
        if (source_parts) source_parts->push_back(index);
        for (int64_t i = p.first_point; i < p.first_point + p.n_points; ++i) copy.add_point(net.lon_deg(i), net.lat_deg(i));
        copy.end_part(p);
    }
    return copy.network(net.flattening());
}

Network on_ellipsoid(const Network &net, double flattening) {
    PartsCopy copy;
    for (const Part &p : net.parts()) {
        for (int64_t i = p.first_point; i < p.first_point + p.n_points; ++i) copy.add_point(net.lon_deg(i), net.lat_deg(i));
        copy.end_part(p);
    }
    return copy.network(flattening);
}

geom::ArcTree segment_arc_tree(const Network *net) {
    if (!net || net->segment_count() == 0) return {};
    std::vector<geom::ArcTree::Arc> arcs;
    arcs.reserve(static_cast<size_t>(net->segment_count()));
    for (int64_t s = 0; s < net->segment_count(); ++s) arcs.push_back({net->segment_a(s), net->segment_b(s)});
    return geom::ArcTree(std::move(arcs));
}

}  // namespace um::features
