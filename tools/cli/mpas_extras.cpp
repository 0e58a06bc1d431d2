#include "mpas_extras.hpp"

#include "nc_read.hpp"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <vector>

namespace {

bool fail(std::string *error, const std::string &message) {
    *error = message;
    return false;
}

}  // namespace

bool write_graph_info(const std::string &mesh_nc, const std::string &path, std::string *error) {
    NcFile f(mesh_nc);
    if (!f.ok()) return fail(error, "cannot read " + mesh_nc);
    size_t n_cells = 0, n_edges = 0, max_edges = 0;
    std::vector<int32_t> n_on, cells_on;
    if (!f.dim("nCells", &n_cells) || !f.dim("nEdges", &n_edges) || !f.dim("maxEdges", &max_edges) ||
        !f.var("nEdgesOnCell", n_on, n_cells) || !f.var("cellsOnCell", cells_on, n_cells * max_edges))
        return fail(error, mesh_nc + " lacks nCells, nEdges, maxEdges, nEdgesOnCell or cellsOnCell");
    std::ofstream out(path);
    out << n_cells << ' ' << n_edges << '\n';
    for (size_t c = 0; c < n_cells; ++c) {
        for (int32_t j = 0; j < n_on[c]; ++j) {
            int32_t other = cells_on[c * max_edges + j];
            if (other > 0) out << (j ? " " : "") << other;
        }
        out << '\n';
    }
    out.flush();
    return out ? true : fail(error, "cannot write " + path);
}

