#include "core/worker_placement.hpp"

#include <cstdlib>
#include <cstring>
#include <mutex>

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

// The placement changes the affinity of oneTBB's workers, shared by
// everything in the process that uses oneTBB: a process-wide side effect, so
// it runs only when asked for. UNIMESH_WORKER_PLACEMENT=on (or 1, yes, true)
// in the environment asks for it for every context; =off (or 0, no, false)
// forbids it, whatever a context asks (an application that places its
// threads itself). Read once.
enum class Switch { unset, on, off };
Switch environment_switch() {
    static const Switch value = [] {
        const char *v = std::getenv("UNIMESH_WORKER_PLACEMENT");
        if (!v) return Switch::unset;
        for (const char *off : {"off", "0", "no", "false", "OFF", "NO", "FALSE"})
            if (std::strcmp(v, off) == 0) return Switch::off;
        for (const char *on : {"on", "1", "yes", "true", "ON", "YES", "TRUE"})
            if (std::strcmp(v, on) == 0) return Switch::on;
        return Switch::unset;
    }();
    return value;
}

#if defined(__linux__)
int32_t this_thread_id() { return static_cast<int32_t>(syscall(SYS_gettid)); }

// Whether `tid` is a thread of this process (signal 0 checks without
// sending): a recorded worker that has ended must not lend its number to a
// thread of another process whose mask we would then change.
bool is_our_thread(int32_t tid) {
    return syscall(SYS_tgkill, static_cast<int>(getpid()), tid, 0) == 0;
}

bool mask_of(int32_t tid, cpu_set_t &mask) {
    CPU_ZERO(&mask);
    return sched_getaffinity(tid, sizeof mask, &mask) == 0;
}

bool set_mask(int32_t tid, const cpu_set_t &mask) { return sched_setaffinity(tid, sizeof mask, &mask) == 0; }

// The masks narrowed by any placement in the process, by thread: every
// change goes through here under one lock, so that two contexts used at once
// from two host threads (sharing oneTBB's workers) cannot lose each other's
// updates, and a CPU goes back only when no call holds it off any more, and
// only to a mask still as set here. A mask that someone else changed
// meanwhile is left as they set it, with one exception: a mask that is the
// one before our first narrowing less only CPUs we took off is ours, put back
// by a thread that saved it during a call and restored it after our
// give-back (oneTBB does so around launching a thread); the next hold
// restores it first.
class NarrowedMasks {
public:
    // Keeps `cpu` off the thread's mask (one hold more); false if it cannot
    // (the mask lacks it, or allows only it, or no room is left).
    bool hold_off(int32_t tid, int32_t cpu) {
        std::lock_guard<std::mutex> lock(mutex_);
        cpu_set_t now;
        if (cpu < 0 || cpu >= CPU_SETSIZE || !mask_of(tid, now)) return false;
        Entry *e = find(tid);
        if (e && e->holds_in_all() == 0) {
            if (e->is_ours_put_back(now) && set_mask(tid, e->original)) now = e->original;
            e->start_from(now);
        } else if (e && !CPU_EQUAL(&now, &e->ours)) {
            e->forget();  // changed by someone else while held: the holds lapse
            e->start_from(now);
        }
        if (Hold *h = e ? e->hold_on(cpu) : nullptr) return ++h->count, true;  // held already
        if (!CPU_ISSET(cpu, &now) || CPU_COUNT(&now) < 2) return false;
        if (!e && (e = add(tid)) != nullptr) e->start_from(now);
        Hold *h = e ? e->new_hold(cpu) : nullptr;
        if (!h) return false;
        cpu_set_t narrowed = now;
        CPU_CLR(cpu, &narrowed);
        if (!set_mask(tid, narrowed)) return false;
        e->ours = narrowed;
        CPU_SET(cpu, &e->taken);
        h->cpu = cpu, h->count = 1;
        return true;
    }

    // One hold of `cpu` fewer; the last gives the CPU back, if the mask is
    // still the one set here. (The entry stays: see is_ours_put_back.)
    void release(int32_t tid, int32_t cpu) {
        std::lock_guard<std::mutex> lock(mutex_);
        Entry *e = find(tid);
        Hold *h = e ? e->hold_on(cpu) : nullptr;
        if (!h || --h->count > 0) return;
        cpu_set_t now;
        if (!mask_of(tid, now) || !CPU_EQUAL(&now, &e->ours)) return e->forget();
        CPU_SET(cpu, &now);
        if (!set_mask(tid, now)) return e->forget();
        e->ours = now;
    }

    // A thread that ended: its entry goes (its number may come back).
    void drop(int32_t tid) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (Entry *e = find(tid)) *e = Entry();
    }

