// Engine tests: polyarc networks (lib/features) and the GeoJSON reader (lib/io).
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "features/network.hpp"
#include "geom/sphere.hpp"
#include "io/geojson.hpp"
#include "support/feature_parts.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using features::Kind;
using features::Network;
using geom::Vec3;

namespace {

constexpr double kEarthKm = 6371.0088;  // the radius the data README measures with
constexpr double kDeg = M_PI / 180.0;

using testing::add;
using testing::LinePart;

LinePart line(std::vector<double> lonlat, int32_t closed = 0, int32_t kind = UM_FEATURE_OTHER,
              int32_t id = 0) {
    LinePart p;
    for (size_t i = 0; i + 1 < lonlat.size(); i += 2) p.lon.push_back(lonlat[i]), p.lat.push_back(lonlat[i + 1]);
    p.closed = closed, p.kind = kind, p.id = id;
    return p;
}

bool contains(const std::string &text, const char *part) {
    if (text.find(part) != std::string::npos) return true;
    std::printf("message \"%s\" lacks \"%s\"\n", text.c_str(), part);
    return false;
}

// A fingerprint of everything stored, to show a failing add changed nothing.
std::string snapshot(const Network &net) {
    std::string s = concat(net.part_count(), "/", net.point_count(), "/", net.segment_count(),
                           "/", net.total_length());
    for (int64_t i = 0; i < net.point_count(); ++i) s += concat(",", net.lon_deg(i), ":", net.lat_deg(i));
    for (const auto &p : net.parts())
        s += concat(";", p.first_point, ":", p.n_points, ":", p.closed, ":", int(p.kind), ":", p.id);
    return s;
}

// --------------------------------------------------------------- network

void parts_segments_and_accessors(void **) {
    Network net;
    assert_int_equal(add(net, {line({0, 0, 10, 0, 10, 10}, 0, UM_FEATURE_RIVER, 17),
                               line({20, 20, 21, 20, 21, 21, 20, 21}, 1, UM_FEATURE_LAKE, -4)}),
                     UM_OK);
    assert_int_equal(net.part_count(), 2);
    assert_int_equal(net.point_count(), 7);
    assert_int_equal(net.segment_count(), 2 + 4);
    const auto &a = net.part(0), &b = net.part(1);
    assert_true(!a.closed && b.closed);
    assert_int_equal(a.n_segments, 2);
    assert_int_equal(b.first_point, 3);
    assert_int_equal(b.first_segment, 2);
    assert_int_equal(b.n_segments, 4);
    // Segment endpoints, and the closing segment back to the first point.
    assert_int_equal(net.segment_start(1), 1);
    assert_int_equal(net.segment_end(1), 2);
    assert_int_equal(net.segment_start(5), 6);
    assert_int_equal(net.segment_end(5), 3);
    for (int64_t s = 0; s < net.segment_count(); ++s) {
        int64_t p = s < 2 ? 0 : 1;
        assert_int_equal(net.segment_part(s), p);
        assert_int_equal(int(net.segment_kind(s)), p == 0 ? UM_FEATURE_RIVER : UM_FEATURE_LAKE);
        assert_int_equal(net.segment_id(s), p == 0 ? 17 : -4);
    }
    // Lengths: segment 0 is 10 degrees of the equator.
    assert_true(std::fabs(net.segment_length(0) - 10 * kDeg) < 1e-15);
    double sum = 0;
    for (int64_t s = 0; s < net.segment_count(); ++s) sum += net.segment_length(s);
    assert_true(std::fabs(sum - net.total_length()) < 1e-14);
    assert_true(std::fabs(net.part_length(0) + net.part_length(1) - net.total_length()) < 1e-15);
    // Original coordinates come back, unit vectors match them.
    assert_true(net.lon_deg(4) == 21 && net.lat_deg(4) == 20);
    Vec3 u = geom::unit_from_lonlat_deg(21, 20), v = net.point(4);
    assert_true(u.x == v.x && u.y == v.y && u.z == v.z);
}

void default_ids_are_network_indices(void **) {
    Network net;
    assert_int_equal(add(net, {line({0, 0, 1, 1}), line({2, 2, 3, 3})}, nullptr, false), UM_OK);
    assert_int_equal(add(net, {line({4, 4, 5, 5})}, nullptr, false), UM_OK);
    for (int64_t p = 0; p < 3; ++p) assert_int_equal(net.part(p).id, p);
}

void duplicates_are_dropped(void **) {
    Network net;
    // Consecutive repeats inside an open line; the first of each run is kept.
    assert_int_equal(add(net, {line({0, 0, 0, 0, 1, 0, 1, 0, 1, 0, 2, 0})}), UM_OK);
    assert_int_equal(net.part(0).n_points, 3);
    // lon 180 and -180 are one point, and so are all longitudes at a pole.
    assert_int_equal(add(net, {line({170, 5, 180, 5, -180, 5, -170, 5})}), UM_OK);
    assert_int_equal(net.part(1).n_points, 3);
    assert_true(net.lon_deg(net.part(1).first_point + 1) == 180);
    assert_int_equal(add(net, {line({0, 80, 0, 90, 45, 90, 90, 90, 90, 80})}), UM_OK);
    assert_int_equal(net.part(2).n_points, 3);
    // 0 and 360 are one meridian.
    assert_int_equal(add(net, {line({0, 1, 360, 1, 5, 1})}), UM_OK);
    assert_int_equal(net.part(3).n_points, 2);
    // An open line that returns to its start keeps both ends (the caller said open).
    assert_int_equal(add(net, {line({0, 0, 1, 0, 1, 1, 0, 0})}), UM_OK);
    assert_int_equal(net.part(4).n_points, 4);
    assert_int_equal(net.part(4).n_segments, 3);
}

void closed_rings(void **) {
    Network net;
    // Given with first == last: stored once, closed, one segment per point.
    assert_int_equal(add(net, {line({0, 0, 1, 0, 1, 1, 0, 1, 0, 0}, 1)}), UM_OK);
    assert_int_equal(net.part(0).n_points, 4);
    assert_int_equal(net.part(0).n_segments, 4);
    assert_true(std::fabs(net.part_length(0) - (1 + 1 + std::cos(1 * kDeg) + 1) * kDeg) < 1e-6);
    // Given without the repeat: the same ring, which one network refuses to
    // hold twice (from any start, either way round); another takes it.
    assert_int_equal(add(net, {line({0, 0, 1, 0, 1, 1, 0, 1}, 1)}), UM_ERR_INPUT);
    assert_int_equal(add(net, {line({1, 1, 1, 0, 0, 0, 0, 1}, 1)}), UM_ERR_INPUT);
    assert_int_equal(net.part_count(), 1);
    Network again;
    assert_int_equal(add(again, {line({0, 0, 1, 0, 1, 1, 0, 1}, 1)}), UM_OK);
    assert_int_equal(again.part(0).n_points, 4);
    assert_true(again.part_length(0) == net.part_length(0));
    // Repeats at both ends and inside, and the closing point written as lon + 360.
    assert_int_equal(add(net, {line({0, 0, 0, 0, 1, 0, 1, 0, 1, 1, 360, 0, 0, 0}, 1)}), UM_OK);
    assert_int_equal(net.part(1).n_points, 3);
    // A closed part of 2 distinct points: there and back, two segments.
    assert_int_equal(add(net, {line({0, 0, 1, 0, 0, 0}, 1)}), UM_OK);
    assert_int_equal(net.part(2).n_points, 2);
    assert_int_equal(net.part(2).n_segments, 2);
}

void self_intersecting_touching_and_overlapping_lines_are_kept(void **) {
    Network net;
    // A figure eight (crosses itself), a line touching its own vertex, and two
    // parts sharing a segment and a vertex.
    assert_int_equal(add(net, {line({0, 0, 2, 2, 2, 0, 0, 2}, 1), line({10, 0, 12, 0, 11, 1, 11, 0, 11, -1}),
                               line({20, 0, 21, 0, 22, 0}), line({21, 0, 22, 0, 23, 1})}),
                     UM_OK);
    assert_int_equal(net.part_count(), 4);
    assert_int_equal(net.point_count(), 4 + 5 + 3 + 3);
    assert_int_equal(net.segment_count(), 4 + 4 + 2 + 2);
}

void dateline_segments_are_short_arcs(void **) {
    Network net;
    assert_int_equal(add(net, {line({179.5, -16.5, -179.5, -16.5, -179.0, -17.0}),
                               line({170, 60, -170, 60, -170, 70, 170, 70}, 1)}),
                     UM_OK);
    // 1 degree of longitude at 16.5 S, not 359 degrees the other way round.
    double expected = std::acos(std::pow(std::sin(16.5 * kDeg), 2) +
                                std::pow(std::cos(16.5 * kDeg), 2) * std::cos(1 * kDeg));
    assert_true(std::fabs(net.segment_length(0) - expected) < 1e-12);
    assert_true(net.segment_length(0) < 1.0 * kDeg);
    // Every segment of the ring around the antimeridian is shorter than 20 degrees.
    for (int64_t s = net.part(1).first_segment; s < net.segment_count(); ++s)
        assert_true(net.segment_length(s) < 20 * kDeg);
    assert_true(net.part_length(1) < 60 * kDeg);
}

void bad_values_are_rejected_with_their_place(void **) {
    Network net;
    std::string m;
    assert_int_equal(add(net, {line({0, 0, 1, 1}), line({0, 0, NAN, 1})}, &m), UM_ERR_NONFINITE_INPUT);
    assert_true(contains(m, "part 1, point 1 longitude"));
    assert_int_equal(add(net, {line({0, 0, 1, INFINITY})}, &m), UM_ERR_NONFINITE_INPUT);
    assert_true(contains(m, "part 0, point 1 latitude = inf"));
    assert_int_equal(add(net, {line({0, 0, 1, 1, 2, 90.5})}, &m), UM_ERR_COORDINATE_RANGE);
    assert_true(contains(m, "part 0, point 2 latitude = 90.5 is outside [-90, 90]"));
    assert_int_equal(add(net, {line({0, 0, 1, -91})}, &m), UM_ERR_COORDINATE_RANGE);
    // Fewer than 2 distinct points: one point, all the same point, none.
    for (const auto &bad : {line({5, 5}), line({5, 5, 5, 5, 365, 5}), line({5, 5, 5, 5}, 1), line({})}) {
        assert_int_equal(add(net, {line({0, 0, 1, 1}), bad}, &m), UM_ERR_TOO_FEW_POINTS);
        assert_int_equal(um_status_class(UM_ERR_TOO_FEW_POINTS), UM_ERR_INPUT);
        assert_true(contains(m, "part 1 has "));
    }
    // Unknown kinds and closed flags.
    assert_int_equal(add(net, {line({0, 0, 1, 1}, 0, 0)}, &m), UM_ERR_INVALID_ARGUMENT);
    assert_true(contains(m, "kind[0] = 0"));
    assert_int_equal(add(net, {line({0, 0, 1, 1}), line({0, 0, 1, 1}, 0, 8)}, &m), UM_ERR_INVALID_ARGUMENT);
    assert_true(contains(m, "kind[1] = 8"));
    assert_int_equal(add(net, {line({0, 0, 1, 1}, 2)}, &m), UM_ERR_INVALID_ARGUMENT);
    assert_true(contains(m, "closed[0] = 2"));
    assert_int_equal(net.part_count(), 0);
}

void antipodal_neighbours_are_rejected(void **) {
    Network net;
    std::string m;
    // Antipodes by degrees (sin(pi) != 0 in doubles), by unit vectors (poles),
    // across repeated points, and through the closing arc.
    assert_int_equal(add(net, {line({0, 0, 180, 0})}, &m), UM_ERR_DEGENERATE_INPUT);
    assert_true(contains(m, "part 0, point 1"));
    assert_int_equal(add(net, {line({1, 1, 10, 20, -170, -20})}, &m), UM_ERR_DEGENERATE_INPUT);
    assert_true(contains(m, "part 0, point 2"));
    assert_int_equal(add(net, {line({0, 90, 0, 90, 33, -90})}, &m), UM_ERR_DEGENERATE_INPUT);
    assert_true(contains(m, "point 2") && contains(m, "(point 0 of the part)"));
    assert_int_equal(add(net, {line({0, 0, 90, 0, 180, 0}, 1)}, &m), UM_ERR_DEGENERATE_INPUT);
    assert_true(contains(m, "closing"));
    assert_int_equal(add(net, {line({-45, 30, 135, -30})}, &m), UM_ERR_DEGENERATE_INPUT);
    assert_int_equal(net.part_count(), 0);
    // Nearly antipodal is a valid (long) arc, and so is an open line through both ends.
    assert_int_equal(add(net, {line({0, 0, 179.999, 0}), line({0, 0, 90, 0, 180, 0})}, &m), UM_OK);
    assert_int_equal(net.part_count(), 2);
}

void inconsistent_layouts_are_rejected(void **) {
    Network net;
    std::string message;
    double lon[] = {0, 1, 2, 3}, lat[] = {0, 1, 2, 3};
    int64_t offsets[] = {0, 2, 4};
    int32_t closed[] = {0, 0}, kind[] = {1, 1};
    auto status_of = [&](features::PartsInput in) -> um_status {
        try {
            net.add(in);
        } catch (const Error &e) {
            message = e.what();
            return e.status();
        }
        return UM_OK;
    };
    features::PartsInput in;
    in.n_points = 4, in.lon_deg = lon, in.lat_deg = lat, in.n_parts = 2;
    in.part_offsets = offsets, in.closed = closed, in.kind = kind;
    offsets[0] = 1;
    assert_int_equal(status_of(in), UM_ERR_INVALID_ARGUMENT);
    assert_true(contains(message, "part_offsets[0] = 1 is not 0"));
    offsets[0] = 0, offsets[1] = 5;
    assert_int_equal(status_of(in), UM_ERR_INVALID_ARGUMENT);
    assert_true(contains(message, "part_offsets[1] = 5 exceeds n_points = 4"));
    offsets[1] = 2, offsets[2] = 1;
    assert_int_equal(status_of(in), UM_ERR_INVALID_ARGUMENT);
    assert_true(contains(message, "part_offsets[2] = 1 is below part_offsets[1] = 2"));
    offsets[2] = 4;
    in.n_points = -1;
    assert_int_equal(status_of(in), UM_ERR_INVALID_ARGUMENT);
    in.n_points = 4, in.kind = nullptr;
    assert_int_equal(status_of(in), UM_ERR_NULL_ARGUMENT);
    in.kind = kind;
    assert_int_equal(net.part_count(), 0);
    offsets[1] = 1;  // part 0 is one point
    assert_int_equal(status_of(in), UM_ERR_TOO_FEW_POINTS);
    offsets[1] = 2;
    assert_int_equal(status_of(in), UM_OK);
    assert_int_equal(net.part_count(), 2);
    // An empty batch is fine and changes nothing.
    in.n_points = 0, in.n_parts = 0, offsets[0] = 0;
    assert_int_equal(status_of(in), UM_OK);
    assert_int_equal(net.part_count(), 2);
}

void failing_adds_change_nothing(void **) {
    Network net;
    assert_int_equal(add(net, {line({0, 0, 1, 0, 1, 1}, 1, UM_FEATURE_LAKE, 3)}), UM_OK);
    const std::string before = snapshot(net);
    // The bad part comes last, after good parts that were already cleaned.
    const std::vector<LinePart> bad_last[] = {
        {line({5, 5, 6, 6}), line({7, 7, 8, 8, 8, 8}, 1), line({9, 9, 9, 95})},
        {line({5, 5, 6, 6}), line({0, 0, 180, 0})},
        {line({5, 5, 6, 6}), line({3, 3, 3, 3})},
        {line({5, 5, 6, 6}), line({3, 3, 4, 4}, 0, 9)},
    };
    for (const auto &batch : bad_last) {
        assert_int_not_equal(add(net, batch), UM_OK);
        assert_true(snapshot(net) == before);
    }
    // Still usable afterwards.
    assert_int_equal(add(net, {line({5, 5, 6, 6})}), UM_OK);
    assert_int_equal(net.part_count(), 2);
    assert_int_equal(net.part(1).first_point, 3);
}

void kind_names(void **) {
    Kind k;
    assert_true(features::kind_from_name("coastline", k) && k == Kind::coastline);
    assert_true(features::kind_from_name("WaterShed", k) && k == Kind::watershed);
    assert_false(features::kind_from_name("lakes", k));
    assert_false(features::kind_from_name("", k));
    assert_string_equal(features::kind_name(Kind::river), "river");
    assert_true(features::is_kind(UM_FEATURE_COASTLINE) && features::is_kind(UM_FEATURE_OTHER));
    assert_true(features::kind_from_name("Passage", k) && k == Kind::passage);
    assert_true(features::is_kind(UM_FEATURE_PASSAGE) && features::is_kind(UM_FEATURE_DOMAIN));
    assert_true(features::kind_from_name("domain", k) && k == Kind::domain);
    assert_false(features::is_kind(0) || features::is_kind(8));
}

// --------------------------------------------------------------- GeoJSON

std::string test_file(const char *name) { return std::string(UNIMESH_TEST_DATA_DIR "/") + name; }

um_status read_file(Network &net, const std::string &path, const io::GeojsonOptions &options = {},
                    std::string *message = nullptr) {
    try {
        io::read_geojson_file(path, options, net);
    } catch (const Error &e) {
        if (message) *message = e.what();
        return e.status();
    }
    return UM_OK;
}

um_status read_text(Network &net, const std::string &text, std::string *message = nullptr,
                    const io::GeojsonOptions &options = {}) {
    try {
        io::read_geojson_text(text, options, net, "text");
    } catch (const Error &e) {
        if (message) *message = e.what();
        return e.status();
    }
    return UM_OK;
}

struct ExpectedPart {
    int32_t kind, id;
    bool closed;
    int64_t n_points;
};

void every_geometry_type(void **) {
    Network net;
    assert_int_equal(read_file(net, test_file("lines.geojson")), UM_OK);
    const ExpectedPart expected[] = {
        {UM_FEATURE_RIVER, 0, false, 3},      // LineString
        {UM_FEATURE_COASTLINE, 42, true, 4},  // first == last: closed, stored once; "id" member
        {UM_FEATURE_LAKE, 2, true, 3},        // "closed": true without the repeat
        {UM_FEATURE_OTHER, 3, false, 4},      // "closed": false wins over first == last
        {UM_FEATURE_WATERSHED, 4, false, 2},  // MultiLineString: two open parts
        {UM_FEATURE_WATERSHED, 4, false, 3},
        {UM_FEATURE_LAKE, 5, true, 4},        // Polygon: outer ring and hole
        {UM_FEATURE_LAKE, 5, true, 3},
        {UM_FEATURE_COASTLINE, 6, true, 3},   // MultiPolygon: one ring each
        {UM_FEATURE_COASTLINE, 6, true, 3},
        {UM_FEATURE_OTHER, -3, false, 2},     // GeometryCollection, nested
        {UM_FEATURE_OTHER, -3, true, 3},
        // feature 8 has a null geometry; feature 9 has a string id, crosses the
        // antimeridian, repeats a point and carries an altitude.
        {UM_FEATURE_COASTLINE, 9, false, 3},
    };
    const int64_t n = sizeof expected / sizeof expected[0];
    assert_int_equal(net.part_count(), n);
    int64_t points = 0, segments = 0;
    for (int64_t p = 0; p < n; ++p) {
        const auto &part = net.part(p);
        assert_int_equal(int(part.kind), expected[p].kind);
        assert_int_equal(part.id, expected[p].id);
        assert_int_equal(part.closed, expected[p].closed);
        assert_int_equal(part.n_points, expected[p].n_points);
        points += part.n_points;
        segments += part.closed ? part.n_points : part.n_points - 1;
    }
    assert_int_equal(net.point_count(), points);
    assert_int_equal(net.segment_count(), segments);
    // The Fiji line: 1 degree of longitude across the antimeridian.
    int64_t s = net.part(12).first_segment;
    assert_true(net.segment_length(s) < 1 * kDeg);
    assert_true(net.lon_deg(net.segment_end(s)) == -179.5);
}

void lone_feature_and_bare_geometry(void **) {
    Network net;
    std::string m;
    assert_int_equal(read_file(net, test_file("feature.geojson")), UM_OK);
    assert_int_equal(net.part_count(), 2);
    assert_int_equal(net.part(0).id, 7);
    assert_int_equal(int(net.part(1).kind), UM_FEATURE_RIVER);
    // A bare geometry has no properties: it needs a default kind.
    assert_int_equal(read_file(net, test_file("polygon.geojson"), {}, &m), UM_ERR_INPUT);
    assert_true(contains(m, "polygon.geojson: the top-level value has no properties"));
    io::GeojsonOptions options;
    options.default_kind = UM_FEATURE_WATERSHED;
    assert_int_equal(read_file(net, test_file("polygon.geojson"), options), UM_OK);
    assert_int_equal(net.part_count(), 3);
    assert_true(net.part(2).closed && net.part(2).n_points == 4 && net.part(2).id == 0);
    assert_int_equal(int(net.part(2).kind), UM_FEATURE_WATERSHED);
}

void kinds_from_a_caller_table(void **) {
    io::GeojsonOptions options;
    options.kind_property = "level";
    options.kind_values = {{"1", Kind::coastline}, {"2", Kind::lake}, {"river", Kind::river}};
    options.id_property = "gid";
    std::string m;
    {
        Network net;  // level 3 is not in the table and there is no default
        assert_int_equal(read_file(net, test_file("levels.geojson"), options, &m), UM_ERR_INPUT);
        assert_true(contains(m, "features[2].properties.level = 3 is not a known feature kind"));
        assert_int_equal(net.part_count(), 0);
    }
    Network net;
    options.default_kind = UM_FEATURE_OTHER;
    assert_int_equal(read_file(net, test_file("levels.geojson"), options), UM_OK);
    const int32_t kinds[] = {UM_FEATURE_COASTLINE, UM_FEATURE_LAKE, UM_FEATURE_OTHER, UM_FEATURE_RIVER};
    const int32_t ids[] = {1001, 1002, 1003, 3};  // the last has no "gid": its index
    for (int p = 0; p < 4; ++p) {
        assert_int_equal(int(net.part(p).kind), kinds[p]);
        assert_int_equal(net.part(p).id, ids[p]);
    }
    // The standard names do not apply to another property without a table.
    Network other;
    io::GeojsonOptions names;
    names.kind_property = "level";
    assert_int_equal(read_file(other, test_file("levels.geojson"), names, &m), UM_ERR_INPUT);
    assert_true(contains(m, "features[0].properties.level = 1"));
    // Missing property with no default.
    names.kind_property = "category";
    assert_int_equal(read_file(other, test_file("levels.geojson"), names, &m), UM_ERR_INPUT);
    assert_true(contains(m, "features[0] has no property \"category\""));
}

void malformed_files(void **) {
    struct Case {
        const char *file;
        um_status status;
        const char *said[2];
    } cases[] = {
        {"bad_syntax.geojson", UM_ERR_FILE_FORMAT, {"malformed JSON at byte 166 (line 3,", "column 68)"}},
        {"truncated.geojson", UM_ERR_FILE_FORMAT, {"the text ends at byte 189", "truncated file?"}},
        {"missing_coordinates.geojson", UM_ERR_FILE_FORMAT,
         {"features[1].geometry is a LineString with no \"coordinates\"", "features[1]"}},
        {"short_position.geojson", UM_ERR_FILE_FORMAT,
         {"features[0].geometry.coordinates[2] has 1 number;", "at least 2 (lon, lat)"}},
        {"string_coordinate.geojson", UM_ERR_FILE_FORMAT,
         {"features[2].geometry.coordinates[1][1] is a string, not a number", "features[2]"}},
        {"latitude_range.geojson", UM_ERR_COORDINATE_RANGE,
         {"features[1].geometry.coordinates[3][1] = 90.5 is outside [-90, 90]", "[3][1]"}},
        {"unknown_kind.geojson", UM_ERR_INPUT,
         {"features[1].properties.kind = \"canal\" is not a known feature kind", "no default"}},
        {"does_not_exist.geojson", UM_ERR_IO, {"cannot open", "no such file or directory"}},
        {"", UM_ERR_IO, {"is a directory", "cannot read"}},  // tests/data itself
    };
    for (const auto &c : cases) {
        Network net;
        assert_int_equal(read_file(net, test_file("lines.geojson")), UM_OK);
        const std::string before = snapshot(net);
        std::string m;
        assert_int_equal(read_file(net, test_file(c.file), {}, &m), c.status);
        for (const char *s : c.said) assert_true(contains(m, s));
        assert_true(contains(m, c.file));
        assert_true(snapshot(net) == before);
    }
    // A file cut anywhere is an error, never a crash or a partial read.
    std::FILE *f = std::fopen(test_file("lines.geojson").c_str(), "rb");
    assert_non_null(f);
    std::string text;
    for (int ch; (ch = std::fgetc(f)) != EOF;) text += static_cast<char>(ch);
    std::fclose(f);
    for (size_t cut = 0; cut < text.size() - 3; cut += 7) {
        Network net;
        std::string m;
        assert_int_equal(read_text(net, text.substr(0, cut), &m), UM_ERR_FILE_FORMAT);
        assert_int_equal(net.part_count(), 0);
    }
}

// Single-byte corruptions of a valid file: each is read or rejected with a
// um::Error (any other exception would end the test), never half-added.
void corrupted_bytes(void **) {
    std::FILE *f = std::fopen(test_file("lines.geojson").c_str(), "rb");
    assert_non_null(f);
    std::string text;
    for (int ch; (ch = std::fgetc(f)) != EOF;) text += static_cast<char>(ch);
    std::fclose(f);
    const char replacements[] = "[]{},:\"-.0159eENaxt \\";
    uint64_t state = 12345;
    int rejected = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;  // LCG, deterministic
        std::string bad = text;
        bad[(state >> 33) % bad.size()] = replacements[(state >> 17) % (sizeof replacements - 1)];
        Network net;
        assert_int_equal(add(net, {line({0, 0, 1, 1})}), UM_OK);
        const std::string before = snapshot(net);
        std::string m;
        io::GeojsonOptions options;
        options.default_kind = UM_FEATURE_OTHER;
        um_status s = read_text(net, bad, &m, options);
        if (s != UM_OK) {
            ++rejected;
            assert_true(snapshot(net) == before);
            assert_true(um_status_class(s) == UM_ERR_INPUT || s == UM_ERR_FILE_FORMAT);
            assert_false(m.empty());
        }
    }
    assert_true(rejected > 1000);
}

