#include "mesh_file_commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "available_memory.hpp"
#include "json_text.hpp"
#include "nc_read.hpp"

namespace {

struct V3 {
    double x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 scale(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(V3 a) { return std::sqrt(dot(a, a)); }
V3 unit(V3 a) { return scale(1 / norm(a), a); }
double arc(V3 a, V3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// The parts of a mesh file both commands read.
struct MeshFile {
    size_t n_cells = 0, n_edges = 0, n_vertices = 0, max_edges = 0, max_edges2 = 0;
    double radius = 0;
    std::vector<V3> cell, edge, vertex;  // unit vectors
    std::vector<int32_t> n_edges_on_cell, edges_on_cell, vertices_on_cell, cells_on_edge, vertices_on_edge,
        cells_on_vertex, n_edges_on_edge, edges_on_edge;
    std::vector<double> area_cell, area_triangle, kites, dc_edge, dv_edge, weights;
    std::vector<int32_t> boundary_vertex;
    // A cut mesh (a component of a unified mesh): some cellsOnEdge(2, e) is 0.
    bool boundary = false;
};

bool positions(const NcFile &f, const char *what, size_t n, std::vector<V3> &out) {
    std::vector<double> x, y, z;
    const std::string s(what);
    if (!f.var(("x" + s).c_str(), x, n) || !f.var(("y" + s).c_str(), y, n) || !f.var(("z" + s).c_str(), z, n))
        return false;
    out.resize(n);
    for (size_t i = 0; i < n; ++i) out[i] = unit({x[i], y[i], z[i]});
    return true;
}

// Every count and index the commands use, checked before use: "" or the
// first one out of range (a damaged or hostile file must not make them read
// outside the arrays). A global mesh has no 0 (boundary) in its
// connectivity; a cut mesh (a component) has 0 where a cell is missing:
// in cellsOnEdge(2, e) and cellsOnVertex, never in cellsOnEdge(1, e).
std::string connectivity_problem(const MeshFile &m) {
    auto index = [](const std::vector<int32_t> &a, size_t at, size_t n) { return a[at] >= 1 && size_t(a[at]) <= n; };
    auto cell_or_cut = [&](const std::vector<int32_t> &a, size_t at) {
        return index(a, at, m.n_cells) || (m.boundary && a[at] == 0);
    };
    auto bad = [](const char *name, size_t row, int32_t value, size_t n) {
        return std::string(name) + "(" + std::to_string(row + 1) + ") = " + std::to_string(value) +
               " is not an index in [1, " + std::to_string(n) + "]";
    };
    if (m.max_edges < 3 || m.n_cells < 4 || m.n_edges < 6 || m.n_vertices < 4)
        return "nCells, nEdges, nVertices or maxEdges is too small for a mesh of the sphere";
    if (!(m.radius > 0) || !std::isfinite(m.radius)) return "sphere_radius is not a length > 0";
    for (size_t c = 0; c < m.n_cells; ++c) {
        const int32_t n = m.n_edges_on_cell[c];
        if (n < 3 || size_t(n) > m.max_edges)
            return "nEdgesOnCell(" + std::to_string(c + 1) + ") = " + std::to_string(n) + " is not in [3, maxEdges]";
        for (int32_t j = 0; j < n; ++j) {
            const size_t at = c * m.max_edges + size_t(j);
            if (!index(m.edges_on_cell, at, m.n_edges)) return bad("edgesOnCell", c, m.edges_on_cell[at], m.n_edges);
            if (!index(m.vertices_on_cell, at, m.n_vertices))
                return bad("verticesOnCell", c, m.vertices_on_cell[at], m.n_vertices);
        }
    }
    for (size_t e = 0; e < 2 * m.n_edges; ++e) {
        if (!(e % 2 == 0 ? index(m.cells_on_edge, e, m.n_cells) : cell_or_cut(m.cells_on_edge, e)))
            return bad("cellsOnEdge", e / 2, m.cells_on_edge[e], m.n_cells);
        if (!index(m.vertices_on_edge, e, m.n_vertices))
            return bad("verticesOnEdge", e / 2, m.vertices_on_edge[e], m.n_vertices);
    }
    for (size_t k = 0; k < 3 * m.n_vertices; ++k)
        if (!cell_or_cut(m.cells_on_vertex, k)) return bad("cellsOnVertex", k / 3, m.cells_on_vertex[k], m.n_cells);
    for (size_t e = 0; e < m.n_edges; ++e) {
        const int32_t n = m.n_edges_on_edge[e];
        if (n < 0 || size_t(n) > m.max_edges2)
            return "nEdgesOnEdge(" + std::to_string(e + 1) + ") = " + std::to_string(n) + " is not in [0, maxEdges2]";
        for (int32_t j = 0; j < n; ++j)
            if (!index(m.edges_on_edge, e * m.max_edges2 + size_t(j), m.n_edges))
                return bad("edgesOnEdge", e, m.edges_on_edge[e * m.max_edges2 + size_t(j)], m.n_edges);
    }
    return "";
}

// "" or why the arrays m's dimensions call for cannot be read: more bytes
// than the machine has available. A netCDF-4 file can declare a billion
// cells in a few kilobytes (its chunks unwritten); a classic file's header
// is held to its size before this.
std::string exceeds_memory(const MeshFile &m) {
    const long double cells = m.n_cells, edges = m.n_edges, vertices = m.n_vertices;
    const long double bytes = cells * (36 + 8.0L * m.max_edges) + edges * (60 + 12.0L * m.max_edges2) + vertices * 68;
    const int64_t available = available_memory();
    if (available <= 0 || bytes <= available) return "";
    return "its arrays need about " + std::to_string(static_cast<long long>(bytes / (1 << 20))) + " MiB (nCells " +
           std::to_string(m.n_cells) + ", nEdges " + std::to_string(m.n_edges) + ", nVertices " +
           std::to_string(m.n_vertices) + "), more than the available memory (" +
           std::to_string(available >> 20) + " MiB)";
}

bool read_mesh(const std::string &path, MeshFile &m) {
    const std::string header = NcFile::header_problem(path);
    if (!header.empty()) {
        std::fprintf(stderr, "unimesh: %s: %s\n", path.c_str(), header.c_str());
        return false;
    }
    NcFile f(path);
    if (!f.ok()) {
        std::fprintf(stderr, "unimesh: cannot read %s as netCDF\n", path.c_str());
        return false;
    }
    bool ok = f.dim("nCells", &m.n_cells) && f.dim("nEdges", &m.n_edges) && f.dim("nVertices", &m.n_vertices) &&
              f.dim("maxEdges", &m.max_edges) && f.dim("maxEdges2", &m.max_edges2);
    if (ok) {
        const std::string too_big = exceeds_memory(m);
        if (!too_big.empty()) {
            std::fprintf(stderr, "unimesh: %s: %s\n", path.c_str(), too_big.c_str());
            return false;
        }
    }
    ok = ok && f.global("sphere_radius", &m.radius) && positions(f, "Cell", m.n_cells, m.cell) &&
              positions(f, "Edge", m.n_edges, m.edge) && positions(f, "Vertex", m.n_vertices, m.vertex) &&
              f.var("nEdgesOnCell", m.n_edges_on_cell, m.n_cells) &&
              f.var("edgesOnCell", m.edges_on_cell, m.n_cells * m.max_edges) &&
              f.var("verticesOnCell", m.vertices_on_cell, m.n_cells * m.max_edges) &&
              f.var("cellsOnEdge", m.cells_on_edge, 2 * m.n_edges) &&
              f.var("verticesOnEdge", m.vertices_on_edge, 2 * m.n_edges) &&
              f.var("cellsOnVertex", m.cells_on_vertex, 3 * m.n_vertices) &&
              f.var("nEdgesOnEdge", m.n_edges_on_edge, m.n_edges) &&
              f.var("edgesOnEdge", m.edges_on_edge, m.n_edges * m.max_edges2) &&
              f.var("areaCell", m.area_cell, m.n_cells) && f.var("areaTriangle", m.area_triangle, m.n_vertices) &&
              f.var("kiteAreasOnVertex", m.kites, 3 * m.n_vertices) && f.var("dcEdge", m.dc_edge, m.n_edges) &&
              f.var("dvEdge", m.dv_edge, m.n_edges) &&
              f.var("weightsOnEdge", m.weights, m.n_edges * m.max_edges2) &&
              f.var("boundaryVertex", m.boundary_vertex, m.n_vertices);
    if (!ok) {
        std::fprintf(stderr, "unimesh: %s is not an MPAS mesh file (a dimension, variable or the "
                             "sphere_radius attribute is missing, or a variable's size does not match "
                             "its dimensions)\n", path.c_str());
        return false;
    }
    for (size_t e = 0; e < m.n_edges; ++e) m.boundary = m.boundary || m.cells_on_edge[2 * e + 1] == 0;
    const std::string problem = connectivity_problem(m);
    if (!problem.empty()) {
        std::fprintf(stderr, "unimesh: %s: %s\n", path.c_str(), problem.c_str());
        return false;
    }
    return true;
}

struct Checker {
    int failed = 0;
    void report(const char *name, bool pass, double worst, const char *what) {
        std::printf("%s %-28s worst %.3e  %s\n", pass ? "PASS" : "FAIL", name, worst, what);
        failed += !pass;
    }
    void skip(const char *name, const char *why) { std::printf("SKIP %-28s %s\n", name, why); }
};

// 1-based indices in [1, n] (0 allowed as padding when pad).
bool indices_in_range(const std::vector<int32_t> &a, size_t n) {
    return std::all_of(a.begin(), a.end(), [n](int32_t i) { return i >= 0 && size_t(i) <= n; });
}

}  // namespace

int run_check(const std::string &path) {
    MeshFile m;
    if (!read_mesh(path, m)) return 1;
    Checker c;
    const double sphere = 4 * M_PI * m.radius * m.radius;
    const long euler = long(m.n_cells) - long(m.n_edges) + long(m.n_vertices);
    const char *const cut = "a cut mesh (a component) covers part of the sphere";
    if (m.boundary)
        c.skip("euler", cut);
    else
        c.report("euler", euler == 2, double(std::abs(euler - 2)), "nCells - nEdges + nVertices == 2");
    bool in_range = indices_in_range(m.cells_on_edge, m.n_cells) && indices_in_range(m.vertices_on_edge, m.n_vertices) &&
                    indices_in_range(m.edges_on_cell, m.n_edges) && indices_in_range(m.vertices_on_cell, m.n_vertices) &&
                    indices_in_range(m.cells_on_vertex, m.n_cells) && indices_in_range(m.edges_on_edge, m.n_edges);
    c.report("index.range", in_range, 0, "every connectivity index in [0, n] (0 = padding)");
    if (!in_range) return 1;  // the other checks would index out of range

    if (m.boundary) {
        // The cut: boundaryVertex marks exactly the vertices that lost a cell.
        size_t wrong = 0;
        for (size_t v = 0; v < m.n_vertices; ++v) {
            const bool lost = m.cells_on_vertex[3 * v] == 0 || m.cells_on_vertex[3 * v + 1] == 0 ||
                              m.cells_on_vertex[3 * v + 2] == 0;
            wrong += (m.boundary_vertex[v] != 0) != lost;
        }
        c.report("boundary.vertices", wrong == 0, double(wrong), "boundaryVertex == 1 where a cellsOnVertex is 0");
        c.skip("area.cells", cut);
        c.skip("area.triangles", cut);
    } else {
        double total = 0, total_t = 0;
        for (double a : m.area_cell) total += a;
        for (double a : m.area_triangle) total_t += a;
        c.report("area.cells", std::abs(total / sphere - 1) < 1e-10, std::abs(total / sphere - 1),
                 "sum(areaCell) == 4 pi R^2");
        c.report("area.triangles", std::abs(total_t / sphere - 1) < 1e-10, std::abs(total_t / sphere - 1),
                 "sum(areaTriangle) == 4 pi R^2");
    }
    double kite_worst = 0;
    std::vector<double> kite_cell(m.n_cells, 0);
    for (size_t v = 0; v < m.n_vertices; ++v) {
        double sum = 0;
        for (int j = 0; j < 3; ++j) {
            sum += m.kites[3 * v + j];
            if (m.cells_on_vertex[3 * v + j] > 0) kite_cell[m.cells_on_vertex[3 * v + j] - 1] += m.kites[3 * v + j];
        }
        kite_worst = std::max(kite_worst, std::abs(sum - m.area_triangle[v]) / std::abs(m.area_triangle[v]));
    }
    c.report("area.kites_triangle", kite_worst < 1e-10, kite_worst, "kites sum to areaTriangle (relative)");
    double kite_cell_worst = 0;
    for (size_t i = 0; i < m.n_cells; ++i)
        kite_cell_worst = std::max(kite_cell_worst, std::abs(kite_cell[i] - m.area_cell[i]) / m.area_cell[i]);
    c.report("area.kites_cell", kite_cell_worst < 1e-9, kite_cell_worst, "a cell's kites sum to areaCell (relative)");

    // Orthogonality: the dual great circle passes through the pole of the
    // primal one, det(x_v1, x_v2, x_c1 x x_c2) = 0.
    double ortho = 0, lengths = 0;
    for (size_t e = 0; e < m.n_edges; ++e) {
        if (m.cells_on_edge[2 * e + 1] == 0) continue;  // a cut edge: its second cell is elsewhere
        const V3 c1 = m.cell[m.cells_on_edge[2 * e] - 1], c2 = m.cell[m.cells_on_edge[2 * e + 1] - 1];
        const V3 v1 = m.vertex[m.vertices_on_edge[2 * e] - 1], v2 = m.vertex[m.vertices_on_edge[2 * e + 1] - 1];
        const V3 pole = unit(cross(c1, c2)), dual = cross(v1, v2);
        if (norm(dual) > 0) ortho = std::max(ortho, std::abs(dot(dual, pole)) / norm(dual));
        lengths = std::max(lengths, std::abs(arc(c1, c2) * m.radius / m.dc_edge[e] - 1));
        // Orientation: the tangent from v1 to v2 is k x n, n from c1 to c2.
        if (dot(cross(c2 - c1, v2 - v1), m.edge[e]) <= 0) ortho = std::max(ortho, 1.0);
    }
    c.report("geom.orthogonal", ortho < 1e-9, ortho, "dual arcs cross primal arcs at right angles, oriented");
    c.report("geom.dcEdge", lengths < 1e-10, lengths, "dcEdge == arc between the cells (relative)");

    // Counter-clockwise cells around their corner centroid.
    double ccw = 0;
    for (size_t i = 0; i < m.n_cells; ++i) {
        const int k = m.n_edges_on_cell[i];
        V3 centre{};
        for (int j = 0; j < k; ++j) centre = centre + m.vertex[m.vertices_on_cell[i * m.max_edges + j] - 1];
        centre = unit(centre);
        for (int j = 0; j < k; ++j) {
            const V3 a = m.vertex[m.vertices_on_cell[i * m.max_edges + j] - 1];
            const V3 b = m.vertex[m.vertices_on_cell[i * m.max_edges + (j + 1) % k] - 1];
            if (dot(cross(a - centre, b - centre), centre) < 0) ccw = 1;
        }
    }
    c.report("order.cells_ccw", ccw == 0, ccw, "verticesOnCell counter-clockwise seen from outside");

    // TRSK: W(e,f) dc(e) dv(e) == -W(f,e) dc(f) dv(f).
    double worst = 0, biggest = 0;
    for (size_t e = 0; e < m.n_edges; ++e)
        for (int j = 0; j < m.n_edges_on_edge[e]; ++j) {
            const size_t f = size_t(m.edges_on_edge[e * m.max_edges2 + j] - 1);
            const double here = m.weights[e * m.max_edges2 + j] * m.dc_edge[e] * m.dv_edge[e];
            double there = NAN;
            for (int k = 0; k < m.n_edges_on_edge[f]; ++k)
                if (size_t(m.edges_on_edge[f * m.max_edges2 + k] - 1) == e)
                    there = m.weights[f * m.max_edges2 + k] * m.dc_edge[f] * m.dv_edge[f];
            biggest = std::max(biggest, std::abs(here));
            worst = std::isnan(there) ? INFINITY : std::max(worst, std::abs(here + there));
        }
    const double relative = biggest > 0 ? worst / biggest : worst;
    c.report("trsk.antisymmetry", relative < 1e-9, relative, "W(e,f) dc dv == -W(f,e) dc' dv'");
    std::printf("%s: %s (%d failed)\n", path.c_str(), c.failed ? "FAIL" : "PASS", c.failed);
    return c.failed ? 1 : 0;
}

namespace {

struct Stats {
    double min = INFINITY, max = -INFINITY, sum = 0, p1 = 0;
    size_t n = 0;
};

Stats stats(std::vector<double> v) {
    Stats s;
    for (double x : v) s.min = std::min(s.min, x), s.max = std::max(s.max, x), s.sum += x;
    s.n = v.size();
    if (!v.empty()) {
        auto p = v.begin() + std::ptrdiff_t(v.size() / 100);
        std::nth_element(v.begin(), p, v.end());
        s.p1 = *p;
    }
    return s;
}

}  // namespace

int run_quality(const std::string &path, bool json) {
    MeshFile m;
    if (!read_mesh(path, m)) return 1;
    std::vector<double> qt, qp, amin, amax;
    size_t obtuse = 0, not_well_centred = 0;
    // Each MPAS vertex is a triangle of three cells; its edges are the MPAS
    // edges between them, whose xEdge is the edge orthocentre.
    std::vector<std::vector<int64_t>> edges_of_vertex(m.n_vertices);
    for (size_t e = 0; e < m.n_edges; ++e)
        for (int k = 0; k < 2; ++k) edges_of_vertex[m.vertices_on_edge[2 * e + k] - 1].push_back(int64_t(e));
    for (size_t v = 0; v < m.n_vertices; ++v) {
        // A triangle the cut of a component mesh split (a cell of it elsewhere) is not measured.
        if (m.cells_on_vertex[3 * v] == 0 || m.cells_on_vertex[3 * v + 1] == 0 || m.cells_on_vertex[3 * v + 2] == 0)
            continue;
        V3 x[3];
        for (int k = 0; k < 3; ++k) x[k] = m.cell[m.cells_on_vertex[3 * v + k] - 1];
        double l[3], l2 = 0, lsum = 0, angle[3];
        for (int k = 0; k < 3; ++k) {
            l[k] = arc(x[(k + 1) % 3], x[(k + 2) % 3]);
            l2 += l[k] * l[k], lsum += l[k];
            const V3 a = x[k], b = x[(k + 1) % 3], c = x[(k + 2) % 3];
            const V3 ta = cross(cross(a, b), a), tc = cross(cross(a, c), a);
            angle[k] = std::atan2(norm(cross(ta, tc)), dot(ta, tc)) * 180 / M_PI;
        }
        qt.push_back(4 * std::sqrt(3.0) * (m.area_triangle[v] / (m.radius * m.radius)) / l2);
        const V3 centroid = unit(x[0] + x[1] + x[2]);
        const double df = arc(m.vertex[v], centroid), lmean = lsum / 3;
        double edge_term = 0;
        for (int64_t e : edges_of_vertex[v]) {
            if (m.cells_on_edge[2 * size_t(e) + 1] == 0) continue;  // a cut edge of a damaged file: no second cell
            const V3 c1 = m.cell[m.cells_on_edge[2 * e] - 1], c2 = m.cell[m.cells_on_edge[2 * e + 1] - 1];
            const double le = arc(c1, c2), de = arc(m.edge[e], unit(c1 + c2));
            edge_term += 1 - (de / le) * (de / le);
        }
        qp.push_back(2.0 / 3.0 * (1 - (df / lmean) * (df / lmean)) + 1.0 / 3.0 * edge_term / 3);
        amin.push_back(std::min({angle[0], angle[1], angle[2]}));
        amax.push_back(std::max({angle[0], angle[1], angle[2]}));
        obtuse += amax.back() > 90;
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside &= dot(cross(x[(k + 1) % 3], x[(k + 2) % 3]), m.vertex[v]) >= 0;
        not_well_centred += !inside;
    }
    const struct {
        const char *name;
        Stats s;
    } rows[] = {{"area_length_ratio", stats(qt)},
                {"primal_dual", stats(qp)},
                {"angle_min_deg", stats(amin)},
                {"angle_max_deg", stats(amax)}};
    if (json) {
        std::printf("{\"file\": \"%s\", \"triangles\": %zu", json_escaped(path).c_str(), qt.size());
        for (const auto &r : rows)
            std::printf(", \"%s\": {\"min\": %.17g, \"p1\": %.17g, \"mean\": %.17g, \"max\": %.17g}", r.name,
                        r.s.min, r.s.p1, r.s.sum / double(r.s.n), r.s.max);
        std::printf(", \"obtuse_triangles\": %zu, \"not_well_centred\": %zu}\n", obtuse, not_well_centred);
        return 0;
    }
    std::printf("%s: %zu cells, %zu triangles\n", path.c_str(), m.n_cells, qt.size());
    std::printf("%-18s %10s %10s %10s %10s\n", "metric", "min", "p1", "mean", "max");
    for (const auto &r : rows)
        std::printf("%-18s %10.4f %10.4f %10.4f %10.4f\n", r.name, r.s.min, r.s.p1, r.s.sum / double(r.s.n), r.s.max);
    std::printf("obtuse triangles: %zu (%.3f %%); not containing their orthocentre: %zu\n", obtuse,
                100.0 * double(obtuse) / double(std::max<size_t>(qt.size(), 1)), not_well_centred);
    return 0;
}
