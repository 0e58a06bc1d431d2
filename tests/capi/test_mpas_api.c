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
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>
#include <netcdf.h>

#include "context_fixture.h"
#include "mpas_checker.h"
#include "unimesh.h"


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

/* Every variable of the file at path, copied out of m through the C API,
 * is the same: reals bit for bit, indices with base 1. */
static void expect_copy_out_equals_file(um_mesh *m, const char *path) {
    int nc = -1, n_vars = 0;
    assert_int_equal(nc_open(path, NC_NOWRITE, &nc), NC_NOERR);
    assert_int_equal(nc_inq_nvars(nc, &n_vars), NC_NOERR);
    int checked = 0;
    for (int var = 0; var < n_vars; ++var) {
        char name[NC_MAX_NAME + 1];
        nc_type type;
        int n_dims, dims[NC_MAX_VAR_DIMS];
        assert_int_equal(nc_inq_var(nc, var, name, &type, &n_dims, dims, NULL), NC_NOERR);
        size_t n = 1;
        for (int d = 0; d < n_dims; ++d) {
            size_t len;
            nc_inq_dimlen(nc, dims[d], &len);
            n *= len;
        }
        int32_t kind = 0;
        int64_t rows = 0, columns = 0;
        assert_int_equal(um_mesh_mpas_variable(m, name, &kind, &rows, &columns), UM_OK);
        assert_int_equal((size_t)(rows * columns), n);
        if (type == NC_DOUBLE) {
            assert_int_equal(kind, UM_MPAS_REAL);
            double *file = malloc(n * sizeof(double)), *copy = malloc(n * sizeof(double));
            assert_int_equal(nc_get_var_double(nc, var, file), NC_NOERR);
            assert_int_equal(um_mesh_copy_mpas_real(m, name, copy, (int64_t)n), UM_OK);
            if (memcmp(file, copy, n * sizeof(double)) != 0) fail_msg("%s differs from the file", name);
            free(file), free(copy);
        } else {
            assert_int_equal(kind, UM_MPAS_INT);
            int *file = malloc(n * sizeof(int));
            int32_t *copy = malloc(n * sizeof(int32_t));
            assert_int_equal(nc_get_var_int(nc, var, file), NC_NOERR);
            assert_int_equal(um_mesh_copy_mpas_int(m, name, 1, copy, (int64_t)n), UM_OK);
            for (size_t i = 0; i < n; ++i)
                if (file[i] != copy[i]) fail_msg("%s[%zu]: file %d, copy %d", name, i, file[i], copy[i]);
            free(file), free(copy);
        }
        ++checked;
    }
    nc_close(nc);
    assert_true(checked > 40);
}

/* Every variable of the written file, copied out through the C API, is the
 * same (reals bit for bit, indices with base 1); the tags hold their
 * promises: masks complement each other, every restricted edge carries its
 * feature, rivers and only rivers have a downstream direction. */
