// The MPAS numbering of a Laguerre triangulation (mpas_mesh.hpp has the
// conventions) and its elements one at a time: a cell's ring, an edge's two
// cells and two vertices, a vertex's three cells and edges, and the unit
// positions of each. It holds only the maps between the numbering and the
// triangulation and each vertex's unit position (about 124 bytes per cell; a
// regional mesh's rows 48 more), so that the staggered mesh can be produced
// a block of rows at a time (mpas_source.hpp) instead of whole.
//
// Two numberings: the whole triangulation's, in which the walks and the
// positions below take and give their indices, and the rows the mesh's
// variables list. They are the same but for a regional mesh, whose rows are
// the region's cells and every edge and vertex of theirs, in the whole
// numbering's order, with kNone for a neighbour outside (cut_mesh.hpp's
// convention: an edge whose first cell is outside is turned around).
// Internal to lib/dual.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/context.hpp"
#include "core/uninit_vector.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/spherical.hpp"
#include "geom/sphere.hpp"
#include "geom/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::dual {

using geom::Vec3;

// An edge: cellsOnEdge (cell[0] < cell[1]), verticesOnEdge, and the
// triangulation's view of it from the lower triangle slot (triangle
// `lower`, local edge `k`), from which its edge point is found.
struct EdgeEnds {
    int32_t cell[2], vertex[2];
    int32_t lower;
    int k;
};

// A cell's ring in MPAS order: verticesOnCell, edgesOnCell, cellsOnCell,
// counter-clockwise from the lowest-numbered vertex.
struct CellRing {
    std::vector<int32_t> vertices, edges, cells;
    int degree() const { return static_cast<int>(vertices.size()); }
};

class MpasLayout {
public:
    // slot_of_vertex: the mesh vertices (checked to be exactly the
    // triangulation's vertices); empty = every vertex in slot order. Throws
    // um::Error on a numbering that does not match, broken neighbour links,
    // counts beyond int32 (UM_ERR_LIMIT). Keeps a reference to tri.
    // surface: what the directions stand for. On an ellipsoid the layout
    // holds a copy of tri with each generator moved to its geodetic lon/lat
    // on the unit sphere (same weights; flips where the move broke
    // regularity), and every position below is of that copy: the staggered
    // mesh is then the power diagram of the generators so placed on the
    // sphere MPAS assumes (orthogonal), its vertices their power vertices.
    // region: per vertex slot, 1 for the cells of a regional mesh (at least
    // one); empty: every cell.
    MpasLayout(Context &ctx, const tri::Triangulation &tri, std::vector<int32_t> slot_of_vertex,
               const geom::Surface &surface = geom::Surface::sphere(1.0),
               const std::vector<uint8_t> &region = {});

    const tri::Triangulation &tri() const { return *tri_; }
    // The whole numbering's counts and widest ring.
    int32_t n_cells() const { return static_cast<int32_t>(cell_slot_.size()); }
    int32_t n_edges() const { return static_cast<int32_t>(edge_half_.size()); }
    int32_t n_vertices() const { return static_cast<int32_t>(vertex_tri_.size()); }
    int32_t max_edges() const { return max_edges_; }

    // The rows: their counts and widest ring (maxEdges), the element of the
    // whole numbering each row is, and the row of each element (kNone:
    // outside the region; kNone gives kNone).
    bool regional() const { return regional_; }
    int32_t cell_rows() const { return regional_ ? cells_.count() : n_cells(); }
    int32_t edge_rows() const { return regional_ ? edges_.count() : n_edges(); }
    int32_t vertex_rows() const { return regional_ ? vertices_.count() : n_vertices(); }
    int32_t row_max_edges() const { return regional_ ? row_max_edges_ : max_edges_; }
    int32_t cell_of_row(int64_t r) const { return regional_ ? cells_.whole[r] : static_cast<int32_t>(r); }
    int32_t edge_of_row(int64_t r) const { return regional_ ? edges_.whole[r] : static_cast<int32_t>(r); }
    int32_t vertex_of_row(int64_t r) const { return regional_ ? vertices_.whole[r] : static_cast<int32_t>(r); }
    int32_t row_of_cell(int32_t c) const { return regional_ && c != kNone ? cells_.row[c] : c; }
    int32_t row_of_edge(int32_t e) const { return regional_ && e != kNone ? edges_.row[e] : e; }
    int32_t row_of_vertex(int32_t v) const { return regional_ && v != kNone ? vertices_.row[v] : v; }
    // Whether the row of an edge runs the other way from the whole
    // numbering's (its cellsOnEdge(1) outside the region): cells and
    // vertices swapped, angleEdge and the river's direction reversed.
    bool turned(const EdgeEnds &ends) const { return regional_ && cells_.row[ends.cell[0]] == kNone; }

