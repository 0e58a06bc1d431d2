#include "io/geojson.hpp"
#include "features/lonlat_ring.hpp"
#include "io/error_text.hpp"
#include "io/input_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include <nlohmann/json.hpp>

#include "core/context.hpp"
#include "core/error.hpp"

namespace um::io {

namespace {

using json = nlohmann::json;
using features::Kind;
using features::Network;

// Peak bytes of the parse per byte of text (the JSON tree costs about five
// times the text for coordinate arrays; the rest is the staged copy).
constexpr int64_t kParseBytesPerTextByte = 8;
constexpr int kMaxCollectionDepth = 32;

struct FileCloser {
    void operator()(std::FILE *f) const { std::fclose(f); }
};

std::string read_whole_file(const std::string &path, const Context *context) {
    namespace fs = std::filesystem;
    require_regular_input(path, "GeoJSON file");
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    errno = 0;
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) fail(UM_ERR_IO, "cannot open '", path, "' for reading: ", system_error_text(errno));
    std::string text;
    // The file size sizes the buffer and the memory check.
    if (!ec && fs::is_regular_file(status)) {
        const uintmax_t size = fs::file_size(path, ec);
        if (!ec && size > 0) {
            if (context)
                context->check_memory(static_cast<int64_t>(size) * kParseBytesPerTextByte,
                                      "reading the GeoJSON file");
            text.reserve(static_cast<size_t>(size));
        }
    }
    char buffer[1 << 16];
    size_t got;
    while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) text.append(buffer, got);
    if (std::ferror(file.get()))
        fail(UM_ERR_IO, "cannot read '", path, "': ", system_error_text(errno));
    return text;
}

const char *type_name(const json &j) {
    switch (j.type()) {
        case json::value_t::null: return "null";
        case json::value_t::object: return "an object";
        case json::value_t::array: return "an array";
        case json::value_t::string: return "a string";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::binary: return "binary data";
        case json::value_t::discarded: return "nothing";
        default: return "a number";
    }
}

// The member `key` of an object, or nullptr.
const json *member(const json &object, const char *key) {
    if (!object.is_object()) return nullptr;
    auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}
const json *member(const json &object, const std::string &key) { return member(object, key.c_str()); }

