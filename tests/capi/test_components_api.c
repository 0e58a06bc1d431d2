/* CMocka suite: component meshes, coupler grids and river routing through the
 * C ABI (um_mesh_write_components, um_mpas_file_write_components,
 * um_mesh_river_report_json).
 *
 * A unified mesh of the shipped GSHHG coastlines and rivers is split into its
 * ocean and land meshes; the files are read back with netCDF-C: the
 * components partition the base (each cell once, areas adding up to the
 * sphere), the maps round-trip, each component passes the shared checker
 * when it is beside the project. The river routing is followed cell by cell,
 * and planted networks (one with a cycle, one that never reaches the coast)
 * must be reported. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>
#include <netcdf.h>

#include "context_fixture.h"
#include "mpas_checker.h"
#include "unimesh.h"


/* A fresh directory under the build tree. */
static void output_dir(char *buf, size_t size, const char *name) {
    snprintf(buf, size, "%s/%s", UNIMESH_TEST_OUTPUT_DIR, name);
    mkdir(buf, 0755);
}

static um_mesh *unified_mesh(um_context *ctx, double km) {
    um_spacing *h = NULL;
    um_features *f = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, km, &h), UM_OK);
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_global_l.geojson", NULL, 0), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/rivers_global_l.geojson", NULL, 0), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, f, NULL, &m), UM_OK);
    assert_int_equal(um_mesh_optimise(m, NULL), UM_OK);
    um_features_destroy(f);
    um_spacing_destroy(h);
    return m;
}

/* ------------------------------------------------------------- netCDF reads */

typedef struct {
    size_t n_cells, n_edges, n_vertices, max_edges;
    double radius;
    int *cells_on_edge, *cells_on_cell, *n_edges_on_cell, *boundary_vertex;
    double *area_cell;
} Mesh;

static int *ints(int nc, const char *name, size_t n) {
    int var = -1;
    int *out = malloc(n * sizeof(int));
    assert_int_equal(nc_inq_varid(nc, name, &var), NC_NOERR);
    assert_int_equal(nc_get_var_int(nc, var, out), NC_NOERR);
    return out;
}

static double *reals(int nc, const char *name, size_t n) {
    int var = -1;
    double *out = malloc(n * sizeof(double));
    assert_int_equal(nc_inq_varid(nc, name, &var), NC_NOERR);
    assert_int_equal(nc_get_var_double(nc, var, out), NC_NOERR);
    return out;
}

static int open_nc(const char *dir, const char *name) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    int nc = -1;
    assert_int_equal(nc_open(path, NC_NOWRITE, &nc), NC_NOERR);
    return nc;
}

static Mesh read_mesh(int nc) {
    Mesh m;
    m.n_cells = dim_length(nc, "nCells"), m.n_edges = dim_length(nc, "nEdges");
    m.n_vertices = dim_length(nc, "nVertices"), m.max_edges = dim_length(nc, "maxEdges");
    assert_int_equal(nc_get_att_double(nc, NC_GLOBAL, "sphere_radius", &m.radius), NC_NOERR);
    m.cells_on_edge = ints(nc, "cellsOnEdge", 2 * m.n_edges);
    m.cells_on_cell = ints(nc, "cellsOnCell", m.n_cells * m.max_edges);
    m.n_edges_on_cell = ints(nc, "nEdgesOnCell", m.n_cells);
    m.boundary_vertex = ints(nc, "boundaryVertex", m.n_vertices);
    m.area_cell = reals(nc, "areaCell", m.n_cells);
    return m;
}

static void free_mesh(Mesh *m) {
    free(m->cells_on_edge), free(m->cells_on_cell), free(m->n_edges_on_cell), free(m->boundary_vertex);
    free(m->area_cell);
}

/* The shared checker on dir/name (mpas_checker.h). */
static void check_file(const char *dir, const char *name) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    run_checker(path);
}

/* The component's map back (base*Id) and the base's map forward (ocean*Id,
 * land*Id) are inverse: element i of the component is base element b, and
 * the base says b is element i there. */