static void copy_out_matches_the_file(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 480.0, UNIMESH_DATA_DIR "/coast_global_l.geojson");
    assert_int_equal(um_mesh_optimise(m, NULL), UM_OK);
    char path[2048];
    output_path(path, sizeof path, "test_mpas_copy_out.nc");
    assert_int_equal(um_mesh_write_mpas(m, path), UM_OK);

    expect_copy_out_equals_file(m, path);

    int64_t n_cells = 0, n_edges = 0, n_restricted = 0;
    assert_int_equal(um_mesh_mpas_dimensions(m, &n_cells, &n_edges, NULL, NULL), UM_OK);
    assert_int_equal(um_mesh_counts(m, NULL, NULL, &n_restricted, NULL), UM_OK);
    int32_t *ocean = malloc(n_cells * sizeof(int32_t)), *land = malloc(n_cells * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_mpas_int(m, "cellOceanMask", 0, ocean, n_cells), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "cellLandMask", 0, land, n_cells), UM_OK);
    int64_t n_ocean = 0;
    for (int64_t c = 0; c < n_cells; ++c) {
        assert_int_equal(ocean[c] + land[c], 1);
        n_ocean += ocean[c];
    }
    assert_true(n_ocean > n_cells / 2 && n_ocean < n_cells);
    int32_t *kind = malloc(n_edges * sizeof(int32_t)), *down = malloc(n_edges * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_mpas_int(m, "edgeFeatureKind", 0, kind, n_edges), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "edgeRiverDownstream", 0, down, n_edges), UM_OK);
    int64_t tagged = 0;
    for (int64_t e = 0; e < n_edges; ++e) {
        tagged += kind[e] != 0;
        assert_int_equal(down[e] != 0, kind[e] == UM_FEATURE_RIVER);
    }
    assert_int_equal(tagged, n_restricted);
    /* 0-based copies: indices one less, padding -1. */
    int64_t max_edges = 0;
    um_mesh_mpas_dimensions(m, NULL, NULL, NULL, &max_edges);
    int32_t *one = malloc(n_cells * max_edges * sizeof(int32_t)), *zero = malloc(n_cells * max_edges * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_mpas_int(m, "edgesOnCell", 1, one, n_cells * max_edges), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "edgesOnCell", 0, zero, n_cells * max_edges), UM_OK);
    for (int64_t i = 0; i < n_cells * max_edges; ++i) assert_int_equal(zero[i], one[i] - 1);

    /* Misuse: unknown names, the other type, short buffers, bad bases. */
    double x = 0;
    assert_int_equal(um_mesh_copy_mpas_real(m, "noSuchVariable", &x, 1), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "noSuchVariable"));
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_copy_mpas_real(m, "cellsOnEdge", &x, 1), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "um_mesh_copy_mpas_int"));
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_copy_mpas_real(m, "areaCell", &x, 1), UM_ERR_BUFFER_TOO_SMALL);
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_copy_mpas_int(m, "cellsOnEdge", 2, zero, 1), UM_ERR_INVALID_ARGUMENT);
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_mpas_variable(m, NULL, NULL, NULL, NULL), UM_ERR_NULL_ARGUMENT);
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_release_mpas(m), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_real(m, "areaCell", &x, 1), UM_ERR_BUFFER_TOO_SMALL); /* rebuilt */
    um_context_clear_error(ctx);
    free(ocean), free(land), free(kind), free(down), free(one), free(zero);
    um_mesh_destroy(m);
    assert_int_equal(um_mesh_release_mpas(m), UM_ERR_INVALID_HANDLE);
    um_context_clear_error(ctx);
}

/* The copy-out makes each variable a block of rows at a time, never the
 * whole staggered mesh: a mesh of several blocks of every kind (uniform 60
 * km, about 164,000 cells and 492,000 edges; blocks of 65,536 rows) copies
 * out every variable as the file holds it under a memory cap of half what
 * the whole staggered mesh would need (1.6 kB per cell). */
static void copy_out_in_blocks_under_a_cap(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 60.0, NULL);
    char path[2048];
    output_path(path, sizeof path, "test_mpas_copy_out_blocks.nc");
    assert_int_equal(um_mesh_write_mpas(m, path), UM_OK);
    int64_t n_cells = 0, n_edges = 0;
    assert_int_equal(um_mesh_mpas_dimensions(m, &n_cells, &n_edges, NULL, NULL), UM_OK);
    assert_true(n_cells > 2 * 65536 && n_edges > 6 * 65536);
    assert_int_equal(um_mesh_release_mpas(m), UM_OK);
    assert_int_equal(um_context_set_memory_cap(ctx, 800 * n_cells), UM_OK);
    expect_copy_out_equals_file(m, path);
    /* The file's writer is judged by its own estimate (two blocks of every
     * kind), whether or not the copy-out's numbering is kept. */
    assert_int_equal(um_mesh_write_mpas(m, path), UM_ERR_MEMORY_CAP);
    um_context_clear_error(ctx);
    assert_int_equal(um_context_set_memory_cap(ctx, 0), UM_OK);
    um_mesh_destroy(m);
    remove(path);
}

static char *read_whole_file(const char *path, long *size) {
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *bytes = malloc((size_t)*size + 1);
    assert_non_null(bytes);
    assert_int_equal(fread(bytes, 1, (size_t)*size, f), (size_t)*size);
    fclose(f);
    return bytes;
}

