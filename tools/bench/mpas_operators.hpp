// The standard MPAS (TRSK C-grid) discrete operators and the mesh diagnostics
// that drive their errors, computed from an MPAS mesh's own arrays, and
// measured against closed-form fields on the unit sphere. Definitions, signs,
// fields and norms are those of the project's operator page (Ringler et al.
// 2010, Thuburn et al. 2009): written here independently of lib/dual, so that
// the benchmark referees what the library writes rather than repeating it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace bench {

struct V3 {
    double x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double norm(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 unit(V3 a) { return (1.0 / norm(a)) * a; }
// The great-circle distance between two unit vectors (stable at every angle).
inline double arc(V3 a, V3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// An MPAS mesh scaled to the unit sphere, connectivity 0-based with -1 padding.
struct MpasArrays {
    int64_t n_cells = 0, n_edges = 0, n_vertices = 0, max_edges = 0;
    std::vector<V3> x_cell, x_edge, x_vertex;
    std::vector<int32_t> n_edges_on_cell, edges_on_cell, vertices_on_cell;  // max_edges per cell
    std::vector<int32_t> cells_on_edge, vertices_on_edge;                   // 2 per edge
    std::vector<int32_t> n_edges_on_edge, edges_on_edge;                    // 2 max_edges per edge
    std::vector<double> weights_on_edge;                                    // 2 max_edges per edge
    std::vector<int32_t> cells_on_vertex, edges_on_vertex;                  // 3 per vertex
    std::vector<double> area_cell, area_triangle, dc_edge, dv_edge;
    std::vector<double> h_edge;  // the spacing at xEdge (unit sphere); empty when unknown
};

// A scalar field on the unit sphere: its value, its tangential gradient and
// its Laplace-Beltrami Laplacian, in closed form.
struct ScalarField {
    std::string name;
    std::function<double(V3)> value;
    std::function<V3(V3)> gradient3;  // the gradient of a smooth extension to R^3
    std::function<double(V3)> laplacian;
    V3 gradient(V3 x) const {
        const V3 g = gradient3(x);
        return g - dot(g, x) * x;
    }
};

// psi = (x^2 - y^2) z: a real Y_3^2, so its Laplacian is -12 psi.
inline ScalarField spherical_harmonic_32() {
    return {"(x^2-y^2)z", [](V3 p) { return (p.x * p.x - p.y * p.y) * p.z; },
            [](V3 p) { return V3{2 * p.x * p.z, -2 * p.y * p.z, p.x * p.x - p.y * p.y}; },
            [](V3 p) { return -12 * (p.x * p.x - p.y * p.y) * p.z; }};
}

// exp(-2 (1 - X.x0) / w^2), w = 15 degrees, x0 = (30N, 40E). With mu = X.x0
// and c = 2 / w^2, the Laplacian of F(mu) is (1 - mu^2) F'' - 2 mu F'.
inline ScalarField gaussian_hill() {
    const double w = 15 * M_PI / 180, c = 2 / (w * w);
    const double lat = 30 * M_PI / 180, lon = 40 * M_PI / 180;
    const V3 x0{std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
    return {"Gaussian hill", [=](V3 p) { return std::exp(-c * (1 - dot(p, x0))); },
            [=](V3 p) { return (c * std::exp(-c * (1 - dot(p, x0)))) * x0; },
            [=](V3 p) {
                const double mu = dot(p, x0), f = std::exp(-c * (1 - mu));
                return f * (c * c * (1 - mu * mu) - 2 * c * mu);
            }};
}

// The stream function of eastward solid-body rotation, -z: u = k x grad(-z)
// = z_hat x X, vorticity 2z.
inline ScalarField solid_body_stream() {
    return {"solid-body rotation", [](V3 p) { return -p.z; }, [](V3) { return V3{0, 0, -1}; },
            [](V3 p) { return 2 * p.z; }};
}

// The Rossby-Haurwitz wave-4 stream function (Williamson et al. 1992, test 6
// shape, omega = K): -z + z Re((x + iy)^4). Both terms are harmonic
// polynomials (degrees 1 and 5), so the Laplacian is 2z - 30 z Re(...).
inline ScalarField rossby_haurwitz_4_stream() {
    auto re4 = [](V3 p) { return p.x * p.x * p.x * p.x - 6 * p.x * p.x * p.y * p.y + p.y * p.y * p.y * p.y; };
    return {"Rossby-Haurwitz wave 4", [=](V3 p) { return -p.z + p.z * re4(p); },
            [=](V3 p) {
                return V3{p.z * (4 * p.x * p.x * p.x - 12 * p.x * p.y * p.y),
                          p.z * (4 * p.y * p.y * p.y - 12 * p.x * p.x * p.y), -1 + re4(p)};
            },
            [=](V3 p) { return 2 * p.z - 30 * p.z * re4(p); }};
}

// A velocity field with its divergence and vorticity: u = grad(psi)
// (divergent: div = lap psi, curl 0) or u = k x grad(psi) (rotational:
// div 0, curl = lap psi).
struct Flow {
    std::string name;
    ScalarField psi;
    bool rotational;
    V3 velocity(V3 x) const {
        const V3 g = psi.gradient(x);
        return rotational ? cross(x, g) : g;
    }
    double divergence(V3 x) const { return rotational ? 0 : psi.laplacian(x); }
    double vorticity(V3 x) const { return rotational ? psi.laplacian(x) : 0; }
};
inline Flow divergent(const ScalarField &s) { return {"grad " + s.name, s, false}; }
inline Flow rotational(const ScalarField &s) { return {"k x grad " + s.name, s, true}; }

// Which elements count: all of them, or those a mask selects (the cells
// next to a coastline, say). An edge counts when either of its cells does,
// a vertex when any of its cells does.
struct Selection {
    std::vector<uint8_t> cell, edge, vertex;  // empty = every element
    static Selection of_cells(const MpasArrays &m, const std::vector<uint8_t> &cells) {
        Selection s;
        s.cell = cells;
        s.edge.assign(static_cast<size_t>(m.n_edges), 0);
        s.vertex.assign(static_cast<size_t>(m.n_vertices), 0);
        for (int64_t e = 0; e < m.n_edges; ++e)
            for (int k = 0; k < 2; ++k) {
                const int32_t c = m.cells_on_edge[2 * e + k];
                if (c >= 0 && cells[c]) s.edge[e] = 1;
            }
        for (int64_t v = 0; v < m.n_vertices; ++v)
            for (int k = 0; k < 3; ++k) {
                const int32_t c = m.cells_on_vertex[3 * v + k];
                if (c >= 0 && cells[c]) s.vertex[v] = 1;
            }
        return s;
    }
};

// Relative errors of approximate values a against exact values e with
// weights w: L2 = sqrt(sum w (a - e)^2 / sum w e^2), Linf = max|a - e| / max|e|.
struct RelativeError {
    double l2 = 0, linf = 0;
};
class ErrorSum {
public:
    void add(double approx, double exact, double weight) {
        const double d = approx - exact;
        num_ += weight * d * d, den_ += weight * exact * exact;
        max_diff_ = std::max(max_diff_, std::fabs(d)), max_exact_ = std::max(max_exact_, std::fabs(exact));
    }
    RelativeError result() const {
        return {den_ > 0 ? std::sqrt(num_ / den_) : 0.0, max_exact_ > 0 ? max_diff_ / max_exact_ : 0.0};
    }

private:
    double num_ = 0, den_ = 0, max_diff_ = 0, max_exact_ = 0;
};

inline bool selected(const std::vector<uint8_t> &mask, int64_t i) { return mask.empty() || mask[i]; }

// n_e: the unit tangent at xEdge of the great circle from cellsOnEdge(e,1) to
// cellsOnEdge(e,2) (pointing out of cell 1).
inline V3 edge_normal(const MpasArrays &m, int64_t e) {
    const V3 a = m.x_cell[m.cells_on_edge[2 * e]], b = m.x_cell[m.cells_on_edge[2 * e + 1]];
    return unit(cross(cross(a, b), m.x_edge[e]));
}
// t_e = k x n_e, k the outward normal at xEdge.
inline V3 edge_tangent(const MpasArrays &m, int64_t e) { return cross(m.x_edge[e], edge_normal(m, e)); }

// The model's unknowns: u_e = u(xEdge) . n_e.
inline std::vector<double> normal_velocities(const MpasArrays &m, const Flow &f) {
    std::vector<double> u(static_cast<size_t>(m.n_edges));
    for (int64_t e = 0; e < m.n_edges; ++e) u[e] = dot(f.velocity(m.x_edge[e]), edge_normal(m, e));
    return u;
}

// Edge weights dcEdge dvEdge / 2 (the area an edge stands for).
inline double edge_weight(const MpasArrays &m, int64_t e) { return 0.5 * m.dc_edge[e] * m.dv_edge[e]; }

// Gradient on edges: (psi(c2) - psi(c1)) / dcEdge against grad psi(xEdge) . n_e.
inline RelativeError gradient_error(const MpasArrays &m, const ScalarField &psi, const Selection &s = {}) {
    ErrorSum err;
    for (int64_t e = 0; e < m.n_edges; ++e) {
        if (!selected(s.edge, e)) continue;
        const double approx =
            (psi.value(m.x_cell[m.cells_on_edge[2 * e + 1]]) - psi.value(m.x_cell[m.cells_on_edge[2 * e]])) /
            m.dc_edge[e];
        err.add(approx, dot(psi.gradient(m.x_edge[e]), edge_normal(m, e)), edge_weight(m, e));
    }
    return err.result();
}

// A cell operator (1/areaCell) sum over the cell's edges of term(i, e)
// against exact(i), area-weighted.
template <class Term, class Exact>
RelativeError cell_operator_error(const MpasArrays &m, const Selection &s, Term &&term, Exact &&exact) {
    ErrorSum err;
    for (int64_t i = 0; i < m.n_cells; ++i) {
        if (!selected(s.cell, i)) continue;
        double sum = 0;
        for (int j = 0; j < m.n_edges_on_cell[i]; ++j) sum += term(i, m.edges_on_cell[i * m.max_edges + j]);
        err.add(sum / m.area_cell[i], exact(i), m.area_cell[i]);
    }
    return err.result();
}

// Divergence on cells: (1/areaCell) sum s u_e dvEdge, s = +1 when the cell is
// cellsOnEdge(e,1), against div u at xCell.
inline RelativeError divergence_error(const MpasArrays &m, const Flow &f, const Selection &s = {}) {
    const std::vector<double> u = normal_velocities(m, f);
    return cell_operator_error(
        m, s, [&](int64_t i, int32_t e) { return (m.cells_on_edge[2 * e] == i ? 1.0 : -1.0) * u[e] * m.dv_edge[e]; },
        [&](int64_t i) { return f.divergence(m.x_cell[i]); });
}

// Curl on dual vertices: (1/areaTriangle) sum s u_e dcEdge, s = -1 when the
// vertex is verticesOnEdge(e,1) else +1, against k . curl u at xVertex.
inline RelativeError curl_error(const MpasArrays &m, const Flow &f, const Selection &s = {}) {
    const std::vector<double> u = normal_velocities(m, f);
    ErrorSum err;
    for (int64_t v = 0; v < m.n_vertices; ++v) {
        if (!selected(s.vertex, v)) continue;
        double sum = 0;
        for (int j = 0; j < 3; ++j) {
            const int32_t e = m.edges_on_vertex[3 * v + j];
            if (e < 0) continue;
            sum += (m.vertices_on_edge[2 * e] == v ? -1.0 : 1.0) * u[e] * m.dc_edge[e];
        }
        err.add(sum / m.area_triangle[v], f.vorticity(m.x_vertex[v]), m.area_triangle[v]);
    }
    return err.result();
}

// TRSK: sum_j weightsOnEdge(e,j) u(edgesOnEdge(e,j)) against u(xEdge) . t_e.
inline RelativeError tangential_error(const MpasArrays &m, const Flow &f, const Selection &s = {}) {
    const std::vector<double> u = normal_velocities(m, f);
    const int64_t row = 2 * m.max_edges;
    ErrorSum err;
    for (int64_t e = 0; e < m.n_edges; ++e) {
        if (!selected(s.edge, e)) continue;
        double sum = 0;
        for (int j = 0; j < m.n_edges_on_edge[e]; ++j)
            sum += m.weights_on_edge[e * row + j] * u[m.edges_on_edge[e * row + j]];
        err.add(sum, dot(f.velocity(m.x_edge[e]), edge_tangent(m, e)), edge_weight(m, e));
    }
    return err.result();
}

// Kinetic energy on cells: (1/areaCell) sum 1/4 dcEdge dvEdge u_e^2 against
// |u(xCell)|^2 / 2.
inline RelativeError kinetic_energy_error(const MpasArrays &m, const Flow &f, const Selection &s = {}) {
    const std::vector<double> u = normal_velocities(m, f);
    return cell_operator_error(
        m, s, [&](int64_t, int32_t e) { return 0.25 * m.dc_edge[e] * m.dv_edge[e] * u[e] * u[e]; },
        [&](int64_t i) {
            const V3 w = f.velocity(m.x_cell[i]);
            return 0.5 * dot(w, w);
        });
}

// ------------------------------------------------------------ diagnostics

struct Spread {
    double min = 0, max = 0, mean = 0, std = 0, rms = 0;
    int64_t count = 0;
};
inline Spread spread_of(const std::vector<double> &x) {
    Spread s;
    if (x.empty()) return s;
    s.min = *std::min_element(x.begin(), x.end()), s.max = *std::max_element(x.begin(), x.end());
    double sum = 0, sum2 = 0;
    for (double v : x) sum += v, sum2 += v * v;
    s.count = static_cast<int64_t>(x.size());
    s.mean = sum / s.count, s.rms = std::sqrt(sum2 / s.count);
    s.std = std::sqrt(std::max(0.0, sum2 / s.count - s.mean * s.mean));
    return s;
}

// The exact centroid direction of a spherical polygon: the integral of X over
// it, which for a triangle (a, b, c) is half the sum over its edges of the
// arc length times the unit normal of the edge's plane (the vector-area
// identity). Fanned from xCell, which lies inside (or on) every power cell's
// star here, with signed triangles so that any position works.
inline V3 cell_centroid(const MpasArrays &m, int64_t i) {
    const V3 c = m.x_cell[i];
    V3 sum{};
    const int n = m.n_edges_on_cell[i];
    for (int j = 0; j < n; ++j) {
        const V3 a = m.x_vertex[m.vertices_on_cell[i * m.max_edges + j]];
        const V3 b = m.x_vertex[m.vertices_on_cell[i * m.max_edges + (j + 1) % n]];
        for (const auto &[p, q] : {std::pair<V3, V3>{c, a}, {a, b}, {b, c}}) {
            const V3 pq = cross(p, q);
            const double len = norm(pq);
            if (len > 0) sum = sum + (0.5 * arc(p, q) / len) * pq;
        }
    }
    return unit(sum);
}

struct Diagnostics {
    Spread centroid_offset;     // arc(xCell, centroid) / sqrt(areaCell)
    Spread dual_edge_offset;    // arc(xEdge, midpoint of v1 v2) / dvEdge
    Spread primal_edge_offset;  // arc(xEdge, midpoint of c1 c2) / dcEdge
    Spread spacing_ratio;       // dcEdge / h(xEdge) (count 0 without h)
    Spread area_length;         // Q^T of the triangles of cell centres (arcs, geodesic area)
    int64_t sides[4] = {0, 0, 0, 0};  // cells with < 5, 5, 7, > 7 sides
};

inline Diagnostics diagnose(const MpasArrays &m) {
    Diagnostics d;
    std::vector<double> x;
    for (int64_t i = 0; i < m.n_cells; ++i)
        x.push_back(arc(m.x_cell[i], cell_centroid(m, i)) / std::sqrt(m.area_cell[i]));
    d.centroid_offset = spread_of(x);
    std::vector<double> dual, primal, ratio;
    for (int64_t e = 0; e < m.n_edges; ++e) {
        const V3 v1 = m.x_vertex[m.vertices_on_edge[2 * e]], v2 = m.x_vertex[m.vertices_on_edge[2 * e + 1]];
        const V3 c1 = m.x_cell[m.cells_on_edge[2 * e]], c2 = m.x_cell[m.cells_on_edge[2 * e + 1]];
        dual.push_back(arc(m.x_edge[e], unit(v1 + v2)) / m.dv_edge[e]);
        primal.push_back(arc(m.x_edge[e], unit(c1 + c2)) / m.dc_edge[e]);
        if (!m.h_edge.empty()) ratio.push_back(m.dc_edge[e] / m.h_edge[e]);
    }
    d.dual_edge_offset = spread_of(dual), d.primal_edge_offset = spread_of(primal);
    d.spacing_ratio = spread_of(ratio);
    std::vector<double> qt;
    for (int64_t v = 0; v < m.n_vertices; ++v) {
        const V3 a = m.x_cell[m.cells_on_vertex[3 * v]], b = m.x_cell[m.cells_on_vertex[3 * v + 1]],
                 c = m.x_cell[m.cells_on_vertex[3 * v + 2]];
        // Spherical excess (Van Oosterom and Strackee) for the area.
        const double area = 2 * std::atan2(std::fabs(dot(a, cross(b, c))), 1 + dot(a, b) + dot(b, c) + dot(c, a));
        const double l1 = arc(a, b), l2 = arc(b, c), l3 = arc(c, a);
        qt.push_back(4 * std::sqrt(3.0) * area / (l1 * l1 + l2 * l2 + l3 * l3));
    }
    d.area_length = spread_of(qt);
    for (int64_t i = 0; i < m.n_cells; ++i) {
        const int n = m.n_edges_on_cell[i];
        if (n < 5) ++d.sides[0];
        else if (n == 5) ++d.sides[1];
        else if (n == 7) ++d.sides[2];
        else if (n > 7) ++d.sides[3];
    }
    return d;
}

}  // namespace bench
