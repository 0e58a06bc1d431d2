// The limited-area boundary layers of a regional mesh, as MPAS reads them
// (bdyMaskCell, bdyMaskEdge, bdyMaskVertex; MPAS-Atmosphere takes 1-5 as
// its relaxation zone and 6-7 as its specified zone): a cell with a
// neighbour missing is kBoundaryLayers, its other neighbours one less, and
// so on down to 1; the rest 0. Edges and vertices take their cells' least.
// Internal to lib/dual.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "dual/mpas_layout.hpp"

namespace um::dual {

// The layers of bdyMaskCell: the boundary is layer kBoundaryLayers.
constexpr int32_t kBoundaryLayers = 7;

// The layer of each cell row of a regional layout (empty for a whole one).
std::vector<int8_t> cell_boundary_layers(Context &ctx, const MpasLayout &layout);

// The least layer of the cells given that are rows (kNone: missing).
inline int32_t least_boundary_layer(const int32_t *cells, int n, const std::vector<int8_t> &layer) {
    int32_t least = kBoundaryLayers;
    for (int j = 0; j < n; ++j)
        if (cells[j] != kNone && layer[cells[j]] < least) least = layer[cells[j]];
    return least;
}

}  // namespace um::dual
