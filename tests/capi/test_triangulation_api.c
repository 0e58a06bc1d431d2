/* CMocka suite: the triangulation through the C ABI, against Qhull's convex
 * hull of the lifted points as an independent reference. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <libqhull_r/qhull_ra.h>

#include "context_fixture.h"
#include "unimesh.h"

#define DEG (180.0 / M_PI)

static uint64_t rng_state = 88172645463325252ull;
static double uniform(void) { /* xorshift64*, deterministic */
    rng_state ^= rng_state >> 12, rng_state ^= rng_state << 25, rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

/* n uniformly random points as lon/lat degrees. */
static void random_lonlat(int64_t n, double *lon, double *lat) {
    for (int64_t i = 0; i < n; ++i) {
        lon[i] = 360.0 * uniform() - 180.0;
        lat[i] = asin(2.0 * uniform() - 1.0) * DEG;
    }
}

static int compare_triples(const void *a, const void *b) {
    const int32_t *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}
static void sort3(int32_t *t) {
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2 - i; ++j)
            if (t[j] > t[j + 1]) { int32_t s = t[j]; t[j] = t[j + 1]; t[j + 1] = s; }
}

/* Triangles of Qhull's hull of the points (xyz, 3 per point), sorted. */
static int64_t qhull_triangles(int64_t n, double *xyz, int32_t *out) {
    qhT qh_storage, *qh = &qh_storage;
    QHULL_LIB_CHECK
    qh_zero(qh, stderr);
    char options[] = "qhull Qt";
    int64_t count = 0;
    int rc = qh_new_qhull(qh, 3, (int)n, xyz, False, options, NULL, stderr);
    assert_int_equal(rc, 0);
    facetT *facet;
    vertexT *vertex, **vertexp;
    FORALLfacets {
        int k = 0;
        FOREACHvertex_(facet->vertices) out[3 * count + k++] = qh_pointid(qh, vertex->point);
        sort3(out + 3 * count);
        ++count;
    }
    int curlong, totlong;
    qh_freeqhull(qh, !qh_ALL);
    qh_memfreeshort(qh, &curlong, &totlong);
    qsort(out, (size_t)count, 3 * sizeof(int32_t), compare_triples);
    return count;
}

/* lon/lat given (the points' degrees); Qhull gets unit vectors made from them through radians. */
static void matches_qhull_at(um_context *ctx, int64_t n, const double *lon, const double *lat,
                             const double *weights) {
    double *xyz = malloc(3 * n * sizeof *xyz);
    for (int64_t i = 0; i < n; ++i) {
        double s = weights ? 1.0 / (1.0 - 0.5 * weights[i]) : 1.0;
        double c = cos(lat[i] / DEG);
        xyz[3 * i] = s * c * cos(lon[i] / DEG);
        xyz[3 * i + 1] = s * c * sin(lon[i] / DEG);
        xyz[3 * i + 2] = s * sin(lat[i] / DEG);
    }
    um_triangulation *t = NULL;
    assert_int_equal(um_triangulation_create(ctx, n, lon, lat, weights, &t), UM_OK);
    assert_int_equal(um_triangulation_check(t), UM_OK);
    int64_t nv = 0, nt = 0, nh = 0;
    assert_int_equal(um_triangulation_counts(t, &nv, &nt, &nh), UM_OK);
    assert_int_equal(nv + nh, n);
    int32_t *ours = malloc(3 * nt * sizeof *ours), *theirs = malloc(6 * n * sizeof *theirs);
    assert_int_equal(um_triangulation_copy_triangles(t, 0, ours, 3 * nt), UM_OK);
    for (int64_t f = 0; f < nt; ++f) sort3(ours + 3 * f);
    qsort(ours, (size_t)nt, 3 * sizeof(int32_t), compare_triples);
    int64_t nq = qhull_triangles(n, xyz, theirs);
    assert_int_equal(nq, nt);
    assert_memory_equal(ours, theirs, 3 * nt * sizeof(int32_t));
    um_triangulation_destroy(t);
    free(ours), free(theirs), free(xyz);
}