static void maps_round_trip(int base, int part, const char *dim, const char *back, const char *forward) {
    const size_t n = dim_length(part, dim), n_base = dim_length(base, dim);
    int *to_base = ints(part, back, n), *to_part = ints(base, forward, n_base);
    size_t mapped = 0;
    for (size_t i = 0; i < n; ++i) {
        assert_true(to_base[i] >= 1 && (size_t)to_base[i] <= n_base);
        assert_int_equal(to_part[to_base[i] - 1], (int)(i + 1));
    }
    for (size_t b = 0; b < n_base; ++b) mapped += to_part[b] != 0;
    assert_int_equal(mapped, n);
    free(to_base), free(to_part);
}

static long double area_sum(const Mesh *m) {
    long double sum = 0;
    for (size_t c = 0; c < m->n_cells; ++c) sum += m->area_cell[c];
    return sum;
}

/* Every connectivity of a component is in range; cellsOnEdge(1) is never
 * missing; the boundary is marked. */
static void check_boundary(const Mesh *m) {
    size_t cut = 0, marked = 0;
    for (size_t e = 0; e < m->n_edges; ++e) {
        assert_true(m->cells_on_edge[2 * e] >= 1 && (size_t)m->cells_on_edge[2 * e] <= m->n_cells);
        assert_true(m->cells_on_edge[2 * e + 1] >= 0 && (size_t)m->cells_on_edge[2 * e + 1] <= m->n_cells);
        cut += m->cells_on_edge[2 * e + 1] == 0;
    }
    for (size_t v = 0; v < m->n_vertices; ++v) marked += m->boundary_vertex[v];
    assert_true(cut > 0);
    assert_true(marked >= cut / 2);
}

static void components_partition_the_base(void **state) {
    um_context *ctx = *state;
    um_mesh *m = unified_mesh(ctx, 240.0);
    char dir[4096];
    output_dir(dir, sizeof dir, "components_240km");
    assert_int_equal(um_mesh_write_components(m, dir), UM_OK);

    int base = open_nc(dir, "mesh.nc"), ocean = open_nc(dir, "ocean.nc"), land = open_nc(dir, "land.nc");
    Mesh b = read_mesh(base), o = read_mesh(ocean), l = read_mesh(land);
    assert_int_equal(o.n_cells + l.n_cells, b.n_cells);
    int *ocean_id = ints(base, "oceanCellId", b.n_cells), *land_id = ints(base, "landCellId", b.n_cells);
    for (size_t c = 0; c < b.n_cells; ++c) assert_int_equal((ocean_id[c] != 0) + (land_id[c] != 0), 1);
    free(ocean_id), free(land_id);
    const long double sphere = 4.0L * acosl(-1.0L) * b.radius * b.radius;
    const double relative = (double)fabsl((area_sum(&o) + area_sum(&l)) / sphere - 1);
    printf("components: ocean %zu cells, land %zu; areas add up to the sphere to %.2e\n", o.n_cells, l.n_cells,
           relative);
    assert_true(relative < 1e-12);
    const char *dims[3] = {"nCells", "nEdges", "nVertices"}, *kinds[3] = {"Cell", "Edge", "Vertex"};
    for (int k = 0; k < 3; ++k) {
        char back[64], to_ocean[64], to_land[64];
        snprintf(back, sizeof back, "base%sId", kinds[k]);
        snprintf(to_ocean, sizeof to_ocean, "ocean%sId", kinds[k]);
        snprintf(to_land, sizeof to_land, "land%sId", kinds[k]);
        maps_round_trip(base, ocean, dims[k], back, to_ocean);
        maps_round_trip(base, land, dims[k], back, to_land);
    }
    check_boundary(&o);
    check_boundary(&l);
    free_mesh(&b), free_mesh(&o), free_mesh(&l);
    nc_close(base), nc_close(ocean), nc_close(land);
    check_file(dir, "ocean.nc");
    check_file(dir, "land.nc");
    check_file(dir, "mesh.nc");
    um_mesh_destroy(m);
}

/* ------------------------------------------------------------ river routing */

static char *river_report(um_mesh *m) {
    int64_t needed = 0;
    assert_int_equal(um_mesh_river_report_json(m, NULL, 0, &needed), UM_ERR_BUFFER_TOO_SMALL);
    char *text = malloc((size_t)needed);
    assert_int_equal(um_mesh_river_report_json(m, text, needed, NULL), UM_OK);
    return text;
}