/* JIGSAW's .msh: the points, weights and triangles of the mesh, counted as
 * the mesh counts them; unwritable paths refused with UM_ERR_IO. */
static void jigsaw_file(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 900.0, NULL);
    int64_t nv = 0, nt = 0;
    assert_int_equal(um_mesh_counts(m, &nv, &nt, NULL, NULL), UM_OK);
    char path[2048];
    output_path(path, sizeof path, "test_jigsaw.msh");
    assert_int_equal(um_mesh_write_jigsaw(m, path), UM_OK);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[512];
    long long points = -1, powers = -1, triangles = -1, lines = 0;
    while (fgets(line, sizeof line, f)) {
        ++lines;
        sscanf(line, "POINT=%lld", &points);
        sscanf(line, "POWER=%lld", &powers);
        sscanf(line, "TRIA3=%lld", &triangles);
    }
    fclose(f);
    assert_int_equal(points, nv);
    assert_int_equal(powers, nv);
    assert_int_equal(triangles, nt);
    assert_int_equal(lines, 1 + 3 + nv + 1 + nv + 1 + nt);
    /* Every point on the sphere of the mesh's radius, its numbers with a
     * decimal point whatever the host's locale: with a comma locale set
     * (where the machine has one), the file is byte for byte the same. */
    f = fopen(path, "r");
    assert_non_null(f);
    for (int i = 0; i < 4; ++i) assert_non_null(fgets(line, sizeof line, f));
    for (long long i = 0; i < nv; ++i) {
        assert_non_null(fgets(line, sizeof line, f));
        assert_null(strchr(line, ','));
        double x, y, z;
        assert_int_equal(sscanf(line, "%lf;%lf;%lf;0", &x, &y, &z), 3);
        assert_true(fabs(sqrt(x * x + y * y + z * z) / 6371220.0 - 1) < 1e-12);
    }
    long size = 0;
    char *first = read_whole_file(path, &size);
    const char *comma_locales[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8", "nl_NL.UTF-8"};
    const char *set = NULL;
    for (size_t i = 0; i < sizeof comma_locales / sizeof comma_locales[0] && !set; ++i)
        set = setlocale(LC_NUMERIC, comma_locales[i]);
    if (set) {
        assert_int_equal(um_mesh_write_jigsaw(m, path), UM_OK);
        setlocale(LC_NUMERIC, "C");
        long again = 0;
        char *second = read_whole_file(path, &again);
        assert_int_equal(again, size);
        assert_memory_equal(first, second, (size_t)size);
        free(second);
    } else {
        print_message("no comma locale on this machine: the file's numbers checked in the C locale only\n");
    }
    free(first);
    assert_int_equal(um_mesh_write_jigsaw(m, "/no/such/dir/x.msh"), UM_ERR_IO);
    assert_non_null(strstr(um_context_last_error(ctx), "/no/such/dir/x.msh"));
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_write_jigsaw(m, ""), UM_ERR_INVALID_ARGUMENT);
    um_context_clear_error(ctx);
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

/* Bytes of a file (malloc'd; *n its size), or NULL. */
static unsigned char *slurp(const char *path, long *n) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)*n + 1);
    if (fread(b, 1, (size_t)*n, f) != (size_t)*n) *n = -1;
    fclose(f);
    return b;
}

/* Entries of the output directory whose names start with prefix. */
static int entries_starting(const char *prefix) {
    DIR *d = opendir(UNIMESH_TEST_OUTPUT_DIR);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));) n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    if (d) closedir(d);
    return n;
}

/* A write that fails half way (the file-size limit of a child process:
 * EFBIG, as a full disk gives ENOSPC) leaves the old file at the path
 * byte for byte and no temporary file; a FIFO or a device at the path is
 * refused and stays. Both writers. */
/* The file is streamed a block of rows at a time with progress between
 * blocks: cancelled part-way (after the cell and edge blocks of a small
 * mesh), the file already at path is kept byte for byte and no temporary
 * file is left. */
