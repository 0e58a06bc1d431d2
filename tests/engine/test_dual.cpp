// Engine tests of the MPAS staggered mesh (lib/dual) and its netCDF writer
// (lib/io/mpas_writer): every invariant of the MPAS mesh contract
// (shared/mpas-format.md) on icosahedral, weighted and refined meshes, thread
// independence, and a netCDF round trip. The checks use their own geometry
// (geom/sphere.hpp), not lib/dual's.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <random>
#include <string>

#include <netcdf.h>

#include "core/error.hpp"
#include "core/options.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/mpas_source.hpp"
#include "dual/spherical.hpp"
#include "features/network.hpp"
#include "hfun/spacing.hpp"
#include "io/direct_regions.hpp"
#include "io/mpas_writer.hpp"
#include "io/replacing_file.hpp"
#include "mesh/refined_mesh.hpp"
#include "support/point_sets.hpp"
#include "tri/triangulation.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
#include <dirent.h>
#include <sys/resource.h>
#include <unistd.h>
}

using namespace um;
using dual::kNone;
using dual::MpasMesh;
using geom::Vec3;

namespace {

constexpr double kRadius = 6371220.0;

tri::Triangulation triangulate(const std::vector<Vec3> &pts, const std::vector<double> *weights,
                               int threads = 1) {
    Context ctx;
    ctx.set_threads(threads);
    tri::Triangulation t;
    t.build(ctx, static_cast<int64_t>(pts.size()), [&](int64_t i) { return pts[i]; },
            weights ? weights->data() : nullptr);
    return t;
}

MpasMesh staggered(const tri::Triangulation &t, int threads = 1) {
    Context ctx;
    ctx.set_threads(threads);
    dual::MpasMeshInput in;
    in.radius_m = kRadius;
    return dual::build_mpas_mesh(ctx, t, in);
}

Vec3 unit_at(const std::vector<double> &x, const std::vector<double> &y,
             const std::vector<double> &z, int32_t i) {
    return geom::normalized({x[i], y[i], z[i]});
}

struct Units {
    std::vector<Vec3> cell, edge, vertex;
    explicit Units(const MpasMesh &m) {
        for (int32_t i = 0; i < m.n_cells; ++i) cell.push_back(unit_at(m.x_cell, m.y_cell, m.z_cell, i));
        for (int32_t i = 0; i < m.n_edges; ++i) edge.push_back(unit_at(m.x_edge, m.y_edge, m.z_edge, i));
        for (int32_t i = 0; i < m.n_vertices; ++i)
            vertex.push_back(unit_at(m.x_vertex, m.y_vertex, m.z_vertex, i));
    }
};

void expect_below(double value, double bound, const char *what) {
    if (!(value <= bound)) fail_msg("%s: %.3e above %.3e", what, value, bound);
}

// ------------------------------------------------------------------ topology

void check_counts(const MpasMesh &m) {
    assert_int_equal(m.n_cells - m.n_edges + m.n_vertices, 2);
    int64_t sum = 0;
    int32_t most = 0;
    for (int32_t c = 0; c < m.n_cells; ++c) {
        sum += m.n_edges_on_cell[c];
        most = std::max(most, m.n_edges_on_cell[c]);
        assert_true(m.n_edges_on_cell[c] >= 3);
    }
    assert_int_equal(sum, 2 * int64_t(m.n_edges));
    assert_int_equal(3 * int64_t(m.n_vertices), 2 * int64_t(m.n_edges));
    assert_int_equal(most, m.max_edges);
}

// Each edge e of cell c: c is on e, cellsOnCell is the cell across,
// verticesOnCell(c, j) is the counter-clockwise end of edgesOnCell(c, j) and
// is shared with edgesOnCell(c, j + 1); padding is kNone.
void check_cells(const MpasMesh &m) {
    const int w = m.max_edges;
    std::vector<int> seen(static_cast<size_t>(m.n_edges), 0);
    for (int32_t c = 0; c < m.n_cells; ++c) {
        const int d = m.n_edges_on_cell[c];
        for (int j = 0; j < w; ++j) {
            int32_t e = m.edges_on_cell[w * c + j], v = m.vertices_on_cell[w * c + j];
            int32_t across = m.cells_on_cell[w * c + j];
            if (j >= d) {
                assert_int_equal(e, kNone), assert_int_equal(v, kNone), assert_int_equal(across, kNone);
                continue;
            }
            assert_true(e >= 0 && e < m.n_edges);
            ++seen[e];
            const int32_t *ce = &m.cells_on_edge[2 * e], *ve = &m.vertices_on_edge[2 * e];
            assert_true(ce[0] == c || ce[1] == c);
            assert_int_equal(across, ce[0] == c ? ce[1] : ce[0]);
            assert_int_equal(v, ce[0] == c ? ve[1] : ve[0]);
            int32_t next = m.edges_on_cell[w * c + (j + 1) % d];
            assert_true(m.vertices_on_edge[2 * next] == v || m.vertices_on_edge[2 * next + 1] == v);
        }
    }
    for (int32_t e = 0; e < m.n_edges; ++e) {
        assert_int_equal(seen[e], 2);
        assert_true(m.cells_on_edge[2 * e] < m.cells_on_edge[2 * e + 1]);
    }
}

// cellsOnVertex(v, j) lies between edgesOnVertex(v, j) and (v, j + 1); every
// edge is on both its vertices; v is a corner of each of its cells.
void check_vertices(const MpasMesh &m) {
    std::vector<int> seen(static_cast<size_t>(m.n_edges), 0);
    const int w = m.max_edges;
    for (int32_t v = 0; v < m.n_vertices; ++v)
        for (int j = 0; j < 3; ++j) {
            int32_t e = m.edges_on_vertex[3 * v + j], e1 = m.edges_on_vertex[3 * v + (j + 1) % 3];
            int32_t c = m.cells_on_vertex[3 * v + j];
            ++seen[e];
            assert_true(m.vertices_on_edge[2 * e] == v || m.vertices_on_edge[2 * e + 1] == v);
            assert_true(m.cells_on_edge[2 * e] == c || m.cells_on_edge[2 * e + 1] == c);
            assert_true(m.cells_on_edge[2 * e1] == c || m.cells_on_edge[2 * e1 + 1] == c);
            const int32_t *corners = &m.vertices_on_cell[w * c];
            assert_int_equal(std::count(corners, corners + m.n_edges_on_cell[c], v), 1);
        }
    for (int32_t e = 0; e < m.n_edges; ++e) assert_int_equal(seen[e], 2);
}

// ------------------------------------------------------------------ geometry

void check_positions(const MpasMesh &m, const Units &u) {
    double worst = 0;
    auto one = [&](const std::vector<double> &x, const std::vector<double> &y,
                   const std::vector<double> &z, const std::vector<double> &lat,
                   const std::vector<double> &lon, const std::vector<Vec3> &unit) {
        for (size_t i = 0; i < unit.size(); ++i) {
            double r = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]);
            worst = std::max(worst, std::fabs(r / kRadius - 1));
            Vec3 back = geom::unit_from_lonlat_deg(lon[i] * 180 / M_PI, lat[i] * 180 / M_PI);
            worst = std::max(worst, geom::norm(back - unit[i]));
            assert_true(lon[i] > -M_PI && lon[i] <= M_PI);
        }
    };
    one(m.x_cell, m.y_cell, m.z_cell, m.lat_cell, m.lon_cell, u.cell);
    one(m.x_edge, m.y_edge, m.z_edge, m.lat_edge, m.lon_edge, u.edge);
    one(m.x_vertex, m.y_vertex, m.z_vertex, m.lat_vertex, m.lon_vertex, u.vertex);
    expect_below(worst, 1e-13, "positions: radius and lat/lon");
}

