// MPAS output through the C ABI: the staggered mesh of a um_mesh, written as
// an MPAS mesh file.
#include <algorithm>
#include <utility>
#include <cstring>

#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "dual/mpas_fields.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/mpas_source.hpp"
#include "io/jigsaw_writer.hpp"
#include "io/mpas_writer.hpp"

using um::fail;
using um::capi::HandleKind;
using um::capi::MeshInUse;
using um::capi::require_handle;
using um::capi::check_base;
using um::capi::check_capacity;
using um::capi::require_pointer;

namespace {

um::Context *mesh_context(const um_mesh *m) {
    return um::capi::is_live(m, HandleKind::mesh) ? m->context.get() : nullptr;
}

// The variable called name of the mesh whose variables `probe` lists,
// checked to be of the given type (0: any).
um::dual::MpasField field_of(const um::dual::MpasMesh &probe, const char *name, int32_t type) {
    require_pointer(name, "name");
    for (const um::dual::MpasField &f : um::dual::mpas_fields(probe)) {
        if (std::strcmp(f.name, name) != 0) continue;
        const int32_t is = f.kind == um::dual::MpasKind::real ? UM_MPAS_REAL : UM_MPAS_INT;
        if (type != 0 && type != is)
            fail(UM_ERR_INVALID_ARGUMENT, "MPAS variable '", name, "' holds ",
                 is == UM_MPAS_REAL ? "reals: use um_mesh_copy_mpas_real" : "integers: use um_mesh_copy_mpas_int");
        return f;
    }
    fail(UM_ERR_INVALID_ARGUMENT, "name = '", name, "' is not an MPAS variable of this mesh");
}

// Variable `name` of m's staggered mesh into out, a block of rows at a time:
// put(field, values, at) for each block: its `values` values go to out + at.
template <class Put>
void copy_variable(const um_mesh *m, const char *name, int32_t type, int64_t capacity, const void *out, Put put) {
    require_pointer(name, "name");
    const um::dual::MpasSource &source = m->staggered();
    um::dual::MpasMesh probe = source.probe(*m->context);
    const um::dual::MpasField f = field_of(probe, name, type);
    const int64_t columns = f.columns(probe);
    check_capacity(capacity, f.rows(probe) * columns, name);
    require_pointer(out, "out");
    um::dual::for_each_block_of(*m->context, source, std::move(probe), f,
                                [&](const um::dual::MpasField &block, int64_t first, int64_t count) {
        const int64_t values = count * columns;
        const size_t have = block.reals ? block.reals->size() : block.ints ? block.ints->size() : size_t(values);
        if (have < static_cast<size_t>(values))
            fail(UM_ERR_INTERNAL, "MPAS mesh: a block of ", name, " has ", have, " values, not ", values);
        put(block, values, first * columns);
    });
}

}  // namespace

extern "C" {

UM_API um_status um_mesh_mpas_dimensions(const um_mesh *m, int64_t *n_cells, int64_t *n_edges,
                                         int64_t *n_vertices, int64_t *max_edges) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    const um::dual::MpasMesh mpas = m->staggered().shape();
    if (n_cells) *n_cells = mpas.n_cells;
    if (n_edges) *n_edges = mpas.n_edges;
    if (n_vertices) *n_vertices = mpas.n_vertices;
    if (max_edges) *max_edges = mpas.max_edges;
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_mpas_variable(const um_mesh *m, const char *name, int32_t *type,
                                       int64_t *n_rows, int64_t *n_columns) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    require_pointer(name, "name");
    const um::dual::MpasMesh fields = m->staggered().probe(*m->context);
    const um::dual::MpasField f = field_of(fields, name, 0);
    if (type) *type = f.kind == um::dual::MpasKind::real ? UM_MPAS_REAL : UM_MPAS_INT;
    if (n_rows) *n_rows = f.rows(fields);
    if (n_columns) *n_columns = f.columns(fields);
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_copy_mpas_real(const um_mesh *m, const char *name, double *out,
                                        int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    copy_variable(m, name, UM_MPAS_REAL, capacity, out,
                  [&](const um::dual::MpasField &block, int64_t values, int64_t at) {
                      std::copy(block.reals->begin(), block.reals->begin() + values, out + at);
                  });
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_copy_mpas_int(const um_mesh *m, const char *name, int32_t base,
                                       int32_t *out, int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    check_base(base);
    copy_variable(m, name, UM_MPAS_INT, capacity, out,
                  [&](const um::dual::MpasField &block, int64_t values, int64_t at) {
                      int32_t *to = out + at;
                      for (int64_t i = 0; i < values; ++i) {
                          switch (block.kind) {
                              case um::dual::MpasKind::index: to[i] = (*block.ints)[i] + base; break;  // kNone -> base - 1
                              case um::dual::MpasKind::id: to[i] = static_cast<int32_t>(at + i) + base; break;
                              default: to[i] = (*block.ints)[i]; break;
                          }
                      }
                  });
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_write_jigsaw(const um_mesh *m, const char *path) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    require_pointer(path, "path");
    if (path[0] == '\0') fail(UM_ERR_INVALID_ARGUMENT, "path is empty");
    // A regional mesh's triangulation covers the sphere: its domain's part.
    const std::vector<uint8_t> cells =
        m->mesh.regional() ? m->mesh.region_cells(*m->context) : std::vector<uint8_t>{};
    um::io::write_jigsaw_mesh(m->mesh, path, m->mesh.regional() ? &cells : nullptr);
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_release_mpas(um_mesh *m) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    m->release_staggered();
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_write_mpas_as(const um_mesh *m, const char *path, int32_t format) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    require_pointer(path, "path");
    if (path[0] == '\0') fail(UM_ERR_INVALID_ARGUMENT, "path is empty");
    if (format != UM_MPAS_FILE_AUTO && format != UM_MPAS_FILE_NETCDF4)
        fail(UM_ERR_INVALID_ARGUMENT, "format = ", format,
             " is not UM_MPAS_FILE_AUTO (0) or UM_MPAS_FILE_NETCDF4 (1)");
    um::Context &ctx = *m->context;
    ctx.progress("MPAS mesh", 0.0);
    um::io::MpasWriteOptions options;
    if (format == UM_MPAS_FILE_NETCDF4) options.format = um::io::MpasFileFormat::netcdf4;
    // Streamed: the file is written a block of rows at a time from the
    // numbering, so the staggered mesh is never held whole.
    // The copy-out's source when there is one, else one for this file
    // (judged as if made here either way, so that the cap's answer does not
    // depend on earlier calls).
    ctx.check_memory(um::dual::mpas_stream_bytes(m->mesh.vertex_count(), m->mesh.gamma != nullptr,
                                                 !m->mesh.surface.is_sphere(), m->mesh.regional()),
                     "the MPAS mesh file");
    std::unique_ptr<um::dual::MpasSource> own;
    if (!m->mpas) own = std::make_unique<um::dual::MpasSource>(ctx, m->mesh);
    um::io::write_mpas_mesh(ctx, own ? *own : *m->mpas, path, options);
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mesh_write_mpas(const um_mesh *m, const char *path) {
    return um_mesh_write_mpas_as(m, path, UM_MPAS_FILE_AUTO);
}

}  // extern "C"
