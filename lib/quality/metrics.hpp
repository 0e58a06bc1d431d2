// Mesh quality metrics (DESIGN.md section 5, the paper's Figure 10), on the
// sphere with arc lengths and spherical (geodesic) areas:
//   Q^T  area-length ratio 4 sqrt(3) A / (l1^2 + l2^2 + l3^2) (1 = equilateral);
//   Q^P  primal-dual staggering, eq. 1: beta_f (1 - (d_f / l_mean)^2)
//        + beta_e mean_e (1 - (d_e / l_e)^2), d_f = |orthocentre - centroid|,
//        d_e = |edge orthocentre - edge midpoint|, beta_f = 2/3, beta_e = 1/3;
//   angles of every triangle (degrees), the share with an angle > 90;
//   h_r = l_e / h(midpoint of e) per edge;
//   well-centred: the triangle contains its orthocentre.
// And the operator diagnostics, the offsets on which the errors of the MPAS
// (TRSK) operators depend (Peixoto 2016, J. Comput. Phys. 310): the
// divergence and the kinetic energy feel the dual-edge offset, the curl the
// primal-edge offset, the TRSK reconstruction the centroid offset; with
// xEdge where the dual arc of an edge crosses its primal arc,
//   centroid offset     arc(x_i, centroid of power cell i) / sqrt(area_i);
//   dual-edge offset    arc(xEdge, midpoint of the dual arc) / dvEdge;
//   primal-edge offset  arc(xEdge, midpoint of the primal arc) / dcEdge;
//   cell spacing ratio  dcEdge / h(xEdge).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/context.hpp"
#include "quality/ocean_connectivity.hpp"
#include "refine/restricted.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::quality {

// The report's arc length (radians) between unit vectors and signed area
// (steradians) of the geodesic triangle (a, b, c), counter-clockwise seen
// from outside positive: dual::arc's and dual::signed_area's values to their
// rounding, at less than half the cost on a mesh's arcs and triangles.
// (glibc's atan2 saves and restores the rounding mode on every call: a
// report made about 24 of them a triangle.)
double arc(const geom::Vec3 &a, const geom::Vec3 &b);
double signed_area(const geom::Vec3 &a, const geom::Vec3 &b, const geom::Vec3 &c);

struct TriangleQuality {
    double area_length;  // Q^T
    double primal_dual;  // Q^P
    double angle_min, angle_max;  // degrees
    bool well_centred;
};

TriangleQuality triangle_quality(const tri::Triangulation &tri, int32_t t);

// The operator diagnostics of edge k of triangle t (from its vertex k + 1 to
// k + 2; neighbour(t, k) on the other side): the dual-edge and primal-edge
// offsets, dcEdge (radians) and xEdge, the edge orthocentre.
struct EdgeOffsets {
    double dual, primal, dc_edge;
    geom::Vec3 x_edge;
};
EdgeOffsets edge_offsets(const tri::Triangulation &tri, int32_t t, int k);

// The centroid offset of the power cell of vertex slot v (in the triangulation).
double centroid_offset(const tri::Triangulation &tri, int32_t v);

struct Summary {
    double min = 0, p1 = 0, mean = 0, max = 0;
    double rms = 0, std = 0;  // root mean square; standard deviation (of the population)
    std::vector<int64_t> histogram;  // kBins bins over [lo, hi]
    double lo = 0, hi = 1;
};
constexpr int kBins = 50;