// Lengths, orthogonality, xEdge on both arcs, orientation, angleEdge.
void check_edges(const MpasMesh &m, const Units &u) {
    double length = 0, orth = 0, on_arcs = 0, angle = 0;
    for (int32_t e = 0; e < m.n_edges; ++e) {
        Vec3 c1 = u.cell[m.cells_on_edge[2 * e]], c2 = u.cell[m.cells_on_edge[2 * e + 1]];
        Vec3 v1 = u.vertex[m.vertices_on_edge[2 * e]], v2 = u.vertex[m.vertices_on_edge[2 * e + 1]];
        Vec3 x = u.edge[e];
        double dc = kRadius * geom::arc_length(c1, c2), dv = kRadius * geom::arc_length(v1, v2);
        length = std::max({length, std::fabs(m.dc_edge[e] / dc - 1), std::fabs(m.dv_edge[e] / dv - 1)});
        // The dual arc is the great circle through xEdge perpendicular to the
        // primal arc: its plane's normal is the primal arc's tangent at xEdge,
        // and both vertices lie on it. (Measured this way, not by the angle
        // between the planes through (c1, c2) and (v1, v2), because the
        // latter is ill-conditioned on the few-metre dual edges of nearly
        // cocircular quadruples.)
        Vec3 nc = geom::normalized(geom::cross(c1, c2));
        Vec3 tangent = geom::normalized(geom::cross(nc, x));
        orth = std::max({orth, std::fabs(geom::dot(tangent, v1)), std::fabs(geom::dot(tangent, v2))});
        on_arcs = std::max(on_arcs, std::fabs(geom::dot(x, nc)));
        if (!(geom::dot(geom::cross(c2 - c1, v2 - v1), x) > 0))
            fail_msg("edge %d: orientation %.3e, dv %.3e m, dc %.3e m", e,
                     geom::dot(geom::cross(c2 - c1, v2 - v1), x), m.dv_edge[e], m.dc_edge[e]);
        // angleEdge from scratch: the direction c1 -> c2 at xEdge against east.
        if (std::hypot(x.x, x.y) < 1e-9) continue;  // east undefined at a pole
        Vec3 normal = geom::cross(geom::cross(c1, c2), x);
        Vec3 east = geom::normalized({-x.y, x.x, 0});
        Vec3 north = geom::cross(x, east);
        double a = std::atan2(geom::dot(normal, north), geom::dot(normal, east));
        double d = std::remainder(m.angle_edge[e] - a, 2 * M_PI);
        angle = std::max(angle, std::fabs(d));
        assert_true(std::fabs(m.angle_edge[e]) <= M_PI);
    }
    // Relative to the arc, as the contract has it; the arcs recomputed here
    // carry rounding of about 1e-16 / length, large on the near-degenerate
    // short dual edges of symmetric meshes.
    expect_below(length, 1e-10, "dcEdge / dvEdge against arcs");
    // Rounding only, but of orthocentres whose value depends in the last
    // bits on which vertex of their triangle comes first, which the
    // insertion order decides: 1.03e-13 was seen on the heavily weighted
    // mesh below after the BRIO rounds changed, against 1e-13 before.
    expect_below(orth, 2e-13, "vertices on the great circle perpendicular to the primal arc at xEdge");
    expect_below(on_arcs, 1e-14, "xEdge on the primal great circle");
    expect_below(angle, 1e-12, "angleEdge");
}

// Power cells convex and counter-clockwise; areaCell the polygon (fanned
// from corner 0 here); areaTriangle the generator triangle; kites sum to
// both; totals 4 pi R^2.
void check_areas(const MpasMesh &m, const Units &u) {
    const int w = m.max_edges;
    const double r2 = kRadius * kRadius;
    double cell = 0, triangle = 0, kite_tri = 0, kite_cell = 0;
    long double total_cells = 0, total_triangles = 0;
    std::vector<double> kites_of_cell(static_cast<size_t>(m.n_cells), 0.0);
    for (int32_t c = 0; c < m.n_cells; ++c) {
        const int d = m.n_edges_on_cell[c];
        const int32_t *corner = &m.vertices_on_cell[w * c];
        double area = 0;
        for (int j = 0; j < d; ++j) {
            Vec3 a = u.vertex[corner[j]], b = u.vertex[corner[(j + 1) % d]];
            Vec3 cc = u.vertex[corner[(j + 2) % d]];
            assert_true(geom::dot(a, geom::cross(b, cc)) > 0);
            if (j > 0 && j < d - 1) area += geom::signed_triangle_area(u.vertex[corner[0]], a, b);
        }
        cell = std::max(cell, std::fabs(m.area_cell[c] / (r2 * area) - 1));
        assert_true(m.area_cell[c] > 0);
        total_cells += m.area_cell[c];
    }
    for (int32_t v = 0; v < m.n_vertices; ++v) {
        const int32_t *cv = &m.cells_on_vertex[3 * v];
        double area = r2 * geom::signed_triangle_area(u.cell[cv[0]], u.cell[cv[1]], u.cell[cv[2]]);
        assert_true(area > 0);
        triangle = std::max(triangle, std::fabs(m.area_triangle[v] / area - 1));
        total_triangles += m.area_triangle[v];
        double sum = 0;
        for (int j = 0; j < 3; ++j) {
            sum += m.kite_areas_on_vertex[3 * v + j];
            kites_of_cell[cv[j]] += m.kite_areas_on_vertex[3 * v + j];
        }
        kite_tri = std::max(kite_tri, std::fabs(sum / m.area_triangle[v] - 1));
    }
    for (int32_t c = 0; c < m.n_cells; ++c)
        kite_cell = std::max(kite_cell, std::fabs(kites_of_cell[c] / m.area_cell[c] - 1));
    const double sphere = 4 * M_PI * r2;
    expect_below(cell, 1e-10, "areaCell against the polygon");
    expect_below(triangle, 1e-10, "areaTriangle against the triangle");
    expect_below(kite_tri, 1e-12, "kites against areaTriangle");
    // Looser: where a generator lies outside its small power cell, its kites
    // nearly cancel and their sum carries their rounding.
    expect_below(kite_cell, 1e-11, "kites against areaCell");
    expect_below(std::fabs(double(total_cells) / sphere - 1), 1e-10, "sum of areaCell");
    expect_below(std::fabs(double(total_triangles) / sphere - 1), 1e-10, "sum of areaTriangle");
}

