// um_features entry points: argument checks, then the engine (lib/features,
// lib/io/geojson).
#include <memory>
#include <string>

#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "features/network.hpp"
#include "io/geojson.hpp"


using um::fail;
using um::capi::HandleKind;
using um::capi::require_handle;
using um::capi::check_capacity;
using um::capi::require_pointer;

namespace {

// Peak bytes per input point while adding: the staged unit vector and
// lon/lat, the cleaning index and the segment's part, then the same again
// when the network's arrays grow.
constexpr int64_t kBytesPerPoint = 112;

um::Context *state_or_null(const um_features *f) {
    return um::capi::is_live(f, HandleKind::features) ? f->context.get() : nullptr;
}
um::Context *context_state_or_null(const um_context *ctx) {
    return um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr;
}


}  // namespace

extern "C" {

UM_API um_status um_features_create(um_context *ctx, um_features **out) {
    UM_API_BEGIN
    if (out) *out = nullptr;
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(out, "out");
    auto handle = std::make_unique<um_features>();
    handle->context = ctx->state;
    um::capi::register_handle(handle.get(), HandleKind::features);
    *out = handle.release();
    return UM_OK;
    UM_API_END(context_state_or_null(ctx))
}

UM_API void um_features_destroy(um_features *f) {
    if (um::capi::unregister_handle(f, HandleKind::features)) delete f;
}

UM_API um_status um_features_add(um_features *f, int64_t n_points, const double *lon_deg,
                                 const double *lat_deg, int64_t n_parts,
                                 const int64_t *part_offsets, const int32_t *closed,
                                 const int32_t *kind, const int32_t *part_id) {
    UM_API_BEGIN
    require_handle(f, HandleKind::features, "f");
    if (n_points < 0) fail(UM_ERR_INVALID_ARGUMENT, "n_points = ", n_points, " is negative");
    if (n_parts < 0) fail(UM_ERR_INVALID_ARGUMENT, "n_parts = ", n_parts, " is negative");
    if (n_points > um::features::Network::kMaxPoints)
        fail(UM_ERR_LIMIT, "n_points = ", n_points, " exceeds the limit of ",
             um::features::Network::kMaxPoints, " points");
    f->context->check_memory(n_points * kBytesPerPoint, "adding the features");
    um::features::PartsInput in;
    in.n_points = n_points;
    in.lon_deg = lon_deg;
    in.lat_deg = lat_deg;
    in.n_parts = n_parts;
    in.part_offsets = part_offsets;
    in.closed = closed;
    in.kind = kind;
    in.part_id = part_id;
    // Places named as the caller sees them: the arrays and their indices.
    auto where = [&](int64_t part, int64_t point, int coordinate) {
        std::string id = part_id ? um::concat(" (part_id ", part_id[part], ")") : std::string();
        if (point < 0)
            return um::concat("part ", part, id, " (points ", part_offsets[part], " to ",
                              part_offsets[part + 1] - 1, " of lon_deg/lat_deg)");
        const char *array = coordinate == 0 ? "lon_deg" : coordinate == 1 ? "lat_deg" : "lon_deg/lat_deg";
        return um::concat(array, "[", part_offsets[part] + point, "] (part ", part, id,
                          ", its point ", point, ")");
    };
    f->network.add(in, where);
    return UM_OK;
    UM_API_END(state_or_null(f))
}

UM_API um_status um_features_read_geojson(um_features *f, const char *path,
                                          const char *kind_property, int32_t default_kind) {
    UM_API_BEGIN
    require_handle(f, HandleKind::features, "f");
    require_pointer(path, "path");
    if (default_kind != 0 && !um::features::is_kind(default_kind))
        fail(UM_ERR_INVALID_ARGUMENT, "default_kind = ", default_kind,
             " is neither 0 (unknown kinds are errors) nor a feature kind "
             "(UM_FEATURE_COASTLINE = 1 to UM_FEATURE_DOMAIN = 7)");
    if (kind_property && kind_property[0] == '\0')
        fail(UM_ERR_INVALID_ARGUMENT, "kind_property is empty (NULL means \"kind\")");
    um::io::GeojsonOptions options;
    if (kind_property) options.kind_property = kind_property;
    options.default_kind = default_kind;
    um::io::read_geojson_file(path, options, f->network, f->context.get());
    return UM_OK;
    UM_API_END(state_or_null(f))
}

UM_API um_status um_features_counts(const um_features *f, int64_t *n_parts, int64_t *n_points,
                                    int64_t *n_segments) {
    UM_API_BEGIN
    require_handle(f, HandleKind::features, "f");
    if (n_parts) *n_parts = f->network.part_count();
    if (n_points) *n_points = f->network.point_count();
    if (n_segments) *n_segments = f->network.segment_count();
    return UM_OK;
    UM_API_END(state_or_null(f))
}

UM_API um_status um_features_copy_points(const um_features *f, double *lon_deg, double *lat_deg,
                                         int64_t capacity) {
    UM_API_BEGIN
    require_handle(f, HandleKind::features, "f");
    const auto &net = f->network;
    check_capacity(capacity, net.point_count(), "the points");
    if (!lon_deg && !lat_deg)
        fail(UM_ERR_NULL_ARGUMENT, "lon_deg and lat_deg are both NULL: nothing to copy");
    for (int64_t i = 0; i < net.point_count(); ++i) {
        if (lon_deg) lon_deg[i] = net.lon_deg(i);
        if (lat_deg) lat_deg[i] = net.lat_deg(i);
    }
    return UM_OK;
    UM_API_END(state_or_null(f))
}

UM_API um_status um_features_copy_parts(const um_features *f, int64_t *part_offsets,
                                        int32_t *closed, int32_t *kind, int32_t *part_id,
                                        int64_t capacity) {
    UM_API_BEGIN
    require_handle(f, HandleKind::features, "f");
    const auto &net = f->network;
    const int64_t n = net.part_count();
    if (!part_offsets && !closed && !kind && !part_id)
        fail(UM_ERR_NULL_ARGUMENT,
             "part_offsets, closed, kind and part_id are all NULL: nothing to copy");
    if (part_offsets)
        check_capacity(capacity, n + 1, "part_offsets (n_parts + 1)");
    else
        check_capacity(capacity, n, "the parts");
    if (part_offsets) part_offsets[0] = 0;
    for (int64_t p = 0; p < n; ++p) {
        const auto &part = net.part(p);
        if (part_offsets) part_offsets[p + 1] = part.first_point + part.n_points;
        if (closed) closed[p] = part.closed ? 1 : 0;
        if (kind) kind[p] = static_cast<int32_t>(part.kind);
        if (part_id) part_id[p] = part.id;
    }
    return UM_OK;
    UM_API_END(state_or_null(f))
}

}  // extern "C"
