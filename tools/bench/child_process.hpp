// What the benchmarks share: running one measurement in a fork()ed child
// (so that its peak memory and first touches are its own) and reading the
// process's resource use. Header-only; each benchmark is one program.
#pragma once

#include <dirent.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <type_traits>

namespace bench {

inline double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

// The process's resource use at a moment (all its threads).
struct Usage {
    int64_t maxrss_kb = 0, faults = 0;  // peak resident size (kB on Linux); minor + major faults
    double system_s = 0.0, user_s = 0.0;
    // Time its threads (those alive now) spent ready to run but waiting for a
    // CPU (Linux schedstat): a worker queued behind a busy thread shows here.
    double runqueue_wait_s = 0.0;
};

// The run-queue wait of the process's live threads, summed; 0 where
// /proc/self/task/<tid>/schedstat cannot be read.
inline double runqueue_wait_now() {
    double total_ns = 0.0;
    DIR *dir = opendir("/proc/self/task");
    if (!dir) return 0.0;
    while (const dirent *entry = readdir(dir)) {
        if (entry->d_name[0] == '.') continue;
        char path[64];
        std::snprintf(path, sizeof path, "/proc/self/task/%.20s/schedstat", entry->d_name);
        if (FILE *f = std::fopen(path, "r")) {
            unsigned long long run_ns = 0, wait_ns = 0;
            if (std::fscanf(f, "%llu %llu", &run_ns, &wait_ns) == 2) total_ns += double(wait_ns);
            std::fclose(f);
        }
    }
    closedir(dir);
    return 1e-9 * total_ns;
}

inline Usage usage_now() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    Usage u;
    u.maxrss_kb = int64_t(ru.ru_maxrss);
    u.faults = int64_t(ru.ru_minflt) + int64_t(ru.ru_majflt);
    u.system_s = double(ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_stime.tv_usec);
    u.user_s = double(ru.ru_utime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec);
    u.runqueue_wait_s = runqueue_wait_now();
    return u;
}

enum class ChildOutcome { ok, failed, timed_out };

// Runs work() (returning a plain Result) in a child process and reads its
// result back through a pipe; after timeout_s seconds (<= 0: none) the child
// is killed. `failed` when the child died or exited without a whole result;
// *wait_status, when asked for, is waitpid()'s. The caller must hold no
// threads (fork() copies only the calling one).
template <class Result, class Work>
ChildOutcome run_in_child(Work &&work, Result &result, double timeout_s = 0.0, int *wait_status = nullptr) {
    static_assert(std::is_trivially_copyable<Result>::value, "the result crosses a pipe as bytes");
    int fds[2];
    if (pipe(fds) != 0) return ChildOutcome::failed;
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]), close(fds[1]);
        return ChildOutcome::failed;
    }
    if (pid == 0) {
        close(fds[0]);
        const Result r = work();
        const char *p = reinterpret_cast<const char *>(&r);
        size_t left = sizeof r;
        while (left > 0) {
            const ssize_t w = write(fds[1], p, left);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) break;
            p += w, left -= size_t(w);
        }
        _exit(left == 0 ? 0 : 1);
    }
    close(fds[1]);
    char *dst = reinterpret_cast<char *>(&result);
    size_t got = 0;
    const double deadline = now_seconds() + timeout_s;
    bool timed_out = false;
    while (got < sizeof result) {
        int wait_ms = -1;
        if (timeout_s > 0) {
            const double left = deadline - now_seconds();
            if (left <= 0) {
                timed_out = true;
                break;
            }
            wait_ms = int(std::min(left, 60.0) * 1000) + 1;
        }
        pollfd pfd = {fds[0], POLLIN, 0};
        const int rc = poll(&pfd, 1, wait_ms);
        if (rc < 0 && errno == EINTR) continue;
        if (rc < 0) break;
        if (rc == 0) continue;
        const ssize_t r = read(fds[0], dst + got, sizeof result - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;  // EOF: the child died before reporting
        got += size_t(r);
    }
    close(fds[0]);
    if (timed_out) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (wait_status) *wait_status = status;
    if (timed_out) return ChildOutcome::timed_out;
    return got == sizeof result && WIFEXITED(status) && WEXITSTATUS(status) == 0 ? ChildOutcome::ok
                                                                                  : ChildOutcome::failed;
}

}  // namespace bench
