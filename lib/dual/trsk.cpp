// The TRSK tangential-velocity stencil (Thuburn et al. 2009, JCP 228:8321;
// Ringler et al. 2010): v_e = sum_j weightsOnEdge(e, j) u(edgesOnEdge(e, j)).
//
// For edge e and each of its cells i (c1, then c2), the other edges e' of i
// are taken counter-clockwise starting after e, and
//     w(e, e') = s (1/2 - sum R_iv) dvEdge(e') / dcEdge(e),
// where sum R_iv adds kite(v, i) / areaCell(i) over the corners v of i passed
// going from e to e' (R_iv are the fractions of the cell's area in its
// kites), s = +1 when i is cellsOnEdge(e', 1), else -1, and s is negated for
// c2. The formula needs only orthogonality, kites that add up to areaCell
// and the orderings, so it holds for power cells with signed kites; it makes
// W dc dv antisymmetric and the dual divergence of the reconstructed
// tangential flux the kite average of the primal divergences. On a cut mesh
// (lib/components) an edge of the boundary has only the stencil of its one
// cell, c1, as on MPAS's culled meshes.
#include "dual/stages.hpp"

namespace um::dual {

namespace {

// R_iv for every corner of every cell, in verticesOnCell order. The
// denominator is the sum of the cell's kites, which equals areaCell to
// rounding; taking it makes the fractions of a cell add up to 1 to the last
// bits, and with them the antisymmetry of W dc dv, even where the generator
// lies far outside a small power cell and its kites nearly cancel.
std::vector<double> corner_fractions(Context &ctx, const MpasMesh &m) {
    const size_t w = static_cast<size_t>(m.max_edges);
    std::vector<double> fraction(w * static_cast<size_t>(m.n_cells), 0.0);
    ctx.parallel_for(m.n_cells, 4096, [&](int64_t b, int64_t e) {
        for (int64_t c = b; c < e; ++c) {
            double *row = &fraction[w * c], sum = 0;
            for (int j = 0; j < m.n_edges_on_cell[c]; ++j) {
                int32_t v = m.vertices_on_cell[w * c + j];
                for (int k = 0; k < 3; ++k)
                    if (m.cells_on_vertex[3 * int64_t(v) + k] == c)
                        row[j] = m.kite_areas_on_vertex[3 * int64_t(v) + k];
                sum += row[j];
            }
            for (int j = 0; j < m.n_edges_on_cell[c]; ++j) row[j] /= sum;
        }
    });
    return fraction;
}

// Appends the weights of edge e from its side `side` (0: c1, 1: c2) at *slot.
void side_weights(MpasMesh &m, const std::vector<double> &fraction, int64_t e, int side,
                  int &slot) {
    const size_t w = static_cast<size_t>(m.max_edges), w2 = 2 * w;
    const int32_t cell = m.cells_on_edge[2 * e + side];
    if (cell == kNone) return;  // cut off with its cell (a component mesh)
    const int d = m.n_edges_on_cell[cell];
    const int32_t *edges = &m.edges_on_cell[w * cell];
    int j0 = 0;
    while (j0 < d && edges[j0] != e) ++j0;
    double passed = 0;
    for (int step = 1; step < d; ++step) {
        int j = (j0 + step) % d;
        int32_t other = edges[j];
        // The corner between edgesOnCell(j - 1) and (j) is verticesOnCell(j - 1).
        passed += fraction[w * cell + (j + d - 1) % d];
        double s = m.cells_on_edge[2 * int64_t(other)] == cell ? 1.0 : -1.0;
        if (side == 1) s = -s;
        m.edges_on_edge[w2 * e + slot] = other;
        m.weights_on_edge[w2 * e + slot] = s * (0.5 - passed) * m.dv_edge[other] / m.dc_edge[e];
        ++slot;
    }
}

}  // namespace

void fill_trsk_weights(Context &ctx, MpasMesh &m) {
    std::vector<double> fraction = corner_fractions(ctx, m);
    const size_t w2 = static_cast<size_t>(m.max_edges2());
    m.n_edges_on_edge.assign(static_cast<size_t>(m.n_edges), 0);
    m.edges_on_edge.assign(w2 * m.n_edges, kNone);
    m.weights_on_edge.assign(w2 * m.n_edges, 0.0);
    ctx.parallel_for(m.n_edges, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            int slot = 0;
            side_weights(m, fraction, i, 0, slot);
            side_weights(m, fraction, i, 1, slot);
            m.n_edges_on_edge[i] = slot;
        }
    });
}

}  // namespace um::dual
