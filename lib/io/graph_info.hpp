// graph.info: the cell adjacency of an MPAS mesh in METIS's graph format,
// which gpmetis partitions into the graph.info.part.N files MPAS reads. The
// first line is the number of cells and of cell pairs that share an edge;
// line i + 1 lists the 1-based cells across cell i's edges (on a cut mesh,
// the ones that are there).
#pragma once

#include <string>

#include "dual/mpas_mesh.hpp"

namespace um::io {

// Written under a temporary name and renamed when complete; throws UM_ERR_IO.
void write_graph_info(const dual::MpasMesh &m, const std::string &path);

}  // namespace um::io
