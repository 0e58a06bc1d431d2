// GeoJSON (RFC 7946 structure; coordinates [lon, lat] in degrees) into a
// polyarc network. Accepted at the top level: a FeatureCollection, a Feature
// or a bare geometry. LineString -> one part, MultiLineString -> one part per
// line, Polygon -> one closed part per ring (outer and holes), MultiPolygon
// -> the rings of every polygon, GeometryCollection -> its members (nested up
// to 32 deep). Features with a null geometry add nothing; Point and
// MultiPoint are rejected (they are not lines). Positions may carry a third
// number (ignored). Edges are the short great-circle arcs (lines across the
// antimeridian are kept whole), see features/network.hpp.
//
// Per feature (all parts of its geometry share these):
//   kind    the value of a property (default "kind"): by default one of the
//           names "coastline", "lake", "river", "watershed", "other" (ASCII
//           case-insensitive); or looked up in a caller's table, where numbers
//           and booleans are matched by their text ("1", "true"). A missing,
//           null or unmapped value takes the default kind, or is an error
//           (UM_ERR_INPUT) when there is none.
//   closed  Polygon rings are always closed. Otherwise the boolean property
//           "closed" when present, else whether the first and last positions
//           are the same point. A closed line given with first == last
//           stores that point once.
//   id      the integer property the caller names (when set and present),
//           else the feature's "id" member when it is a number, else the
//           feature's index in the collection (0 for a lone Feature or
//           geometry). Ids must fit in int32; a string "id" is a name and
//           falls back to the index.
//
// Errors (um::Error; on any error the network is unchanged):
//   UM_ERR_IO           the file cannot be opened or read
//   UM_ERR_FILE_FORMAT  malformed or truncated JSON (with the byte position,
//                       line and column), or valid JSON of the wrong structure
//                       (missing or non-array "coordinates", a position that is
//                       not an array of at least 2 numbers, unknown "type"),
//                       named by a path such as features[12].geometry.coordinates[3][5]
//   UM_ERR_INPUT        unmapped kinds with no default, ids outside int32,
//                       a "closed" property that is not a boolean
//   and the data errors of Network::add (latitudes beyond 90, lines with
//   fewer than 2 distinct points, antipodal consecutive points), named the
//   same way.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "features/network.hpp"

namespace um {
class Context;
}

namespace um::io {

struct GeojsonOptions {
    std::string kind_property = "kind";
    // Property value (as text) -> kind; empty: the standard kind names.
    std::vector<std::pair<std::string, features::Kind>> kind_values;
    // Kind for a missing or unmapped value; 0 = such a feature is an error.
    int32_t default_kind = 0;
    // Integer property holding the part id; empty: the "id" member, else the index.
    std::string id_property;
};

// Reads a file and appends its lines to `network`; returns the number of
// parts added. With a context, the parse's memory estimate is checked
// against the context's memory cap first.
int64_t read_geojson_file(const std::string &path, const GeojsonOptions &options,
                          features::Network &network, const Context *context = nullptr);

// The same from text in memory; `source` names it in messages.
int64_t read_geojson_text(std::string_view text, const GeojsonOptions &options,
                          features::Network &network, const std::string &source = "GeoJSON text");

}  // namespace um::io
