// Positions, lengths, angles and areas of the MPAS mesh (mpas-format.md,
// "What a generator must produce"), from unit vectors, scaled by R at the end.
#include <cmath>

#include "dual/spherical.hpp"
#include "dual/stages.hpp"

namespace um::dual {

namespace {

void place(const std::vector<Vec3> &unit, double radius, std::vector<double> &x,
           std::vector<double> &y, std::vector<double> &z, std::vector<double> &lat,
           std::vector<double> &lon, int64_t i) {
    const Vec3 &u = unit[i];
    x[i] = radius * u.x, y[i] = radius * u.y, z[i] = radius * u.z;
    lat_lon(u, lat[i], lon[i]);
}

void resize_all(size_t n, std::initializer_list<std::vector<double> *> arrays) {
    for (auto *a : arrays) a->resize(n);
}

void cell_geometry(Context &ctx, const UnitPositions &pos, MpasMesh &m) {
    const double r = m.radius_m, r2 = r * r;
    const size_t w = static_cast<size_t>(m.max_edges);
    resize_all(pos.cell.size(), {&m.x_cell, &m.y_cell, &m.z_cell, &m.lat_cell, &m.lon_cell,
                                 &m.area_cell});
    ctx.parallel_for(m.n_cells, 4096, [&](int64_t b, int64_t e) {
        for (int64_t c = b; c < e; ++c) {
            place(pos.cell, r, m.x_cell, m.y_cell, m.z_cell, m.lat_cell, m.lon_cell, c);
            // The power cell's polygon fanned from the centroid of its corners:
            // the generator may lie outside its own cell.
            const int32_t *corner = &m.vertices_on_cell[w * c];
            const int d = m.n_edges_on_cell[c];
            Vec3 sum{};
            for (int j = 0; j < d; ++j) sum = sum + pos.vertex[corner[j]];
            Vec3 centre = geom::normalized(sum);
            double area = 0;
            for (int j = 0; j < d; ++j)
                area += signed_area(centre, pos.vertex[corner[j]], pos.vertex[corner[(j + 1) % d]]);
            m.area_cell[c] = r2 * area;
        }
    });
}

void edge_geometry(Context &ctx, const UnitPositions &pos, MpasMesh &m) {
    const double r = m.radius_m;
    resize_all(pos.edge.size(), {&m.x_edge, &m.y_edge, &m.z_edge, &m.lat_edge, &m.lon_edge,
                                 &m.dc_edge, &m.dv_edge, &m.angle_edge});
    ctx.parallel_for(m.n_edges, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            place(pos.edge, r, m.x_edge, m.y_edge, m.z_edge, m.lat_edge, m.lon_edge, i);
            const Vec3 &c1 = pos.cell[m.cells_on_edge[2 * i]], &c2 = pos.cell[m.cells_on_edge[2 * i + 1]];
            const Vec3 &v1 = pos.vertex[m.vertices_on_edge[2 * i]];
            const Vec3 &v2 = pos.vertex[m.vertices_on_edge[2 * i + 1]];
            m.dc_edge[i] = r * arc(c1, c2);
            m.dv_edge[i] = r * arc(v1, v2);
            // n_e is the direction of the arc c1 -> c2 at xEdge, (c1 x c2) x xEdge.
            // The dual arc is exactly perpendicular, so this is the normal of
            // recompute_angle_edge, (v2 - v1) x xEdge, without its rounding on
            // the metre-long dual edges of nearly cocircular quadruples.
            m.angle_edge[i] = angle_from_east(geom::cross(geom::cross(c1, c2), pos.edge[i]), pos.edge[i]);
        }
    });
}

// areaTriangle: the generator triangle. Kite j of vertex v: the quad
// (v, xEdge_j, xCell_j, xEdge_j+1), signed, as two triangles from v; the
// edge points lie on the cell-cell arcs, so the kites add up to the triangle.
void vertex_geometry(Context &ctx, const UnitPositions &pos, MpasMesh &m) {
    const double r = m.radius_m, r2 = r * r;
    resize_all(pos.vertex.size(), {&m.x_vertex, &m.y_vertex, &m.z_vertex, &m.lat_vertex,
                                   &m.lon_vertex, &m.area_triangle});
    m.kite_areas_on_vertex.resize(3 * pos.vertex.size());
    ctx.parallel_for(m.n_vertices, 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            place(pos.vertex, r, m.x_vertex, m.y_vertex, m.z_vertex, m.lat_vertex, m.lon_vertex, v);
            const int32_t *cell = &m.cells_on_vertex[3 * v], *edge = &m.edges_on_vertex[3 * v];
            const Vec3 &o = pos.vertex[v];
            m.area_triangle[v] = r2 * signed_area(pos.cell[cell[0]], pos.cell[cell[1]], pos.cell[cell[2]]);
            for (int j = 0; j < 3; ++j) {
                const Vec3 &x = pos.cell[cell[j]];
                const Vec3 &before = pos.edge[edge[j]], &after = pos.edge[edge[(j + 1) % 3]];
                m.kite_areas_on_vertex[3 * v + j] =
                    r2 * (signed_area(o, before, x) + signed_area(o, x, after));
            }
        }
    });
}

}  // namespace

void cross_edge_points(Context &ctx, UnitPositions &pos, const MpasMesh &m) {
    ctx.parallel_for(m.n_edges, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i)
            pos.edge[i] = arc_crossing(pos.cell[m.cells_on_edge[2 * i]], pos.cell[m.cells_on_edge[2 * i + 1]],
                                       pos.vertex[m.vertices_on_edge[2 * i]], pos.vertex[m.vertices_on_edge[2 * i + 1]],
                                       pos.edge[i]);
    });
}

void fill_geometry(Context &ctx, const UnitPositions &pos, MpasMesh &m) {
    cell_geometry(ctx, pos, m);
    edge_geometry(ctx, pos, m);
    vertex_geometry(ctx, pos, m);
}

}  // namespace um::dual