// ------------------------------------------------------------------ TRSK

void check_trsk(const MpasMesh &m) {
    const int w2 = m.max_edges2();
    // Stencil: the other edges of both cells, n(c1) + n(c2) - 2 of them.
    std::map<std::pair<int32_t, int32_t>, double> a;
    double scale = 0;
    for (int32_t e = 0; e < m.n_edges; ++e) {
        const int32_t *c = &m.cells_on_edge[2 * e];
        assert_int_equal(m.n_edges_on_edge[e], m.n_edges_on_cell[c[0]] + m.n_edges_on_cell[c[1]] - 2);
        for (int k = 0; k < w2; ++k) {
            if (k >= m.n_edges_on_edge[e]) {
                assert_int_equal(m.edges_on_edge[w2 * e + k], kNone);
                assert_true(m.weights_on_edge[w2 * e + k] == 0.0);
                continue;
            }
            double value = m.weights_on_edge[w2 * e + k] * m.dc_edge[e] * m.dv_edge[e];
            a[{e, m.edges_on_edge[w2 * e + k]}] += value;
            scale = std::max(scale, std::fabs(value));
        }
    }
    // Antisymmetry of W dc dv: the Coriolis term conserves energy.
    double worst = 0;
    for (const auto &[key, value] : a) {
        auto it = a.find({key.second, key.first});
        worst = std::max(worst, std::fabs(value + (it == a.end() ? 0.0 : it->second)));
    }
    expect_below(worst / scale, 1e-13, "TRSK antisymmetry");
    // Thuburn et al. (2009): at each vertex the dual divergence of the
    // reconstructed tangential flux is the kite average of the primal ones.
    std::mt19937_64 rng(99);
    std::normal_distribution<double> g;
    std::vector<double> u(static_cast<size_t>(m.n_edges)), vt(u.size(), 0.0);
    for (double &x : u) x = g(rng);
    std::vector<double> div(static_cast<size_t>(m.n_cells), 0.0), lhs(static_cast<size_t>(m.n_vertices), 0.0);
    for (int32_t e = 0; e < m.n_edges; ++e) {
        for (int k = 0; k < m.n_edges_on_edge[e]; ++k)
            vt[e] += m.weights_on_edge[w2 * e + k] * u[m.edges_on_edge[w2 * e + k]];
        div[m.cells_on_edge[2 * e]] += u[e] * m.dv_edge[e];
        div[m.cells_on_edge[2 * e + 1]] -= u[e] * m.dv_edge[e];
        lhs[m.vertices_on_edge[2 * e]] += vt[e] * m.dc_edge[e];
        lhs[m.vertices_on_edge[2 * e + 1]] -= vt[e] * m.dc_edge[e];
    }
    double rhs_scale = 0, diff = 0;
    for (int32_t v = 0; v < m.n_vertices; ++v) {
        double rhs = 0;
        for (int j = 0; j < 3; ++j) {
            int32_t c = m.cells_on_vertex[3 * v + j];
            rhs += m.kite_areas_on_vertex[3 * v + j] * div[c] / m.area_cell[c];
        }
        rhs_scale = std::max(rhs_scale, std::fabs(rhs));
        diff = std::max(diff, std::fabs(lhs[v] - rhs));
    }
    expect_below(diff / rhs_scale, 1e-11, "Thuburn vertex identity");
}

void check_all(const MpasMesh &m) {
    check_counts(m);
    check_cells(m);
    check_vertices(m);
    Units u(m);
    check_positions(m, u);
    check_edges(m, u);
    check_areas(m, u);
    check_trsk(m);
    for (double d : m.mesh_density) assert_true(d == 1.0);
    for (int32_t b : m.boundary_vertex) assert_int_equal(b, 0);
}

// Neighbours have nearby numbers: the mean |c1 - c2| over the edges is a
// small fraction of the cell count.
// xEdge is the crossing of the primal and dual great circles on the side of
// the edge point. Near the primal arc's midpoint (every edge of a real
// mesh) the side is taken without making the edge point; a crossing far
// from it (here 80 degrees along the primal circle, a cell as large as a
// hemisphere) asks for the edge point and takes its side, whichever it is.
void arc_crossing_takes_the_edge_points_side(void **) {
    const double rad = M_PI / 180;
    auto on_equator = [&](double lon) { return Vec3{std::cos(lon * rad), std::sin(lon * rad), 0.0}; };
    auto on_meridian = [&](double lon, double lat) {
        return Vec3{std::cos(lat * rad) * std::cos(lon * rad), std::cos(lat * rad) * std::sin(lon * rad),
                    std::sin(lat * rad)};
    };
    const Vec3 c1 = on_equator(0), c2 = on_equator(0.6);
    auto crossing = [&](double dual_lon, Vec3 edge_point, int &asked) {
        return dual::arc_crossing(c1, c2, on_meridian(dual_lon, 0.2), on_meridian(dual_lon, -0.2), [&] {
            ++asked;
            return edge_point;
        });
    };
    int asked = 0;
    Vec3 x = crossing(0.3, on_equator(0.3), asked);
    assert_int_equal(asked, 0);
    expect_below(geom::norm(x - on_equator(0.3)), 1e-15, "crossing at the midpoint");
    x = crossing(80, on_equator(80), asked);
    assert_int_equal(asked, 1);
    expect_below(geom::norm(x - on_equator(80)), 1e-15, "crossing 80 degrees away, on the edge point's side");
    x = crossing(80, on_equator(260), asked);
    assert_int_equal(asked, 2);
    expect_below(geom::norm(x - on_equator(260)), 1e-15, "crossing 80 degrees away, the other side");
}

