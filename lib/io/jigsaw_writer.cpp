#include "io/jigsaw_writer.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/error.hpp"
#include "core/text.hpp"
#include "io/replacing_file.hpp"
#include "mesh/refined_mesh.hpp"

namespace um::io {

namespace {

struct CloseFile {
    void operator()(std::FILE *f) const { std::fclose(f); }
};

}  // namespace

// Numbers through to_text (shortest text that reads back exactly), not
// printf: the host may have set a locale whose decimal mark is a comma.
void write_jigsaw_mesh(const mesh::RefinedMesh &m, const std::string &path, const std::vector<uint8_t> *cells) {
    ReplacingFile out(path, "JIGSAW mesh file");
    std::unique_ptr<std::FILE, CloseFile> file(std::fopen(out.temporary_path().c_str(), "w"));
    if (!file) fail(UM_ERR_IO, "cannot create JIGSAW mesh file '", path, "'");
    std::FILE *f = file.get();
    const double r = m.radius_m();
    const geom::Surface &surface = m.surface;
    const tri::Triangulation &tri = m.tri;
    // Which vertices and triangles are written, and each vertex's number in
    // the file: its own, or for a regional mesh its rank among the kept
    // (a table only then: 8 bytes a cell).
    auto kept = [&](int32_t slot) { return !cells || (*cells)[static_cast<size_t>(slot)] != 0; };
    std::vector<int64_t> rank;
    int64_t n = m.vertex_count(), n_triangles = tri.triangle_count();
    if (cells) {
        rank.assign(static_cast<size_t>(m.vertex_count()), -1);
        n = 0;
        for (int64_t i = 0; i < m.vertex_count(); ++i)
            if (kept(m.slot_of_vertex[i])) rank[i] = n++;
    }
    auto number = [&](int64_t vertex) { return cells ? rank[static_cast<size_t>(vertex)] : vertex; };
    auto written = [&](int32_t t) {
        return !tri.is_free(t) && kept(tri.vertex(t, 0)) && kept(tri.vertex(t, 1)) && kept(tri.vertex(t, 2));
    };
    if (cells) {
        n_triangles = 0;
        for (int32_t t = 0; t < tri.triangle_slots(); ++t) n_triangles += written(t);
    }
    std::string text;
    bool ok = true;
    // Written in pieces of about a megabyte, each with one fwrite.
    auto flush = [&](bool always) {
        if (ok && (always || text.size() > (1u << 20))) {
            ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
            text.clear();
        }
    };
    if (surface.is_sphere())
        append_all(text, "# unimesh " UM_VERSION_STRING " Laguerre-Power mesh of the sphere, radius ", r, " m\n");
    else
        append_all(text, "# unimesh " UM_VERSION_STRING " Laguerre-Power mesh of the ellipsoid, semi-major axis ", r,
                   " m, flattening ", surface.f(), ": points on the ellipsoid, power weights on the sphere of its "
                   "directions (radius a)\n");
    if (cells)
        append_all(text, "# a regional mesh: the ", n, " cells inside its domain and the triangles between them\n");
    append_all(text, "MSHID=3;EUCLIDEAN-MESH\nNDIMS=3\nPOINT=", n, "\n");
    for (int64_t i = 0; i < m.vertex_count() && ok; ++i) {
        if (number(i) < 0) continue;
        const geom::Vec3 x = surface.point(tri.direction(m.slot_of_vertex[i]));
        append_all(text, x.x, ";", x.y, ";", x.z, ";0\n");
        flush(false);
    }
    append_all(text, "POWER=", n, ";1\n");
    for (int64_t i = 0; i < m.vertex_count() && ok; ++i) {
        if (number(i) < 0) continue;
        append_all(text, tri.weight(m.slot_of_vertex[i]) * r * r, "\n");
        flush(false);
    }
    append_all(text, "TRIA3=", n_triangles, "\n");
    auto file_number = [&](int32_t t, int k) { return number(m.vertex_of_slot[tri.vertex(t, k)]); };
    for (int32_t t = 0; t < tri.triangle_slots() && ok; ++t) {
        if (!written(t)) continue;
        append_all(text, file_number(t, 0), ";", file_number(t, 1), ";", file_number(t, 2), ";0\n");
        flush(false);
    }
    flush(true);
    if (ok) ok = std::fclose(file.release()) == 0;
    if (!ok) fail(UM_ERR_IO, "cannot write JIGSAW mesh file '", path, "'");  // the old file stays
    out.commit();
}

}  // namespace um::io