void wrong_structures(void **) {
    struct Case {
        const char *text;
        um_status status;
        const char *said;
    } cases[] = {
        {"", UM_ERR_FILE_FORMAT, "the text ends at byte 0"},
        {"  \n ", UM_ERR_FILE_FORMAT, "truncated"},
        {"[1, 2]", UM_ERR_FILE_FORMAT, "the top-level value is an array, not a GeoJSON object"},
        {"{\"features\": []}", UM_ERR_FILE_FORMAT, "has no \"type\""},
        {"{\"type\": 3}", UM_ERR_FILE_FORMAT, "type is a number, not a string"},
        {"{\"type\": \"FeatureCollection\"}", UM_ERR_FILE_FORMAT, "features is missing"},
        {"{\"type\": \"FeatureCollection\", \"features\": {}}", UM_ERR_FILE_FORMAT,
         "features is an object, not an array"},
        {"{\"type\": \"FeatureCollection\", \"features\": [7]}", UM_ERR_FILE_FORMAT,
         "features[0] is a number, not a Feature object"},
        {"{\"type\": \"FeatureCollection\", \"features\": [{\"type\": \"Polygon\"}]}",
         UM_ERR_FILE_FORMAT, "features[0] has type \"Polygon\", not \"Feature\""},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}}", UM_ERR_FILE_FORMAT,
         "has no \"geometry\" member"},
        {"{\"type\": \"Feature\", \"properties\": 5, \"geometry\": null}", UM_ERR_FILE_FORMAT,
         "properties is a number, not an object or null"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"Point\", \"coordinates\": [1, 2]}}",
         UM_ERR_TOO_FEW_POINTS, "geometry.coordinates has 1 distinct point (1 given); a line needs at least 2"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"Circle\", \"coordinates\": [1, 2]}}",
         UM_ERR_FILE_FORMAT, "geometry has type \"Circle\", which is not a GeoJSON geometry"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": 5}}",
         UM_ERR_FILE_FORMAT, "geometry.coordinates is a number, not an array"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": [[0, 0], 5]}}",
         UM_ERR_FILE_FORMAT, "geometry.coordinates[1] is a number, not a position [lon, lat]"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [null, 1]]}}",
         UM_ERR_FILE_FORMAT, "geometry.coordinates[1][0] is null, not a number"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"MultiLineString\", \"coordinates\": [[[0, 0], [1, 1]], [0, 1]]}}",
         UM_ERR_FILE_FORMAT, "geometry.coordinates[1][0] is a number, not a position"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"MultiPolygon\", \"coordinates\": [[[[0, 0], [1, 1], [1, 0]]], 3]}}",
         UM_ERR_FILE_FORMAT, "geometry.coordinates[1] is a number, not an array of rings"},
        // A domain polygon's hole outside its exterior ring (by the first
        // point, drawn in lon/lat: the second one's exterior crosses the
        // antimeridian and its hole at -175 is inside).
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [20, 0], [20, 20], [0, 20], [0, 0]], "
         "[[30, 5], [35, 5], [35, 10], [30, 5]]]}}",
         UM_ERR_INPUT, "geometry.coordinates[1] is a hole of the polygon but lies outside its exterior ring, "
                       "geometry.coordinates[0]"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"MultiPolygon\", \"coordinates\": [[[[0, 0], [20, 0], [20, 20], [0, 0]]], "
         "[[[170, 0], [-170, 0], [-170, 20], [170, 20], [170, 0]], [[-175, 5], [-172, 5], [-172, 10], [-175, 5]], "
         "[[-30, 5], [-25, 5], [-25, 10], [-30, 5]]]]}}",
         UM_ERR_INPUT, "geometry.coordinates[1][2] is a hole of the polygon but lies outside its exterior ring, "
                       "geometry.coordinates[1][0]"},
        // A domain polygon's ring given open (its last position not its
        // first), in a Polygon and in a MultiPolygon's hole; a domain
        // LineString given open.
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"Polygon\", \"coordinates\": [[[-80, 10], [-5, 10], [-5, 65], [-80, 65]]]}}",
         UM_ERR_INPUT, "geometry.coordinates[0] is a domain ring but is open: its last position [-80, 65] is not its "
                       "first [-80, 10] (a GeoJSON ring repeats its first position)"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"MultiPolygon\", \"coordinates\": [[[[0, 0], [20, 0], [20, 20], [0, 0]], "
         "[[5, 5], [8, 5], [8, 8]]]]}}",
         UM_ERR_INPUT, "geometry.coordinates[0][1] is a domain ring but is open"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [20, 0], [20, 20]]}}",
         UM_ERR_INPUT, "geometry.coordinates is a domain ring but is open"},
        // An empty ring of a domain polygon: the network's refusal, not the hole test's.
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"Polygon\", \"coordinates\": [[], [[1, 1], [2, 1], [2, 2], [1, 1]]]}}",
         UM_ERR_TOO_FEW_POINTS, "geometry.coordinates[0] has 0 distinct points"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
         "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [10, 0], [10, 10], [0, 0]], []]}}",
         UM_ERR_TOO_FEW_POINTS, "geometry.coordinates[1] has 0 distinct points"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
         "{\"type\": \"GeometryCollection\"}}",
         UM_ERR_FILE_FORMAT, "geometry.geometries is missing"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\", \"closed\": \"yes\"}, "
         "\"geometry\": {\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}}",
         UM_ERR_INPUT, "properties.closed = \"yes\" is not true or false"},
        {"{\"type\": \"Feature\", \"id\": 1e10, \"properties\": {\"kind\": \"river\"}, "
         "\"geometry\": {\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}}",
         UM_ERR_INPUT, "id = 10000000000.0 is not an integer within int32"},
        {"{\"type\": \"Feature\", \"id\": 2.5, \"properties\": {\"kind\": \"river\"}, "
         "\"geometry\": {\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}}",
         UM_ERR_INPUT, "id = 2.5 is not an integer"},
        {"{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1e400]]}", UM_ERR_FILE_FORMAT,
         "malformed JSON: number overflow parsing '1e400' (first found at byte 51 (line 1, column 52))"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"sea\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}}",
         UM_ERR_INPUT, "text: properties.kind = \"sea\" is not a known feature kind"},
        {"{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, NaN]]}", UM_ERR_FILE_FORMAT,
         "malformed JSON at byte 51 (line 1, column 52)"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"lake\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [0, 0], [360, 0]]}}",
         UM_ERR_TOO_FEW_POINTS, "text: geometry.coordinates has 1 distinct point (3 given)"},
        {"{\"type\": \"Feature\", \"properties\": {\"kind\": \"lake\"}, \"geometry\": "
         "{\"type\": \"LineString\", \"coordinates\": [[10, 10], [-170, -10]]}}",
         UM_ERR_DEGENERATE_INPUT, "text: geometry.coordinates[1] = (-170, -10) is antipodal"},
    };
    for (const auto &c : cases) {
        Network net;
        std::string m;
        um_status s = read_text(net, c.text, &m);
        if (s != c.status) std::printf("case %s: status %d, message %s\n", c.text, s, m.c_str());
        assert_int_equal(s, c.status);
        assert_true(contains(m, c.said));
        assert_int_equal(net.part_count(), 0);
    }
    // GeometryCollections nested too deep.
    std::string deep = "{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": ";
    for (int i = 0; i < 40; ++i) deep += "{\"type\": \"GeometryCollection\", \"geometries\": [";
    deep += "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}";
    for (int i = 0; i < 40; ++i) deep += "]}";
    deep += "}";
    Network net;
    std::string m;
    assert_int_equal(read_text(net, deep, &m), UM_ERR_FILE_FORMAT);
    assert_true(contains(m, "more than 32 deep"));
    // Things that are fine: empty collections, null properties with a default
    // kind, a UTF-8 byte order mark, unknown members, a string id.
    io::GeojsonOptions with_default;
    with_default.default_kind = UM_FEATURE_OTHER;
    assert_int_equal(read_text(net, "{\"type\": \"FeatureCollection\", \"features\": []}"), UM_OK);
    assert_int_equal(read_text(net,
                               "\xEF\xBB\xBF{\"type\": \"Feature\", \"id\": \"x\", \"bbox\": [0, 0, 1, 1], "
                               "\"properties\": null, \"geometry\": {\"type\": \"LineString\", "
                               "\"coordinates\": [[0, 0], [1, 1]]}}",
                               &m, with_default),
                     UM_OK);
    assert_int_equal(net.part_count(), 1);
    assert_int_equal(int(net.part(0).kind), UM_FEATURE_OTHER);
}

