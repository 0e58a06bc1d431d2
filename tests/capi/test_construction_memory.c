/* CMocka suite: the triangulation issue's memory target - a construction
 * grows the process's peak resident size by at most 120 bytes per point (the
 * triangulation it returns included).
 *
 * One configuration per run, given on the command line ("xyz 1": from unit
 * vectors on one thread; "lonlat 2": from lon/lat on two, the worst case in
 * bench_triangulation), each a ctest of its own: a fresh process whose peak
 * no earlier test raised and whose worker threads are started by this
 * construction (in a child forked after TBB had started them, the child has
 * TBB's state but not its threads, and would run on one). Skipped under the
 * sanitizers, whose shadow memory and allocators count too
 * (UNIMESH_SANITIZED, set by CMake). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include <cmocka.h>

#include "unimesh.h"

#define DEG (180.0 / M_PI)

static int from_lonlat = 0;
static int threads = 1;

static uint64_t rng_state = 88172645463325252ull;
static double uniform(void) { /* xorshift64*, deterministic */
    rng_state ^= rng_state >> 12, rng_state ^= rng_state << 25, rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

/* The process's threads now (/proc/self/status), or -1. */
static int thread_count(void) {
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return -1;
    char line[256];
    int count = -1;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "Threads:", 8) == 0) count = atoi(line + 8);
    fclose(f);
    return count;
}

/* The transparent huge page mode, for the message of a failure (with
   "always" the kernel may back any large allocation in 2 MB steps). */
static void print_huge_page_mode(void) {
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    char line[128] = "unknown";
    if (f) {
        if (!fgets(line, sizeof line, f)) strcpy(line, "unknown");
        fclose(f);
    }
    printf("transparent huge pages: %s", line);
}

static void construction_stays_within_120_bytes_per_point(void **state) {
    (void)state;
#if defined(UNIMESH_SANITIZED) || defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    skip();
#else
    enum { N = 300000 };
    double *lon = malloc(N * sizeof *lon), *lat = malloc(N * sizeof *lat), *xyz = malloc(3 * N * sizeof *xyz);
    assert_non_null(lon), assert_non_null(lat), assert_non_null(xyz);
    for (int64_t i = 0; i < N; ++i) {
        lon[i] = 360.0 * uniform() - 180.0;
        lat[i] = asin(2.0 * uniform() - 1.0) * DEG;
        const double phi = lat[i] / DEG, lambda = lon[i] / DEG;
        xyz[3 * i] = cos(phi) * cos(lambda), xyz[3 * i + 1] = cos(phi) * sin(lambda), xyz[3 * i + 2] = sin(phi);
    }
    um_context *ctx = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, threads), UM_OK);
    struct rusage before, after;
    um_triangulation *t = NULL;
    getrusage(RUSAGE_SELF, &before);
    const um_status st = from_lonlat ? um_triangulation_create(ctx, N, lon, lat, NULL, &t)
                                     : um_triangulation_create_xyz(ctx, N, xyz, NULL, &t);
    getrusage(RUSAGE_SELF, &after);
    assert_int_equal(st, UM_OK);
    const long long bytes_per_point = (long long)(after.ru_maxrss - before.ru_maxrss) * 1024 / N;
    const int running = thread_count();
    printf("construction from %s on %d threads (%d running): peak grew by %lld bytes per point\n",
           from_lonlat ? "lon/lat" : "xyz", threads, running, bytes_per_point);
    if (bytes_per_point > 120) print_huge_page_mode();
    /* The threads asked for did run (a second thread's stack and heap count). */
    assert_true(running < 0 || running >= threads);
    assert_true(bytes_per_point > 0 && bytes_per_point <= 120);
    um_triangulation_destroy(t);
    um_context_destroy(ctx);
    free(lon), free(lat), free(xyz);
#endif
}

int main(int argc, char **argv) {
    if (argc != 3 || (strcmp(argv[1], "xyz") != 0 && strcmp(argv[1], "lonlat") != 0) ||
        (threads = atoi(argv[2])) < 1) {
        fprintf(stderr, "usage: test_construction_memory xyz|lonlat THREADS\n");
        return 2;
    }
    from_lonlat = strcmp(argv[1], "lonlat") == 0;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(construction_stays_within_120_bytes_per_point),
    };
    return cmocka_run_group_tests_name("construction memory", tests, NULL, NULL);
}
