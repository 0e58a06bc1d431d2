/* CMocka suite: the bad-input matrix of the hardening issue, one row per
 * class, through the C ABI. Every row must give a status of the right band
 * (um_status_class), a kept message naming the argument or the value, and
 * leave the caller's objects as they were (counts checked before and
 * after); the suite runs under AddressSanitizer/LeakSanitizer in
 * `tools/test.sh --sanitize address`, which also proves nothing leaks. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "unimesh.h"

typedef struct {
    um_context *ctx;
    um_features *f;  /* holds one good part: must keep it */
    um_spacing *h;   /* 500 km */
    um_mesh *m;      /* refined from h */
} fixture;

static int setup(void **state) {
    fixture *x = calloc(1, sizeof *x);
    if (um_context_create(&x->ctx) != UM_OK) return -1;
    um_features_create(x->ctx, &x->f);
    double lon[3] = {0, 10, 20}, lat[3] = {0, 5, 0};
    int64_t off[2] = {0, 3};
    int32_t closed = 0, kind = UM_FEATURE_RIVER;
    if (um_features_add(x->f, 3, lon, lat, 1, off, &closed, &kind, NULL) != UM_OK) return -1;
    if (um_spacing_create_constant(x->ctx, 500.0, &x->h) != UM_OK) return -1;
    if (um_mesh_refine(x->ctx, x->h, NULL, NULL, &x->m) != UM_OK) return -1;
    *state = x;
    return 0;
}

static int teardown(void **state) {
    fixture *x = *state;
    um_mesh_destroy(x->m);
    um_spacing_destroy(x->h);
    um_features_destroy(x->f);
    um_context_destroy(x->ctx);
    free(x);
    return 0;
}

/* The row's status must be in band (class) and the message must hold word. */
static void expect(fixture *x, const char *row, um_status s, int32_t band, const char *word) {
    if (um_status_class(s) != band)
        fail_msg("%s: status %d (class %d), expected class %d; message: %s", row, s, um_status_class(s), band,
                 um_context_last_error(x->ctx));
    if (word && !strstr(um_context_last_error(x->ctx), word))
        fail_msg("%s: message '%s' does not name '%s'", row, um_context_last_error(x->ctx), word);
    um_context_clear_error(x->ctx);
}

static void features_unchanged(fixture *x, const char *row) {
    int64_t parts = 0, points = 0;
    assert_int_equal(um_features_counts(x->f, &parts, &points, NULL), UM_OK);
    if (parts != 1 || points != 3) fail_msg("%s: features changed (%lld parts)", row, (long long)parts);
}

static double nan_spacing(void *user, double lon, double lat) {
    (void)user, (void)lon, (void)lat;
    return NAN;
}

static const char *write_file(const char *name, const char *text) {
    static char path[1024];
    snprintf(path, sizeof path, "%s/%s", UNIMESH_TEST_OUTPUT_DIR, name);
    FILE *f = fopen(path, "wb");
    fputs(text, f);
    fclose(f);
    return path;
}

static int32_t add_part(fixture *x, int n, const double *lon, const double *lat, int32_t closed) {
    int64_t off[2] = {0, n};
    int32_t kind = UM_FEATURE_COASTLINE;
    return um_features_add(x->f, n, lon, lat, 1, off, &closed, &kind, NULL);
}

/* Coordinates and point sets. */
static void coordinates(void **state) {
    fixture *x = *state;
    double lon[3] = {0, NAN, 2}, lat[3] = {0, 1, 2};
    expect(x, "1 NaN coordinate", add_part(x, 3, lon, lat, 0), UM_ERR_INPUT, "lon_deg[1]");
    features_unchanged(x, "1");
    double lon_inf[2] = {0, INFINITY}, lat2[2] = {0, 1};
    expect(x, "2 Inf coordinate", add_part(x, 2, lon_inf, lat2, 0), UM_ERR_INPUT, "inf");
    double lon3[2] = {0, 1}, lat_out[2] = {0, 91};
    expect(x, "3 |lat| > 90", add_part(x, 2, lon3, lat_out, 0), UM_ERR_INPUT, "91");
    int64_t off[2] = {0, 0};
    int32_t closed = 0, kind = UM_FEATURE_RIVER;
    expect(x, "4 empty part", um_features_add(x->f, 0, lon3, lat2, 1, off, &closed, &kind, NULL), UM_ERR_INPUT,
           "part 0");
    double one_lon[1] = {3}, one_lat[1] = {4};
    expect(x, "5 one-point part", add_part(x, 1, one_lon, one_lat, 0), UM_ERR_INPUT, "part 0");
    double dup_lon[2] = {5, 5}, dup_lat[2] = {6, 6};
    expect(x, "6 zero-length part (all duplicates)", add_part(x, 2, dup_lon, dup_lat, 0), UM_ERR_INPUT, "part 0");
    features_unchanged(x, "1-6");

    um_triangulation *t = NULL;
    double tl[5] = {0, 90, 180, -90, 0}, tb[5] = {0, 0, 0, 0, 0};
    expect(x, "7 duplicate points", um_triangulation_create(x->ctx, 5, tl, tb, NULL, &t), UM_ERR_INPUT, "point");
    assert_null(t);
    double gl[4] = {0, 90, 180, -90}, gb[4] = {0, 0, 0, 0};
    expect(x, "8 all points on one great circle", um_triangulation_create(x->ctx, 4, gl, gb, NULL, &t),
           UM_ERR_INPUT, NULL);
    assert_null(t);
}