static long json_count(const char *json, const char *key) {
    char pattern[128];
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    const char *at = strstr(json, pattern);
    assert_non_null(at);
    return strtol(at + strlen(pattern), NULL, 10);
}

/* Follows every river cell downstream: each path ends, within nCells steps,
 * at an outlet beside an ocean cell, or the cell is in a network the report
 * lists as reaching no coast. */
static void every_river_cell_drains(um_mesh *m, long *routed, long *inland) {
    int64_t n = 0, max_edges = 0;
    assert_int_equal(um_mesh_mpas_dimensions(m, &n, NULL, NULL, &max_edges), UM_OK);
    int32_t *kind = malloc(n * sizeof(int32_t)), *down = malloc(n * sizeof(int32_t));
    int32_t *ocean = malloc(n * sizeof(int32_t)), *around = malloc(n * max_edges * sizeof(int32_t));
    int32_t *count = malloc(n * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_mpas_int(m, "riverCellKind", 0, kind, n), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "downstreamCell", 0, down, n), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "cellOceanMask", 0, ocean, n), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "cellsOnCell", 0, around, n * max_edges), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "nEdgesOnCell", 0, count, n), UM_OK);
    *routed = *inland = 0;
    for (int64_t c = 0; c < n; ++c) {
        if (kind[c] == 0) {
            assert_int_equal(down[c], -1);
            continue;
        }
        assert_int_equal(ocean[c], 0); /* rivers are routed on the land mesh */
        if (kind[c] == 3) {
            assert_int_equal(down[c], -1);
            ++*inland;
            continue;
        }
        int64_t at = c, steps = 0;
        while (kind[at] == 1 && steps++ <= n) {
            assert_true(down[at] >= 0 && down[at] < n);
            at = down[at];
        }
        assert_int_equal(kind[at], 2);
        assert_int_equal(down[at], -1);
        int beside_ocean = 0;
        for (int j = 0; j < count[at]; ++j) beside_ocean |= ocean[around[at * max_edges + j]] == 1;
        assert_true(beside_ocean);
        ++*routed;
    }
    free(kind), free(down), free(ocean), free(around), free(count);
}

static void rivers_of_the_main_job_drain_to_the_coast(void **state) {
    um_context *ctx = *state;
    um_mesh *m = unified_mesh(ctx, 120.0);
    long routed = 0, inland = 0;
    every_river_cell_drains(m, &routed, &inland);
    char *json = river_report(m);
    printf("120 km: %ld river cells drain to an outlet, %ld in networks with no coast\n  %.300s\n", routed, inland,
           json);
    assert_true(routed > 100);
    assert_int_equal(json_count(json, "inland_cells"), inland);
    assert_int_equal(json_count(json, "routed_cells") + json_count(json, "outlets"), routed);
    free(json);
    um_mesh_destroy(m);
}

/* The shipped coastlines with two planted rivers: an open one in central
 * Australia and a closed ring in the Sahara, both far from any coast. */
static um_mesh *planted_rivers(um_context *ctx) {
    um_spacing *h = NULL;
    um_features *f = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 150.0, &h), UM_OK);
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_global_l.geojson", NULL, 0), UM_OK);
    const double lon[] = {124, 128, 132, 136, 5, 15, 15, 5};
    const double lat[] = {-24, -23.5, -24.5, -24, 18, 18, 26, 26};
    const int64_t offsets[] = {0, 4, 8};
    const int32_t closed[] = {0, 1}, kind[] = {UM_FEATURE_RIVER, UM_FEATURE_RIVER}, id[] = {9001, 9002};
    assert_int_equal(um_features_add(f, 8, lon, lat, 2, offsets, closed, kind, id), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, f, NULL, &m), UM_OK);
    um_features_destroy(f);
    um_spacing_destroy(h);
    return m;
}

