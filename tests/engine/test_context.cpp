// Engine tests of the context's threads: where its workers may run during and
// after a parallel call (core/worker_placement.hpp).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <mutex>
#include <thread>
#include <vector>

#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "core/context.hpp"
#include "core/worker_placement.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;

namespace {

cpu_set_t mask_of(pid_t tid) {
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (sched_getaffinity(tid, sizeof mask, &mask) != 0) CPU_ZERO(&mask);
    return mask;
}

bool same(const cpu_set_t &a, const cpu_set_t &b) { return CPU_EQUAL(&a, &b); }

pid_t this_tid() { return static_cast<pid_t>(syscall(SYS_gettid)); }

// What a worker saw inside a call: its thread id and its mask.
struct Seen {
    pid_t tid = 0;
    cpu_set_t mask;
};

// Runs `call` with a body of two parts that each wait (up to a second) for
// the other to start, so that a worker takes one; returns what the part run
// by a thread other than the caller saw (tid 0 if no worker came).
template <class Call>
Seen run_two_parts(Call &&call) {
    const pid_t host = this_tid();
    std::atomic<int> started{0};
    Seen seen;
    CPU_ZERO(&seen.mask);
    call([&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            ++started;
            const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(1);
            while (started.load() < 2 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
            if (this_tid() != host) seen.tid = this_tid(), seen.mask = mask_of(0);
        }
    });
    return seen;
}

// One helper thread that runs a part of each call it is handed, as a pool
// worker does (plain threads: ThreadSanitizer sees this test's
// synchronisation, which it would not in Debian's oneTBB).
class Helper {
public:
    Helper() : thread_([this] { loop(); }) {}
    ~Helper() {
        {
            std::lock_guard<std::mutex> lock(m_);
            quit_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    // Runs part(0) on the helper and part(1) here, and waits for both.
    template <class Part>
    void run(Part &&part) {
        {
            std::lock_guard<std::mutex> lock(m_);
            job_ = [&] { part(0); };
            ++posted_;
        }
        cv_.notify_all();
        part(1);
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [&] { return done_ == posted_; });
    }

private:
    void loop() {
        std::unique_lock<std::mutex> lock(m_);
        for (;;) {
            cv_.wait(lock, [&] { return quit_ || done_ != posted_; });
            if (quit_) return;
            lock.unlock();
            job_();
            lock.lock();
            ++done_;
            cv_.notify_all();
        }
    }
    std::mutex m_;
    std::condition_variable cv_;
    std::function<void()> job_;
    long posted_ = 0, done_ = 0;
    bool quit_ = false;
    std::thread thread_;  // last: starts once the rest is made
};

// During a call every recorded worker is kept off the CPU the host was on
// when the call began; after it, its mask is what it was.
void workers_stay_off_the_host_cpu_during_a_call(void **) {
    const cpu_set_t original = mask_of(0);
    if (CPU_COUNT(&original) < 2) skip();
    WorkerPlacement placement;
    placement.ask(true);
    Helper helper;
    for (int round = 0; round < 4; ++round) {
        Seen seen;
        int32_t host_cpu = -1;
        {
            WorkerPlacement::Scope scope(placement);
            host_cpu = placement.host_cpu();
            assert_true(host_cpu >= 0);
            seen = run_two_parts([&](auto body) {
                helper.run([&](int64_t part) {
                    placement.note_part_runner();
                    body(part, part + 1);
                });
            });
        }
        assert_int_equal(placement.host_cpu(), -1);
        assert_true(seen.tid != 0);
        assert_int_equal(placement.recorded_workers(), 1);  // the helper, not the host
        // Recorded by the first call, the helper is off the host's CPU for
        // all of the later ones (in the first only if it ran on that CPU).
        if (round > 0) assert_false(CPU_ISSET(host_cpu, &seen.mask));
        assert_true(same(mask_of(seen.tid), original));
    }
    assert_true(same(mask_of(0), original));
}

void set_mask(pid_t tid, const cpu_set_t &mask) { assert_int_equal(sched_setaffinity(tid, sizeof mask, &mask), 0); }

// The helper's thread id, recording it as a worker of each placement given.
pid_t record_helper(Helper &helper, std::initializer_list<WorkerPlacement *> placements) {
    pid_t tid = 0;
    helper.run([&](int64_t part) {
        if (part != 0) return;
        for (WorkerPlacement *p : placements) p->note_part_runner();
        tid = this_tid();
    });
    return tid;
}

// Two contexts used at once from two host threads on two CPUs share the
// pool's workers: each call holds one CPU off a worker, and every CPU comes
// back when the calls are done. (Changed by read-modify-write without a
// common lock, the masks lost updates and a worker was left on one CPU.)
void two_hosts_at_once_give_every_cpu_back(void **) {
    const cpu_set_t original = mask_of(0);
    if (CPU_COUNT(&original) < 2) skip();
    int cpus[2], found = 0;
    for (int c = 0; c < CPU_SETSIZE && found < 2; ++c)
        if (CPU_ISSET(c, &original)) cpus[found++] = c;
    WorkerPlacement a, b;
    a.ask(true), b.ask(true);
    Helper helper;
    const pid_t worker = record_helper(helper, {&a, &b});
    assert_int_equal(a.recorded_workers(), 1);
    assert_int_equal(b.recorded_workers(), 1);
    std::atomic<int> pinned{0};
    auto host = [&pinned](WorkerPlacement *p, int cpu) {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpu, &one);
        if (sched_setaffinity(0, sizeof one, &one) != 0) return;
        ++pinned;
        for (int i = 0; i < 50000; ++i) WorkerPlacement::Scope scope(*p);
    };
    std::thread host_a(host, &a, cpus[0]), host_b(host, &b, cpus[1]);
    host_a.join();
    host_b.join();
    assert_int_equal(pinned.load(), 2);
    assert_true(same(mask_of(worker), original));
}

// A thread that saves a worker's mask during a call and restores it after
// (oneTBB does so around launching a thread) puts our narrowing back: the
// next call undoes it, whether the other thread widened the mask before our
// give-back (which then leaves it alone) or not.
void a_narrowing_put_back_by_another_is_undone(void **) {
    const cpu_set_t original = mask_of(0);
    if (CPU_COUNT(&original) < 2) skip();
    WorkerPlacement placement;
    placement.ask(true);
    Helper helper;
    const pid_t worker = record_helper(helper, {&placement});
    for (bool widened_first : {true, false}) {
        cpu_set_t saved;
        {
            WorkerPlacement::Scope scope(placement);
            saved = mask_of(worker);
            assert_false(same(saved, original));     // narrowed
            if (widened_first) set_mask(worker, original);  // the other thread widens it...
        }  // (a mask not set here is left as it is; ours gets its CPU back)
        assert_true(same(mask_of(worker), original));
        set_mask(worker, saved);  // ...and restores what it saved
        for (int call = 0; call < 3; ++call) {
            { WorkerPlacement::Scope scope(placement); }
            assert_true(same(mask_of(worker), original));
        }
    }
}

// Nothing of `placement` is recorded or narrowed around a call.
void expect_nothing_placed(WorkerPlacement &placement) {
    const cpu_set_t original = mask_of(0);
    Helper helper;
    const pid_t worker = record_helper(helper, {&placement});
    assert_int_equal(placement.recorded_workers(), 0);
    WorkerPlacement::Scope scope(placement);
    assert_int_equal(placement.host_cpu(), -1);
    assert_true(same(mask_of(worker), original));
}

// UNIMESH_WORKER_PLACEMENT=off (ctest engine.test_context_off): nothing is
// recorded or narrowed, even when asked for.
void the_switch_turns_it_off(void **) {
    WorkerPlacement placement;
    placement.ask(true);
    expect_nothing_placed(placement);
}

// Without being asked for (the default: it changes the affinity of threads
// the whole process shares), nothing is recorded or narrowed; asked for and
// then not, the same.
void off_unless_asked_for(void **) {
    for (bool asked_then_not : {false, true}) {
        WorkerPlacement placement;
        if (asked_then_not) placement.ask(true), placement.ask(false);
        expect_nothing_placed(placement);
    }
}

#ifndef UNIMESH_PLAIN_THREADS
// The context places its workers for its own parallel calls (a worker that
// ran a part of an earlier call is off the host's CPU, also after a call
// nested in the part, which places nothing) and gives their CPU back.
void a_context_places_its_workers_and_gives_them_back(void **) {
    const cpu_set_t original = mask_of(0);
    if (CPU_COUNT(&original) < 2) skip();
    Context ctx;
    ctx.set_worker_placement(true);
    ctx.set_threads(2);
    const pid_t host = this_tid();
    std::vector<pid_t> earlier;
    int checked = 0;
    for (int round = 0; round < 8; ++round) {
        std::atomic<int> started{0};
        pid_t worker = 0;
        int32_t host_cpu = -1;
        cpu_set_t during;
        CPU_ZERO(&during);
        ctx.parallel_for(2, 1, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
                ++started;
                const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(1);
                while (started.load() < 2 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
                ctx.parallel_for(4, 1, [](int64_t, int64_t) {});  // nested
                if (this_tid() != host)
                    worker = this_tid(), during = mask_of(0), host_cpu = ctx.worker_placement().host_cpu();
            }
        });
        assert_int_equal(ctx.worker_placement().host_cpu(), -1);
        if (worker == 0) continue;  // no worker came this time
        if (std::find(earlier.begin(), earlier.end(), worker) != earlier.end()) {
            assert_true(host_cpu >= 0);
            assert_false(CPU_ISSET(host_cpu, &during));
            ++checked;
        }
        earlier.push_back(worker);
        assert_true(same(mask_of(worker), original));
    }
    assert_true(checked > 0);
    assert_true(same(mask_of(0), original));
}
#endif

}  // namespace

int main() {
    const char *placement = std::getenv("UNIMESH_WORKER_PLACEMENT");
    if (placement && std::strcmp(placement, "off") == 0) {
        const struct CMUnitTest off[] = {cmocka_unit_test(the_switch_turns_it_off)};
        return cmocka_run_group_tests_name("context (placement off)", off, nullptr, nullptr);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(off_unless_asked_for),
        cmocka_unit_test(workers_stay_off_the_host_cpu_during_a_call),
        cmocka_unit_test(two_hosts_at_once_give_every_cpu_back),
        cmocka_unit_test(a_narrowing_put_back_by_another_is_undone),
#ifndef UNIMESH_PLAIN_THREADS
        cmocka_unit_test(a_context_places_its_workers_and_gives_them_back),
#endif
    };
    return cmocka_run_group_tests_name("context", tests, nullptr, nullptr);
}
