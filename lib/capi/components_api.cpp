// Component meshes and coupler files through the C ABI: the ocean and land
// meshes cut from a unified mesh (in memory or from an MPAS mesh file), the
// SCRIP and ESMF grid files, and the river routing report.
#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "components/components.hpp"
#include "dual/river_routing.hpp"
#include "io/mpas_reader.hpp"

using um::fail;
using um::capi::HandleKind;
using um::capi::MeshInUse;
using um::capi::require_handle;
using um::capi::require_pointer;

namespace {

um::Context *mesh_context(const um_mesh *m) {
    return um::capi::is_live(m, HandleKind::mesh) ? m->context.get() : nullptr;
}
um::Context *context_or_null(const um_context *ctx) {
    return um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr;
}

void require_text(const char *text, const char *name) {
    require_pointer(text, name);
    if (text[0] == '\0') fail(UM_ERR_INVALID_ARGUMENT, name, " is empty");
}

}  // namespace

extern "C" {

UM_API um_status um_mesh_write_components(const um_mesh *m, const char *directory) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    require_text(directory, "directory");
    um::components::require_directory(directory);
    um::Context &ctx = *m->context;
    ctx.progress("MPAS mesh", 0.0);
    um::dual::MpasMesh base = um::dual::build_mpas_mesh(ctx, m->mesh);
    um::components::write_component_files(ctx, base, directory);
    return UM_OK;
    UM_API_END(mesh_context(m))
}

UM_API um_status um_mpas_file_write_components(um_context *ctx, const char *mesh_path, const char *directory) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_text(mesh_path, "mesh_path");
    require_text(directory, "directory");
    um::components::require_directory(directory);
    um::Context &state = *ctx->state;
    um::dual::MpasMesh base = um::io::read_mpas_mesh(state, mesh_path);
    um::components::write_component_files(state, base, directory);
    return UM_OK;
    UM_API_END(context_or_null(ctx))
}

UM_API um_status um_mesh_river_report_json(const um_mesh *m, char *buf, int64_t capacity, int64_t *needed) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    const um::dual::MpasSource &source = m->staggered();
    const std::string json = um::components::river_report_json(
        source.river_report(), [&](int32_t cell, double &lat, double &lon) { source.cell_lat_lon(cell, lat, lon); });
    return um::capi::copy_out_string(m->context.get(), json, buf, capacity, needed);
    UM_API_END(mesh_context(m))
}

}  // extern "C"
