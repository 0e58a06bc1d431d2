// The MPAS mesh of a regional mesh (mesh::RefinedMesh::regional): the
// staggered mesh of its triangulation cut to the region's cells the way the
// component meshes are cut (cut_mesh.hpp: whole cells, 0 where a neighbour is
// missing), with the limited-area boundary layers MPAS reads (bdyMaskCell,
// bdyMaskEdge, bdyMaskVertex; MPAS-Atmosphere takes 1-5 as its relaxation
// zone and 6-7 as its specified zone).
#pragma once

#include "core/context.hpp"
#include "dual/mpas_mesh.hpp"
#include "mesh/refined_mesh.hpp"

namespace um::components {

// The layers of bdyMaskCell: the boundary is layer kBoundaryLayers.
constexpr int32_t kBoundaryLayers = 7;

// Throws UM_ERR_INVALID_ARGUMENT when m is not regional.
dual::MpasMesh regional_mpas_mesh(Context &ctx, const mesh::RefinedMesh &m);

// Fills m's bdyMask* arrays from its cut (kNone in cellsOnCell): a cell with
// a neighbour missing is kBoundaryLayers, its other neighbours one less, and
// so on down to 1; the rest 0. Edges and vertices take their cells' least.
void mark_boundary_layers(dual::MpasMesh &m);

}  // namespace um::components
