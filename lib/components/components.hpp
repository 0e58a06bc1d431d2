// One unified base mesh, every component's files (DESIGN.md's output
// contract): the ocean mesh and the land mesh (land and river cells) cut out
// of the base along its cell masks, each a valid MPAS mesh with a boundary
// and the maps back to the base; the base carries the maps forward. Every
// base cell is in exactly one component (cellOceanMask = 1 - cellLandMask).
#pragma once

#include <functional>
#include <string>

#include "core/context.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/river_routing.hpp"

namespace um::components {

struct ComponentMeshes {
    dual::MpasMesh ocean, land;
};

// Cuts base into its components and fills base's forward maps. Throws
// UM_ERR_INVALID_ARGUMENT when base has no cell masks (a mesh made without
// closed coastlines) or when a component would have no cells.
ComponentMeshes split_components(Context &ctx, dual::MpasMesh &base);

// Throws UM_ERR_IO naming directory unless it is an existing directory.
void require_directory(const std::string &directory);

// Routes the rivers of base (river_routing.hpp), splits it and writes, into
// directory (which must exist): mesh.nc (the base with the forward maps),
// ocean.nc, land.nc, ocean.graph.info, land.graph.info, mesh.scrip.nc,
// ocean.scrip.nc, land.scrip.nc, mesh.esmf.nc, ocean.esmf.nc, land.esmf.nc
// and rivers.json (river_report_json). The files are written into a
// directory of their own inside `directory` and renamed into it together
// when all are complete. Throws um::Error (UM_ERR_IO naming the file).
dual::RiverReport write_component_files(Context &ctx, dual::MpasMesh &base, const std::string &directory);

// The river report as JSON: counts, and the networks that reach no coast or
// hold cycles, each with its cell count and one cell (1-based base cell id,
// latitude and longitude in degrees) to find it by.
// cell_lat_lon(c, lat, lon): base cell c's latCell and lonCell (radians).
using CellLatLon = std::function<void(int32_t, double &, double &)>;
std::string river_report_json(const dual::RiverReport &report, const CellLatLon &cell_lat_lon);
std::string river_report_json(const dual::RiverReport &report, const dual::MpasMesh &base);

}  // namespace um::components
