// The rows of the staggered mesh, computed from its layout a block at a time
// (mpas_source.cpp puts them together with the tags): geometry.cpp for the
// connectivity, positions, lengths, angles and areas, trsk.cpp for the TRSK
// stencils. Each fills rows [first, first + count) of its element kind into
// block's arrays, resized to `count` rows. Rows and the indices in them are
// the layout's rows (a regional mesh's region: mpas_layout.hpp).
// Internal to lib/dual.
#pragma once

#include <cstdint>

#include "core/context.hpp"
#include "dual/corner_kites.hpp"
#include "dual/mpas_layout.hpp"
#include "dual/mpas_mesh.hpp"

namespace um::dual {

// xCell..lonCell, nEdgesOnCell, edgesOnCell, verticesOnCell, cellsOnCell,
// and areaCell unless !areas (then left as it is).
void cell_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
               MpasMesh &block, bool areas = true);

// xVertex..lonVertex, cellsOnVertex, edgesOnVertex, boundaryVertex, and
// areaTriangle and kiteAreasOnVertex from `kites` unless it is null (then
// left as they are).
void vertex_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
                 MpasMesh &block, const CornerKites *kites);

// xEdge..lonEdge, cellsOnEdge, verticesOnEdge, dcEdge, dvEdge, angleEdge.
void edge_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
               MpasMesh &block);

// nEdgesOnEdge, edgesOnEdge, weightsOnEdge of the rows edge_rows filled
// (it reads their cellsOnEdge and dcEdge), the weights from `kites`.
// Without them (null), only the first two (from the rings alone: no
// geometry); weightsOnEdge is then not meaningful.
void trsk_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
               MpasMesh &block, const CornerKites *kites);

// nEdgesOnEdge, edgesOnEdge and weightsOnEdge of a whole mesh in memory from
// its connectivity, dvEdge, dcEdge and kites (a cut mesh: lib/components).
void fill_trsk_weights(Context &ctx, MpasMesh &m);

}  // namespace um::dual