static void cancel_part_way_keeps_the_old_file(void **state) {
    um_context *ctx = *state;
    um_mesh *old_mesh = refine(ctx, 900.0, NULL), *m = refine(ctx, 700.0, NULL);
    char path[2048];
    output_path(path, sizeof path, "test_mpas_cancel.nc");
    assert_int_equal(um_mesh_write_mpas(old_mesh, path), UM_OK);
    long n_before = 0, n_after = 0;
    unsigned char *before = slurp(path, &n_before);
    int calls = 0;
    assert_int_equal(um_context_set_progress(ctx, cancel_at_half, &calls), UM_OK);
    assert_int_equal(um_mesh_write_mpas(m, path), UM_CANCELLED);
    assert_true(calls >= 3);  /* the start, then blocks: cancelled after the first block */
    assert_int_equal(um_context_set_progress(ctx, NULL, NULL), UM_OK);
    um_context_clear_error(ctx);
    unsigned char *after = slurp(path, &n_after);
    assert_int_equal(n_before, n_after);
    assert_memory_equal(before, after, (size_t)n_before);
    assert_int_equal(entries_starting(".test_mpas_cancel.nc"), 0);
    free(before), free(after);
    remove(path);
    um_mesh_destroy(old_mesh), um_mesh_destroy(m);
}

/* Every variable of two files, read as doubles, is the same. */
static void expect_same_variables(const char *path_a, const char *path_b) {
    int a = -1, b = -1, n_vars = 0, n_vars_b = 0;
    assert_int_equal(nc_open(path_a, NC_NOWRITE, &a), NC_NOERR);
    assert_int_equal(nc_open(path_b, NC_NOWRITE, &b), NC_NOERR);
    assert_int_equal(nc_inq_nvars(a, &n_vars), NC_NOERR);
    assert_int_equal(nc_inq_nvars(b, &n_vars_b), NC_NOERR);
    assert_int_equal(n_vars, n_vars_b);
    for (int var = 0; var < n_vars; ++var) {
        char name[NC_MAX_NAME + 1];
        int n_dims, dims[NC_MAX_VAR_DIMS], var_b = -1;
        assert_int_equal(nc_inq_var(a, var, name, NULL, &n_dims, dims, NULL), NC_NOERR);
        assert_int_equal(nc_inq_varid(b, name, &var_b), NC_NOERR);
        size_t n = 1;
        for (int d = 0; d < n_dims; ++d) {
            size_t len;
            assert_int_equal(nc_inq_dimlen(a, dims[d], &len), NC_NOERR);
            n *= len;
        }
        double *va = malloc((n + 1) * sizeof(double)), *vb = malloc((n + 1) * sizeof(double));
        assert_int_equal(nc_get_var_double(a, var, va), NC_NOERR);
        assert_int_equal(nc_get_var_double(b, var_b, vb), NC_NOERR);
        assert_memory_equal(va, vb, n * sizeof(double));
        free(va), free(vb);
    }
    char id_a[16] = {0}, id_b[16] = {0};
    assert_int_equal(nc_get_att_text(a, NC_GLOBAL, "file_id", id_a), NC_NOERR);
    assert_int_equal(nc_get_att_text(b, NC_GLOBAL, "file_id", id_b), NC_NOERR);
    assert_string_equal(id_a, id_b);
    assert_int_equal(nc_close(a), NC_NOERR);
    assert_int_equal(nc_close(b), NC_NOERR);
}

/* netCDF-4 on request: the same variables and file_id as the automatic
 * (classic) file, the same bytes for 1 and 2 threads, valid for the
 * independent checker; a format that is neither is refused by name. */
