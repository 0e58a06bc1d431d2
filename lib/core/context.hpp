// The state behind a um_context: thread arena, callbacks, memory cap and the
// sticky first error. Objects created from a context share this state, so a
// context may be destroyed before its objects.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>
#ifdef UNIMESH_PLAIN_THREADS
#include <exception>
#include <thread>
#endif

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include "core/growth.hpp"
#include "core/worker_placement.hpp"
#include "unimesh.h"

namespace um {

class Context {
public:
    Context();

    // Threads ------------------------------------------------------------
    void set_threads(int32_t n_threads);  // 0 = all cores
    int32_t threads() const { return threads_; }
    // Where its workers may run during its calls (tests).
    const WorkerPlacement &worker_placement() const { return placement_; }
    // Calls fn(begin, end) over chunks of [0, n) in parallel in this context's
    // arena; serially when n <= grain or with one thread. fn must not depend
    // on how the range is split (that is what keeps results deterministic).
    template <class Fn>
    void parallel_for(int64_t n, int64_t grain, Fn &&fn) {
        if (n <= 0) return;
        if (threads_ == 1 || n <= grain) {
            fn(int64_t(0), n);
            return;
        }
#ifdef UNIMESH_PLAIN_THREADS
        // ThreadSanitizer builds: Debian's libtbb is not instrumented, so TSan
        // cannot see its synchronisation and reports false races. Plain
        // threads, created and joined per call, give TSan the happens-before
        // edges and still run the same bodies concurrently.
        plain_threads_for(n, fn);
#else
        WorkerPlacement::Scope placed(placement_);  // (worker_placement.hpp)
        arena_->execute([&] {
            oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int64_t>(0, n, grain),
                                      [&](const oneapi::tbb::blocked_range<int64_t> &r) {
                                          placement_.note_part_runner();
                                          fn(r.begin(), r.end());
                                      });
        });
#endif
    }

    // Runs background() in this context's arena while host() runs on the
    // calling thread (work that must stay on it, such as the netCDF calls
    // under their lock), returning when both are done: the first to fail
    // is rethrown (host's when both fail) after both finished. background
    // may use parallel_for. With one thread, or plain threads: host(), then
    // background().
    template <class Background, class Host>
    void alongside(Background &&background, Host &&host) {
#ifndef UNIMESH_PLAIN_THREADS
        if (threads_ > 1) {
            WorkerPlacement::Scope placed(placement_);
            oneapi::tbb::task_group group;
            // The worker that runs background() is one of this context's: its
            // parallel_for is then nested and leaves the placement to the host's.
            arena_->execute([&] {
                group.run([&] {
                    placement_.note_part_runner();
                    background();
                });
            });
            std::exception_ptr host_failed, background_failed;
            try {
                host();
            } catch (...) {
                host_failed = std::current_exception();
            }
            try {
                arena_->execute([&] { group.wait(); });
            } catch (...) {
                background_failed = std::current_exception();
            }
            if (host_failed) std::rethrow_exception(host_failed);
            if (background_failed) std::rethrow_exception(background_failed);
            return;
        }
#endif
        host();
        background();
    }

    // parallel_for(n, grain, fn) in consecutive blocks with a heartbeat
    // (stage, the share done) between them, for loops whose steps may call
    // slow user code (a spacing callback): cancel gets in every few tenths
    // of a second. The blocks grow while they take under kBlockSeconds, so
    // that a fast loop pays few of them; fn sees the same indices either way.
    template <class Fn>
    void parallel_for_with_heartbeat(const char *stage, int64_t n, int64_t grain, Fn &&fn) {
        constexpr double kBlockSeconds = 0.05;
        int64_t block = std::max<int64_t>(grain, 16);
        for (int64_t begin = 0; begin < n;) {
            heartbeat(stage, static_cast<double>(begin) / static_cast<double>(n));
            const int64_t end = std::min(n, begin + block);
            const auto start = std::chrono::steady_clock::now();
            parallel_for(end - begin, grain, [&](int64_t b, int64_t e) { fn(begin + b, begin + e); });
            if (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(kBlockSeconds))
                block = std::min<int64_t>(2 * block, int64_t{1} << 24);
            begin = end;
        }
    }

