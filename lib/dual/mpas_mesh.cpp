#include "dual/mpas_mesh.hpp"

#include "dual/mpas_source.hpp"
#include "mesh/refined_mesh.hpp"

namespace um::dual {

namespace {

// Every row of every kind, each kind as one block.
MpasMesh whole_mesh(Context &ctx, const MpasSource &source) {
    MpasMesh m = source.shape();
    ctx.check_memory(kMpasBytesPerCell * static_cast<int64_t>(m.n_cells), "the MPAS mesh");
    source.rows(ctx, MpasDim::nCells, 0, m.n_cells, m);
    source.rows(ctx, MpasDim::nVertices, 0, m.n_vertices, m);
    source.rows(ctx, MpasDim::nEdges, 0, m.n_edges, m);
    return m;
}

}  // namespace

MpasMesh build_mpas_mesh(Context &ctx, const tri::Triangulation &tri, const MpasMeshInput &input) {
    return whole_mesh(ctx, MpasSource(ctx, tri, input));
}

MpasMesh build_mpas_mesh(Context &ctx, const mesh::RefinedMesh &refined) {
    return whole_mesh(ctx, MpasSource(ctx, refined));
}

}  // namespace um::dual
