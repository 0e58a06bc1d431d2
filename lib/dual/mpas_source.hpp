// The MPAS staggered mesh of a triangulation as rows made on request: the
// layout (numbering and maps, about 76 bytes per cell) plus the tags, from
// which any block of cell, edge or vertex rows is computed with every
// variable of the contract. The netCDF writer streams a file from it a
// block at a time, so the whole staggered mesh (about 1.2 kB per cell) is
// never held; build_mpas_mesh (mpas_mesh.hpp) asks it for every row.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/context.hpp"
#include "dual/mpas_fields.hpp"
#include "dual/mpas_layout.hpp"
#include "dual/mpas_mesh.hpp"

namespace um::mesh {
struct RefinedMesh;
}

namespace um::dual {

// Bytes per cell a source holds (its layout, the cell widths, the tags) at
// its peak while being built, for the memory cap.
constexpr int64_t kMpasSourceBytesPerCell = 160;

class MpasSource {
public:
    // Throws um::Error as build_mpas_mesh does. Keeps references to tri and
    // to refined, which must outlive it.
    MpasSource(Context &ctx, const tri::Triangulation &tri, const MpasMeshInput &input);
    MpasSource(Context &ctx, const mesh::RefinedMesh &refined);
    ~MpasSource();

    // The whole mesh's radius, counts and maxEdges, without rows.
    MpasMesh shape() const;
    // Every variable's rows [first, first + count) of the elements along
    // `kind` (nCells, nEdges or nVertices) into block's arrays, resized to
    // `count` rows; the arrays of the other kinds are left as they are.
    // Also fills cell_source_vertex / vertex_source_triangle for the rows.
    void rows(Context &ctx, MpasDim kind, int64_t first, int64_t count, MpasMesh &block) const;

private:
    struct Tags;
    void cell_sides(int64_t first, int64_t count, MpasMesh &block) const;
    void cell_tags(int64_t first, int64_t count, MpasMesh &block) const;
    void edge_tags(int64_t first, int64_t count, MpasMesh &block) const;
    void vertex_tags(int64_t first, int64_t count, MpasMesh &block) const;

    MpasLayout layout_;
    double radius_m_;
    std::vector<double> cell_width_km_;  // per mesh vertex; empty: meshDensity 1
    double min_width_km_ = 0;
    std::unique_ptr<Tags> tags_;
};

// The rows along each kind in blocks of this many (even, so that a block of
// int32 rows is a whole number of 8-byte words for the file_id hash).
constexpr int64_t kMpasBlockRows = int64_t(1) << 17;

}  // namespace um::dual