void expect_local_numbering(const MpasMesh &m) {
    double sum = 0;
    for (int32_t e = 0; e < m.n_edges; ++e)
        sum += m.cells_on_edge[2 * e + 1] - m.cells_on_edge[2 * e];
    expect_below(sum / m.n_edges, 0.1 * m.n_cells, "mean index gap across edges (random: n/3)");
}

// Small random weights: |w| <= 0.2 h^2 with h the mean spacing, and the
// points jittered by 0.2 h, so that power cells differ from Voronoi cells.
void jittered_weighted(int level, uint64_t seed, std::vector<Vec3> &pts, std::vector<double> &w) {
    pts = test::icosahedral_points(level);
    const double h = std::sqrt(4 * M_PI / pts.size());
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.2 * h, 0.2 * h), weight(-0.2 * h * h, 0.2 * h * h);
    w.clear();
    for (Vec3 &p : pts) {
        p = geom::normalized(p + Vec3{jitter(rng), jitter(rng), jitter(rng)});
        w.push_back(weight(rng));
    }
}

// ------------------------------------------------------------------ tests

void icosahedral_mesh(void **) {
    for (int level : {2, 4}) {
        auto pts = test::icosahedral_points(level);
        tri::Triangulation t = triangulate(pts, nullptr);
        MpasMesh m = staggered(t);
        assert_int_equal(m.n_cells, static_cast<int32_t>(pts.size()));
        check_all(m);
        if (level == 4) expect_local_numbering(m);
        // Unweighted: the vertices are the circumcentres, xEdge the midpoints.
        for (int32_t e = 0; e < m.n_edges; ++e) {
            Vec3 c1 = geom::normalized({m.x_cell[m.cells_on_edge[2 * e]], m.y_cell[m.cells_on_edge[2 * e]],
                                        m.z_cell[m.cells_on_edge[2 * e]]});
            Vec3 c2 = geom::normalized({m.x_cell[m.cells_on_edge[2 * e + 1]], m.y_cell[m.cells_on_edge[2 * e + 1]],
                                        m.z_cell[m.cells_on_edge[2 * e + 1]]});
            Vec3 x = geom::normalized({m.x_edge[e], m.y_edge[e], m.z_edge[e]});
            assert_true(std::fabs(geom::arc_length(c1, x) - geom::arc_length(x, c2)) < 1e-12);
        }
    }
}

void weighted_mesh(void **) {
    std::vector<Vec3> pts;
    std::vector<double> w;
    jittered_weighted(4, 5, pts, w);
    tri::Triangulation t = triangulate(pts, &w);
    MpasMesh m = staggered(t);
    assert_int_equal(m.n_cells, t.vertex_count());
    check_all(m);
    expect_local_numbering(m);
    // The weights moved the vertices off the circumcentres and xEdge off
    // the midpoints.
    double off = 0;
    for (int32_t e = 0; e < m.n_edges; ++e) {
        Vec3 c1 = geom::normalized({m.x_cell[m.cells_on_edge[2 * e]], m.y_cell[m.cells_on_edge[2 * e]],
                                    m.z_cell[m.cells_on_edge[2 * e]]});
        Vec3 c2 = geom::normalized({m.x_cell[m.cells_on_edge[2 * e + 1]], m.y_cell[m.cells_on_edge[2 * e + 1]],
                                    m.z_cell[m.cells_on_edge[2 * e + 1]]});
        Vec3 x = geom::normalized({m.x_edge[e], m.y_edge[e], m.z_edge[e]});
        off = std::max(off, std::fabs(geom::arc_length(c1, x) - geom::arc_length(x, c2)) /
                                geom::arc_length(c1, c2));
    }
    assert_true(off > 0.01);
}

// The layout keeps each vertex's unit position: it must be the orthocentre
// of the vertex's triangle to the bit, in row order, on two threads as on
// one (the rows and kites take it from there instead of the triangulation).
void layout_keeps_each_vertex_orthocentre(void **) {
    std::vector<Vec3> pts;
    std::vector<double> w;
    jittered_weighted(4, 7, pts, w);
    tri::Triangulation t = triangulate(pts, &w);
    for (int threads : {1, 2}) {
        Context ctx;
        ctx.set_threads(threads);
        const dual::MpasLayout layout(ctx, t, {});
        assert_int_equal(layout.n_vertices(), t.triangle_count());
        for (int32_t v = 0; v < layout.n_vertices(); ++v) {
            const Vec3 kept = layout.vertex_unit(v), made = t.orthocentre(layout.vertex_triangle(v));
            assert_memory_equal(&kept, &made, sizeof(Vec3));
        }
    }
}

