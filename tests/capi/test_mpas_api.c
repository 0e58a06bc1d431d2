/* CMocka suite: MPAS output through the C ABI (um_mesh_write_mpas).
 *
 * Meshes from um_mesh_refine (constant spacing, and the shipped GSHHG
 * coastlines) are written and read back with netCDF-C. When the shared
 * checker (../shared/tools/mpas_check.py, with /usr/bin/python3, numpy and
 * netCDF4) is beside the project, every file must pass it at its default
 * strict tolerances; without it that part is skipped. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>
#include <netcdf.h>

#include "unimesh.h"

static const char *const kPython = "/usr/bin/python3";
static const char *const kChecker = UNIMESH_SHARED_DIR "/tools/mpas_check.py";

static int setup_context(void **state) {
    um_context *ctx = NULL;
    if (um_context_create(&ctx) != UM_OK) return -1;
    *state = ctx;
    return 0;
}
static int teardown_context(void **state) {
    um_context_destroy((um_context *)*state);
    return 0;
}

static void output_path(char *buf, size_t size, const char *name) {
    snprintf(buf, size, "%s/%s", UNIMESH_TEST_OUTPUT_DIR, name);
}

static um_mesh *refine(um_context *ctx, double km, const char *geojson) {
    um_spacing *h = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, km, &h), UM_OK);
    um_features *f = NULL;
    if (geojson) {
        assert_int_equal(um_features_create(ctx, &f), UM_OK);
        assert_int_equal(um_features_read_geojson(f, geojson, NULL, 0), UM_OK);
    }
    um_mesh *m = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, f, NULL, &m), UM_OK);
    um_features_destroy(f);
    um_spacing_destroy(h);
    return m;
}

/* Runs the shared checker on path and echoes its lines; it must exit 0. */
static void run_checker(const char *path) {
    if (access(kPython, X_OK) != 0 || access(kChecker, R_OK) != 0 ||
        system("/usr/bin/python3 -c 'import numpy, netCDF4' >/dev/null 2>&1") != 0) {
        printf("mpas_check.py or its python modules not found: checker skipped for %s\n", path);
        return;
    }
    char command[4096];
    snprintf(command, sizeof command, "%s %s %s 2>&1", kPython, kChecker, path);
    FILE *out = popen(command, "r");
    assert_non_null(out);
    char line[1024];
    while (fgets(line, sizeof line, out)) printf("  %s", line);
    int status = pclose(out);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
}

static size_t dim_length(int nc, const char *name) {
    int id = -1;
    size_t n = 0;
    assert_int_equal(nc_inq_dimid(nc, name, &id), NC_NOERR);
    assert_int_equal(nc_inq_dimlen(nc, id, &n), NC_NOERR);
    return n;
}

/* The file has the mesh's cells and vertices, 1-based connectivity, and the
 * side tags where the mesh has them. */
static void check_file(const char *path, um_mesh *m) {
    int64_t nv = 0, nt = 0;
    assert_int_equal(um_mesh_counts(m, &nv, &nt, NULL, NULL), UM_OK);
    int nc = -1, format = 0;
    assert_int_equal(nc_open(path, NC_NOWRITE, &nc), NC_NOERR);
    assert_int_equal(nc_inq_format(nc, &format), NC_NOERR);
    assert_int_equal(format, NC_FORMAT_64BIT_OFFSET);
    assert_int_equal(dim_length(nc, "nCells"), (size_t)nv);
    assert_int_equal(dim_length(nc, "nVertices"), (size_t)nt);
    assert_int_equal(dim_length(nc, "nEdges"), (size_t)(3 * nt / 2));
    size_t n_edges = dim_length(nc, "nEdges");
    int var = -1;
    int *coe = malloc(2 * n_edges * sizeof(int));
    assert_int_equal(nc_inq_varid(nc, "cellsOnEdge", &var), NC_NOERR);
    assert_int_equal(nc_get_var_int(nc, var, coe), NC_NOERR);
    for (size_t i = 0; i < 2 * n_edges; ++i) assert_true(coe[i] >= 1 && coe[i] <= nv);
    free(coe);
    /* Cell sides as the mesh reports them per vertex, in some order: compare counts. */
    int32_t *sides = malloc(nv * sizeof(int32_t));
    int *file_sides = malloc(nv * sizeof(int));
    assert_int_equal(um_mesh_copy_vertex_sides(m, sides, nv), UM_OK);
    assert_int_equal(nc_inq_varid(nc, "cellSide", &var), NC_NOERR);
    assert_int_equal(nc_get_var_int(nc, var, file_sides), NC_NOERR);
    int64_t count[3] = {0, 0, 0}, file_count[3] = {0, 0, 0};
    for (int64_t i = 0; i < nv; ++i) ++count[sides[i]], ++file_count[file_sides[i]];
    for (int k = 0; k < 3; ++k) assert_int_equal(count[k], file_count[k]);
    free(sides), free(file_sides);
    assert_int_equal(nc_inq_varid(nc, "vertexSide", &var), NC_NOERR);
    assert_int_equal(nc_close(nc), NC_NOERR);
}

