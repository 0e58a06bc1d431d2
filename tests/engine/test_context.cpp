// Engine tests of the context's threads: where its workers may run during and
// after a parallel call (core/worker_placement.hpp).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
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

#ifndef UNIMESH_PLAIN_THREADS
// The context places its workers for its own parallel calls and leaves
// their masks as they were, with calls nested in them (which place nothing)
// among its calls.
void a_context_gives_its_workers_back(void **) {
    const cpu_set_t original = mask_of(0);
    Context ctx;
    ctx.set_threads(2);
    std::vector<pid_t> workers;
    for (int round = 0; round < 4; ++round) {
        Seen seen = run_two_parts([&](auto body) {
            ctx.parallel_for(2, 1, [&](int64_t b, int64_t e) {
                body(b, e);
                ctx.parallel_for(4, 1, [](int64_t, int64_t) {});  // nested
            });
        });
        if (seen.tid != 0) workers.push_back(seen.tid);
        for (pid_t w : workers) assert_true(same(mask_of(w), original));
    }
    assert_true(same(mask_of(0), original));
}
#endif

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(workers_stay_off_the_host_cpu_during_a_call),
#ifndef UNIMESH_PLAIN_THREADS
        cmocka_unit_test(a_context_gives_its_workers_back),
#endif
    };
    return cmocka_run_group_tests_name("context", tests, nullptr, nullptr);
}
