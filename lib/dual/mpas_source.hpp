// The MPAS staggered mesh of a triangulation as rows made on request: the
// layout (numbering, maps and vertex positions, about 124 bytes per cell, 48
// more for a regional mesh's rows) plus the tags, from which any block of
// cell, edge or vertex rows is computed with every variable of the contract.
// The netCDF writer streams a file from it a block at a time and the C API's
// copy-out one variable at a time, so the whole staggered mesh (about 1.2 kB
// per cell) is never held for them; build_mpas_mesh (mpas_mesh.hpp, for the
// component meshes) asks it for every row.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "core/context.hpp"
#include "dual/corner_kites.hpp"
#include "dual/mpas_fields.hpp"
#include "dual/mpas_layout.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/river_routing.hpp"

namespace um::mesh {
struct RefinedMesh;
}

namespace um::dual {

// Bytes per cell a source holds (its layout, the cell widths, the tags, the
// kites) at its peak, for the memory cap: the river routing of a mesh with
// features needs the whole river graph while it runs, before the kites are
// made.
constexpr int64_t kMpasSourceBytesPerCell = 208 + CornerKites::kBytesPerCell,
                  kMpasSourceWithFeaturesBytesPerCell = 328;
// An ellipsoid mesh's layout also holds a copy of the triangulation
// (MpasLayout): its points, ids and two triangles per cell.
constexpr int64_t kMpasEllipsoidCopyBytesPerCell = 100;

class MpasSource {
public:
    // Throws um::Error as build_mpas_mesh does. Keeps references to tri and
    // to refined, which must outlive it.
    MpasSource(Context &ctx, const tri::Triangulation &tri, MpasMeshInput input);
    MpasSource(Context &ctx, const mesh::RefinedMesh &refined);
    ~MpasSource();

    // The mesh's radius, counts and maxEdges, without rows (a regional
    // mesh's: its region's).
    MpasMesh shape() const;
    // shape() with one row of every kind: every variable this mesh has (the
    // tags only when known), for a file's or a copy-out's list of them.
    MpasMesh probe(Context &ctx) const;
    // Every variable's rows [first, first + count) of the elements along
    // `kind` (nCells, nEdges or nVertices) into block's arrays, resized to
    // `count` rows; the arrays of the other kinds are left as they are.
    // Also fills cell_source_vertex / vertex_source_triangle for the rows.
    // With `only` (a variable's name), the rows need hold that variable
    // only: what no other needs is then not made (the TRSK stencils of the
    // edges, the costly part, unless it is one of them).
    void rows(Context &ctx, MpasDim kind, int64_t first, int64_t count, MpasMesh &block,
              const char *only = nullptr) const;
    // The river report of the routing (all zero without features).
    RiverReport river_report() const;
    // Cell c's latitude and longitude (radians), as latCell and lonCell;
    // c in the whole triangulation's numbering (the river report's).
    void cell_lat_lon(int32_t c, double &lat, double &lon) const;

private:
    struct Tags;
    void cell_sides(int64_t first, int64_t count, MpasMesh &block, bool whole = false) const;
    void cell_tags(int64_t first, int64_t count, MpasMesh &block) const;
    void edge_tags(int64_t first, int64_t count, MpasMesh &block) const;
    void vertex_tags(int64_t first, int64_t count, MpasMesh &block) const;
    void boundary_masks(MpasDim kind, int64_t first, int64_t count, MpasMesh &block) const;

    // The kites, made on the first call that needs them (rows of vertices
    // with areas, or of edges with weights) and kept.
    const CornerKites &kites(Context &ctx) const;

    MpasLayout layout_;
    double radius_m_;
    geom::Surface surface_;
    std::vector<double> cell_width_km_;  // per mesh vertex; empty: meshDensity 1
    double min_width_km_ = 0;
    std::vector<int8_t> boundary_layer_;  // per cell row of a regional mesh
    std::unique_ptr<Tags> tags_;
    mutable std::once_flag kites_made_;
    mutable std::unique_ptr<CornerKites> kites_;
};

// The rows along each kind in blocks of this many.
constexpr int64_t kMpasBlockRows = int64_t(1) << 16;

// Calls take(field, first, count) for each block of rows of `variable` (a
// field of probe, source.probe()'s) in order: field holds rows [first,
// first + count), its arrays starting at row first. The blocks are made in
// probe, one block of one kind at a time.
void for_each_block_of(Context &ctx, const MpasSource &source, MpasMesh probe, const MpasField &variable,
                       const std::function<void(const MpasField &, int64_t, int64_t)> &take);

// What a source holds (kMpasSource*BytesPerCell); a regional mesh's also
// the maps between its rows and the whole numbering (MpasLayout: 8 bytes a
// cell, 3 edges and 2 vertices per cell).
constexpr int64_t kMpasRegionalRowsBytesPerCell = 48;
inline int64_t mpas_source_bytes(int64_t cells, bool features, bool ellipsoid = false, bool regional = false) {
    return cells * ((features ? kMpasSourceWithFeaturesBytesPerCell : kMpasSourceBytesPerCell) +
                    (ellipsoid ? kMpasEllipsoidCopyBytesPerCell : 0) + (regional ? kMpasRegionalRowsBytesPerCell : 0));
}
// What streaming the file of a mesh of `cells` cells adds to the mesh: the
// source, and two blocks of rows (one written while the next is made), each
// holding a block of every kind (a cell row about 190 B with maxEdges 9, an
// edge row 316 B and the stencils of its cells 160 B, a vertex row 108 B).
inline int64_t mpas_stream_bytes(int64_t cells, bool features, bool ellipsoid = false, bool regional = false) {
    auto rows = [](int64_t n) { return std::min(n, kMpasBlockRows); };
    const int64_t block = rows(cells) * 190 + rows(3 * cells) * (316 + 160) + rows(2 * cells) * 108;
    return mpas_source_bytes(cells, features, ellipsoid, regional) + 2 * block;
}
// What the copy-out of one variable holds: the source and a block of rows
// of one kind (the largest, an edge block with its stencils).
inline int64_t mpas_copy_out_bytes(int64_t cells, bool features, bool ellipsoid = false, bool regional = false) {
    return mpas_source_bytes(cells, features, ellipsoid, regional) + std::min(3 * cells, kMpasBlockRows) * (316 + 160);
}

}  // namespace um::dual
