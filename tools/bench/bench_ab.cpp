// Compares builds of the library in one process: loads each given
// libunimesh.so with dlopen (its own copy of every symbol) and times
// um_triangulation_create_xyz (with --lonlat: um_triangulation_create, the
// same points in degrees) on the same random points, alternating the
// builds call by call (the order rotating each round), after one warm-up
// call each. Prints each build's least and median time and the median of
// its per-round ratio to the first build.
//
// Why: on this machine fresh-process timings of one build spread by 20-40 %
// (first touches of memory, the virtual machine's drift), too much to see a
// change of a few per cent; calls alternated in one process see the same
// conditions. Even so, two copies of the same build differ by up to ~5 %,
// which is the noise floor to quote.
//
// With --fresh, every call runs in a child process of its own (fork(), then
// dlopen there), as a program that triangulates once would: then what a
// change does to first touches of memory shows too, and the builds' medians
// of user time, system time, page faults and peak memory growth (bytes per
// point) are printed as well, with the median per-round ratios of system
// time and page faults to the first build. (Fresh-process times spread
// more: take more rounds.)
//
//   bench_ab [--fresh] [--lonlat] POINTS THREADS ROUNDS LIB [LIB ...]
//   e.g. bench_ab 1000000 1 16 /tmp/before/libunimesh.so.0 build/lib/libunimesh.so.0
// POINTS: a number of random points, or a case of bench_triangulation's
// (point_sets.hpp: random-1e6, ico-9, grid-0.25; --lonlat then passes the
// case's degrees, a grid's as they are). The points are bench_triangulation's
// for the same case.
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "point_sets.hpp"

