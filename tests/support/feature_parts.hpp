// Engine tests' parts of a features network in the caller's terms, added
// through features::Network::add (test_features, test_regional).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "features/network.hpp"

namespace um::testing {

// One part for a batch, in the caller's terms.
struct LinePart {
    std::vector<double> lon, lat;
    int32_t closed = 0;
    int32_t kind = UM_FEATURE_OTHER;
    int32_t id = 0;
};

// Adds the parts through Network::add; returns the status (UM_OK or the
// thrown one) and the message.
inline um_status add(features::Network &net, const std::vector<LinePart> &parts, std::string *message = nullptr,
                     bool with_ids = true) {
    std::vector<double> lon, lat;
    std::vector<int64_t> offsets{0};
    std::vector<int32_t> closed, kind, id;
    for (const auto &p : parts) {
        lon.insert(lon.end(), p.lon.begin(), p.lon.end());
        lat.insert(lat.end(), p.lat.begin(), p.lat.end());
        offsets.push_back(static_cast<int64_t>(lon.size()));
        closed.push_back(p.closed), kind.push_back(p.kind), id.push_back(p.id);
    }
    features::PartsInput in;
    in.n_points = static_cast<int64_t>(lon.size());
    in.lon_deg = lon.data(), in.lat_deg = lat.data();
    in.n_parts = static_cast<int64_t>(parts.size());
    in.part_offsets = offsets.data();
    in.closed = closed.data(), in.kind = kind.data();
    in.part_id = with_ids ? id.data() : nullptr;
    try {
        net.add(in);
    } catch (const Error &e) {
        if (message) *message = e.what();
        return e.status();
    }
    return UM_OK;
}

}  // namespace um::testing
