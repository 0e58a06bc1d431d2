// `unimesh components MESH.nc --out DIR`: the component meshes and coupler
// grids of an existing unified MPAS mesh (um_mpas_file_write_components),
// published into DIR as one set (output_set.hpp); and what `unimesh build
// --components` shares with it.
#pragma once

#include <string>
#include <vector>

// The files of the component set beside mesh.nc (a contract: scripts call
// these names).
extern const std::vector<std::string> kComponentFiles;

// One line on stdout from a written rivers.json: networks, cells routed to
// an outlet, cells in networks that reach no coast, cycles.
void print_river_summary(const std::string &rivers_json);

// 0 when every file was written; one-line errors on stderr.
int run_components(const std::string &mesh_path, const std::string &out_dir);
