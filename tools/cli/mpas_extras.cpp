#include "mpas_extras.hpp"

#include "nc_read.hpp"

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
    return out ? true : fail(error, "cannot write " + path);
}

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
    const bool has_side = f.var("cellSide", side, n_cells);
    std::ofstream out(path);
    out.precision(9);  // for viewing: float precision is plenty, and 17 digits cost time
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
        << n_vertices << "\" NumberOfCells=\"" << n_cells << "\">\n<Points>\n"
        << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (size_t v = 0; v < n_vertices; ++v) out << x[v] << ' ' << y[v] << ' ' << z[v] << '\n';
    out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (size_t c = 0; c < n_cells; ++c) {
        for (int32_t j = 0; j < n_on[c]; ++j) out << verts_on[c * max_edges + j] - 1 << ' ';
        out << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    int64_t offset = 0;
    for (size_t c = 0; c < n_cells; ++c) out << (offset += n_on[c]) << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (size_t c = 0; c < n_cells; ++c) out << "7\n";  // VTK_POLYGON
    out << "</DataArray>\n</Cells>\n<CellData>\n<DataArray type=\"Float64\" Name=\"areaCell\" format=\"ascii\">\n";
    for (size_t c = 0; c < n_cells; ++c) out << area[c] << '\n';
    out << "</DataArray>\n";
    if (has_side) {
        out << "<DataArray type=\"Int32\" Name=\"cellSide\" format=\"ascii\">\n";
        for (size_t c = 0; c < n_cells; ++c) out << side[c] << '\n';
        out << "</DataArray>\n";
    }
    out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    return out ? true : fail(error, "cannot write " + path);
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
    const bool has_side = f.var("vertexSide", side, n_vertices);
    std::ofstream out(path);
    out.precision(9);  // for viewing: float precision is plenty, and 17 digits cost time
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
        << n_cells << "\" NumberOfCells=\"" << n_vertices << "\">\n<Points>\n"
        << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (size_t c = 0; c < n_cells; ++c) out << x[c] << ' ' << y[c] << ' ' << z[c] << '\n';
    out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (size_t v = 0; v < n_vertices; ++v)
        out << cells_on_vertex[3 * v] - 1 << ' ' << cells_on_vertex[3 * v + 1] - 1 << ' '
            << cells_on_vertex[3 * v + 2] - 1 << '\n';
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (size_t v = 0; v < n_vertices; ++v) out << 3 * (v + 1) << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (size_t v = 0; v < n_vertices; ++v) out << "5\n";  // VTK_TRIANGLE
    out << "</DataArray>\n</Cells>\n<CellData>\n<DataArray type=\"Float64\" Name=\"areaTriangle\" format=\"ascii\">\n";
    for (size_t v = 0; v < n_vertices; ++v) out << area[v] << '\n';
    out << "</DataArray>\n";
    if (has_side) {
        out << "<DataArray type=\"Int32\" Name=\"vertexSide\" format=\"ascii\">\n";
        for (size_t v = 0; v < n_vertices; ++v) out << side[v] << '\n';
        out << "</DataArray>\n";
    }
    out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    return out ? true : fail(error, "cannot write " + path);
}