struct Report {
    int64_t triangles = 0, edges = 0;
    Summary area_length, primal_dual, angle_min, angle_max, spacing_ratio;
    int64_t obtuse = 0;           // triangles with an angle > 90 degrees
    int64_t not_well_centred = 0;
    // Of those, the ones with a vertex off Gamma (where the optimisation
    // issue allows none: a triangle with its three vertices on Gamma may be
    // forced off-centre by the feature's shape).
    int64_t not_well_centred_off_gamma = 0;
    // The operator diagnostics: per power cell, per edge, per edge, per edge
    // (the last needs h, like spacing_ratio). A dual edge of no length (or a
    // cell of no area) counts as 2^-52 long: an offset of ~1e16.
    Summary centroid_offset, dual_edge_offset, primal_edge_offset, cell_spacing_ratio;
    // The time-step floor: over the edges between two cells of the ocean
    // mesh, the least dcEdge / h(xEdge) and how many are below the floor the
    // mesh was built to (measured when the ocean cells are given). The edges
    // of cells in the ocean mesh only because a passage keeps them open are
    // the exceptions: counted apart (kept_open_*), not in the others.
    struct OceanEdges {
        bool measured = false;
        double floor = 0;
        int64_t edges = 0, below_floor = 0;
        double min_ratio = 0;
        int64_t kept_open_cells = 0, kept_open_below_floor = 0;
        // Its regions, water bodies and the passages the mesh closed.
        OceanConnectivity connectivity;
    } ocean;
    // How closely Tri|Gamma follows the closed coastlines (what the floor's
    // filtering costs): their restricted edges, and eps (the distance from
    // an edge's midpoint to its crossing with the coastline) over beta * h
    // (the boundary refinement's bound, 1 = at it).
    struct CoastlineFidelity {
        bool measured = false;
        double beta = 0;
        int64_t restricted_edges = 0, beyond_beta = 0;
        double eps_mean = 0, eps_max = 0;  // of eps / (beta h)
    } coastline;
    // A mesh of an ellipsoid measured there (quality/geodesic.hpp): its
    // edges' geodesic lengths over h and its power cells' geodesic areas.
    struct Geodesic {
        bool measured = false;
        double a_m = 0, f = 0;  // the ellipsoid
        int64_t edges = 0, cells = 0;
        double length_over_h_min = 0, length_over_h_mean = 0, length_over_h_max = 0;
        double cell_area_m2 = 0;     // the sum over the cells
        double surface_area_m2 = 0;  // the ellipsoid's
    } geodesic;
};

// The ocean edges of a report (Report::ocean): ocean_cell per vertex slot
// (0: its cell is not in the ocean mesh, 1: it is, 2: only because a passage
// keeps it open); contacts as ocean_connectivity takes them.
Report::OceanEdges measure_ocean_edges(Context &ctx, const tri::Triangulation &tri, const refine::SpacingRadians &h,
                                       const std::vector<uint8_t> &ocean_cell, double floor,
                                       const std::vector<std::pair<int32_t, int32_t>> &contacts,
                                       const geom::Surface &surface = geom::Surface::sphere(1.0));

// The coastline fidelity of a report (Report::coastline): the restricted
// edges whose arc coast_arc flags (per Gamma arc: a closed coastline).
Report::CoastlineFidelity measure_coastline_fidelity(const tri::Triangulation &tri,
                                                     const std::vector<refine::RestrictedEdge> &restricted,
                                                     const std::vector<uint8_t> &coast_arc,
                                                     const refine::SpacingRadians &h, double beta);

// Every metric over the live triangles, edges and cells (in parallel; the
// same result for any thread count). h may be empty: then h_r and dcEdge / h
// are not computed. on_segment: per vertex slot its segment of Gamma or -1
// (null: no vertex on Gamma). cells (per vertex slot, null: all) restricts
// the report to a regional mesh's cells: the triangles and edges all of
// whose vertices are among them.
Report measure(Context &ctx, const tri::Triangulation &tri, const refine::SpacingRadians &h,
               const std::vector<int32_t> *on_segment = nullptr, const std::vector<uint8_t> *cells = nullptr);

// The report as JSON text (for quality.json): an object whose lines after
// the first start with `indent` (to nest it in another report), with
// `extra_members` (JSON "key": value text) appended as its last members.
// Its "operator_diagnostics" give rms and max of each offset and min, max,
// mean and std of dcEdge / h; a value that is not finite is null.
std::string to_json(const Report &r, const std::string &indent = "",
                    const std::string &extra_members = "");

}  // namespace um::quality
