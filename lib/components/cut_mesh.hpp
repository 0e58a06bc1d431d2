// A component mesh cut out of an MPAS mesh (the ocean or the land of a
// unified mesh), as MPAS-Tools' cell culler makes culled meshes
// (shared/mpas-format.md section 3): the kept cells, every edge and vertex of
// theirs, numbered 0.. in the base mesh's order (so the cells' and vertices'
// lists still start at their lowest-numbered element), and 0 (kNone here)
// wherever the missing neighbour was. Unlike the culler, an edge whose first
// cell is cut off is turned around whole (cellsOnEdge, verticesOnEdge,
// angleEdge, edgeRiverDownstream), so that cellsOnEdge(1) is always a cell of
// the mesh and the normal still points from cell 1 to cell 2; the TRSK
// weights are those of the kept cells (trsk.cpp). Areas, kites and lengths
// are the base mesh's: the kept cells are whole. A regional base's
// limited-area layers (bdyMask*) go with its elements: they count from the
// domain's open boundary, which the cut does not move.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "dual/mpas_mesh.hpp"

namespace um::components {

// The mesh of the cells c of base with keep[c] != 0 (at least one), with
// base_cell, base_edge and base_vertex mapping each element to base.
dual::MpasMesh cut_mesh(Context &ctx, const dual::MpasMesh &base, const std::vector<uint8_t> &keep);

}  // namespace um::components