// Passages: points and lines, split off Gamma by parts_of_kind.
// A domain polygon's holes inside its exterior are read; so is one in an
// exterior through a pole (its edges there run along meridians: the hole
// at lon -8 lies in the wedge -10..10, outside the lon/lat triangle).
void domain_holes_inside_their_exterior_are_read(void **) {
    for (const char *exterior : {"[[0, 0], [20, 0], [20, 20], [0, 20], [0, 0]]", "[[-10, 80], [10, 80], [0, 90], [-10, 80]]"}) {
        const std::string text = std::string("{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, "
                                             "\"geometry\": {\"type\": \"Polygon\", \"coordinates\": [") +
                                 exterior + ", " +
                                 (exterior[2] == '0' ? "[[5, 5], [8, 5], [8, 8], [5, 5]]" : "[[-8, 85], [-6, 85], [-6, 87], [-8, 85]]") +
                                 "]}}";
        Network net;
        std::string m;
        assert_int_equal(read_text(net, text, &m), UM_OK);
        assert_int_equal(net.part_count(), 2);
    }
}

// A domain ring remembers where it came from (for the errors of the rings
// seen together, features::Domain): the file and JSON path of a GeoJSON
// one; nothing for other kinds or for parts added without names.
void domain_rings_remember_where_they_came_from(void **) {
    Network net;
    const std::string text =
        "{\"type\": \"FeatureCollection\", \"features\": ["
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, \"geometry\": "
        "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}},"
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
        "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [20, 0], [20, 20], [0, 0]], "
        "[[5, 2], [15, 2], [15, 12], [5, 2]]]}}]}";
    assert_int_equal(read_text(net, text), UM_OK);
    assert_int_equal(net.part_count(), 3);
    assert_string_equal(net.domain_origin(0).c_str(), "");
    assert_string_equal(net.domain_origin(1).c_str(), "text: features[1].geometry.coordinates[0]");
    assert_string_equal(net.domain_origin(2).c_str(), "text: features[1].geometry.coordinates[1]");
    assert_string_equal(net.domain_origin(3).c_str(), "");
    // (Two rings: the network refuses a ring it holds already.)
    const std::vector<double> lon{30, 40, 40, 50, 60, 60}, lat{0, 0, 10, 0, 0, 10};
    const std::vector<int64_t> offsets{0, 3};
    const std::vector<int32_t> closed{1}, kind{UM_FEATURE_DOMAIN};
    auto ring = [&](int k) {
        features::PartsInput in;
        in.n_points = 3, in.lon_deg = lon.data() + 3 * k, in.lat_deg = lat.data() + 3 * k, in.n_parts = 1;
        in.part_offsets = offsets.data(), in.closed = closed.data(), in.kind = kind.data();
        return in;
    };
    net.add(ring(0));
    assert_string_equal(net.domain_origin(3).c_str(), "");
    net.add(ring(1), [](int64_t p, int64_t, int) { return concat("batch part ", p); });
    assert_string_equal(net.domain_origin(4).c_str(), "batch part 0");
    assert_string_equal(net.domain_origin(2).c_str(), "text: features[1].geometry.coordinates[1]");
}

