// Compares builds of the library in one process: loads each given
// libunimesh.so with dlopen (its own copy of every symbol) and times
// um_triangulation_create_xyz on the same random points, alternating the
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
//   bench_ab POINTS THREADS ROUNDS LIB [LIB ...]
//   e.g. bench_ab 1000000 1 16 /tmp/before/libunimesh.so.0 build/lib/libunimesh.so.0
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

// The C API's entry points of one loaded build (its own um_* symbols).
struct Build {
    std::string path;
    int (*context_create)(void **) = nullptr;
    int (*set_threads)(void *, int32_t) = nullptr;
    int (*create_xyz)(void *, int64_t, const double *, const double *, void **) = nullptr;
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
        !bind(handle, "um_triangulation_destroy", b.destroy))
        return false;
    if (b.context_create(&b.context) != 0 || b.set_threads(b.context, threads) != 0) {
        std::fprintf(stderr, "bench_ab: '%s': no context with %d threads\n", b.path.c_str(), threads);
        return false;
    }
    return true;
}

// One construction; its time in seconds, or a negative number on failure.
double construct(Build &b, const std::vector<double> &xyz) {
    void *tri = nullptr;
    const auto t0 = std::chrono::steady_clock::now();
    const int status = b.create_xyz(b.context, static_cast<int64_t>(xyz.size() / 3), xyz.data(), nullptr, &tri);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (status != 0) return -1;
    b.destroy(tri);
    return s;
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
    if (argc < 5) {
        std::fprintf(stderr, "usage: bench_ab POINTS THREADS ROUNDS LIB [LIB ...]\n");
        return 2;
    }
    const long n = parse(argv[1], "POINTS", 4), threads = parse(argv[2], "THREADS", 1),
               rounds = parse(argv[3], "ROUNDS", 1);
    // Uniform random directions (normalised normal deviates, fixed seed).
    std::vector<double> xyz(3 * static_cast<size_t>(n));
    std::mt19937_64 random(0x756e696d657368);
    std::normal_distribution<double> normal;
    for (long i = 0; i < n; ++i) {
        double x, y, z, r;
        do x = normal(random), y = normal(random), z = normal(random), r = std::sqrt(x * x + y * y + z * z);
        while (r == 0);
        xyz[3 * i] = x / r, xyz[3 * i + 1] = y / r, xyz[3 * i + 2] = z / r;
    }
    std::vector<Build> builds;
    for (int i = 4; i < argc; ++i) builds.push_back(Build{argv[i]});
    for (Build &b : builds)
        if (!load(b, static_cast<int>(threads))) return 1;
    const size_t k = builds.size();
    for (long r = 0; r <= rounds; ++r)  // round 0 warms each build up
        for (size_t i = 0; i < k; ++i) {
            Build &b = builds[(static_cast<size_t>(r) + i) % k];
            const double s = construct(b, xyz);
            if (s < 0) {
                std::fprintf(stderr, "bench_ab: '%s' failed to triangulate\n", b.path.c_str());
                return 1;
            }
            if (r > 0) b.seconds.push_back(s);
        }
    std::printf("# %ld points, %ld threads, %ld rounds (after one warm-up call each)\n", n, threads, rounds);
    for (const Build &b : builds) {
        std::vector<double> ratio;
        for (long r = 0; r < rounds; ++r) ratio.push_back(b.seconds[r] / builds[0].seconds[r]);
        std::printf("%-48s least %.4f s  median %.4f s  median ratio to the first %.3f\n", b.path.c_str(),
                    *std::min_element(b.seconds.begin(), b.seconds.end()), median(b.seconds), median(ratio));
    }
    return 0;
}
