// Shared machinery of the extern "C" layer: the handle structs, argument
// checks and the UM_API_BEGIN / UM_API_END pair that stops every exception at
// the ABI and turns it into a status with the message kept.
#pragma once

#include <cstdint>
#include <string>

#include "unimesh.h"
#include "capi/handles.hpp"
#include "core/context.hpp"
#include "core/error.hpp"
#include "core/options.hpp"

struct um_context {
    um::ContextPtr state;
};

struct um_options {
    um::ContextPtr context;
    um::Options values;
};

namespace um::capi {

// Maps the exception in flight to a status, recording its message in ctx
// (when there is one). Call only from a catch block.
um_status translate_current_exception(Context *ctx) noexcept;

// Records a usage error found before any engine work (ctx may be null).
um_status usage_error(Context *ctx, um_status status, const std::string &message) noexcept;

// Copies text to a caller buffer as the header describes.
um_status copy_out_string(Context *ctx, const std::string &text, char *buf, int64_t capacity,
                          int64_t *needed) noexcept;

template <class Handle>
Context *context_of(const Handle *h) {
    return h->context.get();
}
inline Context *context_of(const um_context *h) { return h->state.get(); }

// Throws UM_ERR_NULL_ARGUMENT / UM_ERR_INVALID_HANDLE naming the argument.
void require_handle(const void *handle, HandleKind kind, const char *argument);
// An output buffer of `capacity` elements must hold `needed` of them
// (UM_ERR_BUFFER_TOO_SMALL naming both).
void check_capacity(int64_t capacity, int64_t needed, const char *what);
// Index bases are 0 (C, Python) or 1 (Fortran, MPAS).
void check_base(int32_t base);

template <class T>
void require_pointer(const T *p, const char *argument) {
    if (!p) fail(UM_ERR_NULL_ARGUMENT, argument, " is NULL");
}

}  // namespace um::capi

// Every entry point body sits between these; `ctx` is a um::Context* (or
// nullptr when the call has no live context to record into).
#define UM_API_BEGIN try {
#define UM_API_END(ctx)                                          \
    }                                                            \
    catch (...) {                                                \
        return ::um::capi::translate_current_exception(ctx);     \
    }