static void matches_qhull(um_context *ctx, int64_t n, const double *weights) {
    double *lon = malloc(n * sizeof *lon), *lat = malloc(n * sizeof *lat);
    random_lonlat(n, lon, lat);
    matches_qhull_at(ctx, n, lon, lat, weights);
    free(lon), free(lat);
}

/* Big enough for several BRIO rounds to go the parallel way (rounds of 8192
   points and more are inserted by regions). */
static void same_triangles_as_qhull(void **state) {
    matches_qhull(*state, 100000, NULL);
}

static void same_triangles_as_qhull_with_weights(void **state) {
    const int64_t n = 50000;
    double *w = malloc(n * sizeof *w);
    for (int64_t i = 0; i < n; ++i) w[i] = (uniform() - 0.5) * 4e-3;
    matches_qhull(*state, n, w);
    free(w);
}

/* A 1-degree longitude-latitude grid (64,442 points with the poles) with
   weights of about the spacing squared, which hide some points: its points lie
   on the great circles of edges (meridians), so in the parallel rounds the
   walk that decides edges by the filter alone often ends beside an edge it
   cannot decide, and starts cavities there that bury vertices, which the exact
   path then redoes (Triangulation::walk_filtered). Generic weights leave no
   ties, so Qhull's hull is the same triangulation. */
static void same_triangles_as_qhull_on_a_weighted_grid(void **state) {
    const int64_t n = 179 * 360 + 2;
    double *lon = malloc(n * sizeof *lon), *lat = malloc(n * sizeof *lat), *w = malloc(n * sizeof *w);
    int64_t k = 0;
    lon[k] = 0, lat[k++] = -90;
    for (int row = 1; row < 180; ++row)
        for (int col = 0; col < 360; ++col) lon[k] = col - 180.0, lat[k++] = row - 90.0;
    lon[k] = 0, lat[k++] = 90;
    assert_int_equal(k, n);
    for (int64_t i = 0; i < n; ++i) w[i] = (uniform() - 0.5) * 6e-4;
    matches_qhull_at(*state, n, lon, lat, w);
    free(lon), free(lat), free(w);
}

static void counts_copies_and_base(void **state) {
    um_context *ctx = *state;
    const int64_t n = 1000;
    double lon[1000], lat[1000];
    random_lonlat(n, lon, lat);
    um_triangulation *t = NULL;
    assert_int_equal(um_triangulation_create(ctx, n, lon, lat, NULL, &t), UM_OK);
    int64_t nv, nt, nh;
    assert_int_equal(um_triangulation_counts(t, &nv, &nt, &nh), UM_OK);
    assert_int_equal(nv, n);
    assert_int_equal(nt, 2 * n - 4);
    assert_int_equal(nh, 0);
    int32_t *tri0 = malloc(3 * nt * sizeof(int32_t)), *tri1 = malloc(3 * nt * sizeof(int32_t));
    int32_t *nb = malloc(3 * nt * sizeof(int32_t));
    double *oc = malloc(3 * nt * sizeof(double));
    assert_int_equal(um_triangulation_copy_triangles(t, 0, tri0, 3 * nt), UM_OK);
    assert_int_equal(um_triangulation_copy_triangles(t, 1, tri1, 3 * nt), UM_OK);
    for (int64_t i = 0; i < 3 * nt; ++i) assert_int_equal(tri1[i], tri0[i] + 1);
    assert_int_equal(um_triangulation_copy_neighbours(t, 0, nb, 3 * nt), UM_OK);
    /* neighbour k shares the two vertices other than vertex k */
    for (int64_t f = 0; f < nt; ++f)
        for (int k = 0; k < 3; ++k) {
            int32_t g = nb[3 * f + k], a = tri0[3 * f + (k + 1) % 3], b = tri0[3 * f + (k + 2) % 3];
            int shared = 0;
            for (int m = 0; m < 3; ++m) shared += tri0[3 * g + m] == a || tri0[3 * g + m] == b;
            assert_int_equal(shared, 2);
        }
    assert_int_equal(um_triangulation_copy_orthocentres(t, oc, 3 * nt), UM_OK);
    for (int64_t f = 0; f < nt; ++f)
        assert_true(fabs(oc[3 * f] * oc[3 * f] + oc[3 * f + 1] * oc[3 * f + 1] +
                         oc[3 * f + 2] * oc[3 * f + 2] - 1.0) < 1e-14);
    /* too small buffers, bad base */
    assert_int_equal(um_triangulation_copy_triangles(t, 0, tri0, 3 * nt - 1), UM_ERR_BUFFER_TOO_SMALL);
    assert_non_null(strstr(um_context_last_error(ctx), "capacity"));
    um_context_clear_error(ctx);
    assert_int_equal(um_triangulation_copy_triangles(t, 2, tri0, 3 * nt), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_triangulation_copy_triangles(t, 0, NULL, 3 * nt), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_triangulation_copy_hidden(t, 0, NULL, 0), UM_OK);
    um_triangulation_destroy(t);
    um_triangulation_destroy(t); /* double destroy: ignored */
    assert_int_equal(um_triangulation_counts(t, &nv, &nt, &nh), UM_ERR_INVALID_HANDLE);
    free(tri0), free(tri1), free(nb), free(oc);
}