    // The mesh vertex (index into slot_of_vertex) and the slot of cell c; the
    // triangle slot of MPAS vertex v.
    int32_t cell_source_vertex(int32_t c) const { return cell_vertex_[c]; }
    int32_t cell_slot(int32_t c) const { return cell_slot_[c]; }
    int32_t vertex_triangle(int32_t v) const { return vertex_tri_[v]; }
    // The cell of a vertex slot (-1: not a vertex).
    int32_t cell_of_slot(int32_t s) const { return cell_of_slot_[s]; }

    EdgeEnds edge_ends(int32_t e) const;
    void cell_ring(int32_t c, CellRing &ring) const;
    // cellsOnVertex and edgesOnVertex of v.
    void vertex_corners(int32_t v, int32_t cells[3], int32_t edges[3]) const;
    // The j with cellsOnVertex(v, j) = c (-1: c is not at v).
    int corner_of(int32_t v, int32_t c) const;

    Vec3 cell_unit(int32_t c) const { return tri_->direction(cell_slot_[c]); }
    Vec3 vertex_unit(int32_t v) const { return vertex_unit_[v]; }
    // xEdge: the crossing of the edge's primal and dual great circles, from
    // the units of its cells and vertices (in EdgeEnds order).
    Vec3 edge_unit(const EdgeEnds &ends, Vec3 c1, Vec3 c2, Vec3 v1, Vec3 v2) const;
    Vec3 edge_unit(int32_t e) const;
    // dvEdge / R: the arc between the edge's vertices in EdgeEnds order, its
    // one measure (the edge rows and the TRSK stencils of edges outside a
    // block both take it here, so the two agree to the bit).
    double dual_arc(const EdgeEnds &ends) const { return arc(vertex_unit(ends.vertex[0]), vertex_unit(ends.vertex[1])); }

private:
    // The cells at triangle t's corners in its order, and the corner of the
    // lowest (cellsOnVertex starts there).
    int triangle_cells(int32_t t, int32_t cell[3]) const;
    void number_cells(Context &ctx, const std::vector<int32_t> &slots);
    void number_vertices(Context &ctx);
    void number_edges(Context &ctx);
    void check_rings(Context &ctx);
    void number_rows(Context &ctx, const std::vector<uint8_t> &region);

    // The elements of a kind that are rows: row -> whole and whole -> row.
    struct Rows {
        HugePageVector<int32_t> whole, row;
        int32_t count() const { return static_cast<int32_t>(whole.size()); }
    };

    // On huge pages, sized without being written and filled in parallel:
    // filled on one thread with 4 KiB pages, their first touches (page
    // faults and memset) were two thirds of the layout's time at 10 km.
    const tri::Triangulation *tri_;
    std::unique_ptr<tri::Triangulation> on_sphere_;  // an ellipsoid mesh's copy (tri_ points to it)
    HugePageVector<int32_t> cell_vertex_, cell_slot_, cell_of_slot_;
    HugePageVector<int32_t> vertex_tri_, vertex_of_tri_;
    // Each vertex's orthocentre, kept: a cell's rows, kites and stencils
    // reach each of its corners about a dozen times (24 bytes per vertex,
    // 48 per cell).
    HugePageVector<Vec3> vertex_unit_;
    HugePageVector<int64_t> edge_half_;     // edge -> 3 * lower triangle slot + k
    HugePageVector<int32_t> edge_of_half_;  // 3 * triangle slot + k -> edge across edge k
    int32_t max_edges_ = 0;
    bool regional_ = false;
    Rows cells_, edges_, vertices_;
    int32_t row_max_edges_ = 0;
};

}  // namespace um::dual