namespace {

// The C API's entry points of one loaded build (its own um_* symbols).
struct Build {
    std::string path;
    int (*context_create)(void **) = nullptr;
    int (*set_threads)(void *, int32_t) = nullptr;
    int (*create_xyz)(void *, int64_t, const double *, const double *, void **) = nullptr;
    int (*create_lonlat)(void *, int64_t, const double *, const double *, const double *, void **) = nullptr;
    void (*destroy)(void *) = nullptr;
    void *context = nullptr;
    std::vector<double> seconds;
};

template <class Fn>
bool bind(void *handle, const char *name, Fn &fn) {
    fn = reinterpret_cast<Fn>(dlsym(handle, name));
    if (!fn) std::fprintf(stderr, "bench_ab: %s has no %s\n", dlerror(), name);
    return fn != nullptr;
}

bool load(Build &b, int threads) {
    void *handle = dlopen(b.path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        std::fprintf(stderr, "bench_ab: cannot load '%s': %s\n", b.path.c_str(), dlerror());
        return false;
    }
    if (!bind(handle, "um_context_create", b.context_create) ||
        !bind(handle, "um_context_set_threads", b.set_threads) ||
        !bind(handle, "um_triangulation_create_xyz", b.create_xyz) ||
        !bind(handle, "um_triangulation_create", b.create_lonlat) ||
        !bind(handle, "um_triangulation_destroy", b.destroy))
        return false;
    if (b.context_create(&b.context) != 0 || b.set_threads(b.context, threads) != 0) {
        std::fprintf(stderr, "bench_ab: '%s': no context with %d threads\n", b.path.c_str(), threads);
        return false;
    }
    return true;
}

// The points: unit vectors, and (for --lonlat) the same in degrees.
struct Points {
    std::vector<double> xyz, lon, lat;
    int64_t size() const { return static_cast<int64_t>(xyz.size() / 3); }
};

// One construction; its time in seconds, or a negative number on failure.
double construct(Build &b, const Points &points) {
    void *tri = nullptr;
    const int64_t n = points.size();
    const auto t0 = std::chrono::steady_clock::now();
    const int status = points.lon.empty()
                           ? b.create_xyz(b.context, n, points.xyz.data(), nullptr, &tri)
                           : b.create_lonlat(b.context, n, points.lon.data(), points.lat.data(), nullptr, &tri);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (status != 0) return -1;
    b.destroy(tri);
    return s;
}

// One call's measures.
struct Sample {
    double seconds = -1, user = 0, system = 0;
    double faults = 0, bytes_per_point = 0;
};

// One construction by the build at `path`, in a child process that loads it
// (bench::run_in_child): its measures, or seconds < 0 on failure. The parent
// holds no threads (it loads no build in this mode), so fork() is safe.
Sample construct_fresh(const std::string &path, int threads, const Points &points) {
    auto in_child = [&] {
        Build b{path};
        Sample mine;
        if (!load(b, threads)) return mine;
        const bench::Usage before = bench::usage_now();
        mine.seconds = construct(b, points);
        const bench::Usage after = bench::usage_now();
        mine.user = after.user_s - before.user_s;
        mine.system = after.system_s - before.system_s;
        mine.faults = double(after.faults - before.faults);
        mine.bytes_per_point = double(after.maxrss_kb - before.maxrss_kb) * 1024.0 / double(points.size());
        return mine;
    };
    Sample got;
    return bench::run_in_child(in_child, got) == bench::ChildOutcome::ok ? got : Sample();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

long parse(const char *text, const char *what, long least) {
    char *end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (!end || *end || v < least) {
        std::fprintf(stderr, "bench_ab: %s '%s' is not a whole number >= %ld\n", what, text, least);
        std::exit(2);
    }
    return v;
}

}  // namespace

int main(int argc, char **argv) {
    bool fresh = false, lonlat = false;
    for (; argc > 1 && std::strncmp(argv[1], "--", 2) == 0; --argc, ++argv)
        if (std::strcmp(argv[1], "--fresh") == 0)
            fresh = true;
        else if (std::strcmp(argv[1], "--lonlat") == 0)
            lonlat = true;
        else {
            std::fprintf(stderr, "bench_ab: unknown option '%s'\n", argv[1]);
            argc = 0;  // the usage below
            break;
        }
    if (argc < 5) {
        std::fprintf(stderr, "usage: bench_ab [--fresh] [--lonlat] POINTS THREADS ROUNDS LIB [LIB ...]\n");
        return 2;
    }
    const long threads = parse(argv[2], "THREADS", 1), rounds = parse(argv[3], "ROUNDS", 1);
    // A count is the case random-<count>.
    const std::string name = std::strchr(argv[1], '-') ? std::string(argv[1])
                                                        : "random-" + std::to_string(parse(argv[1], "POINTS", 4));
    bench::CaseSpec spec;
    bench::PointSet ps;
    std::string error;
    if (!bench::parse_case(name, spec) || !bench::make_points(spec, ps, error)) {
        std::fprintf(stderr, "bench_ab: POINTS '%s': %s\n", argv[1],
                     error.empty() ? "not a count or a case (random-1e6, ico-9, grid-0.25)" : error.c_str());
        return 2;
    }
    Points points;
    points.xyz = std::move(ps.xyz);
    if (lonlat) points.lon = std::move(ps.lon), points.lat = std::move(ps.lat);
    const long n = static_cast<long>(points.size());
    std::vector<Build> builds;
    for (int i = 4; i < argc; ++i) builds.push_back(Build{argv[i]});
    if (!fresh)
        for (Build &b : builds)
            if (!load(b, static_cast<int>(threads))) return 1;
    const size_t k = builds.size();
    std::vector<std::vector<Sample>> samples(k);
    for (long r = 0; r <= rounds; ++r)  // round 0 warms each build up
        for (size_t i = 0; i < k; ++i) {
            const size_t at = (static_cast<size_t>(r) + i) % k;
            Build &b = builds[at];
            Sample sample;
            if (fresh)
                sample = construct_fresh(b.path, static_cast<int>(threads), points);
            else
                sample.seconds = construct(b, points);
            if (sample.seconds < 0) {
                std::fprintf(stderr, "bench_ab: '%s' failed to triangulate\n", b.path.c_str());
                return 1;
            }
            if (r > 0) b.seconds.push_back(sample.seconds), samples[at].push_back(sample);
        }
    std::printf("# %ld points%s, %ld threads, %ld rounds (after one warm-up call each)%s\n", n,
                lonlat ? " (lon/lat)" : "", threads, rounds, fresh ? ", every call in a fresh process" : "");
    // The median over the rounds of a measure, and of its ratio to the first build's.
    auto of = [&](size_t i, double Sample::*field) {
        std::vector<double> v;
        for (const Sample &x : samples[i]) v.push_back(x.*field);
        return median(v);
    };
    // (Rounds where the first build's value is 0 - system time, in clock
    // ticks, at small sizes - give no ratio; NaN, printed so, if none does.)
    auto ratio_of = [&](size_t i, double Sample::*field) {
        std::vector<double> v;
        for (long r = 0; r < rounds; ++r) {
            const double first = samples[0][r].*field;
            if (first > 0) v.push_back(samples[i][r].*field / first);
        }
        return v.empty() ? std::nan("") : median(v);
    };
    for (size_t i = 0; i < k; ++i) {
        const Build &b = builds[i];
        std::printf("%-48s least %.4f s  median %.4f s  median ratio to the first %.3f\n", b.path.c_str(),
                    *std::min_element(b.seconds.begin(), b.seconds.end()), median(b.seconds),
                    ratio_of(i, &Sample::seconds));
        if (fresh)
            std::printf("%-48s medians: user %.4f s, system %.4f s (ratio %.3f), page faults %.0f (ratio %.3f), "
                        "%.1f B/pt\n",
                        "", of(i, &Sample::user), of(i, &Sample::system), ratio_of(i, &Sample::system),
                        of(i, &Sample::faults), ratio_of(i, &Sample::faults), of(i, &Sample::bytes_per_point));
    }
    return 0;
}