void passages_of_points_and_lines(void **) {
    Network net;
    std::string m;
    const char *text =
        "{\"type\": \"FeatureCollection\", \"features\": ["
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"passage\"}, \"geometry\": "
        "{\"type\": \"Point\", \"coordinates\": [29, 41.1]}},"
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"passage\"}, \"geometry\": "
        "{\"type\": \"MultiPoint\", \"coordinates\": [[26.4, 40.2], [26.4, 40.2, 5]]}},"
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"coastline\"}, \"geometry\": "
        "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}},"
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"passage\"}, \"geometry\": "
        "{\"type\": \"LineString\", \"coordinates\": [[-5.6, 35.7], [-5.6, 36.1]]}}]}";
    assert_int_equal(read_text(net, text, &m), UM_OK);
    assert_int_equal(net.part_count(), 5);
    for (int p : {0, 1, 2}) {
        assert_int_equal(int(net.part(p).kind), UM_FEATURE_PASSAGE);
        assert_int_equal(net.part(p).n_points, 1);
        assert_int_equal(net.part(p).n_segments, 0);
    }
    assert_int_equal(net.segment_count(), 2);
    const Network passages = features::parts_of_kind(net, Kind::passage, true);
    const Network gamma = features::parts_of_kind(net, Kind::passage, false);
    assert_int_equal(passages.part_count(), 4);
    assert_int_equal(passages.part(3).n_points, 2);
    assert_int_equal(passages.part(3).id, 3);
    assert_int_equal(gamma.part_count(), 1);
    assert_int_equal(int(gamma.part(0).kind), UM_FEATURE_COASTLINE);
    assert_true(gamma.lon_deg(1) == 1.0);
    // Only an open passage may be a point.
    Network refused;
    assert_int_equal(add(refused, {line({5, 5}, 1, UM_FEATURE_PASSAGE)}, &m), UM_ERR_TOO_FEW_POINTS);
    assert_true(contains(m, "a closed passage needs at least 2"));
    assert_int_equal(add(refused, {line({5, 5}, 0, UM_FEATURE_PASSAGE)}, &m), UM_OK);
    // A GeoJSON point said to be closed is refused too, not read as open.
    Network closed_point;
    const char *closed_text =
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"passage\", \"closed\": true}, \"geometry\": "
        "{\"type\": \"Point\", \"coordinates\": [29, 41.1]}}";
    assert_int_equal(read_text(closed_point, closed_text, &m), UM_ERR_TOO_FEW_POINTS);
    print_message("%s\n", m.c_str());
    assert_true(contains(m, "geometry.coordinates") && contains(m, "a closed passage needs at least 2"));
    assert_int_equal(closed_point.part_count(), 0);
}

