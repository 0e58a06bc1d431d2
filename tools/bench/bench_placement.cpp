// What keeping a worker off the host's CPU (core/worker_placement.hpp) is
// for, and what it costs, on this machine.
//
//   bench_placement [fresh processes, default 20] [cost loops, default 100000]
//
// 1. A worker woken by a busy host, in fresh processes: each child makes a
//    helper thread that sleeps, keeps its own thread busy for 5 ms, then
//    wakes the helper and both spin for 10 ms. Printed: the wall time from
//    the wake to both done (10 ms if they ran side by side) and the helper's
//    wait for a CPU while ready to run (schedstat), for children that place
//    the helper (WorkerPlacement::Scope around the wake) and children that do
//    not, alternating.
// 2. The cost of a placement: one Scope (restrict, then give back) with one
//    recorded, sleeping worker, per call, in microseconds.
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "core/worker_placement.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void spin_ms(double ms) {
    const auto t0 = Clock::now();
    while (ms_since(t0) < ms) {
    }
}

// The calling thread's wait for a CPU so far (ms), from schedstat.
double runqueue_wait_ms() {
    char path[64];
    std::snprintf(path, sizeof path, "/proc/self/task/%ld/schedstat", static_cast<long>(syscall(SYS_gettid)));
    unsigned long long run_ns = 0, wait_ns = 0;
    if (FILE *f = std::fopen(path, "r")) {
        if (std::fscanf(f, "%llu %llu", &run_ns, &wait_ns) != 2) wait_ns = 0;
        std::fclose(f);
    }
    return 1e-6 * double(wait_ns);
}

// A helper that sleeps until woken, then spins; reports its wait.
struct Wake {
    std::mutex m;
    std::condition_variable cv;
    bool go = false;
    double helper_wait_ms = 0;
};

struct Sample {
    double wall_ms, wait_ms;
};

// In a fresh child: one wake of a sleeping helper by a busy host.
Sample one_wake(bool placed) {
    um::WorkerPlacement placement;
    placement.ask(true);  // (off unless asked for)
    Wake w;
    std::atomic<bool> recorded{false};
    std::thread helper([&] {
        placement.note_part_runner();  // as a worker running its first part
        recorded = true;
        std::unique_lock<std::mutex> lock(w.m);
        w.cv.wait(lock, [&] { return w.go; });
        lock.unlock();
        const double before = runqueue_wait_ms();
        spin_ms(10);
        w.helper_wait_ms = runqueue_wait_ms() - before;
    });
    while (!recorded) std::this_thread::yield();
    spin_ms(5);  // the host is busy
    const auto t0 = Clock::now();
    {
        std::unique_ptr<um::WorkerPlacement::Scope> scope;
        if (placed) scope = std::make_unique<um::WorkerPlacement::Scope>(placement);
        {
            std::lock_guard<std::mutex> lock(w.m);
            w.go = true;
        }
        w.cv.notify_one();
        spin_ms(10);
        helper.join();
    }
    return {ms_since(t0), w.helper_wait_ms};
}

Sample in_child(bool placed) {
    Sample s{-1, -1};
    if (bench::run_in_child([placed] { return one_wake(placed); }, s) != bench::ChildOutcome::ok) s = {-1, -1};
    return s;
}

void print_stats(const char *what, std::vector<double> v, double over) {
    std::sort(v.begin(), v.end());
    const auto n_over = std::count_if(v.begin(), v.end(), [over](double x) { return x > over; });
    std::printf("  %-18s median %6.2f  least %6.2f  greatest %6.2f  above %g: %ld of %zu\n", what,
                v[v.size() / 2], v.front(), v.back(), over, static_cast<long>(n_over), v.size());
}

double placement_cost_us(int loops) {
    um::WorkerPlacement placement;
    placement.ask(true);  // (off unless asked for)
    std::mutex m;
    std::condition_variable cv;
    bool done = false, recorded = false;
    std::thread helper([&] {
        placement.note_part_runner();
        std::unique_lock<std::mutex> lock(m);
        recorded = true;
        cv.notify_all();
        cv.wait(lock, [&] { return done; });
    });
    {
        std::unique_lock<std::mutex> lock(m);
        cv.wait(lock, [&] { return recorded; });
    }
    const auto t0 = Clock::now();
    for (int i = 0; i < loops; ++i) um::WorkerPlacement::Scope scope(placement);
    const double us = 1e3 * ms_since(t0) / loops;
    {
        std::lock_guard<std::mutex> lock(m);
        done = true;
    }
    cv.notify_all();
    helper.join();
    return placement.recorded_workers() == 1 ? us : -1;
}

}  // namespace

int main(int argc, char **argv) {
    const int children = argc > 1 ? std::max(2, std::atoi(argv[1])) : 20;
    const int loops = argc > 2 ? std::max(1, std::atoi(argv[2])) : 100000;
    std::printf("# bench_placement: a sleeping helper woken by a busy host, both then spin 10 ms;\n"
                "# %d fresh processes each way, alternating; wall = wake to both done (ms),\n"
                "# wait = the helper's wait for a CPU while ready to run (ms)\n",
                children);
    std::vector<double> wall[2], wait[2];
    for (int i = 0; i < 2 * children; ++i) {
        const bool placed = i % 2 == 1;
        const Sample s = in_child(placed);
        if (s.wall_ms < 0) {
            std::printf("child failed\n");
            return 1;
        }
        wall[placed].push_back(s.wall_ms);
        wait[placed].push_back(s.wait_ms);
        usleep(20000);  // the machine idle between children, as between a user's runs
    }
    for (int placed = 0; placed < 2; ++placed) {
        std::printf("%s\n", placed ? "placed (helper kept off the host's CPU):" : "not placed:");
        print_stats("wall ms", wall[placed], 11.0);
        print_stats("helper's wait ms", wait[placed], 1.0);
    }
    const double us = placement_cost_us(loops);
    if (us < 0) {
        std::printf("the helper was not recorded\n");
        return 1;
    }
    std::printf("placement of one recorded, sleeping worker (restrict and give back): %.2f us a call\n", us);
    return 0;
}
