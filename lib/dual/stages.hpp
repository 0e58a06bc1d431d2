// The stages of build_mpas_mesh after the numbering and the connectivity
// (mpas_mesh.cpp): geometry (geometry.cpp) and TRSK weights (trsk.cpp).
// Internal to lib/dual.
#pragma once

#include <vector>

#include "core/context.hpp"
#include "dual/mpas_mesh.hpp"

namespace um::dual {

using geom::Vec3;

// Unit vectors of the cells (generators), edges (edge orthocentres) and
// vertices (orthocentres), in the MPAS numbering.
struct UnitPositions {
    std::vector<Vec3> cell, edge, vertex;
};

// Moves each edge point (xEdge) onto the crossing of its primal and dual
// great circles (arc_crossing), from the connectivity and the cell and
// vertex positions: so that a cell's kites add up to its polygon.
void cross_edge_points(Context &ctx, UnitPositions &pos, const MpasMesh &m);

// Fills positions, lat/lon, dcEdge, dvEdge, angleEdge, areaCell,
// areaTriangle and kiteAreasOnVertex from the connectivity and the unit
// positions, scaled by m.radius_m.
void fill_geometry(Context &ctx, const UnitPositions &pos, MpasMesh &m);

// Fills nEdgesOnEdge, edgesOnEdge and weightsOnEdge from the connectivity,
// areas, kites and lengths already in m.
void fill_trsk_weights(Context &ctx, MpasMesh &m);

}  // namespace um::dual