// The GSHHG files: counts against data/README.md. All shorelines are closed
// rings written with first == last, which the network stores once.
struct DataCounts {
    const char *file;
    int64_t features, positions, closing_repeats, coastline, lake, river;
    double length_km;
};

void check_data_file(const std::string &path, const DataCounts &c) {
    Network net;
    std::string m;
    um_status s = read_file(net, path, {}, &m);
    if (s != UM_OK) std::printf("%s\n", m.c_str());
    assert_int_equal(s, UM_OK);
    assert_int_equal(net.part_count(), c.features);
    assert_int_equal(net.point_count(), c.positions - c.closing_repeats);
    int64_t by_kind[6] = {0}, closed = 0, open = 0, long_dlon = 0;
    for (const auto &p : net.parts()) {
        by_kind[int(p.kind)]++;
        (p.closed ? closed : open)++;
    }
    assert_int_equal(closed, c.closing_repeats);
    assert_int_equal(net.segment_count(), net.point_count() - open);
    assert_int_equal(by_kind[UM_FEATURE_COASTLINE], c.coastline);
    assert_int_equal(by_kind[UM_FEATURE_LAKE], c.lake);
    assert_int_equal(by_kind[UM_FEATURE_RIVER], c.river);
    // Lengths as measured in the data README (to its rounding, 1 km).
    assert_true(std::fabs(net.total_length() * kEarthKm - c.length_km) < 1.0);
    // Edges across the antimeridian are short arcs.
    for (int64_t seg = 0; seg < net.segment_count(); ++seg) {
        double d = std::fabs(net.lon_deg(net.segment_start(seg)) - net.lon_deg(net.segment_end(seg)));
        if (d > 180) {
            ++long_dlon;
            assert_true(net.segment_length(seg) < 2 * kDeg);
        }
    }
    if (std::strcmp(c.file, "coast_global_l.geojson") == 0) assert_int_equal(long_dlon, 7);
}

