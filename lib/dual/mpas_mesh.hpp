// The MPAS staggered mesh of a Laguerre triangulation (DESIGN.md section 6,
// shared/mpas-format.md): cells are the power cells of the generators, MPAS
// vertices are the triangles (placed at their orthocentres, the power
// vertices), MPAS edges are the primal/dual edge pairs, one per edge of the
// triangulation. Every field of the MPAS mesh contract is here, in double
// precision, with the contract's orientation and ordering conventions:
//
//   edge e      cellsOnEdge(e) = (c1, c2) with c1 < c2; the normal n_e points
//               from c1 to c2 and the tangent k x n_e from verticesOnEdge(e,1)
//               to verticesOnEdge(e,2), i.e. ((c2-c1) x (v2-v1)) . k > 0;
//   cell i      edgesOnCell, verticesOnCell, cellsOnCell counter-clockwise
//               seen from outside; verticesOnCell(i,j) is the CCW end of
//               edgesOnCell(i,j); cellsOnCell(i,j) lies across it; the lists
//               start at the cell's lowest-numbered vertex;
//   vertex v    cellsOnVertex CCW from its lowest-numbered cell;
//               edgesOnVertex(v,j) lies between cellsOnVertex(v,j-1) and
//               cellsOnVertex(v,j); kiteAreasOnVertex(v,j) belongs to
//               cellsOnVertex(v,j).
//
// Areas are signed geodesic areas (never L'Huilier): areaCell is the polygon
// of the power cell fanned from its corner centroid, areaTriangle the
// generator triangle, kites the quads (vertex, xEdge, xCell, xEdge'), so that
// kites sum to areaTriangle and, per cell, to areaCell, and TRSK (Thuburn et
// al. 2009) holds for power cells whose generator lies outside the cell.
//
// Cells, edges and vertices are numbered along a Hilbert curve of their
// positions (generator, xEdge, orthocentre), ties by their index in the
// triangulation, so that neighbours have nearby numbers. Every array is the
// same for any number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/sphere.hpp"
#include "geom/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::mesh {
struct RefinedMesh;
}

namespace um::dual {

// Connectivity below is 0-based with kNone (-1) as padding; the netCDF
// writer turns it into MPAS's 1-based form with 0 padding.
constexpr int32_t kNone = -1;
constexpr int32_t kVertexDegree = 3;
// Bytes per cell of a whole MPAS mesh in memory and the temporaries of its
// construction (3 edges and 2 vertices per cell; maxEdges about 8), for the
// memory cap (1.19-1.24 kB/cell measured at the peak of `unimesh build` when
// mesh.nc was written from it, tools/bench/bench_scale.py). The file writer
// streams instead (mpas_source.hpp).
constexpr int64_t kMpasBytesPerCell = 1600;

struct MpasMesh {
    double radius_m = 0;
    // A mesh made on an ellipsoid (f > 0; 0 for a sphere): its semi-major
    // axis and flattening. MPAS assumes a sphere: the positions are the
    // ellipsoid points' geodetic lon/lat on the sphere of radius_m (the
    // ellipsoid's authalic radius), every length, area and weight computed
    // on that sphere.
    double ellipsoid_a_m = 0, ellipsoid_f = 0;
    int32_t n_cells = 0, n_edges = 0, n_vertices = 0;
    int32_t max_edges = 0;  // max nEdgesOnCell; edgesOnEdge rows have 2 * max_edges

    // Cells (n_cells; 2-D arrays row-major with max_edges per row).
    std::vector<double> x_cell, y_cell, z_cell, lat_cell, lon_cell;
    std::vector<int32_t> n_edges_on_cell;
    std::vector<int32_t> edges_on_cell, vertices_on_cell, cells_on_cell;
    std::vector<double> area_cell, mesh_density;

    // Edges (n_edges; cells_on_edge and vertices_on_edge 2 per edge,
    // edges_on_edge and weights_on_edge 2 * max_edges per edge).
    std::vector<double> x_edge, y_edge, z_edge, lat_edge, lon_edge;
    std::vector<int32_t> cells_on_edge, vertices_on_edge;
    std::vector<int32_t> n_edges_on_edge, edges_on_edge;
    std::vector<double> weights_on_edge;
    std::vector<double> dc_edge, dv_edge, angle_edge;