static void inland_ends_and_cycles_are_reported(void **state) {
    um_context *ctx = *state;
    um_mesh *m = planted_rivers(ctx);
    long routed = 0, inland = 0;
    every_river_cell_drains(m, &routed, &inland);
    char *json = river_report(m);
    printf("planted: %s", json);
    assert_int_equal(routed, 0);
    assert_true(inland > 10);
    assert_int_equal(json_count(json, "networks"), 2);
    assert_int_equal(json_count(json, "outlets"), 0);
    /* Both networks are listed as inland; the ring, in the Sahara, has a cycle. */
    const char *inland_list = strstr(json, "\"inland_networks\": [");
    const char *cycles_list = strstr(json, "\"networks_with_cycles\": [");
    assert_non_null(inland_list), assert_non_null(cycles_list);
    int listed = 0;
    for (const char *at = strstr(inland_list, "{\"network\""); at && at < cycles_list; at = strstr(at + 1, "{\"network\""))
        ++listed;
    assert_int_equal(listed, 2);
    const char *ring = strstr(cycles_list, "{\"network\"");
    assert_non_null(ring);
    double lat = 0, lon = 0;
    assert_non_null(strstr(ring, "\"lat\": "));
    lat = strtod(strstr(ring, "\"lat\": ") + 7, NULL), lon = strtod(strstr(ring, "\"lon\": ") + 7, NULL);
    assert_true(lat > 16 && lat < 28 && lon > 3 && lon < 17);
    assert_true(json_count(ring, "cycles") >= 1);
    free(json);
    um_mesh_destroy(m);
}

/* ------------------------------------------------- files, bytes and errors */

static char *file_bytes(const char *dir, const char *name, size_t *size) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    char *bytes = malloc(*size + 1);
    assert_int_equal(fread(bytes, 1, *size, f), *size);
    fclose(f);
    return bytes;
}

static void same_file(const char *dir_a, const char *dir_b, const char *name) {
    size_t na = 0, nb = 0;
    char *a = file_bytes(dir_a, name, &na), *b = file_bytes(dir_b, name, &nb);
    if (na != nb || memcmp(a, b, na) != 0) fail_msg("%s differs between %s and %s", name, dir_a, dir_b);
    free(a), free(b);
}

static void copy_file(const char *from, const char *to) {
    size_t n = 0;
    FILE *in = fopen(from, "rb");
    assert_non_null(in);
    fseek(in, 0, SEEK_END);
    n = (size_t)ftell(in);
    fseek(in, 0, SEEK_SET);
    char *bytes = malloc(n);
    assert_int_equal(fread(bytes, 1, n, in), n);
    fclose(in);
    FILE *out = fopen(to, "wb");
    assert_non_null(out);
    assert_int_equal(fwrite(bytes, 1, n, out), n);
    fclose(out);
    free(bytes);
}

static const char *const kFiles[] = {"mesh.nc",        "ocean.nc",      "land.nc",       "ocean.graph.info",
                                     "land.graph.info", "mesh.scrip.nc", "ocean.scrip.nc", "land.scrip.nc",
                                     "mesh.esmf.nc",    "ocean.esmf.nc", "land.esmf.nc",  "rivers.json"};

/* From the mesh in memory with 1 and 3 threads, and from its mesh.nc: the
 * same bytes in every file. */
static void same_files_from_memory_file_and_any_thread_count(void **state) {
    um_context *ctx = *state;
    char one[4096], three[4096], from_file[4096], mesh_nc[4096];
    output_dir(one, sizeof one, "components_1_thread");
    output_dir(three, sizeof three, "components_3_threads");
    output_dir(from_file, sizeof from_file, "components_from_file");
    assert_int_equal(um_context_set_threads(ctx, 1), UM_OK);
    um_mesh *m = unified_mesh(ctx, 300.0);
    assert_int_equal(um_mesh_write_components(m, one), UM_OK);
    um_mesh_destroy(m);
    assert_int_equal(um_context_set_threads(ctx, 3), UM_OK);
    m = unified_mesh(ctx, 300.0);
    assert_int_equal(um_mesh_write_components(m, three), UM_OK);
    um_mesh_destroy(m);
    snprintf(mesh_nc, sizeof mesh_nc, "%s/mesh.nc", one);
    assert_int_equal(um_mpas_file_write_components(ctx, mesh_nc, from_file), UM_OK);
    for (size_t k = 0; k < sizeof kFiles / sizeof kFiles[0]; ++k) {
        same_file(one, three, kFiles[k]);
        same_file(one, from_file, kFiles[k]);
    }
}