void shipped_data(void **) {
    const DataCounts coast = {"coast_global_l.geojson", 813, 44103, 813, 478, 335, 0, 859532};
    const DataCounts rivers = {"rivers_global_l.geojson", 1285, 16512, 0, 0, 0, 1285, 352233};
    for (const auto &c : {coast, rivers}) check_data_file(std::string(UNIMESH_DATA_DIR "/") + c.file, c);
}

void shared_data(void **) {
    // skip() jumps out of the function: decide before any object needing a
    // destructor exists.
    if (std::FILE *f = std::fopen(UNIMESH_SHARED_DATA_DIR "/README.md", "rb"))
        std::fclose(f);
    else
        skip();
    const std::string dir = UNIMESH_SHARED_DATA_DIR;
    const DataCounts cases[] = {
        {"coast_global_c.geojson", 154, 5845, 154, 115, 39, 0, 495465},
        {"coast_global_l.geojson", 813, 44103, 813, 478, 335, 0, 859532},
        {"coast_midatlantic_f.geojson", 548, 64071, 537, 543, 5, 0, 9782},
        {"coast_midatlantic_i.geojson", 147, 2192, 138, 143, 4, 0, 6846},
        {"rivers_midatlantic_f.geojson", 11, 2183, 0, 0, 0, 11, 1164},
    };
    for (const auto &c : cases) check_data_file(dir + "/" + c.file, c);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parts_segments_and_accessors),
        cmocka_unit_test(default_ids_are_network_indices),
        cmocka_unit_test(duplicates_are_dropped),
        cmocka_unit_test(closed_rings),
        cmocka_unit_test(self_intersecting_touching_and_overlapping_lines_are_kept),
        cmocka_unit_test(dateline_segments_are_short_arcs),
        cmocka_unit_test(bad_values_are_rejected_with_their_place),
        cmocka_unit_test(antipodal_neighbours_are_rejected),
        cmocka_unit_test(inconsistent_layouts_are_rejected),
        cmocka_unit_test(failing_adds_change_nothing),
        cmocka_unit_test(kind_names),
        cmocka_unit_test(every_geometry_type),
        cmocka_unit_test(lone_feature_and_bare_geometry),
        cmocka_unit_test(kinds_from_a_caller_table),
        cmocka_unit_test(malformed_files),
        cmocka_unit_test(wrong_structures),
        cmocka_unit_test(domain_holes_inside_their_exterior_are_read),
        cmocka_unit_test(domain_rings_remember_where_they_came_from),
        cmocka_unit_test(passages_of_points_and_lines),
        cmocka_unit_test(corrupted_bytes),
        cmocka_unit_test(shipped_data),
        cmocka_unit_test(shared_data),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