// Cells from 200 m to 1,000 km wide: a graded log-polar patch
// (rings 1.3 times wider each, 24 points a ring, from 1e-4 rad = 640 m) in
// an icosahedral grid. The staggered mesh must stay consistent on the
// smallest cells to the contract's 1e-10 relative: a cell's kites add up to
// its areaCell, areaCell is its polygon (fanned from a corner with the
// relative-accuracy determinant, in long double), and the TRSK weights are
// the formula from the kites and areaCell as stored (what mpas_check.py
// recomputes). With xEdge on the primal great circle only, the sliver it
// left off the dual arc put the kites of the smallest cells (~170 m wide)
// 1e-7 off their areaCell (4e-12 now: the rounding of their corners).
void small_cells_stay_consistent(void **) {
    std::vector<Vec3> pts;
    const Vec3 centre = geom::normalized({0.3, -0.5, 0.8});
    const Vec3 e1 = geom::normalized(geom::cross(centre, {0, 0, 1})), e2 = geom::cross(centre, e1);
    pts.push_back(centre);
    for (double r = 1e-4, k = 0; r < 0.5; r *= 1.3, ++k)
        for (int j = 0; j < 24; ++j) {
            const double a = (j + 0.5 * k) * 2 * M_PI / 24;
            pts.push_back(geom::normalized(centre + r * std::cos(a) * e1 + r * std::sin(a) * e2));
        }
    for (const Vec3 &p : test::icosahedral_points(3))
        if (geom::arc_length(p, centre) > 0.7) pts.push_back(p);
    MpasMesh m = staggered(triangulate(pts, nullptr));
    Units u(m);
    const int w = m.max_edges, w2 = m.max_edges2();
    std::vector<double> kites_of_cell(static_cast<size_t>(m.n_cells), 0.0);
    for (int32_t v = 0; v < m.n_vertices; ++v)
        for (int j = 0; j < 3; ++j) kites_of_cell[m.cells_on_vertex[3 * v + j]] += m.kite_areas_on_vertex[3 * v + j];
    auto polygon = [&](int32_t c) {  // steradians
        const int32_t *corner = &m.vertices_on_cell[w * c];
        long double area = 0;
        for (int j = 1; j + 1 < m.n_edges_on_cell[c]; ++j) {
            long double a[3] = {u.vertex[corner[0]].x, u.vertex[corner[0]].y, u.vertex[corner[0]].z};
            long double b[3] = {u.vertex[corner[j]].x, u.vertex[corner[j]].y, u.vertex[corner[j]].z};
            long double d[3] = {u.vertex[corner[j + 1]].x, u.vertex[corner[j + 1]].y, u.vertex[corner[j + 1]].z};
            long double p[3], q[3];
            for (int i = 0; i < 3; ++i) p[i] = b[i] - a[i], q[i] = d[i] - a[i];
            const long double det = a[0] * (p[1] * q[2] - p[2] * q[1]) + a[1] * (p[2] * q[0] - p[0] * q[2]) +
                                    a[2] * (p[0] * q[1] - p[1] * q[0]);
            const long double den = 1 + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) +
                                    (b[0] * d[0] + b[1] * d[1] + b[2] * d[2]) + (d[0] * a[0] + d[1] * a[1] + d[2] * a[2]);
            area += 2 * std::atan2(det, den);
        }
        return static_cast<double>(area);
    };
    double kites = 0, areas = 0, smallest = 1e300;
    for (int32_t c = 0; c < m.n_cells; ++c) {
        kites = std::max(kites, std::fabs(kites_of_cell[c] / m.area_cell[c] - 1));
        areas = std::max(areas, std::fabs(m.area_cell[c] / (kRadius * kRadius * polygon(c)) - 1));
        smallest = std::min(smallest, m.area_cell[c]);
    }
    // The weights as mpas_check.py recomputes them, with areaCell.
    double weights = 0, scale = 0;
    for (int32_t e = 0; e < m.n_edges; ++e) {
        int k = 0;
        for (int side = 0; side < 2; ++side) {
            const int32_t cell = m.cells_on_edge[2 * e + side];
            const int n = m.n_edges_on_cell[cell];
            int j0 = 0;
            while (m.edges_on_cell[w * cell + j0] != e) ++j0;
            double passed = 0;
            for (int step = 1; step < n; ++step, ++k) {
                const int j = (j0 + step) % n;
                const int32_t other = m.edges_on_cell[w * cell + j], corner = m.vertices_on_cell[w * cell + (j + n - 1) % n];
                for (int i = 0; i < 3; ++i)
                    if (m.cells_on_vertex[3 * corner + i] == cell) passed += m.kite_areas_on_vertex[3 * corner + i] / m.area_cell[cell];
                const double sign = (m.cells_on_edge[2 * other] == cell ? 1.0 : -1.0) * (side == 1 ? -1.0 : 1.0);
                const double formula = sign * (0.5 - passed) * m.dv_edge[other] / m.dc_edge[e];
                weights = std::max(weights, std::fabs(formula - m.weights_on_edge[w2 * e + k]));
                scale = std::max(scale, std::fabs(formula));
            }
        }
    }
    print_message("cells of %.3g to %.3g m^2: kites/areaCell - 1 = %.2g, areaCell/polygon - 1 = %.2g, weights %.2g\n",
                  smallest, *std::max_element(m.area_cell.begin(), m.area_cell.end()), kites, areas, weights / scale);
    assert_true(smallest < 1e5);
    expect_below(kites, 1e-11, "kites against areaCell, 200 m cells");
    expect_below(areas, 1e-10, "areaCell against the polygon, 200 m cells");
    expect_below(weights / scale, 1e-10, "TRSK weights against the formula with areaCell");
    check_trsk(m);
}

// Large weights hide some points: they are no cells, and a numbering that
// lists them is refused.
void hidden_points_are_not_cells(void **) {
    std::vector<Vec3> pts;
    std::vector<double> w;
    jittered_weighted(3, 23, pts, w);
    const double h = std::sqrt(4 * M_PI / pts.size());
    for (size_t i = 0; i < w.size(); i += 7) w[i] = 1.5 * h * h;
    tri::Triangulation t = triangulate(pts, &w);
    assert_true(t.vertex_count() < static_cast<int64_t>(pts.size()));
    MpasMesh m = staggered(t);
    assert_int_equal(m.n_cells, t.vertex_count());
    check_all(m);
    Context ctx;
    dual::MpasMeshInput in;
    in.radius_m = kRadius;
    for (int32_t v = 0; v < t.vertex_slots(); ++v) in.slot_of_vertex.push_back(v);
    try {
        dual::build_mpas_mesh(ctx, t, in);
        fail_msg("a numbering with hidden slots was accepted");
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_INTERNAL);
    }
    in.slot_of_vertex.clear();
    in.radius_m = -1;
    try {
        dual::build_mpas_mesh(ctx, t, in);
        fail_msg("a negative radius was accepted");
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_INVALID_ARGUMENT);
    }
}

std::shared_ptr<const features::Network> square_island() {
    // A closed coastline around a 30 x 30 degree "continent".
    const double lon[] = {-20, 10, 10, -20}, lat[] = {-10, -10, 20, 20};
    const int64_t offsets[] = {0, 4};
    const int32_t closed[] = {1}, kind[] = {UM_FEATURE_COASTLINE};
    features::PartsInput in;
    in.n_points = 4, in.lon_deg = lon, in.lat_deg = lat, in.n_parts = 1;
    in.part_offsets = offsets, in.closed = closed, in.kind = kind;
    auto net = std::make_shared<features::Network>();
    net->add(in);
    return net;
}

