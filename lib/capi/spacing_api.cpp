// um_spacing entry points: argument checks, then the engine (lib/hfun, lib/io).
// A handle holds an immutable spacing; clamp and limit_gradient replace it
// only once the new one is built, so a failed call leaves the handle as it was.
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "mesh/refined_mesh.hpp"
#include "hfun/grid.hpp"
#include "hfun/presets.hpp"
#include "hfun/spacing.hpp"
#include "io/spacing_file.hpp"


using um::fail;
using um::capi::HandleKind;
using um::capi::require_handle;
using um::capi::require_pointer;

namespace {

constexpr int64_t kMaxAxis = int64_t(1) << 31;
constexpr int64_t kMaxCells = int64_t(1) << 40;

um::Context *state_or_null(const um_spacing *s) {
    return um::capi::is_live(s, HandleKind::spacing) ? s->context.get() : nullptr;
}
um::Context *context_state_or_null(const um_context *ctx) {
    return um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr;
}

// The checks every constructor starts with. *out is cleared first, so that
// it is NULL after any error.
void begin_create(um_context *ctx, um_spacing **out) {
    if (out) *out = nullptr;
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(out, "out");
}

um_status finish_create(um_context *ctx, um::hfun::SpacingPtr spacing, um_spacing **out) {
    auto handle = std::make_unique<um_spacing>();
    handle->context = ctx->state;
    handle->spacing = std::move(spacing);
    um::capi::register_handle(handle.get(), HandleKind::spacing);
    *out = handle.release();
    return UM_OK;
}

void check_axis_count(int64_t n, const char *name) {
    if (n < 2) fail(UM_ERR_INVALID_ARGUMENT, name, " = ", n, ": a grid axis needs at least 2 values");
    if (n > kMaxAxis) fail(UM_ERR_LIMIT, name, " = ", n, " exceeds the limit of ", kMaxAxis);
}

void check_grid_size(const um::Context &ctx, int64_t n_lon, int64_t n_lat) {
    check_axis_count(n_lon, "n_lon");
    check_axis_count(n_lat, "n_lat");
    if (n_lat > kMaxCells / n_lon)
        fail(UM_ERR_LIMIT, "n_lat * n_lon = ", n_lat, " * ", n_lon, " exceeds the limit of ",
             kMaxCells, " cells");
    ctx.check_memory(8 * (n_lat * n_lon + n_lat + n_lon), "the spacing grid");
}

void check_lonlat(int64_t n, const double *lon, const double *lat) {
    for (int64_t i = 0; i < n; ++i) {
        if (!std::isfinite(lon[i]))
            fail(UM_ERR_NONFINITE_INPUT, "lon_deg[", i, "] = ", lon[i], " is not finite");
        if (!std::isfinite(lat[i]))
            fail(UM_ERR_NONFINITE_INPUT, "lat_deg[", i, "] = ", lat[i], " is not finite");
        if (std::fabs(lat[i]) > 90.0)
            fail(UM_ERR_COORDINATE_RANGE, "lat_deg[", i, "] = ", lat[i], " is outside [-90, 90]");
    }
}

}  // namespace

extern "C" {

UM_API um_status um_spacing_create_constant(um_context *ctx, double km, um_spacing **out) {
    UM_API_BEGIN
    begin_create(ctx, out);
    return finish_create(ctx, um::hfun::make_constant(km), out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API um_status um_spacing_create_grid(um_context *ctx, int64_t n_lon, const double *lon_deg,
                                        int64_t n_lat, const double *lat_deg,
                                        const double *cell_width_km, um_spacing **out) {
    UM_API_BEGIN
    begin_create(ctx, out);
    check_grid_size(*ctx->state, n_lon, n_lat);
    require_pointer(lon_deg, "lon_deg");
    require_pointer(lat_deg, "lat_deg");
    require_pointer(cell_width_km, "cell_width_km");
    auto grid = std::make_shared<const um::hfun::GridSpacing>(
        std::vector<double>(lon_deg, lon_deg + n_lon), std::vector<double>(lat_deg, lat_deg + n_lat),
        std::vector<double>(cell_width_km, cell_width_km + n_lat * n_lon));
    return finish_create(ctx, std::move(grid), out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API um_status um_spacing_create_from_file(um_context *ctx, const char *path, um_spacing **out) {
    UM_API_BEGIN
    begin_create(ctx, out);
    require_pointer(path, "path");
    return finish_create(ctx, um::io::read_spacing_file(path, *ctx->state), out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API um_status um_spacing_create_callback(um_context *ctx, um_spacing_fn fn, void *user_data,
                                            um_spacing **out) {
    UM_API_BEGIN
    begin_create(ctx, out);
    return finish_create(ctx, um::hfun::make_callback(fn, user_data), out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API um_status um_spacing_create_preset(um_context *ctx, const char *name, um_spacing **out) {
    UM_API_BEGIN
    begin_create(ctx, out);
    require_pointer(name, "name");
    return finish_create(ctx, um::hfun::make_preset(name), out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API void um_spacing_destroy(um_spacing *s) {
    if (um::capi::unregister_handle(s, HandleKind::spacing)) delete s;
}

UM_API um_status um_spacing_limit_gradient(um_spacing *s, double g) {
    UM_API_BEGIN
    require_handle(s, HandleKind::spacing, "s");
    s->spacing = um::hfun::limit_gradient(*s->spacing, g);
    return UM_OK;
    UM_API_END(state_or_null(s))
}

UM_API um_status um_spacing_clamp(um_spacing *s, double km_min, double km_max) {
    UM_API_BEGIN
    require_handle(s, HandleKind::spacing, "s");
    s->spacing = um::hfun::make_clamp(s->spacing, km_min, km_max);
    return UM_OK;
    UM_API_END(state_or_null(s))
}

UM_API um_status um_spacing_evaluate(const um_spacing *s, int64_t n, const double *lon_deg,
                                     const double *lat_deg, double *km_out) {
    UM_API_BEGIN
    require_handle(s, HandleKind::spacing, "s");
    if (n < 0) fail(UM_ERR_INVALID_ARGUMENT, "n = ", n, " is negative");
    if (n == 0) return UM_OK;
    require_pointer(lon_deg, "lon_deg");
    require_pointer(lat_deg, "lat_deg");
    require_pointer(km_out, "km_out");
    check_lonlat(n, lon_deg, lat_deg);
    um::hfun::evaluate(
        *s->context, *s->spacing, n,
        [&](int64_t i) { return um::hfun::Where::from_lonlat(lon_deg[i], lat_deg[i]); }, km_out);
    return UM_OK;
    UM_API_END(state_or_null(s))
}

UM_API um_status um_spacing_estimate(const um_spacing *s, int64_t *cells, int64_t *refine_bytes,
                                     int64_t *mpas_bytes) {
    UM_API_BEGIN
    require_handle(s, HandleKind::spacing, "s");
    const um::mesh::MeshEstimate e = um::mesh::estimate_mesh(*s->context, *s->spacing);
    if (cells) *cells = e.cells;
    if (refine_bytes) *refine_bytes = e.refine_bytes;
    if (mpas_bytes) *mpas_bytes = e.mpas_bytes;
    return UM_OK;
    UM_API_END(state_or_null(s))
}

}  // extern "C"