private:
    static constexpr int kEntries = 64, kHolds = 8;
    struct Hold {
        int32_t cpu = -1, count = 0;
    };
    struct Entry {
        int32_t tid = 0;
        cpu_set_t original{};  // the mask before the holds since start_from
        cpu_set_t taken{};     // the CPUs taken off it since
        cpu_set_t ours{};      // the mask as last set here
        Hold holds[kHolds];

        void start_from(const cpu_set_t &now) {
            original = ours = now;
            CPU_ZERO(&taken);
        }
        // `now` is `original` less some of the CPUs taken off it (not all of
        // it: that is no narrowing).
        bool is_ours_put_back(const cpu_set_t &now) const {
            cpu_set_t within, lost, lost_taken;
            CPU_AND(&within, &now, &original);
            CPU_XOR(&lost, &original, &now);
            CPU_AND(&lost_taken, &lost, &taken);
            return CPU_EQUAL(&within, &now) && CPU_EQUAL(&lost_taken, &lost) && CPU_COUNT(&lost) > 0;
        }
        int holds_in_all() const {
            int n = 0;
            for (const Hold &h : holds) n += h.count;
            return n;
        }
        Hold *hold_on(int32_t cpu) {
            for (Hold &h : holds)
                if (h.count > 0 && h.cpu == cpu) return &h;
            return nullptr;
        }
        Hold *new_hold(int32_t cpu) {
            for (Hold &h : holds)
                if (h.count == 0) return h.cpu = cpu, &h;
            return nullptr;
        }
        void forget() {
            for (Hold &h : holds) h = Hold();
        }
    };
    Entry *find(int32_t tid) {
        for (Entry &e : entries_)
            if (e.tid == tid) return &e;
        return nullptr;
    }
    // A free entry, else one that holds nothing now (its thread may have
    // ended unseen: oneTBB starts new workers when host threads come and go).
    Entry *add(int32_t tid) {
        Entry *e = find(0);
        for (int i = 0; !e && i < kEntries; ++i)
            if (entries_[i].holds_in_all() == 0) e = &entries_[i];
        if (e) *e = Entry(), e->tid = tid;
        return e;
    }
    std::mutex mutex_;
    Entry entries_[kEntries];
};

NarrowedMasks &narrowed_masks() {
    static NarrowedMasks masks;  // (constant-initialised, nothing to destroy)
    return masks;
}
#endif
}  // namespace

WorkerPlacement::WorkerPlacement()
    : id_(next_placement_id.fetch_add(1, std::memory_order_relaxed)), asked_(environment_switch() == Switch::on) {}

void WorkerPlacement::ask(bool on) { asked_.store(on, std::memory_order_relaxed); }

bool WorkerPlacement::enabled() const {
    return environment_switch() != Switch::off && asked_.load(std::memory_order_relaxed);
}

int WorkerPlacement::recorded_workers() const {
    int n = 0;
    for (const Worker &w : workers_) n += w.tid.load(std::memory_order_acquire) > 0;
    return n;
}

bool WorkerPlacement::is_recorded(int32_t tid) const {
    const int n = claimed_.load(std::memory_order_acquire);
    for (int i = 0; i < n; ++i)
        if (workers_[i].tid.load(std::memory_order_acquire) == tid) return true;
    return false;
}

void WorkerPlacement::note_part_runner() {
#if defined(__linux__)
    if (t_hosting || t_recorded_by == id_ || !enabled()) return;  // the host, or recorded here, or off
    t_worker = true;
    t_recorded_by = id_;
    const int32_t tid = this_thread_id();
    if (!is_recorded(tid)) record(tid);
#endif
}

void WorkerPlacement::record(int32_t tid) {
#if defined(__linux__)
    // A slot whose thread ended (kDeadTid), else a new one.
    Worker *w = nullptr;
    const int n = claimed_.load(std::memory_order_acquire);
    for (int i = 0; !w && i < n; ++i) {
        int32_t dead = kDeadTid;
        if (workers_[i].tid.compare_exchange_strong(dead, tid, std::memory_order_acq_rel)) w = &workers_[i];
    }
    if (!w) {
        int slot = claimed_.load(std::memory_order_acquire);
        do {
            if (slot >= kMaxWorkers) return;  // full: this one is not placed
        } while (!claimed_.compare_exchange_weak(slot, slot + 1, std::memory_order_acq_rel));
        w = &workers_[static_cast<size_t>(slot)];
        w->tid.store(tid, std::memory_order_release);
    }
    // Woken onto the host's CPU before anyone could keep it off: move now.
    const int32_t host_cpu = host_cpu_.load(std::memory_order_acquire);
    if (host_cpu >= 0 && sched_getcpu() == host_cpu && narrowed_masks().hold_off(tid, host_cpu))
        w->removed_cpu.store(host_cpu, std::memory_order_release);
#else
    (void)tid;
#endif
}

WorkerPlacement::Scope::Scope(WorkerPlacement &placement) {
#if defined(__linux__)
    if (t_hosting || t_worker || !placement.enabled()) return;  // nested, or off
    t_hosting = true;  // (before anything else: the host's parts must not record it)
    placement_ = &placement;
    const int32_t cpu = static_cast<int32_t>(sched_getcpu());
    if (cpu < 0) return;
    placement.host_cpu_.store(cpu, std::memory_order_release);
    const int n = placement.claimed_.load(std::memory_order_acquire);
    try {
        for (int i = 0; i < n; ++i) {
            Worker &w = placement.workers_[static_cast<size_t>(i)];
            const int32_t tid = w.tid.load(std::memory_order_acquire);
            if (tid <= 0 || w.removed_cpu.load(std::memory_order_acquire) >= 0) continue;
            if (!is_our_thread(tid)) {  // it ended: its slot is free again
                narrowed_masks().drop(tid);
                w.tid.store(kDeadTid, std::memory_order_release);
                continue;
            }
            if (narrowed_masks().hold_off(tid, cpu)) w.removed_cpu.store(cpu, std::memory_order_release);
        }
    } catch (...) {  // (a lock that fails: the rest are not placed; the destructor gives back)
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
    const int n = placement_->claimed_.load(std::memory_order_acquire);
    for (int i = 0; i < n; ++i) {
        Worker &w = placement_->workers_[static_cast<size_t>(i)];
        const int32_t tid = w.tid.load(std::memory_order_acquire);
        const int32_t cpu = w.removed_cpu.exchange(-1, std::memory_order_acq_rel);
        if (tid <= 0 || cpu < 0) continue;
        try {
            narrowed_masks().release(tid, cpu);
        } catch (...) {  // (a lock that fails: the mask stays narrowed)
        }
    }
#endif
}

}  // namespace um
