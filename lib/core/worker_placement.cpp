#include "core/worker_placement.hpp"

#include <algorithm>

#if defined(__linux__)
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace um {

namespace {
// The calling thread: whether it is the host of a placed call now; whether
// it ran a part of a call as a worker (ever), and for which placement last.
// A call made by a host inside its call, or by a worker, is nested in
// another and places nothing.
thread_local bool t_hosting = false;
thread_local bool t_worker = false;
thread_local uint64_t t_recorded_by = 0;

std::atomic<uint64_t> next_placement_id{1};

#if defined(__linux__)
int32_t this_thread_id() { return static_cast<int32_t>(syscall(SYS_gettid)); }

// Whether `tid` is a thread of this process (signal 0 checks without
// sending): a recorded worker that has ended must not lend its number to a
// thread of another process whose mask we would then change.
bool is_our_thread(int32_t tid) {
    return syscall(SYS_tgkill, static_cast<int>(getpid()), tid, 0) == 0;
}

// Takes `cpu` out of the thread's mask when the mask holds it and others.
bool remove_cpu(int32_t tid, int32_t cpu) {
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (sched_getaffinity(tid, sizeof mask, &mask) != 0) return false;
    if (cpu >= CPU_SETSIZE || !CPU_ISSET(cpu, &mask) || CPU_COUNT(&mask) < 2) return false;
    CPU_CLR(cpu, &mask);
    return sched_setaffinity(tid, sizeof mask, &mask) == 0;
}

void give_back_cpu(int32_t tid, int32_t cpu) {
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (sched_getaffinity(tid, sizeof mask, &mask) != 0) return;
    CPU_SET(cpu, &mask);
    sched_setaffinity(tid, sizeof mask, &mask);
}
#endif
}  // namespace

WorkerPlacement::WorkerPlacement() : id_(next_placement_id.fetch_add(1, std::memory_order_relaxed)) {}

int WorkerPlacement::recorded_workers() const {
    int n = 0;
    for (const Worker &w : workers_) n += w.tid.load(std::memory_order_acquire) != 0;
    return n;
}

bool WorkerPlacement::is_recorded(int32_t tid) const {
    const int n = std::min(claimed_.load(std::memory_order_acquire), kMaxWorkers);
    for (int i = 0; i < n; ++i)
        if (workers_[i].tid.load(std::memory_order_acquire) == tid) return true;
    return false;
}

void WorkerPlacement::note_part_runner() {
#if defined(__linux__)
    if (t_hosting || t_recorded_by == id_) return;  // the host, or recorded here
    t_worker = true;
    t_recorded_by = id_;
    const int32_t tid = this_thread_id();
    if (!is_recorded(tid)) record(tid);
#endif
}

void WorkerPlacement::record(int32_t tid) {
#if defined(__linux__)
    const int slot = claimed_.fetch_add(1, std::memory_order_acq_rel);
    if (slot >= kMaxWorkers) return;
    Worker &w = workers_[static_cast<size_t>(slot)];
    // Woken onto the host's CPU before anyone could keep it off: move now.
    const int32_t host_cpu = host_cpu_.load(std::memory_order_acquire);
    if (host_cpu >= 0 && sched_getcpu() == host_cpu && remove_cpu(tid, host_cpu))
        w.removed_cpu.store(host_cpu, std::memory_order_release);
    w.tid.store(tid, std::memory_order_release);
#else
    (void)tid;
#endif
}

WorkerPlacement::Scope::Scope(WorkerPlacement &placement) {
#if defined(__linux__)
    if (t_hosting || t_worker) return;  // nested: the outer call placed the workers
    const int32_t cpu = static_cast<int32_t>(sched_getcpu());
    if (cpu < 0) return;
    placement_ = &placement;
    t_hosting = true;
    placement.host_cpu_.store(cpu, std::memory_order_release);
    const int n = std::min(placement.claimed_.load(std::memory_order_acquire), kMaxWorkers);
    for (int i = 0; i < n; ++i) {
        Worker &w = placement.workers_[static_cast<size_t>(i)];
        const int32_t tid = w.tid.load(std::memory_order_acquire);
        if (tid == 0 || w.removed_cpu.load(std::memory_order_acquire) >= 0) continue;
        if (is_our_thread(tid) && remove_cpu(tid, cpu)) w.removed_cpu.store(cpu, std::memory_order_release);
    }
#else
    (void)placement;
#endif
}

WorkerPlacement::Scope::~Scope() {
#if defined(__linux__)
    if (!placement_) return;
    t_hosting = false;
    placement_->host_cpu_.store(-1, std::memory_order_release);
    const int n = std::min(placement_->claimed_.load(std::memory_order_acquire), kMaxWorkers);
    for (int i = 0; i < n; ++i) {
        Worker &w = placement_->workers_[static_cast<size_t>(i)];
        const int32_t tid = w.tid.load(std::memory_order_acquire);
        if (tid == 0) continue;
        const int32_t cpu = w.removed_cpu.exchange(-1, std::memory_order_acq_rel);
        if (cpu >= 0 && is_our_thread(tid)) give_back_cpu(tid, cpu);
    }
#endif
}

}  // namespace um
