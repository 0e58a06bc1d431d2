#include "dual/corner_kites.hpp"

#include "core/error.hpp"
#include "dual/spherical.hpp"

namespace um::dual {

namespace {

// xEdge of edge e, vertex v's edge j (between cellsOnVertex(j - 1) and (j)),
// as MpasLayout::edge_unit(e) gives it, from the units at hand of v (o) and
// of its cells (x): only the vertex across the edge is placed anew.
Vec3 corner_edge_unit(const MpasLayout &layout, int32_t v, Vec3 o, const int32_t cell[3], const Vec3 x[3], int j,
                      int32_t e) {
    const EdgeEnds ends = layout.edge_ends(e);
    const int before = (j + 2) % 3;
    const bool j_first = ends.cell[0] == cell[j];
    if (ends.cell[j_first ? 1 : 0] != cell[before] || ends.cell[j_first ? 0 : 1] != cell[j] ||
        (ends.vertex[0] != v && ends.vertex[1] != v))
        return layout.edge_unit(e);  // (not the corner's edge: never, with the layout's links checked)
    const Vec3 v1 = ends.vertex[0] == v ? o : layout.vertex_unit(ends.vertex[0]);
    const Vec3 v2 = ends.vertex[1] == v ? o : layout.vertex_unit(ends.vertex[1]);
    return layout.edge_unit(ends, j_first ? x[j] : x[before], j_first ? x[before] : x[j], v1, v2);
}

// Kite j of vertex v: the quad (v, xEdge_j, xCell_j, xEdge_j+1), signed, as
// two triangles from v; the edge points lie on the cell-cell arcs, so the
// kites add up to the generator triangle.
void vertex_kites(const MpasLayout &layout, double r2, int32_t v, double kite[3]) {
    int32_t cell[3], edge[3];
    layout.vertex_corners(v, cell, edge);
    const Vec3 o = layout.vertex_unit(v);
    Vec3 x[3], xe[3];
    for (int j = 0; j < 3; ++j) x[j] = layout.cell_unit(cell[j]);
    for (int j = 0; j < 3; ++j) xe[j] = corner_edge_unit(layout, v, o, cell, x, j, edge[j]);
    for (int j = 0; j < 3; ++j)
        kite[j] = r2 * (signed_area(o, xe[j], x[j]) + signed_area(o, x[j], xe[(j + 1) % 3]));
}

}  // namespace

CornerKites::CornerKites(Context &ctx, const MpasLayout &layout, double radius) {
    const double r2 = radius * radius;
    const int64_t rows = layout.vertex_rows();
    kites_.resize(3 * static_cast<size_t>(rows));
    ctx.parallel_for(rows, 4096, [&](int64_t b, int64_t e) {
        for (int64_t r = b; r < e; ++r) vertex_kites(layout, r2, layout.vertex_of_row(r), &kites_[3 * r]);
    });
}

double CornerKites::of_cell(const MpasLayout &layout, int32_t v, int32_t c) const {
    const int j = layout.corner_of(v, c);
    const int32_t r = layout.row_of_vertex(v);
    if (j >= 0 && r != kNone) return of_row(r, j);
    fail(UM_ERR_INTERNAL, "MPAS mesh: cell ", c, " is not at vertex ", v);
}

}  // namespace um::dual
