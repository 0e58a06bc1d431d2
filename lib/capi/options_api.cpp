// um_options entry points and the option table queries.
#include <memory>

#include "capi/api.hpp"

using um::capi::HandleKind;
using um::capi::require_handle;
using um::capi::require_pointer;

namespace {
um::Context *state_or_null(const um_options *o) {
    return um::capi::is_live(o, HandleKind::options) ? o->context.get() : nullptr;
}
}  // namespace

extern "C" {

UM_API um_status um_options_create(um_context *ctx, um_options **out) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(out, "out");
    auto handle = std::make_unique<um_options>();
    handle->context = ctx->state;
    um::capi::register_handle(handle.get(), HandleKind::options);
    *out = handle.release();
    return UM_OK;
    UM_API_END(um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr)
}

UM_API void um_options_destroy(um_options *opts) {
    if (um::capi::unregister_handle(opts, HandleKind::options)) delete opts;
}

UM_API um_status um_options_set_double(um_options *opts, um_option key, double value) {
    UM_API_BEGIN
    require_handle(opts, HandleKind::options, "opts");
    opts->values.set_real(key, value);
    return UM_OK;
    UM_API_END(state_or_null(opts))
}

UM_API um_status um_options_set_int(um_options *opts, um_option key, int64_t value) {
    UM_API_BEGIN
    require_handle(opts, HandleKind::options, "opts");
    opts->values.set_int(key, value);
    return UM_OK;
    UM_API_END(state_or_null(opts))
}

UM_API um_status um_options_get_double(const um_options *opts, um_option key, double *value) {
    UM_API_BEGIN
    require_handle(opts, HandleKind::options, "opts");
    require_pointer(value, "value");
    *value = opts->values.real(key);
    return UM_OK;
    UM_API_END(state_or_null(opts))
}

UM_API um_status um_options_get_int(const um_options *opts, um_option key, int64_t *value) {
    UM_API_BEGIN
    require_handle(opts, HandleKind::options, "opts");
    require_pointer(value, "value");
    *value = opts->values.integer(key);
    return UM_OK;
    UM_API_END(state_or_null(opts))
}

UM_API um_status um_options_set_string(um_options *opts, const char *assignments) {
    UM_API_BEGIN
    require_handle(opts, HandleKind::options, "opts");
    require_pointer(assignments, "assignments");
    opts->values.set_from_string(assignments);
    return UM_OK;
    UM_API_END(state_or_null(opts))
}

UM_API um_status um_option_info(um_option key, int32_t *type, double *min_value,
                                double *max_value, double *default_value) {
    UM_API_BEGIN
    const um::OptionSpec &s = um::option_spec(key);
    if (type) *type = s.type;
    if (min_value) *min_value = s.min_value;
    if (max_value) *max_value = s.max_value;
    if (default_value) *default_value = s.default_value;
    return UM_OK;
    UM_API_END(nullptr)
}

UM_API um_status um_option_name(um_option key, char *buf, int64_t capacity, int64_t *needed) {
    UM_API_BEGIN
    return um::capi::copy_out_string(nullptr, um::option_spec(key).name, buf, capacity, needed);
    UM_API_END(nullptr)
}

UM_API um_status um_option_key(const char *name, um_option *key) {
    UM_API_BEGIN
    require_pointer(name, "name");
    require_pointer(key, "key");
    const um::OptionSpec *s = um::option_spec_by_name(name);
    if (!s) um::fail(UM_ERR_UNKNOWN_OPTION, "option name '", name, "' is not known");
    *key = s->key;
    return UM_OK;
    UM_API_END(nullptr)
}

}  // extern "C"
