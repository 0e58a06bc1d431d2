// um_triangulation entry points: input checks, then the engine (lib/tri).
#include <cmath>
#include <memory>
#include <vector>

#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "tri/triangulation.hpp"
#include "tri/validate.hpp"


using um::fail;
using um::capi::HandleKind;
using um::capi::require_handle;
using um::capi::check_base;
using um::capi::check_capacity;
using um::capi::require_pointer;
using um::geom::Vec3;

namespace {

// Largest n whose 2n - 4 triangles and 3 indices each stay within int32.
constexpr int64_t kMaxPoints = int64_t(1) << 28;
// Peak bytes per point of construction (see the memory note in triangulation.hpp).
constexpr int64_t kBytesPerPoint = 120;

um::Context *state_or_null(const um_triangulation *t) {
    return um::capi::is_live(t, HandleKind::triangulation) ? t->context.get() : nullptr;
}
um::Context *context_state_or_null(const um_context *ctx) {
    return um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr;
}

void check_count(um::Context &ctx, int64_t n) {
    if (n < 4) fail(UM_ERR_TOO_FEW_POINTS, "n = ", n, ": a triangulation of the sphere needs at least 4 points");
    if (n > kMaxPoints)
        fail(UM_ERR_LIMIT, "n = ", n, " exceeds the limit of ", kMaxPoints, " points");
    ctx.check_memory(n * kBytesPerPoint, "the triangulation");
}

// Runs check(begin, end), which throws at the first bad point of its range,
// over chunks of the points in parallel; then again, alone, over the first
// chunk that failed, so that the error is the first bad point's whatever
// the thread count. (A serial scan of 10^6 points took some 2 ms.)
template <class Check>
void check_in_parallel(um::Context &ctx, int64_t n, Check check) {
    constexpr int64_t kChunks = 64;
    std::vector<char> failed(kChunks, 0);
    auto chunk = [&](int64_t c) { return n * c / kChunks; };
    ctx.parallel_for(kChunks, 1, [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) try {
                check(chunk(c), chunk(c + 1));
            } catch (const um::Error &) {
                failed[c] = 1;
            }
    });
    for (int64_t c = 0; c < kChunks; ++c)
        if (failed[c]) check(chunk(c), chunk(c + 1));
}

void check_weights(const double *weights, int64_t begin, int64_t end) {
    if (!weights) return;
    for (int64_t i = begin; i < end; ++i)
        if (!std::isfinite(weights[i]) || weights[i] >= 2.0)
            fail(std::isfinite(weights[i]) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT,
                 "weights[", i, "] = ", weights[i],
                 " is not a finite weight below 2 (units of R^2)");
}

void check_lonlat(const double *lon, const double *lat, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
        if (!std::isfinite(lon[i]))
            fail(UM_ERR_NONFINITE_INPUT, "lon_deg[", i, "] = ", lon[i], " is not finite");
        if (!std::isfinite(lat[i]))
            fail(UM_ERR_NONFINITE_INPUT, "lat_deg[", i, "] = ", lat[i], " is not finite");
        if (std::fabs(lat[i]) > 90.0)
            fail(UM_ERR_COORDINATE_RANGE, "lat_deg[", i, "] = ", lat[i],
                 " is outside [-90, 90]");
    }
}

void check_xyz(const double *xyz, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
        const double *p = xyz + 3 * i;
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(p[k]))
                fail(UM_ERR_NONFINITE_INPUT, "xyz[", 3 * i + k, "] (point ", i, ") = ", p[k],
                     " is not finite");
        if (p[0] == 0 && p[1] == 0 && p[2] == 0)
            fail(UM_ERR_INVALID_ARGUMENT, "point ", i, " of xyz is the zero vector");
    }
}

std::unique_ptr<um_triangulation> new_handle(um_context *ctx) {
    auto handle = std::make_unique<um_triangulation>();
    handle->context = ctx->state;
    return handle;
}

// Builds the handle's triangulation and hands it out.
template <class DirectionFn, class KeyDirectionFn, class PrefetchFn>
um_status create(um_context *ctx, std::unique_ptr<um_triangulation> handle, int64_t n,
                 DirectionFn direction, KeyDirectionFn key_direction, PrefetchFn prefetch,
                 const double *weights, um_triangulation **out) {
    handle->tri.prepare(*ctx->state, n, direction, weights, key_direction, prefetch);
    handle->tri.finish_build(*ctx->state);
    um::capi::register_handle(handle.get(), HandleKind::triangulation);
    *out = handle.release();
    return UM_OK;
}



// Fills out[3f + k] = index(f, k) + base for every triangle f and corner k.
template <class IndexFn>
void copy_per_corner(const um_triangulation *t, int32_t base, int32_t *out, int64_t capacity,
                     const char *what, IndexFn index) {
    check_base(base);
    const int32_t n = t->tri.triangle_count();
    check_capacity(capacity, 3 * int64_t(n), what);
    require_pointer(out, "out");
    t->context->parallel_for(n, 16384, [&](int64_t b, int64_t e) {
        for (int64_t f = b; f < e; ++f)
            for (int k = 0; k < 3; ++k) out[3 * f + k] = index(static_cast<int32_t>(f), k) + base;
    });
}

}  // namespace