namespace {

// A VTK unstructured grid of polygons (ASCII): points, each cell's corners
// (0-based) and where each cell's corners end, one real and one optional
// integer value per cell.
struct VtuGrid {
    const std::vector<double> &x, &y, &z;
    std::vector<int64_t> corners, ends;
    int vtk_type;  // 7 polygon, 5 triangle
    const char *real_name;
    const std::vector<double> &real;
    const char *int_name;
    const std::vector<int32_t> *ints;  // null: none
};

bool write_vtu(const std::string &path, const VtuGrid &g, std::string *error) {
    std::ofstream out(path);
    out.precision(9);  // for viewing: float precision is plenty, and 17 digits cost time
    const size_t n_points = g.x.size(), n_cells = g.ends.size();
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
        << n_points << "\" NumberOfCells=\"" << n_cells << "\">\n<Points>\n"
        << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (size_t v = 0; v < n_points; ++v) out << g.x[v] << ' ' << g.y[v] << ' ' << g.z[v] << '\n';
    out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (size_t c = 0, k = 0; c < n_cells; ++c) {
        for (; k < static_cast<size_t>(g.ends[c]); ++k) out << g.corners[k] << ' ';
        out << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (int64_t end : g.ends) out << end << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (size_t c = 0; c < n_cells; ++c) out << g.vtk_type << '\n';
    out << "</DataArray>\n</Cells>\n<CellData>\n<DataArray type=\"Float64\" Name=\"" << g.real_name
        << "\" format=\"ascii\">\n";
    for (double v : g.real) out << v << '\n';
    out << "</DataArray>\n";
    if (g.ints) {
        out << "<DataArray type=\"Int32\" Name=\"" << g.int_name << "\" format=\"ascii\">\n";
        for (int32_t v : *g.ints) out << v << '\n';
        out << "</DataArray>\n";
    }
    out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    out.flush();
    return out ? true : fail(error, "cannot write " + path);
}

// A mesh made on an ellipsoid (the file's ellipsoid_semi_major_axis and
// ellipsoid_flattening) is drawn there: each point at its geodetic lat/lon on
// the ellipsoid, not on the sphere mesh.nc (for MPAS) places it on.
// `where` is "Cell" or "Vertex"; false when the file lacks the lat/lon.
bool place_on_ellipsoid(const NcFile &f, const std::string &where, size_t n, std::vector<double> &x,
                        std::vector<double> &y, std::vector<double> &z) {
    double a = 0, flattening = 0;
    if (!f.global("ellipsoid_semi_major_axis", &a) || !f.global("ellipsoid_flattening", &flattening)) return true;
    std::vector<double> lat, lon;
    if (!f.var(("lat" + where).c_str(), lat, n) || !f.var(("lon" + where).c_str(), lon, n)) return false;
    const double e2 = flattening * (2 - flattening);
    for (size_t i = 0; i < n; ++i) {
        const double s = std::sin(lat[i]), c = std::cos(lat[i]);
        const double normal = a / std::sqrt(1 - e2 * s * s);  // the prime vertical's radius of curvature
        x[i] = normal * c * std::cos(lon[i]), y[i] = normal * c * std::sin(lon[i]), z[i] = normal * (1 - e2) * s;
    }
    return true;
}

}  // namespace

bool write_cells_vtu(const std::string &mesh_nc, const std::string &path, std::string *error) {
    NcFile f(mesh_nc);
    if (!f.ok()) return fail(error, "cannot read " + mesh_nc);
    size_t n_cells = 0, n_vertices = 0, max_edges = 0;
    std::vector<int32_t> n_on, verts_on, side;
    std::vector<double> x, y, z, area;
    if (!f.dim("nCells", &n_cells) || !f.dim("nVertices", &n_vertices) || !f.dim("maxEdges", &max_edges) ||
        !f.var("nEdgesOnCell", n_on, n_cells) || !f.var("verticesOnCell", verts_on, n_cells * max_edges) ||
        !f.var("xVertex", x, n_vertices) || !f.var("yVertex", y, n_vertices) ||
        !f.var("zVertex", z, n_vertices) || !f.var("areaCell", area, n_cells))
        return fail(error, mesh_nc + " lacks the cell polygons (verticesOnCell, x/y/zVertex, areaCell)");
    if (!place_on_ellipsoid(f, "Vertex", n_vertices, x, y, z))
        return fail(error, mesh_nc + " lacks latVertex or lonVertex");
    const bool has_side = f.var("cellSide", side, n_cells);
    VtuGrid g{x, y, z, {}, {}, 7 /* VTK_POLYGON */, "areaCell", area, "cellSide", has_side ? &side : nullptr};
    for (size_t c = 0; c < n_cells; ++c) {
        for (int32_t j = 0; j < n_on[c]; ++j) g.corners.push_back(verts_on[c * max_edges + j] - 1);
        g.ends.push_back(static_cast<int64_t>(g.corners.size()));
    }
    return write_vtu(path, g, error);
}

bool write_triangles_vtu(const std::string &mesh_nc, const std::string &path, std::string *error) {
    NcFile f(mesh_nc);
    if (!f.ok()) return fail(error, "cannot read " + mesh_nc);
    size_t n_cells = 0, n_vertices = 0;
    std::vector<int32_t> cells_on_vertex, side;
    std::vector<double> x, y, z, area;
    if (!f.dim("nCells", &n_cells) || !f.dim("nVertices", &n_vertices) ||
        !f.var("cellsOnVertex", cells_on_vertex, 3 * n_vertices) || !f.var("xCell", x, n_cells) ||
        !f.var("yCell", y, n_cells) || !f.var("zCell", z, n_cells) || !f.var("areaTriangle", area, n_vertices))
        return fail(error, mesh_nc + " lacks the triangles (cellsOnVertex, x/y/zCell, areaTriangle)");
    if (!place_on_ellipsoid(f, "Cell", n_cells, x, y, z)) return fail(error, mesh_nc + " lacks latCell or lonCell");
    const bool has_side = f.var("vertexSide", side, n_vertices);
    VtuGrid g{x, y, z, {}, {}, 5 /* VTK_TRIANGLE */, "areaTriangle", area, "vertexSide", has_side ? &side : nullptr};
    for (size_t v = 0; v < n_vertices; ++v) {
        for (int k = 0; k < 3; ++k) g.corners.push_back(cells_on_vertex[3 * v + k] - 1);
        g.ends.push_back(static_cast<int64_t>(g.corners.size()));
    }
    return write_vtu(path, g, error);
}
