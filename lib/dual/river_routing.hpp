// River routing on the cells of an MPAS mesh, the way a routing model
// (MOSART-style) needs it: each land cell on a river has one downstream cell.
//
// The river graph joins the two land cells of every edge a river's line
// crosses (edgeOnRiver: the cells along each river segment, in order, from
// the input lines; where a mesh does not carry that, a file without it, the
// edges whose dual crosses a river, edgeFeatureKind == river), and bridges
// the gaps of up to one land cell where those chains break (a spanning
// forest of the pieces: no bridge closes a cycle). The direction
// comes from the graph's topology, not from the order of the points in the
// input:
// a river cell from which the river crosses into an ocean cell, or out of
// a regional mesh across its open boundary, is an outlet
// (a network whose lines end short of the sea has its river cells on the
// coast, beside an ocean cell, as outlets instead), and every other cell drains along the shortest path of river edges to the
// nearest outlet of its network (a breadth-first search from all outlets at
// once, in cell order, so the result does not depend on threads or input
// order). What the graph cannot route is reported, not hidden: networks with
// no cell on the coast (their cells get no downstream cell) and networks with
// cycles (braids or loops; the search keeps one path per cell and says how
// many independent cycles it broke).
#pragma once

#include <cstdint>
#include <vector>

#include "dual/mpas_mesh.hpp"

namespace um::dual {

// Values of MpasMesh::cell_river_kind (the riverCellKind variable).
enum RiverCellKind : int32_t {
    kNotRiver = 0,  // no river edge on the cell (or an ocean cell)
    kRouted = 1,    // drains to downstreamCell
    kOutlet = 2,    // on the coast: the river leaves the land here
    kInland = 3     // its network reaches no coast: no downstream cell
};

struct RiverNetworkNote {
    int32_t network = 0;  // 0-based, numbered by their lowest cell
    int32_t cells = 0;    // river cells in the network
    int32_t cell = 0;     // the network's lowest-numbered cell (0-based), to find it
    int32_t cycles = 0;   // independent cycles (edges - cells + 1)
};

struct RiverReport {
    int32_t networks = 0, river_cells = 0, routed_cells = 0, outlets = 0;
    int32_t bridges = 0;  // gaps joined between neighbouring river cells
    // Of the outlets, those where a river leaves a regional mesh across its
    // open boundary (a missing neighbour) rather than into an ocean cell.
    int32_t boundary_outlets = 0;
    std::vector<RiverNetworkNote> inland;       // networks with no outlet
    std::vector<RiverNetworkNote> with_cycles;  // networks whose graph has cycles
};

struct RiverRouting {
    // As MpasMesh's cell_downstream, cell_river_kind, edge_river_downstream.
    std::vector<int32_t> cell_downstream, cell_river_kind, edge_river_downstream;
    RiverReport report;
};

// The routing of m from m.edge_feature_kind, m.cell_land_mask and the
// connectivity (every cell is land when the mesh has no masks). A mesh
// without edge features gets empty arrays.
RiverRouting river_routing(const MpasMesh &m);

// river_routing(m) stored in m (cell_downstream, cell_river_kind,
// edge_river_downstream); returns its report.
RiverReport route_rivers(MpasMesh &m);

}  // namespace um::dual
