// Keeps a context's worker threads off the host thread's CPU while a
// parallel call runs, so that a worker woken for the call starts on another
// CPU at once.
//
// Why: Linux wakes a sleeping thread on the CPU of the thread that woke it
// when it judges that CPU's cache worth more than an idle one, and some
// kernels pack tasks onto few CPUs on purpose (this project's virtual
// machines: sched_vcpu_pack). oneTBB's workers sleep between parallel loops,
// and the host thread wakes them, then keeps working: the worker waits in
// that CPU's queue, behind the host, until the load balancer moves it, while
// the other CPU idles. On this machine that took 3-6 ms in a fresh process
// (schedstat: the worker waited 5-11 ms of a 15-24 ms construction from
// 10^5 points on two threads); with the worker kept off the host's CPU it
// waits 0.1-0.4 ms and the construction takes 12-15 ms.
//
// How: every thread that runs a part of one of the context's parallel calls
// other than the host is recorded (its thread id) the first time. For the
// length of one parallel call from the host thread, each recorded worker's
// affinity mask loses the host's current CPU (when it has others), and gets
// it back when the call returns; a worker that runs its first part on the
// host's CPU, before being recorded, moves itself the same way. Every mask
// change in the process goes through one record under one lock (oneTBB's
// workers are shared, and two contexts may run calls at once from two host
// threads): a CPU goes back when no call holds it off any more, and only to
// a mask that is still the one set here; a mask someone else changed
// meanwhile is left as they set it, unless it is our narrowing put back (a
// thread that saved the mask during a call and restored it after our
// give-back: the next call undoes it). So nothing is pinned between calls.
// Best effort: a failed system call leaves that worker where the kernel puts
// it. Off unless the caller asks for it (um_context_set_worker_placement, or
// UNIMESH_WORKER_PLACEMENT=on in the environment): it changes the affinity
// of threads the whole process shares. UNIMESH_WORKER_PLACEMENT=off keeps it
// off whatever is asked.
//
// Known limits: on kernels that keep a requested mask across cpuset changes
// (6.2 and later), a worker once narrowed no longer follows a cpuset that
// grows; a process forked from a worker during a call (a spacing callback)
// inherits the narrowed mask; a worker that ended, whose thread id another
// thread of the process took before the next call, lends that thread its
// place (oneTBB's workers live as long as the pool, so this takes a pool
// shut down and restarted while a context lives).
//
// (Workers are recorded from the parts they run, not by a oneTBB
// task_scheduler_observer: an observer initialises the arena, which made
// with the context raised the pipeline's peak memory by 4-6 MB, and oneTBB
// frees an observer's record only when the workers that saw it leave the
// arena, after the context may be gone: LeakSanitizer reported it.)
//
// Linux only; elsewhere the placement does nothing.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace um {

class WorkerPlacement {
public:
    WorkerPlacement();
    WorkerPlacement(const WorkerPlacement &) = delete;
    WorkerPlacement &operator=(const WorkerPlacement &) = delete;

    // One parallel call: recorded workers off the calling thread's CPU from
    // construction to destruction. Does nothing when the call is nested in
    // another (made from a part of one, on the host or on a worker) or the
    // CPU is unknown.
    class Scope {
    public:
        explicit Scope(WorkerPlacement &placement);
        ~Scope();
        Scope(const Scope &) = delete;
        Scope &operator=(const Scope &) = delete;

    private:
        WorkerPlacement *placement_ = nullptr;  // null: nothing to undo
    };

    // Called at the start of every part of a parallel call, by the thread
    // that runs it: records a worker the first time.
    void note_part_runner();

    // Off unless asked for (here, or by UNIMESH_WORKER_PLACEMENT=on);
    // UNIMESH_WORKER_PLACEMENT=off keeps it off whatever is asked.
    void ask(bool on);
    bool enabled() const;

    // For tests: the CPU kept free for the host during a call (else -1), and
    // how many workers were recorded.
    int32_t host_cpu() const { return host_cpu_.load(std::memory_order_acquire); }
    int recorded_workers() const;

private:
    // More workers than this are not placed. Each placed worker costs a
    // parallel call about 3 us of system calls (restrict and give back, a
    // sleeping thread, this machine): some 870 calls of the coast-rivers-60km
    // pipeline pay 2.8 ms a worker. What a packed worker costs is a share of
    // the machine that shrinks as it has more CPUs, so past a few workers
    // the placement would cost more than it saves.
    static constexpr int kMaxWorkers = 8;
    static constexpr int32_t kDeadTid = -1;  // a slot whose thread ended
    struct Worker {
        std::atomic<int32_t> tid{0};           // 0: not filled yet; kDeadTid
        std::atomic<int32_t> removed_cpu{-1};  // the CPU its mask lost, -1: none
    };
    bool is_recorded(int32_t tid) const;
    void record(int32_t tid);
    const uint64_t id_;  // unique in the process (a thread's last placement)
    std::atomic<bool> asked_;
    std::array<Worker, kMaxWorkers> workers_;
    std::atomic<int> claimed_{0};          // slots claimed (at most kMaxWorkers)
    std::atomic<int32_t> host_cpu_{-1};    // the host's CPU during a call, else -1
};

}  // namespace um