    // Calls fn(i, out) for every i in [0, n) in parallel over fixed blocks of
    // `block` indices, each block appending to its own list, and returns the
    // lists joined in block order: the same result for any thread count.
    template <class T, class Fn>
    std::vector<T> collect_in_order(int64_t n, int64_t block, Fn &&fn) {
        std::vector<std::vector<T>> found(static_cast<size_t>(n > 0 ? (n + block - 1) / block : 0));
        parallel_for(static_cast<int64_t>(found.size()), 1, [&](int64_t b0, int64_t b1) {
            for (int64_t b = b0; b < b1; ++b)
                for (int64_t i = b * block; i < std::min(n, (b + 1) * block); ++i) fn(i, found[b]);
        });
        size_t total = 0;
        for (const auto &f : found) total += f.size();
        std::vector<T> out;
        out.reserve(total);
        for (auto &f : found) {
            out.insert(out.end(), f.begin(), f.end());
            release(f);
        }
        return out;
    }

#ifdef UNIMESH_PLAIN_THREADS
    // An exception in a part is caught in its thread (one escaping a
    // std::thread would terminate) and the first part's is rethrown after
    // every thread joined, as TBB rethrows one.
    template <class Fn>
    void plain_threads_for(int64_t n, Fn &fn) {
        const int64_t parts = std::min<int64_t>(threads_, n);
        std::vector<std::exception_ptr> failed(static_cast<size_t>(parts));
        auto run_part = [&](int64_t p) {
            try {
                fn(n * p / parts, n * (p + 1) / parts);
            } catch (...) {
                failed[static_cast<size_t>(p)] = std::current_exception();
            }
        };
        std::vector<std::thread> pool;
        try {
            for (int64_t p = 1; p < parts; ++p) pool.emplace_back(run_part, p);
        } catch (...) {  // no thread: run what is left here
            for (int64_t p = static_cast<int64_t>(pool.size()) + 1; p < parts; ++p) run_part(p);
        }
        run_part(0);
        for (auto &t : pool) t.join();
        for (const auto &e : failed)
            if (e) std::rethrow_exception(e);
    }
#endif

    // Callbacks -----------------------------------------------------------
    void set_progress(um_progress_fn fn, void *user) { progress_fn_ = fn, progress_user_ = user; }
    void set_log(um_log_fn fn, void *user, int32_t min_level) {
        log_fn_ = fn, log_user_ = user, log_min_level_ = min_level;
    }
    // Reports progress; throws um::Error(UM_CANCELLED) when the callback asks
    // to stop. Host thread only.
    void progress(const char *stage, double fraction) const;
    // progress(), but only when the last report is kHeartbeatSeconds old: a
    // cancel point for serial loops whose steps may call slow user code (a
    // spacing callback of 100 us a call kept cancel out for 97 s). Cheap
    // enough for every step. Host thread only.
    static constexpr double kHeartbeatSeconds = 0.25;
    void heartbeat(const char *stage, double fraction) const {
        if (progress_fn_ && std::chrono::steady_clock::now() - last_report_ >
                                std::chrono::duration<double>(kHeartbeatSeconds))
            progress(stage, fraction);
    }
    void log(int32_t level, const std::string &message) const;

    // Limits ---------------------------------------------------------------
    void set_memory_cap(int64_t bytes) { memory_cap_ = bytes; }
    void set_worker_placement(bool on) { placement_.ask(on); }
    int64_t memory_cap() const { return memory_cap_; }
    // Throws UM_ERR_MEMORY_CAP, naming `what` and the estimate, when the
    // estimate exceeds the cap.
    void check_memory(int64_t estimate_bytes, const char *what) const;

    // Errors ---------------------------------------------------------------
    void set_error_mode(int32_t mode, um_abort_fn hook, void *user);
    // Keeps the message if it is the first since the last clear, logs it and,
    // in abort mode, calls the hook.
    void record_error(um_status status, const std::string &message);
    void clear_error();
    const std::string &last_error() const { return first_message_; }
    um_status last_status() const { return first_status_; }

private:
    int32_t threads_ = 1;
    std::unique_ptr<oneapi::tbb::task_arena> arena_;
    WorkerPlacement placement_;  // the workers that ran parts of its calls

    mutable std::chrono::steady_clock::time_point last_report_{};  // of progress()
    um_progress_fn progress_fn_ = nullptr;
    void *progress_user_ = nullptr;
    um_log_fn log_fn_ = nullptr;
    void *log_user_ = nullptr;
    int32_t log_min_level_ = UM_LOG_WARNING;

    int64_t memory_cap_ = 0;

    int32_t error_mode_ = UM_ERROR_MODE_RETURN;
    um_abort_fn abort_hook_ = nullptr;
    void *abort_user_ = nullptr;

    um_status first_status_ = UM_OK;
    std::string first_message_;
};

using ContextPtr = std::shared_ptr<Context>;

}  // namespace um
