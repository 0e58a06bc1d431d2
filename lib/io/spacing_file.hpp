// The spacing file of the MPAS mesh tools (what mpas_tools' jigsaw driver
// reads): netCDF with 1-D `lon` (degrees), 1-D `lat` (degrees) and
// `cellWidth(lat, lon)` (km), read into a GridSpacing (hfun/grid.hpp).
//
// Any numeric netCDF type is accepted. A `units` attribute, when present,
// must say km on cellWidth and must not say radians on lon/lat, and no cell
// may hold cellWidth's fill value (unwritten data), so that a file in other
// units or with holes is an error rather than a wrong mesh.
//
// Errors (um::Error; the message names the file and the variable):
//   UM_ERR_IO           the file cannot be opened (missing, unreadable)
//   UM_ERR_FILE_FORMAT  not netCDF, truncated, a variable missing, of the
//                       wrong shape or type, or values a grid rejects
//                       (descending or duplicate coordinates, NaN, <= 0, ...)
//   UM_ERR_MEMORY_CAP   the grid exceeds the context's memory cap
//   UM_ERR_LIMIT        the grid has more than 2^40 cells
#pragma once

#include <memory>
#include <string>

#include "core/context.hpp"
#include "hfun/grid.hpp"

namespace um::io {

std::shared_ptr<const hfun::GridSpacing> read_spacing_file(const std::string &path,
                                                           const Context &ctx);

}  // namespace um::io
