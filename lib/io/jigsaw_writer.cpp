#include "io/jigsaw_writer.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/error.hpp"
#include "io/replacing_file.hpp"
#include "mesh/refined_mesh.hpp"

namespace um::io {

namespace {

struct CloseFile {
    void operator()(std::FILE *f) const { std::fclose(f); }
};

}  // namespace

void write_jigsaw_mesh(const mesh::RefinedMesh &m, const std::string &path) {
    ReplacingFile out(path, "JIGSAW mesh file");
    std::unique_ptr<std::FILE, CloseFile> file(std::fopen(out.temporary_path().c_str(), "w"));
    if (!file) fail(UM_ERR_IO, "cannot create JIGSAW mesh file '", path, "'");
    std::FILE *f = file.get();
    const double r = m.radius_m;
    const int64_t n = m.vertex_count();
    const tri::Triangulation &tri = m.tri;
    bool ok = std::fprintf(f, "# unimesh " UM_VERSION_STRING " Laguerre-Power mesh of the sphere, radius %.17g m\n"
                              "MSHID=3;EUCLIDEAN-MESH\nNDIMS=3\nPOINT=%lld\n",
                           r, static_cast<long long>(n)) > 0;
    for (int64_t i = 0; i < n && ok; ++i) {
        const geom::Vec3 x = tri.direction(m.slot_of_vertex[i]);
        ok = std::fprintf(f, "%.17g;%.17g;%.17g;0\n", r * x.x, r * x.y, r * x.z) > 0;
    }
    ok = ok && std::fprintf(f, "POWER=%lld;1\n", static_cast<long long>(n)) > 0;
    for (int64_t i = 0; i < n && ok; ++i)
        ok = std::fprintf(f, "%.17g\n", tri.weight(m.slot_of_vertex[i]) * r * r) > 0;
    ok = ok && std::fprintf(f, "TRIA3=%d\n", tri.triangle_count()) > 0;
    for (int32_t t = 0; t < tri.triangle_slots() && ok; ++t) {
        if (tri.is_free(t)) continue;
        ok = std::fprintf(f, "%d;%d;%d;0\n", m.vertex_of_slot[tri.vertex(t, 0)],
                          m.vertex_of_slot[tri.vertex(t, 1)], m.vertex_of_slot[tri.vertex(t, 2)]) > 0;
    }
    if (ok) ok = std::fclose(file.release()) == 0;
    if (!ok) fail(UM_ERR_IO, "cannot write JIGSAW mesh file '", path, "'");  // the old file stays
    out.commit();
}

}  // namespace um::io