static void hidden_points_are_listed(void **state) {
    um_context *ctx = *state;
    const int64_t n = 2000;
    double lon[2000], lat[2000], w[2000];
    random_lonlat(n, lon, lat);
    for (int64_t i = 0; i < n; ++i) w[i] = i % 100 == 0 ? -0.5 : 0.0;
    um_triangulation *t = NULL;
    assert_int_equal(um_triangulation_create(ctx, n, lon, lat, w, &t), UM_OK);
    int64_t nv, nt, nh;
    assert_int_equal(um_triangulation_counts(t, &nv, &nt, &nh), UM_OK);
    assert_int_equal(nh, 20);
    int32_t hidden[20];
    assert_int_equal(um_triangulation_copy_hidden(t, 1, hidden, 20), UM_OK);
    for (int i = 0; i < 20; ++i) assert_int_equal(hidden[i], 100 * i + 1);
    assert_int_equal(um_triangulation_copy_hidden(t, 1, hidden, 19), UM_ERR_BUFFER_TOO_SMALL);
    um_triangulation_destroy(t);
}

static void bad_input_is_rejected_with_the_index(void **state) {
    um_context *ctx = *state;
    double lon[100], lat[100], w[100];
    random_lonlat(100, lon, lat);
    um_triangulation *t = (um_triangulation *)&lon; /* must be reset to NULL on failure */
    lat[17] = NAN;
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_ERR_NONFINITE_INPUT);
    assert_null(t);
    assert_non_null(strstr(um_context_last_error(ctx), "lat_deg[17]"));
    um_context_clear_error(ctx);
    lat[17] = 90.5;
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_ERR_COORDINATE_RANGE);
    assert_non_null(strstr(um_context_last_error(ctx), "90.5"));
    um_context_clear_error(ctx);
    lat[17] = 10;
    lon[3] = INFINITY;
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_ERR_NONFINITE_INPUT);
    assert_non_null(strstr(um_context_last_error(ctx), "lon_deg[3]"));
    um_context_clear_error(ctx);
    lon[3] = 20;
    assert_int_equal(um_triangulation_create(ctx, 3, lon, lat, NULL, &t), UM_ERR_TOO_FEW_POINTS);
    assert_int_equal(um_triangulation_create(ctx, -1, lon, lat, NULL, &t), UM_ERR_TOO_FEW_POINTS);
    for (int i = 0; i < 100; ++i) w[i] = 0;
    w[50] = 2.0;
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, w, &t), UM_ERR_INVALID_ARGUMENT);
    w[50] = NAN;
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, w, &t), UM_ERR_NONFINITE_INPUT);
    um_context_clear_error(ctx);
    /* duplicates: the message names both indices */
    lon[60] = lon[20], lat[60] = lat[20];
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_ERR_DUPLICATE_POINTS);
    assert_non_null(strstr(um_context_last_error(ctx), "20"));
    assert_non_null(strstr(um_context_last_error(ctx), "60"));
    um_context_clear_error(ctx);
    /* every longitude at a pole is the same point */
    lat[60] = 90, lat[20] = 90, lon[60] = 10, lon[20] = -100;
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_ERR_DUPLICATE_POINTS);
    um_context_clear_error(ctx);
    /* and longitudes a whole turn apart at one latitude (unimesh.h) */
    const double turn_apart[2][2] = {{-180, 180}, {0, 360}};
    for (int k = 0; k < 2; ++k) {
        lat[20] = lat[60] = 35, lon[20] = turn_apart[k][0], lon[60] = turn_apart[k][1];
        assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_ERR_DUPLICATE_POINTS);
        assert_non_null(strstr(um_context_last_error(ctx), "20"));
        assert_non_null(strstr(um_context_last_error(ctx), "60"));
        um_context_clear_error(ctx);
    }
    lat[60] = 90, lon[60] = 10, lon[20] = -100;
    lat[20] = -90;
    /* one hemisphere */
    double hlon[100], hlat[100];
    for (int i = 0; i < 100; ++i) hlon[i] = 3.6 * i, hlat[i] = 10 + (i % 7);
    assert_int_equal(um_triangulation_create(ctx, 100, hlon, hlat, NULL, &t), UM_ERR_DEGENERATE_INPUT);
    assert_non_null(strstr(um_context_last_error(ctx), "hemisphere"));
    um_context_clear_error(ctx);
    assert_int_equal(um_triangulation_create(ctx, 100, NULL, lat, NULL, &t), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_triangulation_create(NULL, 100, lon, lat, NULL, &t), UM_ERR_NULL_ARGUMENT);
    /* the fixed input works */
    assert_int_equal(um_triangulation_create(ctx, 100, lon, lat, NULL, &t), UM_OK);
    um_triangulation_destroy(t);
}