/* Lines that must work: restricted meshing filters them. */
static void awkward_lines_work(void **state) {
    fixture *x = *state;
    um_features *g = NULL;
    assert_int_equal(um_features_create(x->ctx, &g), UM_OK);
    double bow_lon[5] = {0, 20, 20, 0, 0}, bow_lat[5] = {0, 20, 0, 20, 0};          /* 9 self-intersecting */
    double dup_lon[3] = {0, 20, 0}, dup_lat[3] = {0, 20, 0};                        /* 10 overlapping itself */
    double touch_lon[4] = {40, 60, 60, 40}, touch_lat[4] = {0, 0, 20, 0};           /* 11 touches at a vertex */
    double pole_lon[4] = {0, 0, 180, 180}, pole_lat[4] = {60, 90, 90, 60};          /* 12 through a pole */
    const double *lons[4] = {bow_lon, dup_lon, touch_lon, pole_lon}, *lats[4] = {bow_lat, dup_lat, touch_lat, pole_lat};
    const int n[4] = {5, 3, 4, 4};
    for (int i = 0; i < 4; ++i) {
        int64_t off[2] = {0, n[i]};
        int32_t closed = i == 2, kind = UM_FEATURE_COASTLINE;
        assert_int_equal(um_features_add(g, n[i], lons[i], lats[i], 1, off, &closed, &kind, NULL), UM_OK);
    }
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_constant(x->ctx, 400.0, &h), UM_OK);
    assert_int_equal(um_mesh_refine(x->ctx, h, g, NULL, &m), UM_OK);
    assert_int_equal(um_mesh_optimise(m, NULL), UM_OK);
    int64_t nv = 0, nt = 0;
    um_mesh_counts(m, &nv, &nt, NULL, NULL);
    assert_int_equal(nt, 2 * nv - 4);
    um_mesh_destroy(m);
    um_spacing_destroy(h);
    um_features_destroy(g);
}

/* Spacings. */
static void spacings(void **state) {
    fixture *x = *state;
    um_spacing *h = NULL;
    expect(x, "13 spacing <= 0", um_spacing_create_constant(x->ctx, 0.0, &h), UM_ERR_USAGE, "0");
    expect(x, "14 spacing NaN", um_spacing_create_constant(x->ctx, NAN, &h), UM_ERR_INPUT, "nan");
    expect(x, "15 spacing Inf", um_spacing_create_constant(x->ctx, INFINITY, &h), UM_ERR_INPUT, "inf");
    double lon[3] = {0, 10, 5}, lat[2] = {0, 10}, w[6] = {1, 1, 1, 1, 1, 1};
    expect(x, "16 descending grid coordinates", um_spacing_create_grid(x->ctx, 3, lon, 2, lat, w, &h), UM_ERR_USAGE,
           "lon_deg");
    double dlon[3] = {0, 10, 10};
    expect(x, "17 duplicate grid coordinates", um_spacing_create_grid(x->ctx, 3, dlon, 2, lat, w, &h), UM_ERR_USAGE,
           "lon_deg");
    double ok_lon[3] = {0, 10, 20}, bad_w[6] = {1, 1, NAN, 1, 1, 1};
    expect(x, "18 NaN grid cell", um_spacing_create_grid(x->ctx, 3, ok_lon, 2, lat, bad_w, &h), UM_ERR_INPUT, NULL);
    expect(x, "19 grid of the wrong shape", um_spacing_create_grid(x->ctx, 1, ok_lon, 2, lat, w, &h), UM_ERR_USAGE,
           "n_lon");
    assert_null(h);
    assert_int_equal(um_spacing_create_callback(x->ctx, nan_spacing, NULL, &h), UM_OK);
    um_mesh *m = NULL;
    expect(x, "20 callback returning NaN", um_mesh_refine(x->ctx, h, NULL, NULL, &m), UM_ERR_INPUT, "lon");
    assert_null(m);
    um_spacing_destroy(h);
}