    // Vertices (n_vertices; 3 per vertex for the 2-D arrays).
    std::vector<double> x_vertex, y_vertex, z_vertex, lat_vertex, lon_vertex;
    std::vector<int32_t> cells_on_vertex, edges_on_vertex;
    std::vector<double> area_triangle, kite_areas_on_vertex;
    std::vector<int32_t> boundary_vertex;  // 1 where a cell of the vertex is missing (a cut mesh)
    // A regional mesh's limited-area layers (empty otherwise): per cell 7 on
    // the boundary (a neighbour missing), 6 beside those, ... 1, then 0;
    // per edge and vertex the least of its cells' values.
    std::vector<int32_t> bdy_mask_cell, bdy_mask_edge, bdy_mask_vertex;

    // Where each element came from: the mesh vertex (index into the vertex
    // numbering given) of each cell, the triangle of each MPAS vertex.
    std::vector<int32_t> cell_source_vertex, vertex_source_triangle;

    // Unified tags (empty when not known): UM_SIDE_* of each cell (its
    // generator) and of each vertex (its orthocentre); the cell masks of the
    // ocean mesh and of the land + river mesh (each cell in exactly one);
    // per edge the feature its dual crosses (UM_FEATURE_*, 0 none), that
    // feature part's id (-1 none) and, for rivers, the downstream direction
    // relative to cellsOnEdge (+1 from cell 1 to cell 2, -1 back, 0 none).
    std::vector<int32_t> cell_side, vertex_side;
    std::vector<int32_t> cell_ocean_mask, cell_land_mask;
    std::vector<int32_t> edge_feature_kind, edge_feature_id, edge_river_downstream;
    // Per edge, 1 where a river's line passes from one of its cells into the
    // other (empty: not known, e.g. a file without it; the routing then takes
    // the edges whose dual crosses a river).
    std::vector<int32_t> edge_on_river;
    // River routing (river_routing.hpp; empty without edge features): per
    // cell the cell its river drains to (kNone: none) and its RiverCellKind.
    std::vector<int32_t> cell_downstream, cell_river_kind;

    // Component meshes (lib/components; empty otherwise). In a component:
    // the base mesh's cell, edge and vertex of each element. In the base:
    // each element's index in the ocean and the land component (kNone where
    // it is not in that component; edges and vertices on the cut are in both).
    std::vector<int32_t> base_cell, base_edge, base_vertex;
    std::vector<int32_t> ocean_cell, ocean_edge, ocean_vertex;
    std::vector<int32_t> land_cell, land_edge, land_vertex;

    int32_t max_edges2() const { return 2 * max_edges; }
};

struct MpasMeshInput {
    // The mesh vertices: slot_of_vertex[i] is the triangulation slot of mesh
    // vertex i. Empty = every slot in the triangulation, in slot order.
    std::vector<int32_t> slot_of_vertex;
    double radius_m = 0;
    // What the triangulation's directions stand for: on an ellipsoid, each
    // position is placed at its geodetic lon/lat on the sphere of radius_m.
    geom::Surface surface = geom::Surface::sphere(1.0);
    // Optional spacing per mesh vertex (km, finite and > 0): meshDensity =
    // (min h / h)^4 as MPAS-Tools' inject_meshDensity (the minimum taken over
    // the cells); empty = 1.0 everywhere.
    std::vector<double> cell_width_km;
    // Per triangulation vertex slot, 1 for the cells of a regional mesh
    // (RefinedMesh::region_cells): the mesh is then those cells and every
    // edge and vertex of theirs (mpas_layout.hpp), kNone where a neighbour
    // is missing, with the limited-area layers bdyMask*
    // (boundary_layers.hpp). Empty: every cell.
    std::vector<uint8_t> region;
};

// Builds the MPAS mesh of tri (free triangle slots are skipped). Throws
// um::Error: a radius that is not finite and > 0, a vertex numbering that is
// not exactly the vertices of tri, counts beyond int32 (UM_ERR_LIMIT), the
// context's memory cap.
MpasMesh build_mpas_mesh(Context &ctx, const tri::Triangulation &tri, const MpasMeshInput &input);

// The same for the refinement stage's mesh, with its vertex numbering, its
// sphere radius, meshDensity from the spacing it was refined to (evaluated
// at the generators) and its ocean/land sides as tags.
MpasMesh build_mpas_mesh(Context &ctx, const mesh::RefinedMesh &refined);

}  // namespace um::dual
