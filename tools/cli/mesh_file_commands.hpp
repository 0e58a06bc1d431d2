// `unimesh check MESH.nc` and `unimesh quality MESH.nc`: an MPAS mesh file
// read back and judged on its own, whoever wrote it.
//   check    the invariants of the MPAS mesh contract (Euler, index ranges,
//            area sums, kites, orthogonality of primal and dual arcs,
//            counter-clockwise orderings, TRSK antisymmetry); one line per
//            check, exit 0 only when all pass;
//   quality  the Figure 10 metrics of the triangles (Q^T, Q^P from xVertex
//            and xEdge, angles, well-centredness), as text or JSON.
#pragma once

#include <string>

int run_check(const std::string &mesh_nc);
int run_quality(const std::string &mesh_nc, bool json);