static void memory_cap_refuses_up_front(void **state) {
    um_context *ctx = *state;
    enum { N = 10000 };
    static double lon[N], lat[N];
    random_lonlat(N, lon, lat);
    assert_int_equal(um_context_set_memory_cap(ctx, 100000), UM_OK);
    um_triangulation *t = NULL;
    assert_int_equal(um_triangulation_create(ctx, N, lon, lat, NULL, &t), UM_ERR_MEMORY_CAP);
    assert_non_null(strstr(um_context_last_error(ctx), "memory cap"));
    assert_int_equal(um_context_set_memory_cap(ctx, 0), UM_OK);
    assert_int_equal(um_triangulation_create(ctx, N, lon, lat, NULL, &t), UM_OK);
    um_triangulation_destroy(t);
}

/* Same bytes out for 1, 2 and 4 threads. */
static void identical_for_any_thread_count(void **state) {
    um_context *ctx = *state;
    const int64_t n = 300000;
    double *lon = malloc(n * sizeof *lon), *lat = malloc(n * sizeof *lat);
    random_lonlat(n, lon, lat);
    int32_t *ref = NULL;
    int64_t nt_ref = 0;
    const int32_t threads[] = {1, 2, 4};
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(um_context_set_threads(ctx, threads[i]), UM_OK);
        um_triangulation *t = NULL;
        assert_int_equal(um_triangulation_create(ctx, n, lon, lat, NULL, &t), UM_OK);
        int64_t nv, nt, nh;
        um_triangulation_counts(t, &nv, &nt, &nh);
        int32_t *tri = malloc(3 * nt * sizeof *tri);
        assert_int_equal(um_triangulation_copy_triangles(t, 0, tri, 3 * nt), UM_OK);
        if (!ref) {
            ref = tri, nt_ref = nt;
        } else {
            assert_int_equal(nt, nt_ref);
            assert_memory_equal(tri, ref, 3 * nt * sizeof *tri);
            free(tri);
        }
        um_triangulation_destroy(t);
    }
    free(ref), free(lon), free(lat);
}