static void netcdf4_on_request(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 480.0, UNIMESH_DATA_DIR "/coast_global_l.geojson");
    char classic[2048], path1[2048], path2[2048];
    output_path(classic, sizeof classic, "test_mpas_auto.nc");
    output_path(path1, sizeof path1, "test_mpas_netcdf4_1.nc");
    output_path(path2, sizeof path2, "test_mpas_netcdf4_2.nc");
    assert_int_equal(um_mesh_write_mpas_as(m, classic, UM_MPAS_FILE_AUTO), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, 1), UM_OK);
    assert_int_equal(um_mesh_write_mpas_as(m, path1, UM_MPAS_FILE_NETCDF4), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, 2), UM_OK);
    assert_int_equal(um_mesh_write_mpas_as(m, path2, UM_MPAS_FILE_NETCDF4), UM_OK);
    int nc = -1, format = 0;
    assert_int_equal(nc_open(path1, NC_NOWRITE, &nc), NC_NOERR);
    assert_int_equal(nc_inq_format(nc, &format), NC_NOERR);
    assert_int_equal(format, NC_FORMAT_NETCDF4);
    assert_int_equal(nc_close(nc), NC_NOERR);
    expect_same_variables(classic, path1);
    long n1 = 0, n2 = 0;
    unsigned char *a = slurp(path1, &n1), *b = slurp(path2, &n2);
    assert_int_equal(n1, n2);
    assert_memory_equal(a, b, (size_t)n1);
    free(a), free(b);
    run_checker(path1);

    for (int32_t bad = -1; bad <= 2; bad += 3) {
        assert_int_equal(um_mesh_write_mpas_as(m, path1, bad), UM_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(um_context_last_error(ctx), "format"));
        um_context_clear_error(ctx);
    }
    remove(classic), remove(path1), remove(path2);
    assert_int_equal(entries_starting(".test_mpas_netcdf4"), 0);
    um_mesh_destroy(m);
}

static void failed_writes_keep_the_old_file(void **state) {
    um_context *ctx = *state;
    um_mesh *m = refine(ctx, 900.0, NULL);
    const char *names[2] = {"test_mpas_keep.nc", "test_mpas_keep.msh"};
    for (int w = 0; w < 2; ++w) {
        char path[2048];
        output_path(path, sizeof path, names[w]);
        um_status (*write)(const um_mesh *, const char *) = w == 0 ? um_mesh_write_mpas : um_mesh_write_jigsaw;
        assert_int_equal(write(m, path), UM_OK);
        long n_before = 0, n_after = 0;
        unsigned char *before = slurp(path, &n_before);
        assert_non_null(before);
        assert_true(n_before > 8192);
        pid_t pid = fork();
        if (pid == 0) {
            signal(SIGXFSZ, SIG_IGN);
            struct rlimit limit = {4096, 4096};
            setrlimit(RLIMIT_FSIZE, &limit);
            const um_status s = write(m, path);
            const int named = strstr(um_context_last_error(ctx), path) != NULL;
            _exit(s == UM_ERR_IO && named ? 0 : 1);
        }
        int status = -1;
        waitpid(pid, &status, 0);
        assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
        unsigned char *after = slurp(path, &n_after);
        assert_non_null(after);
        assert_int_equal(n_after, n_before);
        assert_memory_equal(after, before, (size_t)n_before);
        char prefix[256];
        snprintf(prefix, sizeof prefix, ".%s.part-", names[w]);
        assert_int_equal(entries_starting(prefix), 0);
        free(before), free(after);
        remove(path);

        char fifo[2048];
        output_path(fifo, sizeof fifo, "test_mpas_fifo");
        remove(fifo);
        assert_int_equal(mkfifo(fifo, 0600), 0);
        assert_int_equal(write(m, fifo), UM_ERR_IO);
        assert_non_null(strstr(um_context_last_error(ctx), "not a regular file"));
        um_context_clear_error(ctx);
        struct stat st;
        assert_int_equal(stat(fifo, &st), 0);
        assert_true(S_ISFIFO(st.st_mode));
        remove(fifo);
        assert_int_equal(write(m, "/dev/null"), UM_ERR_IO);
        um_context_clear_error(ctx);
        assert_int_equal(stat("/dev/null", &st), 0);
        assert_true(S_ISCHR(st.st_mode));
    }
    um_mesh_destroy(m);
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
        cmocka_unit_test_setup_teardown(copy_out_matches_the_file, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(copy_out_in_blocks_under_a_cap, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(netcdf4_on_request, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(cancel_part_way_keeps_the_old_file, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(jigsaw_file, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(misuse_and_errors, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(failed_writes_keep_the_old_file, setup_context, teardown_context),
        cmocka_unit_test(mesh_outlives_context),
    };
    return cmocka_run_group_tests_name("mpas_api", tests, NULL, NULL);
}
