#include "core/context.hpp"

#include <algorithm>

#include <oneapi/tbb/info.h>

#include "core/error.hpp"

namespace um {

namespace {
constexpr int32_t kMaxThreads = 1024;

int32_t all_cores() {
    int32_t n = static_cast<int32_t>(oneapi::tbb::info::default_concurrency());
    return n > 0 ? n : 1;
}
}  // namespace

Context::Context() { set_threads(0); }

void Context::set_threads(int32_t n_threads) {
    if (n_threads < 0 || n_threads > kMaxThreads)
        fail(UM_ERR_INVALID_ARGUMENT, "n_threads = ", n_threads, " is out of range [0, ",
             kMaxThreads, "] (0 = all cores)");
    int32_t resolved = n_threads == 0 ? all_cores() : n_threads;
    // Build the new arena first so that a failure leaves the context as it was.
    // It never asks for more threads than the machine has (TBB would warn on
    // stderr); results do not depend on the number of threads anyway.
    auto arena = std::make_unique<oneapi::tbb::task_arena>(std::min(resolved, all_cores()));
    arena_ = std::move(arena);
    threads_ = resolved;
}

void Context::progress(const char *stage, double fraction) const {
    last_report_ = std::chrono::steady_clock::now();
    if (progress_fn_ && progress_fn_(progress_user_, stage, fraction) != 0)
        fail(UM_CANCELLED, "cancelled by the progress callback during '", stage, "'");
}

void Context::log(int32_t level, const std::string &message) const {
    if (log_fn_ && level >= log_min_level_) log_fn_(log_user_, level, message.c_str());
}

void Context::check_memory(int64_t estimate_bytes, const char *what) const {
    if (memory_cap_ > 0 && estimate_bytes > memory_cap_)
        fail(UM_ERR_MEMORY_CAP, what, " needs about ", estimate_bytes / (1024 * 1024),
             " MiB (", estimate_bytes, " bytes), more than the memory cap of ", memory_cap_,
             " bytes");
}

void Context::set_error_mode(int32_t mode, um_abort_fn hook, void *user) {
    if (mode != UM_ERROR_MODE_RETURN && mode != UM_ERROR_MODE_ABORT)
        fail(UM_ERR_INVALID_ARGUMENT, "mode = ", mode,
             " is not UM_ERROR_MODE_RETURN (0) or UM_ERROR_MODE_ABORT (1)");
    if (mode == UM_ERROR_MODE_ABORT && hook == nullptr)
        fail(UM_ERR_NULL_ARGUMENT, "hook is NULL: UM_ERROR_MODE_ABORT needs an abort hook");
    error_mode_ = mode;
    abort_hook_ = hook;
    abort_user_ = user;
}

void Context::record_error(um_status status, const std::string &message) {
    if (first_status_ == UM_OK) {
        first_status_ = status;
        first_message_ = message;
    }
    log(UM_LOG_ERROR, message);
    if (error_mode_ == UM_ERROR_MODE_ABORT && abort_hook_)
        abort_hook_(abort_user_, status, message.c_str());
}

void Context::clear_error() {
    first_status_ = UM_OK;
    first_message_.clear();
}

}  // namespace um
