// Reads an MPAS mesh file (shared/mpas-format.md; ours, or any with the
// contract's variables) back into an MpasMesh: every variable of the mesh
// contract, and the unified tags (cellSide, vertexSide, the cell masks, the
// edge features, the river routing) where the file has them; the maps of an
// earlier split are left out (a new split makes its own). Every count and
// index is checked before use, so a damaged or hostile file gets an error,
// never a read outside the arrays.
#pragma once

#include <string>

#include "core/context.hpp"
#include "dual/mpas_mesh.hpp"

namespace um::io {

// Throws UM_ERR_IO (cannot open), UM_ERR_FILE_FORMAT (naming the file and
// the dimension, variable or value that is wrong), UM_ERR_LIMIT (counts
// beyond int32) or the context's UM_ERR_MEMORY_CAP (from the dimensions,
// before any array is read).
dual::MpasMesh read_mpas_mesh(Context &ctx, const std::string &path);

}  // namespace um::io