extern "C" {

UM_API um_status um_triangulation_create(um_context *ctx, int64_t n, const double *lon_deg,
                                         const double *lat_deg, const double *weights,
                                         um_triangulation **out) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(out, "out");
    *out = nullptr;
    check_count(*ctx->state, n);
    require_pointer(lon_deg, "lon_deg");
    require_pointer(lat_deg, "lat_deg");
    um::Context &state = *ctx->state;
    check_in_parallel(state, n, [&](int64_t b, int64_t e) { check_lonlat(lon_deg, lat_deg, b, e); });
    check_in_parallel(state, n, [&](int64_t b, int64_t e) { check_weights(weights, b, e); });
    // Unit vectors once, up front: the construction reads each point twice.
    // (In the build's room, which the triangles take over after prepare();
    // first written, page by page, by the parallel loop.)
    auto handle = new_handle(ctx);
    Vec3 *const xyz = handle->tri.reserve_build(n).take<Vec3>(static_cast<size_t>(n));
    ctx->state->parallel_for(n, 8192, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) xyz[i] = um::geom::unit_from_lonlat_deg(lon_deg[i], lat_deg[i]);
    });
    auto direction = [xyz](int64_t i) { return xyz[i]; };
    auto prefetch = [xyz](int64_t i) { __builtin_prefetch(xyz + i); };
    return create(ctx, std::move(handle), n, direction, direction, prefetch, weights, out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API um_status um_triangulation_create_xyz(um_context *ctx, int64_t n, const double *xyz,
                                             const double *weights, um_triangulation **out) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(out, "out");
    *out = nullptr;
    check_count(*ctx->state, n);
    require_pointer(xyz, "xyz");
    um::Context &state = *ctx->state;
    check_in_parallel(state, n, [&](int64_t b, int64_t e) { check_xyz(xyz, b, e); });
    check_in_parallel(state, n, [&](int64_t b, int64_t e) { check_weights(weights, b, e); });
    auto raw = [xyz](int64_t i) { return Vec3{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; };
    auto direction = [raw](int64_t i) { return um::geom::normalized(raw(i)); };
    auto prefetch = [xyz](int64_t i) { __builtin_prefetch(xyz + 3 * i); };
    return create(ctx, new_handle(ctx), n, direction, raw, prefetch, weights, out);
    UM_API_END(context_state_or_null(ctx))
}

UM_API void um_triangulation_destroy(um_triangulation *t) {
    if (um::capi::unregister_handle(t, HandleKind::triangulation)) delete t;
}

UM_API um_status um_triangulation_counts(const um_triangulation *t, int64_t *n_vertices,
                                         int64_t *n_triangles, int64_t *n_hidden) {
    UM_API_BEGIN
    require_handle(t, HandleKind::triangulation, "t");
    int64_t v = t->tri.vertex_count();
    if (n_vertices) *n_vertices = v;
    if (n_triangles) *n_triangles = t->tri.triangle_count();
    if (n_hidden) *n_hidden = static_cast<int64_t>(t->tri.hidden_ids().size());
    return UM_OK;
    UM_API_END(state_or_null(t))
}

UM_API um_status um_triangulation_copy_triangles(const um_triangulation *t, int32_t base,
                                                 int32_t *out, int64_t capacity) {
    UM_API_BEGIN
    require_handle(t, HandleKind::triangulation, "t");
    const auto &tri = t->tri;
    copy_per_corner(t, base, out, capacity, "the triangles",
                    [&](int32_t f, int k) { return tri.id(tri.vertex(f, k)); });
    return UM_OK;
    UM_API_END(state_or_null(t))
}

UM_API um_status um_triangulation_copy_neighbours(const um_triangulation *t, int32_t base,
                                                  int32_t *out, int64_t capacity) {
    UM_API_BEGIN
    require_handle(t, HandleKind::triangulation, "t");
    const auto &tri = t->tri;
    copy_per_corner(t, base, out, capacity, "the neighbours",
                    [&](int32_t f, int k) { return tri.neighbour(f, k); });
    return UM_OK;
    UM_API_END(state_or_null(t))
}

UM_API um_status um_triangulation_copy_orthocentres(const um_triangulation *t, double *out,
                                                    int64_t capacity) {
    UM_API_BEGIN
    require_handle(t, HandleKind::triangulation, "t");
    const auto &tri = t->tri;
    check_capacity(capacity, 3 * int64_t(tri.triangle_count()), "the orthocentres");
    require_pointer(out, "out");
    t->context->parallel_for(tri.triangle_count(), 8192, [&](int64_t b, int64_t e) {
        for (int64_t f = b; f < e; ++f) {
            Vec3 c = tri.orthocentre(static_cast<int32_t>(f));
            out[3 * f] = c.x, out[3 * f + 1] = c.y, out[3 * f + 2] = c.z;
        }
    });
    return UM_OK;
    UM_API_END(state_or_null(t))
}

UM_API um_status um_triangulation_copy_hidden(const um_triangulation *t, int32_t base,
                                              int32_t *out, int64_t capacity) {
    UM_API_BEGIN
    require_handle(t, HandleKind::triangulation, "t");
    check_base(base);
    std::vector<int32_t> hidden = t->tri.hidden_ids();
    check_capacity(capacity, static_cast<int64_t>(hidden.size()), "the hidden list");
    if (!hidden.empty()) require_pointer(out, "out");
    for (size_t i = 0; i < hidden.size(); ++i) out[i] = hidden[i] + base;
    return UM_OK;
    UM_API_END(state_or_null(t))
}

UM_API um_status um_triangulation_check(const um_triangulation *t) {
    UM_API_BEGIN
    require_handle(t, HandleKind::triangulation, "t");
    std::string problem = um::tri::check_triangulation(t->tri);
    if (!problem.empty()) fail(UM_ERR_INTERNAL, "triangulation check failed: ", problem);
    return UM_OK;
    UM_API_END(state_or_null(t))
}

}  // extern "C"
