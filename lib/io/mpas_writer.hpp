// The MPAS mesh file (shared/mpas-format.md section 1): netCDF classic
// 64-bit offset (CDF-5 when a variable is larger than that format allows),
// int32 connectivity 1-based with 0 padding, double reals, the global
// attributes of MpasMeshConverter.x, and the unified tags (cellSide,
// vertexSide) when the mesh has them. netCDF writes the header; a classic
// file's values are written at the offsets that header gives them (netCDF
// would read each region back first), around the page cache for a large
// file; a netCDF-4 file's through netCDF.
#pragma once

#include <cstdint>
#include <string>

#include "core/context.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/mpas_source.hpp"

namespace um::io {

// The largest fixed-size variable a netCDF 64-bit offset file can hold.
constexpr uint64_t kOffset64VariableLimit = (uint64_t(1) << 32) - 4;

// The container: netCDF classic 64-bit offset, or CDF-5 when a variable is
// larger than variable_limit (automatic), or netCDF-4 (HDF5) on request.
enum class MpasFileFormat { automatic, netcdf4 };

struct MpasWriteOptions {
    MpasFileFormat format = MpasFileFormat::automatic;
    // A parameter so that tests can reach the CDF-5 branch with small meshes.
    uint64_t variable_limit = kOffset64VariableLimit;
    // Rows per block of the streamed writer (tests cut small meshes into many).
    int64_t block_rows = dual::kMpasBlockRows;
    // A classic file with at least this many bytes of values is written
    // around the page cache where the file system allows (io/direct_regions.hpp);
    // a smaller one gains nothing from it and would wait on each write.
    uint64_t direct_min_bytes = uint64_t(256) << 20;
};

// Writes m to path (created or overwritten; netCDF calls under the
// process-wide netCDF lock). The bytes depend only on m and the options:
// file_id is a hash of its content, no clock, no randomness. Throws
// UM_ERR_IO naming the file; a partly written file is removed.
void write_mpas_mesh(const dual::MpasMesh &m, const std::string &path, const MpasWriteOptions &options = {});

// The same file streamed from source a block of rows at a time (the whole
// staggered mesh is never held), reporting progress on ctx between blocks
// (a cancel there removes the partial file). Identical bytes to writing
// the mesh build_mpas_mesh makes from the same input, for any thread count.
void write_mpas_mesh(Context &ctx, const dual::MpasSource &source, const std::string &path,
                     const MpasWriteOptions &options = {});

// The file_id attribute: 10 characters [0-9a-z] from a hash of every array
// and the radius of m.
std::string mpas_file_id(const dual::MpasMesh &m);

}  // namespace um::io
