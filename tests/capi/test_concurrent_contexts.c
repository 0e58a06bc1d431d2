/* CMocka suite: independent contexts used from several host threads at
 * once (the header's thread rules). Each thread builds, optimises, reports
 * and writes a mesh with its own context; every thread's mesh must be the
 * one a lone thread makes, bit for bit. Run under ThreadSanitizer by
 * `tools/test.sh --sanitize thread`, this is also the race check of the
 * process-wide parts (handle registry, netCDF lock). */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "unimesh.h"

enum { kThreads = 3 };

typedef struct {
    int index;
    int32_t threads;  /* of the context */
    um_status status;
    int64_t nv, nt;
    double *lon, *lat;
    int32_t *tri;
    char message[256];
} job;

static void *build_mesh(void *arg) {
    job *j = arg;
    um_context *ctx = NULL;
    um_spacing *h = NULL;
    um_features *f = NULL;
    um_mesh *m = NULL;
    j->status = um_context_create(&ctx);
    if (j->status != UM_OK) return NULL;
    um_context_set_threads(ctx, j->threads);
    if ((j->status = um_spacing_create_constant(ctx, 700.0, &h)) == UM_OK &&
        (j->status = um_features_create(ctx, &f)) == UM_OK &&
        (j->status = um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_global_l.geojson", NULL, 0)) == UM_OK &&
        (j->status = um_mesh_refine(ctx, h, f, NULL, &m)) == UM_OK &&
        (j->status = um_mesh_optimise(m, NULL)) == UM_OK &&
        (j->status = um_mesh_counts(m, &j->nv, &j->nt, NULL, NULL)) == UM_OK) {
        j->lon = malloc(j->nv * sizeof(double)), j->lat = malloc(j->nv * sizeof(double));
        j->tri = malloc(3 * j->nt * sizeof(int32_t));
        char path[1024];
        snprintf(path, sizeof path, "%s/concurrent_%d.nc", UNIMESH_TEST_OUTPUT_DIR, j->index);
        int64_t obtuse = 0;
        if ((j->status = um_mesh_copy_vertices(m, j->lon, j->lat, j->nv)) == UM_OK &&
            (j->status = um_mesh_copy_triangles(m, 0, j->tri, 3 * j->nt)) == UM_OK &&
            (j->status = um_mesh_quality_counts(m, &obtuse, NULL)) == UM_OK)
            j->status = um_mesh_write_mpas(m, path);
    }
    if (j->status != UM_OK) snprintf(j->message, sizeof j->message, "%s", um_context_last_error(ctx));
    um_mesh_destroy(m);
    um_features_destroy(f);
    um_spacing_destroy(h);
    um_context_destroy(ctx);
    return NULL;
}

static void contexts_on_several_host_threads(void **state) {
    (void)state;
    job alone = {.index = 9, .threads = 1};
    build_mesh(&alone);
    assert_int_equal(alone.status, UM_OK);
    job jobs[kThreads];
    pthread_t threads[kThreads];
    for (int i = 0; i < kThreads; ++i) {
        memset(&jobs[i], 0, sizeof jobs[i]);
        jobs[i].index = i, jobs[i].threads = 1 + i % 2;
        assert_int_equal(pthread_create(&threads[i], NULL, build_mesh, &jobs[i]), 0);
    }
    for (int i = 0; i < kThreads; ++i) assert_int_equal(pthread_join(threads[i], NULL), 0);
    for (int i = 0; i < kThreads; ++i) {
        if (jobs[i].status != UM_OK) fail_msg("thread %d: status %d: %s", i, jobs[i].status, jobs[i].message);
        assert_int_equal(jobs[i].nv, alone.nv);
        assert_int_equal(jobs[i].nt, alone.nt);
        assert_memory_equal(jobs[i].lon, alone.lon, alone.nv * sizeof(double));
        assert_memory_equal(jobs[i].lat, alone.lat, alone.nv * sizeof(double));
        assert_memory_equal(jobs[i].tri, alone.tri, 3 * alone.nt * sizeof(int32_t));
        free(jobs[i].lon), free(jobs[i].lat), free(jobs[i].tri);
    }
    free(alone.lon), free(alone.lat), free(alone.tri);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(contexts_on_several_host_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
