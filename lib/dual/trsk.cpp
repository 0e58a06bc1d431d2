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
// (a component mesh, lib/components, or a regional mesh's rows) an edge of
// the boundary has only the stencil of its one cell, c1, as on MPAS's
// culled meshes.
#include <algorithm>

#include "core/buffer.hpp"
#include "core/radix_sort.hpp"
#include "core/uninit_vector.hpp"
#include "dual/stages.hpp"

namespace um::dual {

namespace {

// One cell as its TRSK stencils see it: its edges counter-clockwise, the
// fraction of its area in each corner (R_iv, corner j between edges j - 1
// and j), dvEdge of each edge and whether the cell is that edge's
// cellsOnEdge(1).
struct CellStencil {
    int degree = 0;
    const int32_t *edges = nullptr;
    const double *fraction = nullptr, *dv = nullptr;
    const uint8_t *cell_first = nullptr;
};

// Appends the stencil of edge e from the side of `cell` (side 0: it is c1,
// 1: c2) at *slot of the row: its edges, and their weights unless
// weights_out is null.
void side_weights(const CellStencil &cell, int32_t e, int side, double dc, int32_t *edges_out,
                  double *weights_out, int &slot) {
    const int d = cell.degree;
    int j0 = 0;
    while (j0 < d && cell.edges[j0] != e) ++j0;
    if (j0 == d) j0 = 0;
    double passed = 0;
    for (int step = 1, j = j0; step < d; ++step) {
        const int corner = j;  // verticesOnCell(j), between edgesOnCell(j) and the next one
        if (++j == d) j = 0;
        edges_out[slot] = cell.edges[j];
        if (weights_out) {
            passed += cell.fraction[corner];
            double s = cell.cell_first[j] ? 1.0 : -1.0;
            if (side == 1) s = -s;
            weights_out[slot] = s * (0.5 - passed) * cell.dv[j] / dc;
        }
        ++slot;
    }
}

// Turns kites into R_iv. The denominator is the sum of the cell's kites,
// which equals areaCell to rounding; taking it makes the fractions of a cell
// add up to 1 to the last bits, and with them the antisymmetry of W dc dv,
// even where the generator lies far outside a small power cell and its kites
// nearly cancel.
void kites_to_fractions(double *kite, int d) {
    double sum = 0;
    for (int j = 0; j < d; ++j) sum += kite[j];
    for (int j = 0; j < d; ++j) kite[j] /= sum;
}

// The stencils of whole cells, max_edges wide, in a block of rows: built
// from a mesh in memory (stencils_of_mesh) or from a layout (trsk_rows).
// Sized without being written: each cell's first `degree` entries are
// filled before they are read (fraction, dv and cell_first only for the
// weights).
struct Stencils {
    size_t width = 0;
    UninitVector<int32_t> degree, edges;
    UninitVector<double> fraction, dv;
    UninitVector<uint8_t> cell_first;

    void resize(size_t cells, size_t w) {
        width = w;
        degree.resize(cells);
        edges.resize(w * cells);
        fraction.resize(w * cells);
        dv.resize(w * cells);
        cell_first.resize(w * cells);
    }
    CellStencil operator[](size_t i) const {
        return {degree[i], &edges[width * i], &fraction[width * i], &dv[width * i], &cell_first[width * i]};
    }
};

Stencils stencils_of_mesh(Context &ctx, const MpasMesh &m) {
    const size_t w = static_cast<size_t>(m.max_edges);
    Stencils st;
    st.resize(static_cast<size_t>(m.n_cells), w);
    ctx.parallel_for(m.n_cells, 4096, [&](int64_t b, int64_t e) {
        for (int64_t c = b; c < e; ++c) {
            const int d = st.degree[c] = m.n_edges_on_cell[c];
            for (int j = 0; j < d; ++j) {
                const int32_t v = m.vertices_on_cell[w * c + j], edge = m.edges_on_cell[w * c + j];
                st.fraction[w * c + j] = 0.0;
                for (int k = 0; k < 3; ++k)
                    if (m.cells_on_vertex[3 * int64_t(v) + k] == c)
                        st.fraction[w * c + j] = m.kite_areas_on_vertex[3 * int64_t(v) + k];
                st.edges[w * c + j] = edge;
                st.dv[w * c + j] = m.dv_edge[edge];
                st.cell_first[w * c + j] = m.cells_on_edge[2 * int64_t(edge)] == c;
            }
            kites_to_fractions(&st.fraction[w * c], d);
        }
    });
    return st;
}

// Rows [0, count) of nEdgesOnEdge, edgesOnEdge and, with `weights`,
// weightsOnEdge of m, whose cellsOnEdge and dcEdge hold those rows;
// stencil_of(row, side) gives the stencil of the row's cell on that side.
// Each row is written whole (its unused entries kNone and 0) in the
// parallel loop: a block's arrays are 14 values a row.
template <class StencilOf>
void stencil_rows(Context &ctx, int64_t first, int64_t count, size_t w2, MpasMesh &m, bool weights,
                  StencilOf stencil_of) {
    m.n_edges_on_edge.resize(static_cast<size_t>(count));
    m.edges_on_edge.resize(w2 * count);
    m.weights_on_edge.resize(w2 * count);
    ctx.parallel_for(count, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            int32_t *edges = &m.edges_on_edge[w2 * i];
            double *row_weights = &m.weights_on_edge[w2 * i];
            int slot = 0;
            for (int side = 0; side < 2; ++side) {
                if (m.cells_on_edge[2 * i + side] == kNone) continue;  // cut off with its cell (a component mesh)
                side_weights(stencil_of(i, side), static_cast<int32_t>(first + i), side, m.dc_edge[i], edges,
                             weights ? row_weights : nullptr, slot);
            }
            m.n_edges_on_edge[i] = slot;
            std::fill(edges + slot, edges + w2, kNone);
            std::fill(row_weights + (weights ? slot : 0), row_weights + w2, 0.0);
        }
    });
}

