// JIGSAW's .msh format (MSHID=3, EUCLIDEAN-MESH) for interchange with the
// JIGSAW tools: the generators as 3-D points on the sphere of the mesh's
// radius (m), their power weights (m^2) and the triangles (0-based, counter-
// clockwise seen from outside).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace um::mesh {
struct RefinedMesh;
}

namespace um::io {

// Writes path (created or overwritten); UM_ERR_IO naming the file, and a
// partly written file is removed. With `cells` (per vertex slot, a regional
// mesh's RefinedMesh::region_cells) only those generators, numbered in the
// mesh's vertex order without the others, and the triangles of three of
// them: the domain's triangulation, without the cover around it.
void write_jigsaw_mesh(const mesh::RefinedMesh &m, const std::string &path,
                       const std::vector<uint8_t> *cells = nullptr);

}  // namespace um::io