static void xyz_input(void **state) {
    um_context *ctx = *state;
    double xyz[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1}; /* not unit: normalised */
    um_triangulation *t = NULL;
    assert_int_equal(um_triangulation_create_xyz(ctx, 4, xyz, NULL, &t), UM_OK);
    int64_t nv, nt, nh;
    um_triangulation_counts(t, &nv, &nt, &nh);
    assert_int_equal(nt, 4);
    um_triangulation_destroy(t);
    xyz[4] = NAN;
    assert_int_equal(um_triangulation_create_xyz(ctx, 4, xyz, NULL, &t), UM_ERR_NONFINITE_INPUT);
    assert_non_null(strstr(um_context_last_error(ctx), "xyz[4]"));
    xyz[3] = xyz[4] = xyz[5] = 0;
    assert_int_equal(um_triangulation_create_xyz(ctx, 4, xyz, NULL, &t), UM_ERR_INVALID_ARGUMENT);
}

/* The inputs are checked in parallel chunks; the error is still the first
   bad point's, whatever the thread count (the later ones lie in other chunks). */
static void first_bad_point_is_named_on_any_thread_count(void **state) {
    um_context *ctx = *state;
    enum { N = 200000 };
    double *lon = malloc(N * sizeof *lon), *lat = malloc(N * sizeof *lat);
    double *xyz = malloc(3 * N * sizeof *xyz), *w = malloc(N * sizeof *w);
    random_lonlat(N, lon, lat);
    for (int i = 0; i < N; ++i) {
        xyz[3 * i] = cos(lat[i] / DEG) * cos(lon[i] / DEG);
        xyz[3 * i + 1] = cos(lat[i] / DEG) * sin(lon[i] / DEG);
        xyz[3 * i + 2] = sin(lat[i] / DEG);
        w[i] = 0;
    }
    lat[150000] = NAN, lat[70001] = 95, lon[190000] = INFINITY;
    xyz[3 * 180000 + 1] = NAN, xyz[3 * 90000] = xyz[3 * 90000 + 1] = xyz[3 * 90000 + 2] = 0;
    w[120000] = 2.5, w[199999] = NAN;
    for (int threads = 1; threads <= 2; ++threads) {
        assert_int_equal(um_context_set_threads(ctx, threads), UM_OK);
        um_triangulation *t = NULL;
        assert_int_equal(um_triangulation_create(ctx, N, lon, lat, NULL, &t), UM_ERR_COORDINATE_RANGE);
        assert_non_null(strstr(um_context_last_error(ctx), "lat_deg[70001] = 95"));
        um_context_clear_error(ctx);
        assert_int_equal(um_triangulation_create_xyz(ctx, N, xyz, NULL, &t), UM_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(um_context_last_error(ctx), "point 90000 of xyz"));
        um_context_clear_error(ctx);
        xyz[3 * 90000] = 1;
        assert_int_equal(um_triangulation_create_xyz(ctx, N, xyz, w, &t), UM_ERR_NONFINITE_INPUT);
        assert_non_null(strstr(um_context_last_error(ctx), "xyz[540001]"));
        um_context_clear_error(ctx);
        xyz[3 * 180000 + 1] = 0;
        assert_int_equal(um_triangulation_create_xyz(ctx, N, xyz, w, &t), UM_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(um_context_last_error(ctx), "weights[120000] = 2.5"));
        assert_null(t);
        xyz[3 * 90000] = 0, xyz[3 * 180000 + 1] = NAN;
        um_context_clear_error(ctx);
    }
    free(lon), free(lat), free(xyz), free(w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(same_triangles_as_qhull, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(same_triangles_as_qhull_with_weights, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(same_triangles_as_qhull_on_a_weighted_grid, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(counts_copies_and_base, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(hidden_points_are_listed, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(bad_input_is_rejected_with_the_index, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(memory_cap_refuses_up_front, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(identical_for_any_thread_count, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(xyz_input, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(first_bad_point_is_named_on_any_thread_count, setup_context,
                                        teardown_context),
    };
    return cmocka_run_group_tests_name("triangulation_api", tests, NULL, NULL);
}
