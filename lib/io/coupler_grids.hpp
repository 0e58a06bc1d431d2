// The grid files couplers and remappers read, for an MPAS mesh (a whole one
// or a component): each cell a polygon of its vertices (the power cell's
// corners, counter-clockwise seen from outside), its centre the generator.
//
// SCRIP (Jones 1998; what CDO, NCO and ESMF_RegridWeightGen read):
// grid_size x grid_corners, grid_rank 1; grid_dims, grid_center_lat/lon,
// grid_corner_lat/lon (degrees; a cell with fewer corners than grid_corners
// repeats its last corner), grid_area (the cell's area, radians^2, i.e. on
// the unit sphere) and grid_imask (1).
//
// ESMF unstructured mesh (ESMF_RegridWeightGen's "ESMF" format, version 0.9):
// nodeCount, elementCount, maxNodePElement, coordDim 2; nodeCoords (the mesh
// vertices, degrees), elementConn (1-based node indices, -1 padding),
// numElementConn, centerCoords, elementArea (radians^2), elementMask (1).
//
// Both are netCDF 64-bit offset files (CDF-5 when a variable needs it),
// written under a temporary name and renamed when complete.
#pragma once

#include <string>

#include "dual/mpas_mesh.hpp"

namespace um::io {

void write_scrip_grid(const dual::MpasMesh &m, const std::string &path);
void write_esmf_mesh(const dual::MpasMesh &m, const std::string &path);

}  // namespace um::io
