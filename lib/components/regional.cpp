#include "components/regional.hpp"

#include <algorithm>

#include "components/cut_mesh.hpp"
#include "core/error.hpp"

namespace um::components {

using dual::kNone;

dual::MpasMesh regional_mpas_mesh(Context &ctx, const mesh::RefinedMesh &m) {
    if (!m.regional()) fail(UM_ERR_INVALID_ARGUMENT, "the mesh is not regional (it has no domain rings)");
    // (cut_mesh makes the TRSK stencils of the cells it keeps.)
    const dual::MpasMesh whole = dual::build_mpas_mesh(ctx, m, dual::TrskStencils::left_out);
    const std::vector<uint8_t> region = m.region_cells(ctx);
    std::vector<uint8_t> keep(static_cast<size_t>(whole.n_cells));
    for (int32_t c = 0; c < whole.n_cells; ++c) keep[c] = region[m.slot_of_vertex[whole.cell_source_vertex[c]]];
    dual::MpasMesh cut = cut_mesh(ctx, whole, keep);
    // The maps back index the whole sphere's mesh, which no output holds.
    cut.base_cell.clear(), cut.base_edge.clear(), cut.base_vertex.clear();
    mark_boundary_layers(cut);
    return cut;
}

void mark_boundary_layers(dual::MpasMesh &m) {
    const size_t w = static_cast<size_t>(m.max_edges);
    std::vector<int32_t> layer(static_cast<size_t>(m.n_cells), 0);
    std::vector<int32_t> front;
    for (int32_t c = 0; c < m.n_cells; ++c)
        for (int32_t j = 0; j < m.n_edges_on_cell[c]; ++j)
            if (m.cells_on_cell[c * w + j] == kNone) {
                layer[c] = kBoundaryLayers, front.push_back(c);
                break;
            }
    for (int32_t value = kBoundaryLayers - 1; value >= 1 && !front.empty(); --value) {
        std::vector<int32_t> next;
        for (int32_t c : front)
            for (int32_t j = 0; j < m.n_edges_on_cell[c]; ++j) {
                const int32_t d = m.cells_on_cell[c * w + j];
                if (d != kNone && layer[d] == 0) layer[d] = value, next.push_back(d);
            }
        std::sort(next.begin(), next.end());
        front.swap(next);
    }
    // The least value among an element's cells (those present).
    auto least = [&](const std::vector<int32_t> &cells, int32_t n, int32_t per, std::vector<int32_t> &out) {
        out.assign(static_cast<size_t>(n), 0);
        for (int32_t e = 0; e < n; ++e) {
            int32_t best = kBoundaryLayers;
            for (int32_t j = 0; j < per; ++j) {
                const int32_t c = cells[static_cast<size_t>(e) * per + j];
                if (c != kNone) best = std::min(best, layer[c]);
            }
            out[e] = best;
        }
    };
    least(m.cells_on_edge, m.n_edges, 2, m.bdy_mask_edge);
    least(m.cells_on_vertex, m.n_vertices, dual::kVertexDegree, m.bdy_mask_vertex);
    m.bdy_mask_cell = std::move(layer);
}

}  // namespace um::components