// A JSON value as it reads in a message (strings quoted, long values cut).
// Arrays and objects are named, not written out: json::dump recurses, and a
// value nested 100,000 deep (a small file) would overflow the stack.
std::string shown(const json &j) {
    if (j.is_array() || j.is_object())
        return concat(type_name(j), " of ", j.size(), j.is_array() ? " value" : " member", j.size() == 1 ? "" : "s");
    std::string s = j.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

// The text a kind table is matched against: strings as they are, numbers and
// booleans as JSON writes them; other values have none.
bool value_text(const json &j, std::string &text) {
    if (j.is_string()) {
        text = j.get_ref<const std::string &>();
        return true;
    }
    if (j.is_number() || j.is_boolean()) {
        text = j.dump();
        return true;
    }
    return false;
}

// An integral number within int32, or false.
bool int32_value(const json &j, int32_t &out) {
    constexpr double lo = std::numeric_limits<int32_t>::min(), hi = std::numeric_limits<int32_t>::max();
    if (j.is_number_integer() && !j.is_number_unsigned()) {
        int64_t i = j.get<int64_t>();
        if (i < lo || i > hi) return false;
        out = static_cast<int32_t>(i);
        return true;
    }
    if (j.is_number_unsigned()) {
        uint64_t u = j.get<uint64_t>();
        if (u > static_cast<uint64_t>(hi)) return false;
        out = static_cast<int32_t>(u);
        return true;
    }
    if (!j.is_number_float()) return false;
    const double v = j.get<double>();
    if (!(v >= lo && v <= hi) || v != std::floor(v)) return false;
    out = static_cast<int32_t>(v);
    return true;
}

// The path of a place in the document, for messages.
std::string shown_path(const std::string &path) { return path.empty() ? "the top-level value" : path; }

// Appends ".key" or "key" (at the root) to a path; restores it when it goes out of scope.
class PathScope {
public:
    PathScope(std::string &path, const std::string &step) : path_(path), size_(path.size()) {
        path_ += step;
    }
    ~PathScope() { path_.resize(size_); }
    PathScope(const PathScope &) = delete;
    PathScope &operator=(const PathScope &) = delete;

private:
    std::string &path_;
    size_t size_;
};
std::string field(const std::string &path, const char *key) {
    return path.empty() ? std::string(key) : concat(".", key);
}

class Reader {
public:
    Reader(const GeojsonOptions &options, const std::string &source)
        : options_(options), source_(source) {
        offsets_.push_back(0);
        if (options_.default_kind != 0 && !features::is_kind(options_.default_kind))
            fail(UM_ERR_INVALID_ARGUMENT, "default_kind = ", options_.default_kind,
                 " is neither 0 (no default) nor a feature kind (UM_FEATURE_COASTLINE = 1 to "
                 "UM_FEATURE_OTHER = 5)");
        if (options_.kind_property.empty())
            fail(UM_ERR_INVALID_ARGUMENT, "the kind property name is empty");
    }

    void read_document(const json &doc) {
        std::string path;
        const std::string type = type_of(doc, path, "a GeoJSON object");
        if (type == "FeatureCollection") {
            const json *list = member(doc, "features");
            PathScope scope(path, "features");
            if (!list) format_error(path, " is missing (a FeatureCollection needs it)");
            if (!list->is_array())
                format_error(path, " is ", type_name(*list), ", not an array of features");
            for (size_t i = 0; i < list->size(); ++i) {
                PathScope item(path, concat("[", i, "]"));
                read_feature((*list)[i], static_cast<int64_t>(i), path);
            }
        } else if (type == "Feature") {
            read_feature(doc, 0, path);
        } else {
            Attributes attributes;
            attributes.kind = kind_of(nullptr, path);
            attributes.id = 0;
            read_geometry(doc, type, attributes, path, 0);
        }
    }

    int64_t commit(Network &network) const {
        features::PartsInput in;
        in.n_points = static_cast<int64_t>(lon_.size());
        in.lon_deg = lon_.data();
        in.lat_deg = lat_.data();
        in.n_parts = static_cast<int64_t>(kind_.size());
        in.part_offsets = offsets_.data();
        in.closed = closed_.data();
        in.kind = kind_.data();
        in.part_id = id_.data();
        network.add(in, [this](int64_t part, int64_t point, int coordinate) {
            std::string s = concat(source_, ": ", part_path_[part]);
            if (point >= 0) s += concat("[", point, "]");
            if (coordinate >= 0) s += concat("[", coordinate, "]");
            return s;
        });
        return in.n_parts;
    }

private:
    struct Attributes {
        int32_t kind = 0;
        int32_t id = 0;
        int32_t closed = -1;  // from the "closed" property: -1 absent, 0, 1
    };

    template <class... Parts>
    [[noreturn]] void format_error(const std::string &path, const Parts &...parts) const {
        fail(UM_ERR_FILE_FORMAT, source_, ": ", shown_path(path), parts...);
    }
    template <class... Parts>
    [[noreturn]] void input_error(const std::string &path, const Parts &...parts) const {
        fail(UM_ERR_INPUT, source_, ": ", shown_path(path), parts...);
    }

    // The "type" member of an object that must have one.
    std::string type_of(const json &j, std::string &path, const char *what) const {
        if (!j.is_object()) format_error(path, " is ", type_name(j), ", not ", what);
        const json *type = member(j, "type");
        if (!type) format_error(path, " has no \"type\" member");
        if (!type->is_string()) {
            PathScope scope(path, field(path, "type"));
            format_error(path, " is ", type_name(*type), ", not a string");
        }
        return type->get<std::string>();
    }

    void read_feature(const json &feature, int64_t index, std::string &path) {
        const std::string type = type_of(feature, path, "a Feature object");
        if (type != "Feature") format_error(path, " has type \"", type, "\", not \"Feature\"");
        const json *properties = member(feature, "properties");
        if (properties && !properties->is_null() && !properties->is_object()) {
            PathScope scope(path, field(path, "properties"));
            format_error(path, " is ", type_name(*properties), ", not an object or null");
        }
        if (properties && properties->is_null()) properties = nullptr;
        const json *geometry = member(feature, "geometry");
        if (!geometry) format_error(path, " has no \"geometry\" member (null if it has none)");
        if (geometry->is_null()) return;  // an unlocated feature: nothing to add

        Attributes attributes;
        attributes.kind = kind_of(properties, path);
        attributes.id = id_of(feature, properties, index, path);
        if (const json *closed = properties ? member(*properties, "closed") : nullptr) {
            if (closed->is_boolean()) {
                attributes.closed = closed->get<bool>() ? 1 : 0;
            } else if (!closed->is_null()) {
                PathScope scope(path, field(path, "properties.closed"));
                input_error(path, " = ", shown(*closed), " is not true or false");
            }
        }
        PathScope scope(path, field(path, "geometry"));
        read_geometry(*geometry, type_of(*geometry, path, "a geometry object"), attributes, path, 0);
    }

    int32_t kind_of(const json *properties, const std::string &path) const {
        const std::string &name = options_.kind_property;
        const json *value = properties ? member(*properties, name) : nullptr;
        std::string text;
        if (value && !value->is_null()) {
            if (value_text(*value, text)) {
                Kind kind;
                if (options_.kind_values.empty()) {
                    if (features::kind_from_name(text, kind)) return static_cast<int32_t>(kind);
                } else {
                    for (const auto &entry : options_.kind_values)
                        if (entry.first == text) return static_cast<int32_t>(entry.second);
                }
            }
            if (options_.default_kind != 0) return options_.default_kind;
            input_error(path + field(path, "properties.") + name, " = ", shown(*value),
                        " is not a known feature kind (",
                        options_.kind_values.empty()
                            ? "coastline, lake, river, watershed, other or passage"
                            : "not in the caller's table of values",
                        ") and no default kind was given");
        }
        if (options_.default_kind != 0) return options_.default_kind;
        input_error(path, properties ? " has no property \"" : " has no properties, so no \"", name,
                    "\" to give its feature kind, and no default kind was given");
    }

    int32_t id_of(const json &feature, const json *properties, int64_t index,
                  std::string &path) const {
        int32_t id = 0;
        if (!options_.id_property.empty() && properties) {
            if (const json *value = member(*properties, options_.id_property)) {
                if (!value->is_null()) {
                    if (!int32_value(*value, id)) {
                        PathScope scope(path, field(path, "properties.") + options_.id_property);
                        input_error(path, " = ", shown(*value), " is not an integer within int32");
                    }
                    return id;
                }
            }
        }
        if (const json *value = member(feature, "id")) {
            if (value->is_number()) {
                if (!int32_value(*value, id)) {
                    PathScope scope(path, field(path, "id"));
                    input_error(path, " = ", shown(*value), " is not an integer within int32");
                }
                return id;
            }
        }
        if (index > std::numeric_limits<int32_t>::max())
            fail(UM_ERR_LIMIT, source_, ": feature index ", index, " does not fit an int32 part id");
        return static_cast<int32_t>(index);
    }

    // The "coordinates" array of a geometry.
    const json &coordinates_of(const json &geometry, const std::string &type,
                               std::string &path) const {
        const json *coordinates = member(geometry, "coordinates");
        if (!coordinates) format_error(path, " is a ", type, " with no \"coordinates\"");
        if (!coordinates->is_array()) {
            PathScope scope(path, field(path, "coordinates"));
            format_error(path, " is ", type_name(*coordinates), ", not an array");
        }
        return *coordinates;
    }

    void read_geometry(const json &geometry, const std::string &type, const Attributes &attributes,
                       std::string &path, int depth) {
        if (type == "LineString") {
            const json &c = coordinates_of(geometry, type, path);
            PathScope scope(path, field(path, "coordinates"));
            read_line(c, false, attributes, path);
        } else if (type == "MultiLineString" || type == "Polygon") {
            const json &c = coordinates_of(geometry, type, path);
            PathScope scope(path, field(path, "coordinates"));
            const size_t exterior = kind_.size();
            for (size_t k = 0; k < c.size(); ++k) {
                PathScope line(path, concat("[", k, "]"));
                read_line(c[k], type == "Polygon", attributes, path);
                if (type == "Polygon" && k > 0) require_inside(exterior, path);
            }
        } else if (type == "MultiPolygon") {
            const json &c = coordinates_of(geometry, type, path);
            PathScope scope(path, field(path, "coordinates"));
            for (size_t k = 0; k < c.size(); ++k) {
                PathScope polygon(path, concat("[", k, "]"));
                if (!c[k].is_array())
                    format_error(path, " is ", type_name(c[k]), ", not an array of rings");
                const size_t exterior = kind_.size();
                for (size_t r = 0; r < c[k].size(); ++r) {
                    PathScope ring(path, concat("[", r, "]"));
                    read_line(c[k][r], true, attributes, path);
                    if (r > 0) require_inside(exterior, path);
                }
            }
        } else if (type == "GeometryCollection") {
            if (depth >= kMaxCollectionDepth)
                format_error(path, " nests GeometryCollections more than ", kMaxCollectionDepth,
                             " deep");
            const json *members = member(geometry, "geometries");
            PathScope scope(path, field(path, "geometries"));
            if (!members) format_error(path, " is missing (a GeometryCollection needs it)");
            if (!members->is_array())
                format_error(path, " is ", type_name(*members), ", not an array of geometries");
            for (size_t k = 0; k < members->size(); ++k) {
                PathScope item(path, concat("[", k, "]"));
                const json &g = (*members)[k];
                read_geometry(g, type_of(g, path, "a geometry object"), attributes, path,
                              depth + 1);
            }
        } else if (type == "Point") {
            // A part of one point: the network refuses it unless it is a passage.
            const json &c = coordinates_of(geometry, type, path);
            PathScope scope(path, field(path, "coordinates"));
            read_point(c, attributes, path);
        } else if (type == "MultiPoint") {
            const json &c = coordinates_of(geometry, type, path);
            PathScope scope(path, field(path, "coordinates"));
            for (size_t k = 0; k < c.size(); ++k) {
                PathScope point(path, concat("[", k, "]"));
                read_point(c[k], attributes, path);
            }
        } else {
            format_error(path, " has type \"", type, "\", which is not a GeoJSON geometry");
        }
    }

    // One array of positions -> one part (a ring of a polygon is closed).
    void read_line(const json &positions, bool ring, const Attributes &attributes,
                   std::string &path) {
        if (!positions.is_array())
            format_error(path, " is ", type_name(positions), ", not an array of positions");
        const size_t n = positions.size();
        for (size_t i = 0; i < n; ++i) {
            PathScope scope(path, concat("[", i, "]"));
            read_position(positions[i], path);
        }
        if (ring && attributes.kind == static_cast<int32_t>(features::Kind::domain)) require_closed(n, path);
        int32_t closed = ring ? 1 : attributes.closed;
        if (closed < 0) closed = ends_where_it_starts(n) ? 1 : 0;
        end_part(closed, attributes, path);
    }

    // Whether the last n positions read are at least 2 and end where they start.
    bool ends_where_it_starts(size_t n) const {
        if (n < 2) return false;
        const size_t a = lon_.size() - n, b = lon_.size() - 1;
        return features::same_point(lon_[a], lat_[a], geom::unit_from_lonlat_deg(lon_[a], lat_[a]), lon_[b], lat_[b],
                                    geom::unit_from_lonlat_deg(lon_[b], lat_[b]));
    }

    // One position -> a part of one point (the network refuses it unless it
    // is an open passage: "closed": true is passed on, to be refused).
    void read_point(const json &position, const Attributes &attributes, std::string &path) {
        read_position(position, path);
        end_part(attributes.closed == 1 ? 1 : 0, attributes, path);
    }

    void read_position(const json &p, std::string &path) {
        if (!p.is_array())
            format_error(path, " is ", type_name(p), ", not a position [lon, lat]");
        if (p.size() < 2)
            format_error(path, " has ", p.size(), " number", p.size() == 1 ? "" : "s",
                         "; a position needs at least 2 (lon, lat)");
        for (size_t k = 0; k < 2; ++k)
            if (!p[k].is_number()) {
                PathScope scope(path, concat("[", k, "]"));
                format_error(path, " is ", type_name(p[k]), ", not a number");
            }
        lon_.push_back(p[0].get<double>());
        lat_.push_back(p[1].get<double>());
    }

    // A domain polygon's ring (the n positions just read, at `path`) ends
    // where it starts, as GeoJSON draws rings: a ring given open may have
    // lost its end, and a domain is the region its ring bounds. (Rings of
    // other kinds are closed as given: a coastline polygon's land is the same
    // either way.) Rings too short to be rings are the network's to refuse.
    void require_closed(size_t n, const std::string &path) const {
        if (n < 2 || ends_where_it_starts(n)) return;
        const size_t a = lon_.size() - n, b = lon_.size() - 1;
        input_error(path, " is a domain ring but is open: its last position [", lon_[b], ", ", lat_[b],
                    "] is not its first [", lon_[a], ", ", lat_[a], "] (a GeoJSON ring repeats its first position)");
    }

    // A domain polygon's hole (the part just read, at `path`) lies inside
    // its exterior ring (part `exterior`): else it would be a region of its
    // own by the parity rule, which the GeoJSON polygon does not mean. Its
    // first point is tested, in longitude and latitude as the rings are
    // drawn (rings crossing each other are refused later). Not tested: an
    // exterior round a pole (it encloses nothing there) or through one (its
    // edges there run along meridians, features/domain.hpp), and rings too
    // short to be rings or with a point out of range (the network refuses
    // them, naming the point).
    void require_inside(size_t exterior, const std::string &path) const {
        const size_t hole = kind_.size() - 1;
        if (kind_[hole] != static_cast<int32_t>(features::Kind::domain)) return;
        const int64_t first = offsets_[exterior], n = offsets_[exterior + 1] - first;
        if (n < 3 || offsets_[hole + 1] == offsets_[hole]) return;
        for (int64_t k = first; k < first + n; ++k)
            if (!(std::fabs(lat_[k]) < 90) || !std::isfinite(lon_[k])) return;
        const double x = lon_[offsets_[hole]], y = lat_[offsets_[hole]];
        if (!(std::fabs(y) <= 90) || !std::isfinite(x)) return;
        const features::LonLatRing ring(&lon_[first], &lat_[first], n);
        if (ring.round_a_pole() || ring.encloses(x, y)) return;
        input_error(path, " is a hole of the polygon but lies outside its exterior ring, ", shown_path(part_path_[exterior]));
    }

    void end_part(int32_t closed, const Attributes &attributes, const std::string &path) {
        offsets_.push_back(static_cast<int64_t>(lon_.size()));
        closed_.push_back(closed);
        kind_.push_back(attributes.kind);
        id_.push_back(attributes.id);
        part_path_.push_back(path);
    }

    const GeojsonOptions &options_;
    const std::string &source_;
    std::vector<double> lon_, lat_;
    std::vector<int64_t> offsets_;
    std::vector<int32_t> closed_, kind_, id_;
    std::vector<std::string> part_path_;
};

// nlohmann's message without its "[json.exception.<name>.<id>] " tag and
// "parse error at line L, column C: " prefix (we give the position ourselves).
std::string parse_detail(const char *what) {
    std::string s(what);
    if (s.rfind("[json.exception.", 0) == 0) {
        size_t end = s.find("] ");
        if (end != std::string::npos) s.erase(0, end + 2);
    }
    if (s.rfind("parse error at line ", 0) == 0) {
        size_t colon = s.find(": ", s.find("column "));
        if (colon != std::string::npos) s.erase(0, colon + 2);
    }
    return s;
}

// "byte B (line L, column C)" of a 0-based offset into the text.
std::string text_position(std::string_view text, size_t position) {
    int64_t line = 1, column = 1;
    for (size_t i = 0; i < position && i < text.size(); ++i) {
        if (text[i] == '\n') ++line, column = 1;
        else ++column;
    }
    return concat("byte ", position, " (line ", line, ", column ", column, ")");
}

json parse_document(std::string_view text, const std::string &source) {
    try {
        return json::parse(text.data(), text.data() + text.size());
    } catch (const json::parse_error &e) {
        // e.byte counts from 1 and points at the character that did not fit.
        const size_t position = e.byte > 0 ? static_cast<size_t>(e.byte) - 1 : 0;
        if (position >= text.size())
            fail(UM_ERR_FILE_FORMAT, source, ": malformed JSON: the text ends at byte ",
                 text.size(), " before the JSON value is complete (truncated file?): ",
                 parse_detail(e.what()));
        fail(UM_ERR_FILE_FORMAT, source, ": malformed JSON at ", text_position(text, position),
             ": ", parse_detail(e.what()));
    } catch (const json::exception &e) {
        // Number overflow (e.g. 1e400) comes without a position; the number
        // is quoted in the message, so point at its first occurrence.
        std::string detail = parse_detail(e.what()), where;
        size_t open = detail.find('\''), close = detail.rfind('\'');
        if (open != std::string::npos && close > open + 1) {
            size_t at = text.find(std::string_view(detail).substr(open + 1, close - open - 1));
            if (at != std::string_view::npos) where = " (first found at " + text_position(text, at) + ")";
        }
        fail(UM_ERR_FILE_FORMAT, source, ": malformed JSON: ", detail, where);
    }
}

}  // namespace

int64_t read_geojson_text(std::string_view text, const GeojsonOptions &options,
                          features::Network &network, const std::string &source) {
    Reader reader(options, source);
    try {
        json doc = parse_document(text, source);
        reader.read_document(doc);
    } catch (const json::exception &e) {
        // Not expected (every access is checked first), but nothing of the
        // parser's own exception types may leave the library.
        fail(UM_ERR_FILE_FORMAT, source, ": unexpected JSON structure: ", e.what());
    }
    return reader.commit(network);
}

int64_t read_geojson_file(const std::string &path, const GeojsonOptions &options,
                          features::Network &network, const Context *context) {
    return read_geojson_text(read_whole_file(path, context), options, network, path);
}

}  // namespace um::io