/* Options, handles, order, buffers. */
static void usage(void **state) {
    fixture *x = *state;
    um_options *o = NULL;
    assert_int_equal(um_options_create(x->ctx, &o), UM_OK);
    expect(x, "21 option out of range", um_options_set_double(o, UM_OPT_REFINE_RHO, 0.5), UM_ERR_USAGE, "refine_rho");
    expect(x, "22 unknown option name", um_options_set_string(o, "optim_speed=11"), UM_ERR_USAGE, "optim_speed");
    um_options_destroy(o);
    expect(x, "23 destroyed handle", um_mesh_optimise(x->m, o), UM_ERR_USAGE, "options");
    expect(x, "24 null handle", um_mesh_counts(NULL, NULL, NULL, NULL, NULL), UM_ERR_USAGE, NULL);
    um_mesh *dead = NULL;
    um_mesh_refine(x->ctx, x->h, NULL, NULL, &dead);
    um_mesh_destroy(dead);
    expect(x, "25 use after destroy", um_mesh_write_mpas(dead, "x.nc"), UM_ERR_USAGE, NULL);
    /* 26 message buffers of size 0 and 1 */
    int32_t small[1];
    um_mesh_copy_triangles(x->m, 0, small, 1);
    char one[1] = {'x'};
    int64_t needed = 0;
    assert_int_equal(um_context_copy_last_error(x->ctx, NULL, 0, &needed), UM_ERR_BUFFER_TOO_SMALL);
    assert_true(needed > 1);
    assert_int_equal(um_context_copy_last_error(x->ctx, one, 1, &needed), UM_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(one[0], '\0');
    um_context_clear_error(x->ctx);
    int32_t tri[3];
    expect(x, "27 output buffer too small", um_mesh_copy_triangles(x->m, 0, tri, 3), UM_ERR_USAGE, "triangles");
}

/* Files and limits. */
static void files_and_limits(void **state) {
    fixture *x = *state;
    const char *truncated = write_file("matrix_truncated.geojson", "{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1");
    expect(x, "28 truncated GeoJSON", um_features_read_geojson(x->f, truncated, NULL, 0), UM_ERR_IO,
           "matrix_truncated.geojson");
    const char *malformed = write_file("matrix_malformed.geojson", "{\"type\": \"Feature\", \"properties\": {\"kind\": \"river\"}, "
                                       "\"geometry\": {\"type\": \"LineString\", \"coordinates\": \"east\"}}");
    expect(x, "29 malformed GeoJSON", um_features_read_geojson(x->f, malformed, NULL, 0), UM_ERR_IO,
           "matrix_malformed.geojson");
    features_unchanged(x, "28-29");
    um_spacing *h = NULL;
    const char *not_nc = write_file("matrix_not_netcdf.nc", "CDF\001 this is not netCDF");
    expect(x, "30 malformed netCDF", um_spacing_create_from_file(x->ctx, not_nc, &h), UM_ERR_IO, "matrix_not_netcdf.nc");
    expect(x, "31 missing file", um_spacing_create_from_file(x->ctx, "/no/such/file.nc", &h), UM_ERR_IO, "/no/such");
    expect(x, "31a netCDF header with impossible counts (fuzzing)",
           um_spacing_create_from_file(x->ctx, UNIMESH_TEST_DATA_DIR "/netcdf_huge_counts.nc", &h), UM_ERR_IO,
           "malformed");
    expect(x, "31b netCDF header with an over-long name (fuzzing)",
           um_spacing_create_from_file(x->ctx, UNIMESH_TEST_DATA_DIR "/netcdf_long_name.nc", &h), UM_ERR_IO,
           "name of 1536 bytes");
    assert_null(h);
    assert_int_equal(um_context_set_memory_cap(x->ctx, 64 << 20), UM_OK);
    assert_int_equal(um_spacing_create_constant(x->ctx, 2.0, &h), UM_OK);
    um_mesh *m = NULL;
    expect(x, "32 memory cap the request would exceed", um_mesh_refine(x->ctx, h, NULL, NULL, &m), UM_ERR_OUT_OF_MEMORY,
           "MiB");
    assert_null(m);
    um_context_set_memory_cap(x->ctx, 0);
    um_spacing_destroy(h);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(coordinates, setup, teardown),
        cmocka_unit_test_setup_teardown(awkward_lines_work, setup, teardown),
        cmocka_unit_test_setup_teardown(spacings, setup, teardown),
        cmocka_unit_test_setup_teardown(usage, setup, teardown),
        cmocka_unit_test_setup_teardown(files_and_limits, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