// The refinement stage's mesh, with its numbering, radius and sides.
void refined_mesh_with_sides(void **) {
    Context ctx;
    ctx.set_threads(1);
    Options options;
    auto h = hfun::make_constant(600.0);
    mesh::RefinedMesh refined = mesh::refine_mesh(ctx, h, square_island(), options);
    MpasMesh m = dual::build_mpas_mesh(ctx, refined);
    assert_int_equal(m.n_cells, refined.vertex_count());
    assert_true(m.radius_m == options.real(UM_OPT_SPHERE_RADIUS));
    check_all(m);
    expect_local_numbering(m);
    assert_int_equal(m.cell_side.size(), m.n_cells);
    assert_int_equal(m.vertex_side.size(), m.n_vertices);
    int count[3] = {0, 0, 0};
    for (int32_t c = 0; c < m.n_cells; ++c) {
        assert_true(m.cell_side[c] >= 0 && m.cell_side[c] <= 2);
        ++count[m.cell_side[c]];
        // Cell c is mesh vertex cell_source_vertex[c]: its side is that vertex's.
        int32_t slot = refined.slot_of_vertex[m.cell_source_vertex[c]];
        assert_int_equal(m.cell_side[c], static_cast<int32_t>(refined.vertex_side[slot]));
        double lon = m.lon_cell[c] * 180 / M_PI, lat = m.lat_cell[c] * 180 / M_PI;
        if (std::fabs(lon + 5) < 8 && std::fabs(lat - 5) < 8) assert_int_equal(m.cell_side[c], UM_SIDE_LAND);
        if (std::fabs(lat) > 50) assert_int_equal(m.cell_side[c], UM_SIDE_OCEAN);
    }
    assert_true(count[UM_SIDE_OCEAN] > 0 && count[UM_SIDE_LAND] > 0 && count[UM_SIDE_COASTAL] > 0);
    for (int32_t v = 0; v < m.n_vertices; ++v)
        assert_int_equal(m.vertex_side[v],
                         static_cast<int32_t>(refined.triangle_side[m.vertex_source_triangle[v]]));
}

template <class T>
void expect_same(const std::vector<T> &a, const std::vector<T> &b, const char *name) {
    if (a.size() != b.size() || (!a.empty() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) != 0))
        fail_msg("%s differs between thread counts", name);
}

void same_mesh_for_any_thread_count(void **) {
    std::vector<Vec3> pts;
    std::vector<double> w;
    jittered_weighted(6, 17, pts, w);  // 40962 points: every loop splits
    tri::Triangulation t = triangulate(pts, &w);
    MpasMesh a = staggered(t, 1), b = staggered(t, 2);
#define UM_SAME(field) expect_same(a.field, b.field, #field)
    assert_int_equal(a.max_edges, b.max_edges);
    UM_SAME(x_cell), UM_SAME(lat_cell), UM_SAME(lon_cell), UM_SAME(area_cell);
    UM_SAME(n_edges_on_cell), UM_SAME(edges_on_cell), UM_SAME(vertices_on_cell), UM_SAME(cells_on_cell);
    UM_SAME(x_edge), UM_SAME(y_edge), UM_SAME(z_edge), UM_SAME(cells_on_edge), UM_SAME(vertices_on_edge);
    UM_SAME(n_edges_on_edge), UM_SAME(edges_on_edge), UM_SAME(weights_on_edge);
    UM_SAME(dc_edge), UM_SAME(dv_edge), UM_SAME(angle_edge);
    UM_SAME(x_vertex), UM_SAME(cells_on_vertex), UM_SAME(edges_on_vertex);
    UM_SAME(area_triangle), UM_SAME(kite_areas_on_vertex);
#undef UM_SAME
    assert_string_equal(io::mpas_file_id(a).c_str(), io::mpas_file_id(b).c_str());
}

// ------------------------------------------------------------------ netCDF

std::string output_path(const char *name) { return std::string(UNIMESH_TEST_OUTPUT_DIR) + "/" + name; }

