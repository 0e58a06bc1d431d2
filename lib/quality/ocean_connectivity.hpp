// Whether the ocean mesh connects what the coastlines connect: its regions
// (cells joined by edges), the bodies of water they belong to, and where the
// mesh closed a passage between two regions of one body (issue "A time-step
// floor": a channel the floor removes must not close silently).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geom/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::quality {

struct OceanConnectivity {
    // A connected region of the ocean mesh: its cells and the position
    // (degrees) of its cell of the lowest slot.
    struct Region {
        int64_t cells;
        double lon, lat;
    };
    // Largest first (ties: lowest slot first).
    std::vector<Region> regions;
    // The bodies of water the regions belong to. A closed coastline ring has
    // one ocean side, so the regions that touch one ring are in one body of
    // water of the input; a region that touches no ring is a body of its own.
    int64_t water_bodies = 0;
    // Per region more than its body has, where the mesh closed the passage:
    // the middle of the way between it and the rest of its body through the
    // fewest cells not in the ocean mesh that no coastline passes through
    // (dry land), then the fewest that one does (where the cells hide water
    // they do not resolve); land_cells counts both. Thinnest first.
    struct ClosedPassage {
        double lon, lat;
        int64_t land_cells;
    };
    std::vector<ClosedPassage> closed_passages;
};

// ocean_cell: per vertex slot, non-zero when its cell is in the ocean mesh.
// contacts: (vertex slot, ring) pairs, each a cell that a closed coastline
// ring (any id) passes through or along. Deterministic; serial, O(cells).
// The places are the geodetic lon/lat of the surface's points.
OceanConnectivity ocean_connectivity(const tri::Triangulation &tri, const std::vector<uint8_t> &ocean_cell,
                                     const std::vector<std::pair<int32_t, int32_t>> &contacts,
                                     const geom::Surface &surface = geom::Surface::sphere(1.0));

}  // namespace um::quality
