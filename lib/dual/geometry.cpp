// Connectivity, positions, lengths, angles and areas of the MPAS mesh
// (mpas-format.md, "What a generator must produce"), a block of rows at a
// time from the layout's unit vectors, scaled by R.
#include <algorithm>
#include <cmath>
#include <utility>

#include "dual/spherical.hpp"
#include "dual/stages.hpp"

namespace um::dual {

namespace {

struct Placed {
    std::vector<double> *x, *y, *z, *lat, *lon;
};

void resize_rows(Placed p, size_t n) {
    for (auto *a : {p.x, p.y, p.z, p.lat, p.lon}) a->resize(n);
}

void place(Placed p, Vec3 u, double radius, int64_t i, double axis) {
    (*p.x)[i] = radius * u.x, (*p.y)[i] = radius * u.y, (*p.z)[i] = radius * u.z;
    lat_lon(u, axis, (*p.lat)[i], (*p.lon)[i]);
}
void place(Placed p, Vec3 u, double radius, int64_t i) { place(p, u, radius, i, axis_distance(u)); }

}  // namespace

void cell_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
               MpasMesh &m, bool areas) {
    const double r2 = radius * radius;
    const size_t w = static_cast<size_t>(layout.row_max_edges()), n = static_cast<size_t>(count);
    const Placed placed{&m.x_cell, &m.y_cell, &m.z_cell, &m.lat_cell, &m.lon_cell};
    resize_rows(placed, n);
    if (areas) m.area_cell.resize(n);
    m.n_edges_on_cell.resize(n);
    // Each row written whole (its ring, then kNone) in the parallel loop.
    for (auto *a : {&m.edges_on_cell, &m.vertices_on_cell, &m.cells_on_cell}) a->resize(w * n);
    ctx.parallel_for(count, 1024, [&](int64_t b, int64_t e) {
        CellRing ring;
        std::vector<Vec3> corner;
        for (int64_t i = b; i < e; ++i) {
            const int32_t c = layout.cell_of_row(first + i);
            layout.cell_ring(c, ring);
            const int d = ring.degree();
            m.n_edges_on_cell[i] = d;
            int32_t *edges = &m.edges_on_cell[w * i], *vertices = &m.vertices_on_cell[w * i],
                    *cells = &m.cells_on_cell[w * i];
            for (int j = 0; j < d; ++j) {
                edges[j] = layout.row_of_edge(ring.edges[j]);
                vertices[j] = layout.row_of_vertex(ring.vertices[j]);
                cells[j] = layout.row_of_cell(ring.cells[j]);
            }
            for (int32_t *row : {edges, vertices, cells}) std::fill(row + d, row + w, kNone);
            place(placed, layout.cell_unit(c), radius, i);
            if (!areas) continue;
            // The power cell's polygon fanned from the centroid of its corners:
            // the generator may lie outside its own cell.
            corner.resize(d);
            Vec3 sum{};
            for (int j = 0; j < d; ++j) sum = sum + (corner[j] = layout.vertex_unit(ring.vertices[j]));
            const Vec3 centre = geom::normalized(sum);
            double area = 0;
            for (int j = 0; j < d; ++j) area += signed_area(centre, corner[j], corner[(j + 1) % d]);
            m.area_cell[i] = r2 * area;
        }
    });
}

// areaTriangle: the generator triangle.
void vertex_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
                 MpasMesh &m, const CornerKites *kites) {
    const bool areas = kites != nullptr;
    const double r2 = radius * radius;
    const size_t n = static_cast<size_t>(count);
    const Placed placed{&m.x_vertex, &m.y_vertex, &m.z_vertex, &m.lat_vertex, &m.lon_vertex};
    resize_rows(placed, n);
    m.cells_on_vertex.resize(3 * n);
    m.edges_on_vertex.resize(3 * n);
    if (areas) m.area_triangle.resize(n), m.kite_areas_on_vertex.resize(3 * n);
    m.boundary_vertex.resize(n);
    ctx.parallel_for(count, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t v = layout.vertex_of_row(first + i);
            int32_t cell[3], edge[3];
            layout.vertex_corners(v, cell, edge);
            m.boundary_vertex[i] = 0;
            for (int j = 0; j < 3; ++j) {
                m.cells_on_vertex[3 * i + j] = layout.row_of_cell(cell[j]);
                m.edges_on_vertex[3 * i + j] = layout.row_of_edge(edge[j]);
                if (m.cells_on_vertex[3 * i + j] == kNone) m.boundary_vertex[i] = 1;
            }
            const Vec3 o = layout.vertex_unit(v);
            place(placed, o, radius, i);
            if (!areas) continue;
            Vec3 x[3];
            for (int j = 0; j < 3; ++j) x[j] = layout.cell_unit(cell[j]);
            m.area_triangle[i] = r2 * signed_area(x[0], x[1], x[2]);
            for (int j = 0; j < 3; ++j) m.kite_areas_on_vertex[3 * i + j] = kites->of_row(first + i, j);
        }
    });
}

void edge_rows(Context &ctx, const MpasLayout &layout, double radius, int64_t first, int64_t count,
               MpasMesh &m) {
    const size_t n = static_cast<size_t>(count);
    const Placed placed{&m.x_edge, &m.y_edge, &m.z_edge, &m.lat_edge, &m.lon_edge};
    resize_rows(placed, n);
    for (auto *a : {&m.dc_edge, &m.dv_edge, &m.angle_edge}) a->resize(n);
    m.cells_on_edge.resize(2 * n);
    m.vertices_on_edge.resize(2 * n);
    ctx.parallel_for(count, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const EdgeEnds ends = layout.edge_ends(layout.edge_of_row(first + i));
            const Vec3 c1 = layout.cell_unit(ends.cell[0]), c2 = layout.cell_unit(ends.cell[1]);
            const Vec3 v1 = layout.vertex_unit(ends.vertex[0]), v2 = layout.vertex_unit(ends.vertex[1]);
            const Vec3 x = layout.edge_unit(ends, c1, c2, v1, v2);
            const double axis = axis_distance(x);
            place(placed, x, radius, i, axis);
            const bool turned = layout.turned(ends);  // (its cell outside the region last)
            const int first_end = turned ? 1 : 0;
            m.cells_on_edge[2 * i] = layout.row_of_cell(ends.cell[first_end]);
            m.cells_on_edge[2 * i + 1] = layout.row_of_cell(ends.cell[1 - first_end]);
            m.vertices_on_edge[2 * i] = layout.row_of_vertex(ends.vertex[first_end]);
            m.vertices_on_edge[2 * i + 1] = layout.row_of_vertex(ends.vertex[1 - first_end]);
            m.dc_edge[i] = radius * arc(c1, c2);
            m.dv_edge[i] = radius * layout.dual_arc(ends);
            // n_e is the direction of the arc c1 -> c2 at xEdge, (c1 x c2) x xEdge.
            // The dual arc is exactly perpendicular, so this is the normal of
            // recompute_angle_edge, (v2 - v1) x xEdge, without its rounding on
            // the metre-long dual edges of nearly cocircular quadruples.
            double angle = angle_from_east(geom::cross(geom::cross(c1, c2), x), x, axis);
            if (turned) {
                angle += M_PI;
                if (angle > M_PI) angle -= 2 * M_PI;
            }
            m.angle_edge[i] = angle;
        }
    });
}

}  // namespace um::dual