std::string file_bytes(const std::string &path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

size_t dim_length(int nc, const char *name) {
    int id = -1;
    size_t n = 0;
    assert_int_equal(nc_inq_dimid(nc, name, &id), NC_NOERR);
    assert_int_equal(nc_inq_dimlen(nc, id, &n), NC_NOERR);
    return n;
}

std::vector<int> read_ints(int nc, const char *name, size_t n) {
    int id = -1;
    nc_type type;
    assert_int_equal(nc_inq_varid(nc, name, &id), NC_NOERR);
    assert_int_equal(nc_inq_vartype(nc, id, &type), NC_NOERR);
    assert_int_equal(type, NC_INT);
    std::vector<int> out(n);
    assert_int_equal(nc_get_var_int(nc, id, out.data()), NC_NOERR);
    return out;
}

std::vector<double> read_doubles(int nc, const char *name, size_t n) {
    int id = -1;
    nc_type type;
    assert_int_equal(nc_inq_varid(nc, name, &id), NC_NOERR);
    assert_int_equal(nc_inq_vartype(nc, id, &type), NC_NOERR);
    assert_int_equal(type, NC_DOUBLE);
    std::vector<double> out(n);
    assert_int_equal(nc_get_var_double(nc, id, out.data()), NC_NOERR);
    return out;
}

std::string text_attribute(int nc, const char *name) {
    size_t n = 0;
    assert_int_equal(nc_inq_attlen(nc, NC_GLOBAL, name, &n), NC_NOERR);
    std::string s(n, '\0');
    assert_int_equal(nc_get_att_text(nc, NC_GLOBAL, name, s.data()), NC_NOERR);
    return s;
}

// Connectivity comes back 1-based with 0 padding.
void expect_indices(const std::vector<int32_t> &mine, const std::vector<int> &file) {
    assert_int_equal(mine.size(), file.size());
    for (size_t i = 0; i < mine.size(); ++i) assert_int_equal(file[i], mine[i] + 1);
}

void netcdf_round_trip(void **) {
    Context ctx;
    Options options;
    mesh::RefinedMesh refined = mesh::refine_mesh(ctx, hfun::make_constant(900.0), square_island(), options);
    MpasMesh m = dual::build_mpas_mesh(ctx, refined);
    const std::string path = output_path("test_dual_round_trip.nc");
    io::write_mpas_mesh(m, path);
    const std::string first = file_bytes(path);
    io::write_mpas_mesh(m, path);
    assert_true(first == file_bytes(path));  // same mesh, same bytes

    int nc = -1, format = 0;
    assert_int_equal(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
    assert_int_equal(nc_inq_format(nc, &format), NC_NOERR);
    assert_int_equal(format, NC_FORMAT_64BIT_OFFSET);
    const size_t nC = m.n_cells, nE = m.n_edges, nV = m.n_vertices, w = m.max_edges;
    assert_int_equal(dim_length(nc, "nCells"), nC);
    assert_int_equal(dim_length(nc, "nEdges"), nE);
    assert_int_equal(dim_length(nc, "nVertices"), nV);
    assert_int_equal(dim_length(nc, "maxEdges"), w);
    assert_int_equal(dim_length(nc, "maxEdges2"), 2 * w);
    assert_int_equal(dim_length(nc, "TWO"), 2);
    assert_int_equal(dim_length(nc, "vertexDegree"), 3);
    assert_int_equal(dim_length(nc, "Time"), 0);
    int unlimited = -1, time = -1;
    assert_int_equal(nc_inq_unlimdim(nc, &unlimited), NC_NOERR);
    assert_int_equal(nc_inq_dimid(nc, "Time", &time), NC_NOERR);
    assert_int_equal(unlimited, time);

    assert_true(read_doubles(nc, "xCell", nC) == m.x_cell);
    assert_true(read_doubles(nc, "lonVertex", nV) == m.lon_vertex);
    assert_true(read_doubles(nc, "areaCell", nC) == m.area_cell);
    assert_true(read_doubles(nc, "weightsOnEdge", nE * 2 * w) == m.weights_on_edge);
    assert_true(read_doubles(nc, "kiteAreasOnVertex", nV * 3) == m.kite_areas_on_vertex);
    assert_true(read_doubles(nc, "angleEdge", nE) == m.angle_edge);
    expect_indices(m.cells_on_edge, read_ints(nc, "cellsOnEdge", 2 * nE));
    expect_indices(m.edges_on_cell, read_ints(nc, "edgesOnCell", nC * w));
    expect_indices(m.edges_on_edge, read_ints(nc, "edgesOnEdge", nE * 2 * w));
    expect_indices(m.cells_on_vertex, read_ints(nc, "cellsOnVertex", 3 * nV));
    std::vector<int> ids = read_ints(nc, "indexToEdgeID", nE);
    for (size_t i = 0; i < nE; ++i) assert_int_equal(ids[i], static_cast<int>(i + 1));
    assert_true(read_ints(nc, "nEdgesOnCell", nC) == m.n_edges_on_cell);
    assert_true(read_ints(nc, "cellSide", nC) == m.cell_side);
    assert_true(read_ints(nc, "vertexSide", nV) == m.vertex_side);

    assert_string_equal(text_attribute(nc, "on_a_sphere").c_str(), "YES");
    assert_string_equal(text_attribute(nc, "is_periodic").c_str(), "NO");
    assert_string_equal(text_attribute(nc, "mesh_spec").c_str(), "1.0");
    assert_string_equal(text_attribute(nc, "Conventions").c_str(), "MPAS");
    assert_string_equal(text_attribute(nc, "source").c_str(), "unimesh " UM_VERSION_STRING);
    assert_string_equal(text_attribute(nc, "file_id").c_str(), io::mpas_file_id(m).c_str());
    double radius = 0;
    assert_int_equal(nc_get_att_double(nc, NC_GLOBAL, "sphere_radius", &radius), NC_NOERR);
    assert_true(radius == m.radius_m);
    int side = -1;
    size_t n_flags = 0;
    assert_int_equal(nc_inq_varid(nc, "cellSide", &side), NC_NOERR);
    assert_int_equal(nc_inq_attlen(nc, side, "flag_values", &n_flags), NC_NOERR);
    assert_int_equal(n_flags, 3);
    assert_int_equal(nc_close(nc), NC_NOERR);
    std::remove(path.c_str());
}

// The streamed file (rows made a block at a time from the layout) has the
// bytes of the whole mesh's file: one row per block, a few, one block; with
// the tags and for any thread count; CDF-5 as well; written around the page
// cache (io/direct_regions.hpp: whole 4 KiB blocks direct, region ends
// through the cache) or through it.
void streamed_file_matches_whole_mesh(void **) {
    Context ctx;
    Options options;
    mesh::RefinedMesh refined = mesh::refine_mesh(ctx, hfun::make_constant(900.0), square_island(), options);
    const std::string whole_path = output_path("test_dual_whole.nc"), path = output_path("test_dual_streamed.nc");
    const MpasMesh m = dual::build_mpas_mesh(ctx, refined);
    assert_false(m.edge_feature_kind.empty());
    for (uint64_t limit : {io::kOffset64VariableLimit, uint64_t(1000)}) {
        io::MpasWriteOptions options;
        options.variable_limit = limit;
        io::write_mpas_mesh(m, whole_path, options);
        const std::string whole = file_bytes(whole_path);
        for (int threads : {1, 3}) {
            Context streaming;
            streaming.set_threads(threads);
            const dual::MpasSource source(streaming, refined);
            for (int64_t rows : {int64_t(1), int64_t(777), dual::kMpasBlockRows})
                for (uint64_t direct_min : {uint64_t(0), ~uint64_t(0)}) {
                    options.block_rows = rows;
                    options.direct_min_bytes = direct_min;
                    io::write_mpas_mesh(streaming, source, path, options);
                    assert_true(file_bytes(path) == whole);
                }
            // Another file system (tmpfs, which may refuse O_DIRECT at the open
            // or at the first write): the same bytes.
            if (::access("/dev/shm", W_OK) == 0) {
                const std::string shm = "/dev/shm/test_dual_streamed_" + std::to_string(::getpid()) + ".nc";
                options.block_rows = 777, options.direct_min_bytes = 0;
                io::write_mpas_mesh(streaming, source, shm, options);
                assert_true(file_bytes(shm) == whole);
                std::remove(shm.c_str());
            }
        }
    }
    std::remove(whole_path.c_str()), std::remove(path.c_str());
}

// Variables too large for a 64-bit offset file switch the file to CDF-5
// (reached here with a small mesh and a small limit).
void large_variables_give_cdf5(void **) {
    auto pts = test::icosahedral_points(2);
    MpasMesh m = staggered(triangulate(pts, nullptr));
    const std::string path = output_path("test_dual_cdf5.nc");
    const uint64_t weights_bytes = m.weights_on_edge.size() * sizeof(double);
    for (uint64_t limit : {weights_bytes, weights_bytes - 1}) {
        io::MpasWriteOptions options;
        options.variable_limit = limit;
        io::write_mpas_mesh(m, path, options);
        int nc = -1, format = 0;
        assert_int_equal(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
        assert_int_equal(nc_inq_format(nc, &format), NC_NOERR);
        assert_int_equal(format, limit == weights_bytes ? NC_FORMAT_64BIT_OFFSET : NC_FORMAT_CDF5);
        assert_true(read_doubles(nc, "weightsOnEdge", m.weights_on_edge.size()) == m.weights_on_edge);
        expect_indices(m.edges_on_edge, read_ints(nc, "edgesOnEdge", m.edges_on_edge.size()));
        assert_int_equal(nc_close(nc), NC_NOERR);
    }
    std::remove(path.c_str());
}

// Every byte of every region lands where it belongs whatever the layout:
// regions smaller than a block, inside one block, aligned or not at either
// end, some empty, gaps between them; pieces from 1 byte to several blocks,
// the regions' pieces interleaved (each region front to back).
void direct_regions_write_every_byte(void **) {
    std::mt19937_64 rng(17);
    for (int round = 0; round < 20; ++round) {
        std::vector<uint64_t> begin, end;
        uint64_t at = rng() % 5000;
        for (int r = 0; r < 12; ++r) {
            at += (rng() % 3 == 0) ? rng() % 9000 : 0;  // a gap or none
            if (rng() % 4 == 0) at = (at + 4095) / 4096 * 4096;  // an aligned begin
            const uint64_t sizes[] = {0, 1, 7, 4095, 4096, 4097, 8192, 30000, 100000};
            begin.push_back(at);
            at += sizes[rng() % 9];
            end.push_back(at);
        }
        std::string expected(at + 100, '\0');
        for (char &c : expected) c = static_cast<char>(rng());
        const std::string path = output_path("test_dual_direct_regions.bin");
        {
            io::ReplacingFile file(path, "test file");
            io::DirectRegions regions(file, begin, end);
            std::vector<uint64_t> next = begin;
            for (bool left = true; left;) {
                left = false;
                for (size_t r = 0; r < begin.size(); ++r) {
                    if (next[r] == end[r]) continue;
                    const uint64_t piece = std::min<uint64_t>(end[r] - next[r], 1 + rng() % (rng() % 2 ? 13 : 20000));
                    regions.append(r, next[r], expected.data() + next[r], piece);
                    next[r] += piece, left = true;
                }
            }
            regions.finish();
            file.write_at(at, expected.data() + at, 100);  // the end of the file, as the header is written
            file.commit();
        }
        const std::string got = file_bytes(path);
        assert_int_equal(got.size(), expected.size());
        for (size_t r = 0; r < begin.size(); ++r)
            assert_true(got.compare(begin[r], end[r] - begin[r], expected, begin[r], end[r] - begin[r]) == 0);
        std::remove(path.c_str());
    }
}

// A write that fails on the device thread (here: beyond the process's file
// size limit, EFBIG with SIGXFSZ ignored) is thrown to the caller, by a
// later append or by finish, as an I/O error naming the file.
void direct_regions_report_failed_writes(void **) {
    const std::string path = output_path("test_dual_direct_regions_limit.bin");
    const size_t piece = size_t(1) << 20;
    const std::vector<unsigned char> bytes(piece, 0x5a);
    rlimit old_limit{};
    assert_int_equal(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    rlimit limit = old_limit;
    limit.rlim_cur = 4 * piece;
    void (*old_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(::setrlimit(RLIMIT_FSIZE, &limit), 0);
    int status = UM_OK;
    std::string message;
    try {
        io::ReplacingFile file(path, "test file");
        io::DirectRegions regions(file, {0}, {16 * piece});
        for (size_t k = 0; k < 16; ++k) regions.append(0, k * piece, bytes.data(), piece);
        regions.finish();
    } catch (const Error &e) {
        status = e.status(), message = e.what();
    } catch (...) {
        status = UM_ERR_INTERNAL;  // anything else fails the test below, after the limit is restored
    }
    ::setrlimit(RLIMIT_FSIZE, &old_limit);
    std::signal(SIGXFSZ, old_handler);
    assert_int_equal(status, UM_ERR_IO);
    assert_non_null(std::strstr(message.c_str(), path.c_str()));
    assert_int_equal(::access(path.c_str(), F_OK), -1);  // nothing left under the final name
}

// The threads of this process: its entries in /proc/self/task.
int threads_now() {
    DIR *tasks = ::opendir("/proc/self/task");
    if (!tasks) return -1;
    int n = 0;
    for (const dirent *e = ::readdir(tasks); e; e = ::readdir(tasks)) n += e->d_name[0] != '.';
    ::closedir(tasks);
    return n;
}

// The thread of the direct writes (io/device_writes.hpp) ends with them:
// after finish, and when the regions are dropped before it, their writes
// abandoned (as when making the next block fails); a file never committed
// leaves nothing under its name. First in the suite, before any context's
// workers exist.
void direct_writes_end_their_thread(void **) {
    const std::string path = output_path("test_dual_direct_thread.bin");
    const size_t piece = size_t(1) << 20;
    const std::vector<unsigned char> bytes(piece, 0x3c);
    const int before = threads_now();
    assert_true(before > 0);
    for (bool finished : {true, false}) {
        std::remove(path.c_str());
        int during = -1;
        {
            io::ReplacingFile file(path, "test file");
            io::DirectRegions regions(file, {0}, {8 * piece});
            for (size_t k = 0; k < 4; ++k) regions.append(0, k * piece, bytes.data(), piece);
            during = threads_now();
            if (finished) {
                for (size_t k = 4; k < 8; ++k) regions.append(0, k * piece, bytes.data(), piece);
                regions.finish();
                file.commit();
            }
        }
        if (during == before) {  // O_DIRECT refused here: no thread was started
            std::remove(path.c_str());
            skip();
        }
        assert_int_equal(during, before + 1);
        assert_int_equal(threads_now(), before);
        assert_int_equal(::access(path.c_str(), F_OK), finished ? 0 : -1);
        if (finished) assert_true(file_bytes(path) == std::string(8 * piece, 0x3c));
    }
    std::remove(path.c_str());
}

void write_errors_name_the_file(void **) {
    auto pts = test::icosahedral_points(1);
    MpasMesh m = staggered(triangulate(pts, nullptr));
    for (const std::string path : {output_path("no/such/directory/mesh.nc"), std::string(UNIMESH_TEST_OUTPUT_DIR)}) {
        try {
            io::write_mpas_mesh(m, path);
            fail_msg("writing to %s succeeded", path.c_str());
        } catch (const Error &e) {
            assert_int_equal(e.status(), UM_ERR_IO);
            assert_non_null(std::strstr(e.what(), path.c_str()));
        }
    }
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(direct_writes_end_their_thread),
        cmocka_unit_test(arc_crossing_takes_the_edge_points_side),
        cmocka_unit_test(icosahedral_mesh),
        cmocka_unit_test(weighted_mesh),
        cmocka_unit_test(layout_keeps_each_vertex_orthocentre),
        cmocka_unit_test(small_cells_stay_consistent),
        cmocka_unit_test(hidden_points_are_not_cells),
        cmocka_unit_test(refined_mesh_with_sides),
        cmocka_unit_test(same_mesh_for_any_thread_count),
        cmocka_unit_test(netcdf_round_trip),
        cmocka_unit_test(streamed_file_matches_whole_mesh),
        cmocka_unit_test(large_variables_give_cdf5),
        cmocka_unit_test(direct_regions_write_every_byte),
        cmocka_unit_test(direct_regions_report_failed_writes),
        cmocka_unit_test(write_errors_name_the_file),
    };
    return cmocka_run_group_tests_name("dual", tests, nullptr, nullptr);
}