static void bad_input_is_refused(void **state) {
    um_context *ctx = *state;
    char dir[4096], garbage[4096], missing[4096];
    output_dir(dir, sizeof dir, "components_refused");
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 600.0, &h), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_OK);
    um_spacing_destroy(h);
    /* No coastlines: no masks to split by. */
    assert_int_equal(um_mesh_write_components(m, dir), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "land component has no cells"));
    um_context_clear_error(ctx);
    assert_int_equal(um_mesh_write_components(m, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_mesh_write_components(m, ""), UM_ERR_INVALID_ARGUMENT);
    um_context_clear_error(ctx);
    snprintf(missing, sizeof missing, "%s/no/such/dir", dir);
    assert_int_equal(um_mesh_write_components(m, missing), UM_ERR_IO);
    assert_non_null(strstr(um_context_last_error(ctx), missing));
    um_context_clear_error(ctx);
    um_mesh_destroy(m);
    assert_int_equal(um_mesh_write_components(NULL, dir), UM_ERR_NULL_ARGUMENT);
    /* A file that is not netCDF, and one that is not there. */
    snprintf(garbage, sizeof garbage, "%s/garbage.nc", dir);
    FILE *f = fopen(garbage, "w");
    assert_non_null(f);
    fputs("not a mesh\n", f);
    fclose(f);
    assert_int_equal(um_mpas_file_write_components(ctx, garbage, dir), UM_ERR_FILE_FORMAT);
    assert_non_null(strstr(um_context_last_error(ctx), "garbage.nc"));
    um_context_clear_error(ctx);
    assert_int_equal(um_mpas_file_write_components(ctx, missing, dir), UM_ERR_IO);
    um_context_clear_error(ctx);
    assert_int_equal(um_mpas_file_write_components(NULL, garbage, dir), UM_ERR_NULL_ARGUMENT);
    /* A mesh file whose lists disagree, or with a NaN area or TRSK weight
     * (every real variable is checked): refused, naming the variable; the
     * cut would otherwise keep an edge without its cells. */
    char good_dir[4096], good[4096];
    output_dir(good_dir, sizeof good_dir, "components_damaged");
    um_mesh *unified = unified_mesh(ctx, 900.0);
    assert_int_equal(um_mesh_write_components(unified, good_dir), UM_OK);
    um_mesh_destroy(unified);
    snprintf(good, sizeof good, "%s/mesh.nc", good_dir);
    const struct {
        const char *variable, *expected;
    } damages[] = {{"cellsOnEdge", "cellsOnEdge"}, {"areaCell", "areaCell"}, {"weightsOnEdge", "weightsOnEdge"}};
    for (int k = 0; k < 3; ++k) {
        char damaged[4096];
        snprintf(damaged, sizeof damaged, "%s/damaged_%d.nc", good_dir, k);
        copy_file(good, damaged);
        int nc = -1, var = -1;
        assert_int_equal(nc_open(damaged, NC_WRITE, &nc), NC_NOERR);
        assert_int_equal(nc_inq_varid(nc, damages[k].variable, &var), NC_NOERR);
        const size_t at[2] = {0, 0};
        if (k == 0) {
            int cells[2] = {0, 0};
            const size_t count[2] = {1, 2};
            assert_int_equal(nc_get_vara_int(nc, var, at, count, cells), NC_NOERR);
            cells[0] = cells[0] == 1 ? 2 : 1; /* another cell, which does not list this edge */
            cells[1] = cells[0] + 1;
            assert_int_equal(nc_put_vara_int(nc, var, at, count, cells), NC_NOERR);
        } else {
            const double nan_value = NAN;
            assert_int_equal(nc_put_var1_double(nc, var, at, &nan_value), NC_NOERR);
        }
        assert_int_equal(nc_close(nc), NC_NOERR);
        assert_int_equal(um_mpas_file_write_components(ctx, damaged, dir), UM_ERR_FILE_FORMAT);
        printf("damaged %s: %s\n", damages[k].variable, um_context_last_error(ctx));
        assert_non_null(strstr(um_context_last_error(ctx), damages[k].expected));
        um_context_clear_error(ctx);
    }

    /* Nothing was written. */
    char path[4096];
    snprintf(path, sizeof path, "%s/ocean.nc", dir);
    assert_int_not_equal(access(path, F_OK), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(components_partition_the_base, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(rivers_of_the_main_job_drain_to_the_coast, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(inland_ends_and_cycles_are_reported, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(same_files_from_memory_file_and_any_thread_count, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(bad_input_is_refused, setup_context, teardown_context),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
