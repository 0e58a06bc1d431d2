#include "dual/mpas_fields.hpp"

#include "dual/river_routing.hpp"
#include "unimesh.h"

namespace um::dual {

using D = MpasDim;

const char *mpas_dim_name(MpasDim d) {
    static const char *const names[kMpasDimCount] = {"nCells",    "nEdges", "nVertices",    "maxEdges",
                                                     "maxEdges2", "TWO",    "vertexDegree", "Time"};
    return names[static_cast<int>(d)];
}

int64_t mpas_dim_length(const MpasMesh &m, MpasDim d) {
    switch (d) {
        case D::nCells: return m.n_cells;
        case D::nEdges: return m.n_edges;
        case D::nVertices: return m.n_vertices;
        case D::maxEdges: return m.max_edges;
        case D::maxEdges2: return m.max_edges2();
        case D::TWO: return 2;
        case D::vertexDegree: return kVertexDegree;
        case D::Time: return 1;
    }
    return 0;
}

namespace {

// The side tags: flag attributes as CF's flag_values / flag_meanings.
constexpr int32_t kSideFlags[3] = {UM_SIDE_OCEAN, UM_SIDE_LAND, UM_SIDE_COASTAL};
constexpr const char *kSideMeanings = "ocean land coastal";
constexpr int32_t kFeatureFlags[7] = {0, UM_FEATURE_COASTLINE, UM_FEATURE_LAKE, UM_FEATURE_RIVER,
                                      UM_FEATURE_WATERSHED, UM_FEATURE_OTHER, UM_FEATURE_DOMAIN};
constexpr const char *kFeatureMeanings = "none coastline lake river watershed other domain";
constexpr int32_t kRiverFlags[4] = {kNotRiver, kRouted, kOutlet, kInland};
constexpr const char *kRiverMeanings = "none routed outlet inland";

// The maps between a base mesh and its component meshes, where m has them.
void add_component_maps(const MpasMesh &m, std::vector<MpasField> &f) {
    const struct {
        const char *name;
        MpasDim dim;
        const std::vector<int32_t> &map;
        const char *long_name;
    } maps[] = {
        {"baseCellId", D::nCells, m.base_cell, "the cell of the base mesh this cell is"},
        {"baseEdgeId", D::nEdges, m.base_edge, "the edge of the base mesh this edge is"},
        {"baseVertexId", D::nVertices, m.base_vertex, "the vertex of the base mesh this vertex is"},
        {"oceanCellId", D::nCells, m.ocean_cell, "the cell of the ocean mesh this cell is, 0 where none"},
        {"oceanEdgeId", D::nEdges, m.ocean_edge, "the edge of the ocean mesh this edge is, 0 where none"},
        {"oceanVertexId", D::nVertices, m.ocean_vertex, "the vertex of the ocean mesh this vertex is, 0 where none"},
        {"landCellId", D::nCells, m.land_cell, "the cell of the land mesh this cell is, 0 where none"},
        {"landEdgeId", D::nEdges, m.land_edge, "the edge of the land mesh this edge is, 0 where none"},
        {"landVertexId", D::nVertices, m.land_vertex, "the vertex of the land mesh this vertex is, 0 where none"},
    };
    for (const auto &map : maps)
        if (!map.map.empty())
            f.push_back(MpasField{map.name, {map.dim}, MpasKind::index, nullptr, &map.map, map.long_name, nullptr});
}

}  // namespace

std::vector<MpasField> mpas_fields(const MpasMesh &m) {
    const std::vector<double> *no_reals = nullptr;
    const std::vector<int32_t> *no_ints = nullptr;
    auto real = [&](const char *name, std::vector<MpasDim> dims, const std::vector<double> &a,
                    const char *long_name, const char *units) {
        return MpasField{name, std::move(dims), MpasKind::real, &a, no_ints, long_name, units};
    };
    auto integer = [&](const char *name, std::vector<MpasDim> dims, const std::vector<int32_t> &a,
                       MpasKind kind, const char *long_name) {
        return MpasField{name, std::move(dims), kind, no_reals, &a, long_name, nullptr};
    };
    auto id = [&](const char *name, MpasDim dim, const char *long_name) {
        return MpasField{name, {dim}, MpasKind::id, no_reals, no_ints, long_name, nullptr};
    };
    const MpasKind I = MpasKind::index, N = MpasKind::integer;
    std::vector<MpasField> f = {
        real("latCell", {D::nCells}, m.lat_cell, "latitude of the cell generator", "radians"),
        real("lonCell", {D::nCells}, m.lon_cell, "longitude of the cell generator", "radians"),
        real("xCell", {D::nCells}, m.x_cell, "x of the cell generator", "m"),
        real("yCell", {D::nCells}, m.y_cell, "y of the cell generator", "m"),
        real("zCell", {D::nCells}, m.z_cell, "z of the cell generator", "m"),
        id("indexToCellID", D::nCells, "global cell index"),
        real("latEdge", {D::nEdges}, m.lat_edge, "latitude of the edge orthocentre", "radians"),
        real("lonEdge", {D::nEdges}, m.lon_edge, "longitude of the edge orthocentre", "radians"),
        real("xEdge", {D::nEdges}, m.x_edge, "x of the edge orthocentre", "m"),
        real("yEdge", {D::nEdges}, m.y_edge, "y of the edge orthocentre", "m"),
        real("zEdge", {D::nEdges}, m.z_edge, "z of the edge orthocentre", "m"),
        id("indexToEdgeID", D::nEdges, "global edge index"),
        real("latVertex", {D::nVertices}, m.lat_vertex, "latitude of the orthocentre (power vertex)", "radians"),
        real("lonVertex", {D::nVertices}, m.lon_vertex, "longitude of the orthocentre (power vertex)", "radians"),
        real("xVertex", {D::nVertices}, m.x_vertex, "x of the orthocentre (power vertex)", "m"),
        real("yVertex", {D::nVertices}, m.y_vertex, "y of the orthocentre (power vertex)", "m"),
        real("zVertex", {D::nVertices}, m.z_vertex, "z of the orthocentre (power vertex)", "m"),
        id("indexToVertexID", D::nVertices, "global vertex index"),
        integer("nEdgesOnCell", {D::nCells}, m.n_edges_on_cell, N, "number of edges of the cell"),
        integer("nEdgesOnEdge", {D::nEdges}, m.n_edges_on_edge, N, "number of edges in the TRSK stencil"),
        integer("cellsOnCell", {D::nCells, D::maxEdges}, m.cells_on_cell, I, "cells across edgesOnCell, counter-clockwise"),
        integer("edgesOnCell", {D::nCells, D::maxEdges}, m.edges_on_cell, I, "edges of the cell, counter-clockwise"),
        integer("verticesOnCell", {D::nCells, D::maxEdges}, m.vertices_on_cell, I, "vertices of the cell, counter-clockwise"),
        integer("edgesOnEdge", {D::nEdges, D::maxEdges2}, m.edges_on_edge, I, "TRSK stencil edges"),
        real("weightsOnEdge", {D::nEdges, D::maxEdges2}, m.weights_on_edge, "TRSK weights (Thuburn et al. 2009)", nullptr),
        integer("cellsOnEdge", {D::nEdges, D::TWO}, m.cells_on_edge, I, "cells of the edge, normal from 1 to 2"),
        integer("verticesOnEdge", {D::nEdges, D::TWO}, m.vertices_on_edge, I, "vertices of the edge, tangent from 1 to 2"),
        integer("cellsOnVertex", {D::nVertices, D::vertexDegree}, m.cells_on_vertex, I, "cells of the vertex, counter-clockwise"),
        integer("edgesOnVertex", {D::nVertices, D::vertexDegree}, m.edges_on_vertex, I, "edges of the vertex, counter-clockwise"),
        real("areaCell", {D::nCells}, m.area_cell, "area of the power cell", "m2"),
        real("areaTriangle", {D::nVertices}, m.area_triangle, "area of the triangle of cell generators", "m2"),
        real("kiteAreasOnVertex", {D::nVertices, D::vertexDegree}, m.kite_areas_on_vertex, "area of the triangle inside each cell (signed)", "m2"),
        real("dcEdge", {D::nEdges}, m.dc_edge, "great-circle distance between the two cell generators", "m"),
        real("dvEdge", {D::nEdges}, m.dv_edge, "great-circle distance between the two vertices", "m"),
        real("angleEdge", {D::nEdges}, m.angle_edge, "angle of the edge normal counter-clockwise from east", "radians"),
        real("meshDensity", {D::nCells}, m.mesh_density, "mesh density (min cell width / cell width)^4", nullptr),
        integer("boundaryVertex", {D::nVertices}, m.boundary_vertex, N, "1 where the vertex has fewer than vertexDegree cells (a cut mesh's boundary)"),
    };
    auto side = [&](const char *name, MpasDim dim, const std::vector<int32_t> &a, const char *long_name) {
        MpasField field = integer(name, {dim}, a, N, long_name);
        field.flag_values = kSideFlags, field.n_flags = 3, field.flag_meanings = kSideMeanings;
        return field;
    };
    if (!m.bdy_mask_cell.empty()) {
        f.push_back(integer("bdyMaskCell", {D::nCells}, m.bdy_mask_cell, N,
                            "limited-area boundary layer of the cell: 7 on the boundary, 6 next, ... 1, "
                            "0 in the interior"));
        f.push_back(integer("bdyMaskEdge", {D::nEdges}, m.bdy_mask_edge, N,
                            "the least bdyMaskCell of the edge's cells"));
        f.push_back(integer("bdyMaskVertex", {D::nVertices}, m.bdy_mask_vertex, N,
                            "the least bdyMaskCell of the vertex's cells"));
    }
    if (!m.cell_side.empty())
        f.push_back(side("cellSide", D::nCells, m.cell_side,
                         "side of the closed coastlines of the cell generator"));
    if (!m.vertex_side.empty())
        f.push_back(side("vertexSide", D::nVertices, m.vertex_side,
                         "side of the closed coastlines of the vertex (orthocentre)"));
    if (!m.cell_ocean_mask.empty()) {
        f.push_back(integer("cellOceanMask", {D::nCells}, m.cell_ocean_mask, N,
                            "1: the cell belongs to the ocean mesh (ocean, or coastal with most of "
                            "its corners on the ocean side); exactly 1 - cellLandMask"));
        f.push_back(integer("cellLandMask", {D::nCells}, m.cell_land_mask, N,
                            "1: the cell belongs to the land and river mesh; exactly 1 - cellOceanMask"));
    }
    if (!m.edge_feature_kind.empty()) {
        MpasField kind = integer("edgeFeatureKind", {D::nEdges}, m.edge_feature_kind, N,
                                 "feature whose segment the edge's dual (the cell face) crosses: "
                                 "the edge is a restricted edge of that feature");
        kind.flag_values = kFeatureFlags, kind.n_flags = 7, kind.flag_meanings = kFeatureMeanings;
        f.push_back(kind);
        f.push_back(integer("edgeFeatureId", {D::nEdges}, m.edge_feature_id, N,
                            "id of the feature part the edge's dual crosses, -1 where none"));
        f.push_back(integer("edgeRiverDownstream", {D::nEdges}, m.edge_river_downstream, N,
                            "river edges: +1 when the routed river flows from cellsOnEdge(1) to "
                            "cellsOnEdge(2) (towards its outlet on the coast, or into the sea), "
                            "-1 the other way, 0 not a river edge or no flow decided (a network "
                            "with no coast, an edge between cells as far from the outlet)"));
    }
    if (!m.edge_on_river.empty())
        f.push_back(integer("edgeOnRiver", {D::nEdges}, m.edge_on_river, N,
                            "1 where a river's line passes from one cell of the edge into the other "
                            "(the river network the routing follows)"));
    if (!m.cell_downstream.empty()) {
        f.push_back(integer("downstreamCell", {D::nCells}, m.cell_downstream, I,
                            "the cell this cell's river drains to; 0 where none (outlets, "
                            "networks with no coast, cells without rivers)"));
        MpasField kind = integer("riverCellKind", {D::nCells}, m.cell_river_kind, N,
                                 "river routing of the cell: none, drains to downstreamCell, "
                                 "outlet on the coast, in a network that reaches no coast");
        kind.flag_values = kRiverFlags, kind.n_flags = 4, kind.flag_meanings = kRiverMeanings;
        f.push_back(kind);
    }
    add_component_maps(m, f);
    return f;
}


}  // namespace um::dual
