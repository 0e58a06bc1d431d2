#include "capi/api.hpp"

#include <cstring>
#include <new>

namespace um::capi {

um_status usage_error(Context *ctx, um_status status, const std::string &message) noexcept {
    try {
        if (ctx) ctx->record_error(status, message);
    } catch (...) {
        // Recording can only fail on memory exhaustion; the status still goes back.
    }
    return status;
}

um_status translate_current_exception(Context *ctx) noexcept {
    try {
        throw;
    } catch (const Error &e) {
        return usage_error(ctx, e.status(), e.what());
    } catch (const std::bad_alloc &) {
        return usage_error(ctx, UM_ERR_OUT_OF_MEMORY, "out of memory");
    } catch (const std::exception &e) {
        return usage_error(ctx, UM_ERR_INTERNAL,
                           std::string("internal error (please report): ") + e.what());
    } catch (...) {
        return usage_error(ctx, UM_ERR_INTERNAL, "internal error (please report): unknown exception");
    }
}

um_status copy_out_string(Context *ctx, const std::string &text, char *buf, int64_t capacity,
                          int64_t *needed) noexcept {
    int64_t need = static_cast<int64_t>(text.size()) + 1;
    if (needed) *needed = need;
    if (capacity < 0)
        return usage_error(ctx, UM_ERR_INVALID_ARGUMENT,
                           "capacity = " + to_text(capacity) + " is negative");
    if (capacity > 0 && !buf)
        return usage_error(ctx, UM_ERR_NULL_ARGUMENT,
                           "buf is NULL but capacity = " + to_text(capacity));
    if (capacity > 0) {
        int64_t n = need <= capacity ? need - 1 : capacity - 1;
        std::memcpy(buf, text.data(), static_cast<size_t>(n));
        buf[n] = '\0';
    }
    // A too-small buffer for a message is reported through the status only:
    // recording it would replace nothing (the first error is kept) but could
    // confuse a caller that is reading that very error.
    if (need > capacity) return UM_ERR_BUFFER_TOO_SMALL;
    return UM_OK;
}

void check_capacity(int64_t capacity, int64_t needed, const char *what) {
    if (capacity < needed)
        fail(UM_ERR_BUFFER_TOO_SMALL, "capacity = ", capacity, " is below the ", needed,
             " elements ", what, " needs");
}

void check_base(int32_t base) {
    if (base != 0 && base != 1) fail(UM_ERR_INVALID_ARGUMENT, "base = ", base, " is not 0 or 1");
}

void require_handle(const void *handle, HandleKind kind, const char *argument) {
    if (!handle) fail(UM_ERR_NULL_ARGUMENT, argument, " is NULL");
    if (!is_live(handle, kind))
        fail(UM_ERR_INVALID_HANDLE, argument, " is not a live ", kind_name(kind),
             " (destroyed, foreign or never created)");
}

}  // namespace um::capi
