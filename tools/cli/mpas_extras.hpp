// Files derived from a written MPAS mesh: graph.info (METIS adjacency, the
// input of gpmetis for MPAS decompositions) and mesh.vtu (the cells as
// polygons, for ParaView). Both are read back from mesh.nc, so their cell
// numbering is the file's.
#pragma once

#include <string>

bool write_graph_info(const std::string &mesh_nc, const std::string &path, std::string *error);
bool write_cells_vtu(const std::string &mesh_nc, const std::string &path, std::string *error);
