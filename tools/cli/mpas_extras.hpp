// Files derived from a written MPAS mesh: graph.info (METIS adjacency, the
// input of gpmetis for MPAS decompositions) and mesh.vtu (the cells as
// polygons, for ParaView) and triangles.vtu (the triangulation of the
// generators, one triangle per MPAS vertex). All are read back from
// mesh.nc, so their numbering is the file's.
#pragma once

#include <string>

bool write_graph_info(const std::string &mesh_nc, const std::string &path, std::string *error);
bool write_cells_vtu(const std::string &mesh_nc, const std::string &path, std::string *error);
bool write_triangles_vtu(const std::string &mesh_nc, const std::string &path, std::string *error);