static void uniform_500km(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 500.0, NULL);
    char path[2048];
    output_path(path, sizeof path, "test_mpas_uniform_500km.nc");
    assert_int_equal(um_mesh_write_mpas(m, path), UM_OK);
    check_file(path, m);
    run_checker(path);
    um_mesh_destroy(m);
}

static void global_coastline_480km(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 480.0, UNIMESH_DATA_DIR "/coast_global_l.geojson");
    char path[2048];
    output_path(path, sizeof path, "test_mpas_coast_480km.nc");
    assert_int_equal(um_mesh_write_mpas(m, path), UM_OK);
    check_file(path, m);
    run_checker(path);
    um_mesh_destroy(m);
}

static char *read_file(const char *path, long *size) {
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *data = malloc(*size > 0 ? *size : 1);
    assert_int_equal(fread(data, 1, *size, f), (size_t)*size);
    fclose(f);
    return data;
}

static void same_bytes_for_any_thread_count(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 700.0, NULL);
    char path1[2048], path2[2048];
    output_path(path1, sizeof path1, "test_mpas_threads_1.nc");
    output_path(path2, sizeof path2, "test_mpas_threads_2.nc");
    assert_int_equal(um_context_set_threads(ctx, 1), UM_OK);
    assert_int_equal(um_mesh_write_mpas(m, path1), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, 2), UM_OK);
    assert_int_equal(um_mesh_write_mpas(m, path2), UM_OK);
    long n1 = 0, n2 = 0;
    char *a = read_file(path1, &n1), *b = read_file(path2, &n2);
    assert_int_equal(n1, n2);
    assert_memory_equal(a, b, n1);
    free(a), free(b);
    remove(path1), remove(path2);
    um_mesh_destroy(m);
}

static int32_t cancel_at_half(void *user, const char *stage, double fraction) {
    (void)stage;
    ++*(int *)user;
    return fraction >= 0.5;
}

static void misuse_and_errors(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 900.0, NULL);
    char path[2048];
    output_path(path, sizeof path, "test_mpas_misuse.nc");
    assert_int_equal(um_mesh_write_mpas(NULL, path), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_mesh_write_mpas((const um_mesh *)ctx, path), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_mesh_write_mpas(m, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_mesh_write_mpas(m, ""), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "path"));
    um_context_clear_error(ctx);

    /* An unwritable place: UM_ERR_IO, the message names the file. */
    char bad[2048];
    output_path(bad, sizeof bad, "no/such/directory/mesh.nc");
    assert_int_equal(um_mesh_write_mpas(m, bad), UM_ERR_IO);
    assert_int_equal(um_context_last_status(ctx), UM_ERR_IO);
    assert_non_null(strstr(um_context_last_error(ctx), bad));
    um_context_clear_error(ctx);

    /* Cancelled before writing: no file. */
    int calls = 0;
    remove(path);
    assert_int_equal(um_context_set_progress(ctx, cancel_at_half, &calls), UM_OK);
    assert_int_equal(um_mesh_write_mpas(m, path), UM_CANCELLED);
    assert_true(calls >= 2);
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(um_context_set_progress(ctx, NULL, NULL), UM_OK);
    um_context_clear_error(ctx);

    /* The mesh outlives its context. */
    um_mesh_destroy(m);
    assert_int_equal(um_mesh_write_mpas(m, path), UM_ERR_INVALID_HANDLE);
}

static void mesh_outlives_context(void **state) {
    (void)state;
    um_context *ctx = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    um_mesh *m = refine(ctx, 1200.0, NULL);
    um_context_destroy(ctx);
    char path[2048];
    output_path(path, sizeof path, "test_mpas_orphan.nc");
    assert_int_equal(um_mesh_write_mpas(m, path), UM_OK);
    remove(path);
    um_mesh_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(uniform_500km, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(global_coastline_480km, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(same_bytes_for_any_thread_count, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(misuse_and_errors, setup_context, teardown_context),
        cmocka_unit_test(mesh_outlives_context),
    };
    return cmocka_run_group_tests_name("mpas_api", tests, NULL, NULL);
}