// Entry i of st: the stencil of cell c (whole numbering) from its ring, its
// corners' kites and the dvEdge of its edges. The block's rows [first,
// first + count) of m have their dvEdge made (edge_rows): an edge among them
// takes it from there, any other is measured as edge_rows measures it
// (MpasLayout::dual_arc).
void fill_stencil(const MpasLayout &layout, const CornerKites &kites, double radius, int64_t first, int64_t count,
                  const MpasMesh &m, int32_t c, CellRing &ring, Stencils &st, size_t i) {
    layout.cell_ring(c, ring);
    const int d = st.degree[i] = ring.degree();
    const size_t w = st.width;
    for (int j = 0; j < d; ++j) {
        const EdgeEnds ends = layout.edge_ends(ring.edges[j]);
        const int64_t row = layout.row_of_edge(ring.edges[j]);
        st.edges[w * i + j] = static_cast<int32_t>(row);
        st.fraction[w * i + j] = kites.of_cell(layout, ring.vertices[j], c);
        st.dv[w * i + j] = row >= first && row < first + count ? m.dv_edge[row - first] : radius * layout.dual_arc(ends);
        st.cell_first[w * i + j] = ends.cell[layout.turned(ends) ? 1 : 0] == c;
    }
    kites_to_fractions(&st.fraction[w * i], d);
}

}  // namespace

void fill_trsk_weights(Context &ctx, MpasMesh &m) {
    const Stencils st = stencils_of_mesh(ctx, m);
    stencil_rows(ctx, 0, m.n_edges, static_cast<size_t>(m.max_edges2()), m, true, [&](int64_t row, int side) {
        return st[static_cast<size_t>(m.cells_on_edge[2 * row + side])];
    });
}

// The stencils of the cells the block's edges touch, each built once from
// its ring geometry (neighbouring edges share cells: rows are numbered along
// a Hilbert curve), then the rows from them.
void trsk_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
               MpasMesh &m, const CornerKites *kites) {
    const bool weights = kites != nullptr;
    // The block's cells, sorted (in parallel: this is on the writer's
    // critical path) and each once; of each cellsOnEdge value, the index of
    // its cell among them.
    Buffer<uint64_t> keys(static_cast<size_t>(2 * count));
    ctx.parallel_for(2 * count, 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i)
            keys[i] = uint64_t(static_cast<uint32_t>(m.cells_on_edge[i])) << 32 | uint64_t(i);  // kNone: last
    });
    radix_sort(ctx, keys, 32, 64);
    std::vector<int32_t> cells;
    cells.reserve(static_cast<size_t>(count));
    UninitVector<int32_t> index_of(keys.size());
    for (size_t k = 0; k < keys.size(); ++k) {
        const uint32_t cell = static_cast<uint32_t>(keys[k] >> 32);
        if (cell == uint32_t(kNone)) break;
        if (cells.empty() || static_cast<int32_t>(cell) != cells.back()) cells.push_back(static_cast<int32_t>(cell));
        index_of[keys[k] & 0xffffffffu] = static_cast<int32_t>(cells.size() - 1);
    }
    // (A block's cells are rows; their rings are walked in the whole
    // numbering, their edges given as rows.)
    const size_t w = static_cast<size_t>(layout.max_edges());
    Stencils st;
    st.resize(cells.size(), w);
    ctx.parallel_for(static_cast<int64_t>(cells.size()), 256, [&](int64_t b, int64_t e) {
        CellRing ring;
        for (int64_t i = b; i < e; ++i) {
            const int32_t c = layout.cell_of_row(cells[i]);
            if (weights) {
                fill_stencil(layout, *kites, radius, first, count, m, c, ring, st, static_cast<size_t>(i));
                continue;
            }
            layout.cell_ring(c, ring);  // the edges of the ring are all edgesOnEdge needs
            const int d = st.degree[i] = ring.degree();
            for (int j = 0; j < d; ++j) st.edges[w * i + j] = layout.row_of_edge(ring.edges[j]);
        }
    });
    stencil_rows(ctx, first, count, 2 * static_cast<size_t>(layout.row_max_edges()), m, weights,
                 [&](int64_t row, int side) { return st[static_cast<size_t>(index_of[2 * row + side])]; });
}

}  // namespace um::dual
