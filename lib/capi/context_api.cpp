// um_context entry points.
#include <memory>

#include "capi/api.hpp"

using um::capi::HandleKind;
using um::capi::require_handle;
using um::capi::require_pointer;

namespace {
// The context behind a handle that has already been checked.
um::Context *live_state(const um_context *ctx) { return ctx->state.get(); }

um::Context *state_or_null(const um_context *ctx) {
    return um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr;
}
}  // namespace

extern "C" {

UM_API um_status um_context_create(um_context **out) {
    UM_API_BEGIN
    require_pointer(out, "out");
    auto handle = std::make_unique<um_context>();
    handle->state = std::make_shared<um::Context>();
    um::capi::register_handle(handle.get(), HandleKind::context);
    *out = handle.release();
    return UM_OK;
    UM_API_END(nullptr)
}

UM_API void um_context_destroy(um_context *ctx) {
    if (um::capi::unregister_handle(ctx, HandleKind::context)) delete ctx;
}

UM_API um_status um_context_set_threads(um_context *ctx, int32_t n_threads) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    live_state(ctx)->set_threads(n_threads);
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_get_threads(const um_context *ctx, int32_t *n_threads) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(n_threads, "n_threads");
    *n_threads = live_state(ctx)->threads();
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_set_progress(um_context *ctx, um_progress_fn fn, void *user_data) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    live_state(ctx)->set_progress(fn, user_data);
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_set_log(um_context *ctx, um_log_fn fn, void *user_data,
                                    int32_t min_level) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    live_state(ctx)->set_log(fn, user_data, min_level);
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_set_memory_cap(um_context *ctx, int64_t bytes) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    if (bytes < 0)
        um::fail(UM_ERR_INVALID_ARGUMENT, "bytes = ", bytes, " is negative (0 = no cap)");
    live_state(ctx)->set_memory_cap(bytes);
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_set_worker_placement(um_context *ctx, int32_t on) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    if (on != 0 && on != 1) um::fail(UM_ERR_INVALID_ARGUMENT, "on = ", on, " is not 0 or 1");
    live_state(ctx)->set_worker_placement(on == 1);
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_get_memory_cap(const um_context *ctx, int64_t *bytes) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(bytes, "bytes");
    *bytes = live_state(ctx)->memory_cap();
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_set_error_mode(um_context *ctx, int32_t mode, um_abort_fn hook,
                                           void *user_data) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    live_state(ctx)->set_error_mode(mode, hook, user_data);
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

UM_API const char *um_context_last_error(const um_context *ctx) {
    um::Context *s = state_or_null(ctx);
    return s ? s->last_error().c_str() : "";
}

UM_API um_status um_context_last_status(const um_context *ctx) {
    um::Context *s = state_or_null(ctx);
    return s ? s->last_status() : UM_OK;
}

UM_API um_status um_context_copy_last_error(const um_context *ctx, char *buf, int64_t capacity,
                                            int64_t *needed) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    return um::capi::copy_out_string(live_state(ctx), live_state(ctx)->last_error(), buf, capacity,
                                     needed);
    UM_API_END(state_or_null(ctx))
}

UM_API um_status um_context_clear_error(um_context *ctx) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    live_state(ctx)->clear_error();
    return UM_OK;
    UM_API_END(state_or_null(ctx))
}

}  // extern "C"
