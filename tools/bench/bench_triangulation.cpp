// bench_triangulation: times the construction of the Delaunay triangulation of
// points on the unit sphere by unimesh (through its public C API) against two
// references in the same run:
//   - CGAL's Delaunay_triangulation_on_sphere_2 (Epick kernel, points inserted
//     as one range so CGAL shuffles and spatially sorts them itself);
//   - Qhull's 3-D convex hull ("qhull Qt", libqhull_r C API).
//
// Every single measurement (one method, one thread count, one run) happens in a
// child process made by fork(), so that the peak memory of one method cannot
// pollute another's. The child reads getrusage(RUSAGE_SELF).ru_maxrss once its
// input is ready (baseline) and again after the construction; it sends the time
// and the two values back through a pipe. The parent only generates the points
// and never starts threads, so fork() is safe.
//
// Usage: bench_triangulation [--quick] [--cases LIST] [--repeat R]
//                            [--timeout S] [--qhull-limit S] [--no-qhull] [--cold]
// See README.md in this folder.
#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <malloc.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CGAL/Delaunay_triangulation_on_sphere_2.h>
#include <CGAL/Delaunay_triangulation_on_sphere_traits_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/version.h>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "child_process.hpp"
#include "point_sets.hpp"
#include "unimesh.h"

namespace {

using bench::CaseSpec;
using bench::kSeed;
using bench::PointSet;

// ------------------------------------------------------------ measurement

// What a child sends back through the pipe (plain data, fixed size).
struct ChildResult {
    int32_t ok = 0;
    double seconds = 0.0;
    int64_t rss_base_kb = 0;  // ru_maxrss when the input was ready
    int64_t rss_peak_kb = 0;  // ru_maxrss after the construction
    int64_t faults = 0;       // page faults during the construction (ru_minflt + ru_majflt)
    double system_s = 0.0;    // system time during it, all threads (mostly first touches)
    double user_s = 0.0;      // user time during it, all threads
    double wait_s = 0.0;      // run-queue wait during it, all threads (Usage::runqueue_wait_s)
    // unimesh: seconds from the call to the end of the first BRIO round (the
    // library's first progress report), about the time to the first
    // insertions: the input checks, the conversion, the ordering and the
    // gather, and in a fresh process the threads' start and first touches.
    // Negative for the references.
    double setup_s = -1.0;
    int64_t n_vertices = 0;
    int64_t n_triangles = 0;
    int64_t n_hidden = 0;
    char message[480] = {0};
};

using bench::now_seconds;
using bench::Usage;
using bench::usage_now;

// What the construction since `before` used, into r.
void record_usage(ChildResult &r, const Usage &before) {
    const Usage after = usage_now();
    r.rss_base_kb = before.maxrss_kb;
    r.rss_peak_kb = after.maxrss_kb;
    r.faults = after.faults - before.faults;
    r.system_s = after.system_s - before.system_s;
    r.user_s = after.user_s - before.user_s;
    r.wait_s = after.runqueue_wait_s - before.runqueue_wait_s;
}

void set_message(ChildResult &r, const std::string &text) {
    std::snprintf(r.message, sizeof r.message, "%s", text.c_str());
}

using Outcome = bench::ChildOutcome;

// Runs `work` in a child process (bench::run_in_child); gives up (SIGKILL to
// that child) after timeout_s. An exception in the child, its death, or a
// result not ok is a failure with a message.
Outcome run_in_child(const std::function<ChildResult()> &work, double timeout_s, ChildResult &result) {
    auto guarded = [&work] {
        ChildResult r;
        try {
            r = work();
        } catch (const std::exception &e) {
            r.ok = 0;
            set_message(r, std::string("exception: ") + e.what());
        } catch (...) {
            r.ok = 0;
            set_message(r, "unknown exception");
        }
        return r;
    };
    int status = 0;
    const Outcome outcome = bench::run_in_child(guarded, result, timeout_s, &status);
    if (outcome == Outcome::failed) {
        result = ChildResult();
        if (WIFSIGNALED(status))
            set_message(result, "child killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                                    strsignal(WTERMSIG(status)) + ")");
        else
            set_message(result, "child exited with status " + std::to_string(WEXITSTATUS(status)) +
                                    " without reporting");
    }
    if (outcome != Outcome::ok) return outcome;
    return result.ok ? Outcome::ok : Outcome::failed;
}

// --- the methods; each body runs inside a child process ---

ChildResult measure_unimesh(const PointSet &ps, int threads, bool from_lonlat) {
    ChildResult r;
    um_context *ctx = nullptr;
    if (um_context_create(&ctx) != UM_OK) {
        set_message(r, "um_context_create failed");
        return r;
    }
    if (um_context_set_threads(ctx, threads) != UM_OK) {
        set_message(r, std::string("um_context_set_threads: ") + um_context_last_error(ctx));
        um_context_destroy(ctx);
        return r;
    }
    // The library's debug line on its parallel rounds: how many points they
    // held and how many of those were deferred to the serial pass.
    struct Rounds {
        long long parallel = -1, deferred = -1;
    } rounds;
    // The first progress report of the construction: the end of its first round.
    struct FirstRound {
        double at = -1.0;
    } first_round;
    um_context_set_progress(ctx, [](void *user, const char *, double) -> int32_t {
        auto *f = static_cast<FirstRound *>(user);
        if (f->at < 0) f->at = now_seconds();
        return 0;
    }, &first_round);
    um_context_set_log(ctx, [](void *user, int32_t, const char *msg) {
        auto *x = static_cast<Rounds *>(user);
        long long points = 0;
        std::sscanf(msg, "triangulate: %lld points, %lld in parallel rounds, %lld of them deferred",
                    &points, &x->parallel, &x->deferred);
    }, &rounds, UM_LOG_DEBUG);
    const int64_t n = ps.size();
    um_triangulation *tri = nullptr;
    const Usage before = usage_now();
    const double t0 = now_seconds();
    const um_status st =
        from_lonlat ? um_triangulation_create(ctx, n, ps.lon.data(), ps.lat.data(), nullptr, &tri)
                    : um_triangulation_create_xyz(ctx, n, ps.xyz.data(), nullptr, &tri);
    const double t1 = now_seconds();
    record_usage(r, before);
    r.seconds = t1 - t0;
    if (first_round.at >= 0) r.setup_s = first_round.at - t0;
    if (st != UM_OK) {
        set_message(r, "status " + std::to_string(st) + ": " + um_context_last_error(ctx));
    } else if (um_triangulation_counts(tri, &r.n_vertices, &r.n_triangles, &r.n_hidden) != UM_OK) {
        set_message(r, std::string("um_triangulation_counts: ") + um_context_last_error(ctx));
    } else {
        r.ok = 1;
        if (rounds.parallel > 0)
            std::snprintf(r.message, sizeof r.message, "deferred %.1f %% of the %lld points of parallel rounds",
                          100.0 * double(rounds.deferred) / double(rounds.parallel), rounds.parallel);
    }
    um_triangulation_destroy(tri);
    um_context_destroy(ctx);
    return r;
}

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SphereTraits = CGAL::Delaunay_triangulation_on_sphere_traits_2<Kernel>;
using SphereDT = CGAL::Delaunay_triangulation_on_sphere_2<SphereTraits>;

ChildResult measure_cgal(const PointSet &ps) {
    ChildResult r;
    const int64_t n = ps.size();
    // CGAL's input format; made before the baseline, like unimesh's input arrays.
    std::vector<Kernel::Point_3> points;
    points.reserve(size_t(n));
    for (int64_t i = 0; i < n; ++i)
        points.emplace_back(ps.xyz[size_t(3 * i)], ps.xyz[size_t(3 * i + 1)], ps.xyz[size_t(3 * i + 2)]);
    const SphereTraits traits(Kernel::Point_3(0, 0, 0), 1.0);
    const Usage before = usage_now();
    const double t0 = now_seconds();
    {
        SphereDT dt(traits);
        dt.insert(points.begin(), points.end());  // shuffles and spatially sorts itself
        const double t1 = now_seconds();
        record_usage(r, before);
        r.seconds = t1 - t0;
        r.n_vertices = int64_t(dt.number_of_vertices());
        r.n_triangles = int64_t(dt.number_of_solid_faces());
        // Points CGAL dropped (not on the sphere within its tolerance, or too close
        // to another point) are reported as hidden.
        r.n_hidden = n - r.n_vertices;
        if (dt.dimension() != 2)
            set_message(r, "triangulation has dimension " + std::to_string(dt.dimension()));
        else
            r.ok = 1;
    }
    return r;
}

ChildResult measure_qhull(const PointSet &ps) {
    ChildResult r;
    const int64_t n = ps.size();
    if (n > INT32_MAX) {
        set_message(r, "too many points for qhull");
        return r;
    }
    qhT qh_storage;
    qhT *qh = &qh_storage;
    qh_zero(qh, stderr);
    char command[] = "qhull Qt";
    // The child owns a copy-on-write copy of the points; qhull does not change them.
    coordT *coords = const_cast<coordT *>(ps.xyz.data());
    const Usage before = usage_now();
    const double t0 = now_seconds();
    const int exitcode = qh_new_qhull(qh, 3, int(n), coords, False, command, nullptr, stderr);
    const double t1 = now_seconds();
    record_usage(r, before);
    r.seconds = t1 - t0;
    if (exitcode != 0) {
        set_message(r, "qh_new_qhull exit code " + std::to_string(exitcode));
    } else {
        int64_t facets = 0, vertices = 0;
        for (facetT *f = qh->facet_list; f && f->next; f = f->next)
            if (!f->visible) ++facets;
        for (vertexT *v = qh->vertex_list; v && v->next; v = v->next) ++vertices;
        r.n_triangles = facets;
        r.n_vertices = vertices;
        r.n_hidden = n - vertices;  // interior or coplanar points, not hull vertices
        r.ok = 1;
    }
    qh_freeqhull(qh, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(qh, &curlong, &totlong);
    return r;
}

// ------------------------------------------------------------------ driver

struct Row {
    std::string case_name;
    std::string method;
    int threads = 1;
    int64_t n = 0;
    int runs = 0;
    bool ok = false;
    bool skipped = false;
    double seconds = 0.0;  // best of the runs
    int64_t peak_kb = 0;   // largest increase of the child's max RSS over the runs
    int64_t faults = 0;    // page faults of the best run
    double system_s = 0.0; // system time of the best run
    std::vector<double> times;  // every counted run's, in round order
    std::vector<double> user_times, system_times;  // their user and system times
    std::vector<double> setup_times;               // their ChildResult::setup_s
    std::vector<double> wait_times;                // their ChildResult::wait_s
    int64_t n_vertices = 0, n_triangles = 0, n_hidden = 0;
    std::string note;
};

struct Options {
    bool quick = false;
    std::vector<std::string> cases;
    int repeat = 0;  // 0: the defaults (usage())
    double timeout = 1800.0;
    double qhull_limit = 180.0;  // seconds; Qhull above 1e6 points is skipped beyond this
    bool cold = false;           // no warm-up run
    bool qhull = true;           // --no-qhull: CGAL the only reference
};

void usage(FILE *f) {
    std::fprintf(f,
                 "usage: bench_triangulation [--quick] [--cases LIST] [--repeat R]\n"
                 "                           [--timeout S] [--qhull-limit S] [--no-qhull] [--cold]\n"
                 "  --quick          only random-1e5 and ico-6 (smoke test)\n"
                 "  --cases LIST     comma-separated cases: random-<points> (e.g. random-1e6),\n"
                 "                   ico-<level> (0..11) and grid-<degrees> (a longitude-\n"
                 "                   latitude grid, the step dividing 180); default\n"
                 "                   random-1e5,random-1e6,random-4e6,ico-9,grid-0.25\n"
                 "  --repeat R       rounds of runs (every method once a round), best time\n"
                 "                   kept; default 5 (3 for cases of 3e6 points or more);\n"
                 "                   Qhull's runs: default 3 (1 from 3e6 points)\n"
                 "  --timeout S      give up a single run after S seconds (default 1800)\n"
                 "  --qhull-limit S  above 1e6 points, skip Qhull when it would take, or\n"
                 "                   takes, more than S seconds (default 180)\n"
                 "  --no-qhull       leave Qhull out (CGAL stays)\n"
                 "  --cold           no uncounted run of the same method before each\n"
                 "                   counted one (on a virtual machine the first touch of\n"
                 "                   memory the host took back costs 20-40 times more:\n"
                 "                   see measure_by_rounds())\n");
}

void print_row(const Row &row) {
    if (!row.ok) {
        std::printf("%-12s %-15s %3d %9" PRId64 "  %s: %s\n", row.case_name.c_str(), row.method.c_str(),
                    row.threads, row.n, row.skipped ? "SKIPPED" : "FAILED", row.note.c_str());
        return;
    }
    const double mb = double(row.peak_kb) / 1024.0;
    const double bytes_per_point = double(row.peak_kb) * 1024.0 / double(row.n);
    std::printf("%-12s %-15s %3d %9" PRId64 " %9.4f %8.3f %9.1f %8.1f %8" PRId64 " %7.3f %9" PRId64
                " %9" PRId64 " %6" PRId64 " %4d%s%s\n",
                row.case_name.c_str(), row.method.c_str(), row.threads, row.n, row.seconds,
                double(row.n) / row.seconds / 1e6, mb, bytes_per_point, row.faults, row.system_s,
                row.n_vertices, row.n_triangles, row.n_hidden, row.runs, row.note.empty() ? "" : "  ",
                row.note.c_str());
}

// One method of a case: what a row measures, and the work of one run.
struct Method {
    std::string name;
    int threads = 1;
    std::function<ChildResult()> work;
    // A reference's run that times out is skipped (Qhull is allowed to be
    // too slow); unimesh's is a failure: the product did not deliver.
    bool timeout_skips = true;
};

// The methods of a case measured by rounds: in each round every method makes
// one run, the first method of round k being method k (mod their number),
// so that each pair of methods ran seconds apart in every round (in the same
// cyclic order: which of two runs first changes only when a round starts
// between them). This machine's speed drifts by 20-40 % within minutes; a method's
// best run and another's could come from different minutes, but the ratio of
// two methods' times in one round sees the same machine (the summary prints
// the median of those ratios next to the ratio of the best times).
//
// With warm_up, every counted run comes right after an uncounted run of the
// same method: this project's machine is a virtual machine whose host backs
// the guest's memory only when it is first touched and takes back memory
// that stays free for a few seconds (free page reporting), and a child
// first-touches what the previous one left at 0.1 ms per MB or at 2-4 ms
// (bench_first_touch), depending on what that one was. A warm-up run per
// method (the first design) left each counted run after another method: in
// the rotation unimesh's one-thread run came right after CGAL's in every
// round, and there it took 0.94-1.12 s of system time at 4*10^6 points, 0.03
// - 0.09 s after a unimesh run (CGAL frees 640 MB of small pages). After a
// run of its own every method starts as the later runs of a method did
// before the rounds.
// A method that fails drops out of the rounds after it.
std::vector<Row> measure_by_rounds(const CaseSpec &spec, const std::vector<Method> &methods, int runs,
                                   double timeout, bool warm_up) {
    const size_t m = methods.size();
    std::vector<Row> rows(m);
    std::vector<bool> out(m, false);  // failed: no more runs
    for (size_t i = 0; i < m; ++i) {
        rows[i].case_name = spec.name;
        rows[i].method = methods[i].name;
        rows[i].threads = methods[i].threads;
        rows[i].n = spec.n;
        rows[i].ok = true;
    }
    auto run = [&](size_t i, int k) {  // k < 0: the warm-up run
        Row &row = rows[i];
        malloc_trim(0);  // give freed memory back, so the child starts from a lean heap
        ChildResult r;
        const Outcome outcome = run_in_child(methods[i].work, timeout, r);
        if (outcome != Outcome::ok) {
            row.ok = false;
            row.skipped = outcome == Outcome::timed_out && methods[i].timeout_skips;
            char limit[64];
            std::snprintf(limit, sizeof limit, "did not finish within %g s", timeout);
            row.note = outcome == Outcome::timed_out ? std::string(limit) : std::string(r.message);
            if (k < 0) row.note = "(warm-up run) " + row.note;
            out[i] = true;  // row.runs stays the count of counted runs that finished
            return;
        }
        if (k < 0) return;
        const int64_t delta = r.rss_peak_kb - r.rss_base_kb;
        if (row.runs == 0 || r.seconds < row.seconds) row.seconds = r.seconds, row.faults = r.faults, row.system_s = r.system_s;
        if (row.runs == 0 || delta > row.peak_kb) row.peak_kb = delta;
        if (row.runs > 0 && (r.n_triangles != row.n_triangles || r.n_vertices != row.n_vertices))
            row.note = "counts differ between runs";
        row.n_vertices = r.n_vertices;
        row.n_triangles = r.n_triangles;
        row.n_hidden = r.n_hidden;
        row.times.push_back(r.seconds);
        row.user_times.push_back(r.user_s);
        row.setup_times.push_back(r.setup_s);
        row.wait_times.push_back(r.wait_s);
        row.system_times.push_back(r.system_s);
        ++row.runs;
        if (row.note.empty()) row.note = r.message;  // what the method adds (unimesh: deferrals)
    };
    for (int k = 0; k < runs; ++k)
        for (size_t j = 0; j < m; ++j) {
            const size_t i = (static_cast<size_t>(k) + j) % m;
            if (warm_up && !out[i]) run(i, -1);
            if (!out[i]) run(i, k);
        }
    return rows;
}

// The row of a case's method that ran, or null.
const Row *find_row(const std::vector<Row> &rows, const CaseSpec &spec, const std::string &method, int threads) {
    for (const Row &r : rows)
        if (r.case_name == spec.name && r.method == method && r.threads == threads && r.ok) return &r;
    return nullptr;
}

// The ratios ref/um of the rounds where both ran (times[k] is round k's).
std::vector<double> round_ratios(const Row &ref, const Row &um) {
    std::vector<double> ratios;
    if (!ref.ok || !um.ok) return ratios;
    for (size_t k = 0; k < ref.times.size() && k < um.times.size(); ++k)
        if (um.times[k] > 0) ratios.push_back(ref.times[k] / um.times[k]);
    std::sort(ratios.begin(), ratios.end());
    return ratios;
}

}  // namespace

int main(int argc, char **argv) {
    Options opt;
    std::string cases_arg;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char *name) -> const char * {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "bench_triangulation: %s needs a value\n", name);
                usage(stderr);
                std::exit(2);
            }
            return argv[++i];
        };
        auto positive = [&](const char *name, const char *text) {
            char *end = nullptr;
            const double v = std::strtod(text, &end);
            if (end == text || *end != '\0' || !(v > 0)) {
                std::fprintf(stderr, "bench_triangulation: %s '%s' is not a positive number\n", name, text);
                std::exit(2);
            }
            return v;
        };
        if (a == "--quick") {
            opt.quick = true;
        } else if (a == "--cases") {
            cases_arg = value("--cases");
        } else if (a == "--repeat") {
            const double v = positive("--repeat", value("--repeat"));
            if (v != std::floor(v) || v > 1000) {
                std::fprintf(stderr, "bench_triangulation: --repeat must be an integer in 1..1000\n");
                return 2;
            }
            opt.repeat = int(v);
        } else if (a == "--timeout") {
            opt.timeout = positive("--timeout", value("--timeout"));
        } else if (a == "--qhull-limit") {
            opt.qhull_limit = positive("--qhull-limit", value("--qhull-limit"));
        } else if (a == "--no-qhull") {
            opt.qhull = false;
        } else if (a == "--cold") {
            opt.cold = true;
        } else if (a == "-h" || a == "--help") {
            usage(stdout);
            return 0;
        } else {
            std::fprintf(stderr, "bench_triangulation: unknown argument '%s'\n", a.c_str());
            usage(stderr);
            return 2;
        }
    }
    if (!cases_arg.empty()) {
        size_t start = 0;
        while (start <= cases_arg.size()) {
            const size_t comma = cases_arg.find(',', start);
            const std::string item =
                cases_arg.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            if (!item.empty()) opt.cases.push_back(item);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
    } else if (opt.quick) {
        opt.cases = {"random-1e5", "ico-6"};
    } else {
        opt.cases = {"random-1e5", "random-1e6", "random-4e6", "ico-9", "grid-0.25"};
    }
    std::vector<CaseSpec> specs;
    for (const std::string &c : opt.cases) {
        CaseSpec spec;
        if (!bench::parse_case(c, spec)) {
            std::fprintf(stderr, "bench_triangulation: bad case '%s' (random-<points>, ico-<level> or grid-<degrees>)\n",
                         c.c_str());
            return 2;
        }
        specs.push_back(spec);
    }
    if (specs.empty()) {
        std::fprintf(stderr, "bench_triangulation: no cases\n");
        return 2;
    }

    const int unimesh_threads[] = {1, 2};

    std::printf("# bench_triangulation: Delaunay triangulation of points on the unit sphere\n");
    std::printf("# unimesh %s (header %s) | CGAL %s Delaunay_triangulation_on_sphere_2, Epick | "
                "Qhull %s \"qhull Qt\"\n",
                um_version_string(), UM_VERSION_STRING, CGAL_VERSION_STR, qh_version);
    std::printf("# hardware threads: %u | random points: normalised 3-D normal deviates, seed 0x%" PRIx64
                " | icosahedral grid: 10*4^L+2 points\n",
                std::thread::hardware_concurrency(), kSeed);
    std::printf("# every run in its own fork()ed child; the methods of a case run by rounds, each once a\n"
                "# round, the first one rotating; seconds = best of 'runs' (construction only);\n"
                "# peak_MB = increase of the child's max RSS from when its input was ready to the end of\n"
                "# the construction (largest over the runs); B/pt = that in bytes per input point;\n"
                "# faults, sys_s = page faults and system time of the construction (the best run);\n"
                "# '# rounds' lines: every run's seconds (u user, s system, qw the threads' wait for a\n"
                "# CPU while ready to run; unimesh: r1 = seconds to the end of its first insertion\n"
                "# round, the set-up before nearly all insertions).\n");
    if (opt.cold)
        std::printf("# --cold: no warm-up run (the first run of a case may meet memory the host took back)\n");
    else
        std::printf("# unimesh and CGAL: an uncounted run before each counted one (see measure_by_rounds())\n");
    std::printf("# methods: unimesh-xyz = um_triangulation_create_xyz; unimesh-lonlat = um_triangulation_create\n"
                "# (lon/lat in degrees); cgal-dtos2 and qhull-Qt are single threaded.\n");
    std::printf("# %-10s %-15s %3s %9s %9s %8s %9s %8s %8s %7s %9s %9s %6s %4s\n", "case", "method", "thr",
                "points", "seconds", "Mpts/s", "peak_MB", "B/pt", "faults", "sys_s", "vertices", "triangles",
                "hidden", "runs");
    std::fflush(stdout);

    bool any_failure = false;
    std::vector<Row> all_rows;
    // For the Qhull skip rule: the largest case Qhull finished (points, seconds).
    int64_t qhull_done_n = 0;
    double qhull_done_s = 0.0;

    for (const CaseSpec &spec : specs) {
        PointSet ps;
        const double g0 = now_seconds();
        std::string error;
        if (!bench::make_points(spec, ps, error)) {
            std::printf("%-12s FAILED to build the grid: %s\n", spec.name.c_str(), error.c_str());
            any_failure = true;
            continue;
        }
        const double g1 = now_seconds();
        if (spec.kind == CaseSpec::icosahedral)
            std::printf("# %s: icosahedral grid level %d, %" PRId64 " points = 10*4^%d+2 (verified), "
                        "%" PRId64 " triangles, made in %.2f s\n",
                        spec.name.c_str(), spec.level, ps.size(), spec.level, 2 * ps.size() - 4, g1 - g0);
        if (spec.kind == CaseSpec::grid)
            std::printf("# %s: longitude-latitude grid of %g degrees with both poles, %" PRId64
                        " points, made in %.2f s (unimesh-lonlat gets the degrees as they are)\n",
                        spec.name.c_str(), spec.step, ps.size(), g1 - g0);
        // Rounds of unimesh and CGAL; Qhull, minutes at 4*10^6 points and not a
        // target, keeps fewer runs.
        const int runs = opt.repeat > 0 ? opt.repeat : (spec.n >= 3000000 ? 3 : 5);
        const int qhull_runs = opt.repeat > 0 ? opt.repeat : (spec.n >= 3000000 ? 1 : 3);
        // (Qhull, not a target and minutes at 4*10^6 points, has no warm-up run.)
        const bool warm_up = !opt.cold;

        std::vector<Row> rows;
        auto add = [&](Row row) {
            print_row(row);
            std::fflush(stdout);
            if (!row.ok && !row.skipped) any_failure = true;
            rows.push_back(row);
            all_rows.push_back(row);
        };

        std::vector<Method> methods;
        for (int t : unimesh_threads)
            methods.push_back({"unimesh-xyz", t, [&ps, t] { return measure_unimesh(ps, t, false); }, false});
        // The C API's call from degrees (the signature), conversion included.
        for (int t : unimesh_threads)
            methods.push_back({"unimesh-lonlat", t, [&ps, t] { return measure_unimesh(ps, t, true); }, false});
        methods.push_back({"cgal-dtos2", 1, [&ps] { return measure_cgal(ps); }});
        const std::vector<Row> by_rounds = measure_by_rounds(spec, methods, runs, opt.timeout, warm_up);
        for (const Row &row : by_rounds) add(row);
        // Every round's time (the rows show the best), with its user and
        // system time: a run slower than the others with as much user time
        // waited on something else (the host, first touches). For unimesh,
        // r1 splits it: the seconds to the end of the first BRIO round, the
        // set-up before nearly all insertions (ChildResult::setup_s).
        for (const Row &row : by_rounds) {
            std::printf("# rounds %s %s/%dT:", spec.name.c_str(), row.method.c_str(), row.threads);
            for (size_t k = 0; k < row.times.size(); ++k) {
                std::printf(" %.4f (u %.3f s %.3f qw %.4f", row.times[k], row.user_times[k],
                            row.system_times[k], row.wait_times[k]);
                if (row.setup_times[k] >= 0) std::printf(" r1 %.4f", row.setup_times[k]);
                std::printf(")");
            }
            std::printf("\n");
        }

        // Qhull: above 1e6 points only when it finishes within the limit; the time is
        // predicted from the largest case it already did (n log n), else bounded by a timeout.
        if (!opt.qhull) {
            // left out
        } else if (spec.n <= 1000000) {
            Row row = measure_by_rounds(spec, {{"qhull-Qt", 1, [&ps] { return measure_qhull(ps); }}}, qhull_runs,
                                        opt.timeout, false)[0];
            if (row.ok && spec.n > qhull_done_n) {
                qhull_done_n = spec.n;
                qhull_done_s = row.seconds;
            }
            add(row);
        } else {
            double predicted = -1.0;
            if (qhull_done_n > 0)
                predicted = qhull_done_s * (double(spec.n) / double(qhull_done_n)) *
                            (std::log(double(spec.n)) / std::log(double(qhull_done_n)));
            if (predicted > opt.qhull_limit) {
                Row row;
                row.case_name = spec.name;
                row.method = "qhull-Qt";
                row.n = spec.n;
                row.skipped = true;
                char buf[200];
                std::snprintf(buf, sizeof buf,
                              "Qhull skipped above 1e6 points: predicted %.0f s > limit %.0f s (--qhull-limit)",
                              predicted, opt.qhull_limit);
                row.note = buf;
                add(row);
            } else {
                const double limit = std::min(opt.qhull_limit, opt.timeout);
                Row row = measure_by_rounds(spec, {{"qhull-Qt", 1, [&ps] { return measure_qhull(ps); }}}, qhull_runs,
                                            limit, false)[0];
                if (row.skipped) {
                    char buf[120];
                    std::snprintf(buf, sizeof buf,
                                  "Qhull skipped above 1e6 points: too slow, did not finish within %g s (--qhull-limit)",
                                  limit);
                    row.note = buf;
                }
                add(row);
            }
        }

        // Consistency of the triangle counts: every point is a vertex, so each
        // method must give 2V-4 triangles, and unimesh must agree with CGAL.
        const Row *cgal = nullptr;
        for (const Row &r : rows)
            if (r.ok && r.method == "cgal-dtos2") cgal = &r;
        std::string line;
        bool mismatch = false;
        const int64_t expected = 2 * spec.n - 4;
        for (const Row &r : rows) {
            if (!r.ok) continue;
            line += " " + r.method + (r.method.rfind("unimesh", 0) == 0 ? "/" + std::to_string(r.threads) + "T" : "") +
                    "=" + std::to_string(r.n_triangles);
            if (r.method.rfind("unimesh", 0) == 0) {
                if (cgal && r.n_triangles != cgal->n_triangles) mismatch = true;
                if (r.n_triangles != expected || r.n_vertices != spec.n) mismatch = true;
            }
        }
        if (cgal && (cgal->n_triangles != expected || cgal->n_vertices != spec.n))
            line += " (CGAL kept " + std::to_string(cgal->n_vertices) + " of " + std::to_string(spec.n) + " points)";
        if (!cgal) line += " (no CGAL count to compare with)";
        if (mismatch) {
            std::printf("MISMATCH %s: triangle counts differ (2V-4 = %" PRId64 "):%s\n", spec.name.c_str(),
                        expected, line.c_str());
            any_failure = true;
        } else {
            std::printf("# check %s: triangles OK, unimesh = CGAL = 2V-4 = %" PRId64 ":%s\n", spec.name.c_str(),
                        expected, line.c_str());
        }
        std::fflush(stdout);
    }

    // Summary: throughput ratios unimesh / CGAL (= CGAL seconds / unimesh seconds).
    std::printf("\n# summary: throughput ratio unimesh / CGAL (CGAL's best time / unimesh's best time; > 1:\n"
                "# unimesh faster); the last column is unimesh (2 threads) / Qhull\n");
    std::printf("# %-10s %9s %14s %14s %16s %16s %14s\n", "case", "points", "xyz 1T/CGAL", "xyz 2T/CGAL",
                "lonlat 1T/CGAL", "lonlat 2T/CGAL", "xyz 2T/Qhull");
    for (const CaseSpec &spec : specs) {
        auto find = [&](const std::string &method, int threads) { return find_row(all_rows, spec, method, threads); };
        auto ratio = [](const Row *ref, const Row *um) {
            char buf[32];
            if (ref && um && um->seconds > 0)
                std::snprintf(buf, sizeof buf, "%.2f", ref->seconds / um->seconds);
            else
                std::snprintf(buf, sizeof buf, "n/a");
            return std::string(buf);
        };
        const Row *cgal = find("cgal-dtos2", 1);
        const Row *qhull = find("qhull-Qt", 1);
        std::printf("  %-10s %9" PRId64 " %14s %14s %16s %16s %14s\n", spec.name.c_str(), spec.n,
                    ratio(cgal, find("unimesh-xyz", 1)).c_str(), ratio(cgal, find("unimesh-xyz", 2)).c_str(),
                    ratio(cgal, find("unimesh-lonlat", 1)).c_str(), ratio(cgal, find("unimesh-lonlat", 2)).c_str(),
                    ratio(qhull, find("unimesh-xyz", 2)).c_str());
    }
    // The same ratios round by round: each from two runs seconds apart.
    std::printf("\n# by rounds: CGAL time / unimesh time of the same round, median [least - greatest]\n"
                "# over the rounds\n");
    std::printf("# %-10s %9s %22s %22s %22s %22s\n", "case", "points", "xyz 1T/CGAL", "xyz 2T/CGAL",
                "lonlat 1T/CGAL", "lonlat 2T/CGAL");
    for (const CaseSpec &spec : specs) {
        auto find = [&](const std::string &method, int threads) { return find_row(all_rows, spec, method, threads); };
        const Row *cgal = find("cgal-dtos2", 1);
        auto spread = [cgal](const Row *um) {
            char buf[48];
            const std::vector<double> ratios = cgal && um ? round_ratios(*cgal, *um) : std::vector<double>();
            if (ratios.empty()) return std::string("n/a");
            const size_t h = ratios.size() / 2;
            const double median = ratios.size() % 2 ? ratios[h] : 0.5 * (ratios[h - 1] + ratios[h]);
            std::snprintf(buf, sizeof buf, "%.2f [%.2f - %.2f]", median, ratios.front(), ratios.back());
            return std::string(buf);
        };
        std::printf("  %-10s %9" PRId64 " %22s %22s %22s %22s\n", spec.name.c_str(), spec.n,
                    spread(find("unimesh-xyz", 1)).c_str(), spread(find("unimesh-xyz", 2)).c_str(),
                    spread(find("unimesh-lonlat", 1)).c_str(), spread(find("unimesh-lonlat", 2)).c_str());
    }
    std::printf("%s\n", any_failure ? "# RESULT: FAILURES (see FAILED / MISMATCH lines above)" : "# RESULT: all runs OK");
    return any_failure ? 1 : 0;
}
