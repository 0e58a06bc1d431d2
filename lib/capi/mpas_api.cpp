// MPAS output through the C ABI: the staggered mesh of a um_mesh, written as
// an MPAS mesh file.
#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "dual/mpas_mesh.hpp"
#include "io/mpas_writer.hpp"

using um::fail;
using um::capi::HandleKind;
using um::capi::require_handle;
using um::capi::require_pointer;

namespace {

um::Context *mesh_context(const um_mesh *m) {
    return um::capi::is_live(m, HandleKind::mesh) ? m->context.get() : nullptr;
}

}  // namespace

extern "C" {

UM_API um_status um_mesh_write_mpas(const um_mesh *m, const char *path) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    require_pointer(path, "path");
    if (path[0] == '\0') fail(UM_ERR_INVALID_ARGUMENT, "path is empty");
    um::Context &ctx = *m->context;
    ctx.progress("MPAS mesh", 0.0);
    um::dual::MpasMesh mpas = um::dual::build_mpas_mesh(ctx, m->mesh);
    // The last chance to cancel: once writing starts the file is finished.
    ctx.progress("MPAS mesh", 0.5);
    um::io::write_mpas_mesh(mpas, path);
    return UM_OK;
    UM_API_END(mesh_context(m))
}

}  // extern "C"
