/* CMocka suite: spacing functions through the C ABI. Every entry point, every
 * class of bad input (h <= 0, NaN, Inf, wrong shapes, descending or duplicate
 * coordinates, bad callback values, unknown presets, null and destroyed
 * handles), and spacing files written here with the netCDF-C API: valid ones
 * and malformed ones (missing variable, wrong shape, descending lon, NaN cell,
 * other units, unwritten cells, truncated). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <netcdf.h>

#include "unimesh.h"

#define DEG (M_PI / 180.0)

/* ------------------------------------------------------------- helpers */

static um_context *ctx_of(void **state) { return (um_context *)*state; }

static int setup_context(void **state) {
    um_context *ctx = NULL;
    if (um_context_create(&ctx) != UM_OK) return -1;
    *state = ctx;
    return 0;
}
static int teardown_context(void **state) {
    um_context_destroy(ctx_of(state));
    return 0;
}

static void expect_message(um_context *ctx, const char *word) {
    const char *m = um_context_last_error(ctx);
    if (!strstr(m, word)) fail_msg("message '%s' lacks '%s'", m, word);
}

/* The call must return `status` with a message holding w1 and w2 (NULL: none). */
#define EXPECT_ERROR(ctx, call, status, w1, w2)                     \
    do {                                                            \
        um_context_clear_error(ctx);                                \
        assert_int_equal((call), (status));                         \
        if (w1) expect_message((ctx), (const char *)(w1));         \
        if (w2) expect_message((ctx), (const char *)(w2));         \
    } while (0)

/* A create call that must fail and leave *out NULL. */
#define EXPECT_CREATE_ERROR(ctx, out, call, status, w1, w2)          \
    do {                                                             \
        (out) = (um_spacing *)&(out);                                \
        EXPECT_ERROR(ctx, call, status, w1, w2);                     \
        assert_null(out);                                            \
    } while (0)

static double eval1(const um_spacing *s, double lon, double lat) {
    double km = -1;
    assert_int_equal(um_spacing_evaluate(s, 1, &lon, &lat, &km), UM_OK);
    return km;
}

static void assert_close(double a, double b, double tolerance) {
    if (!(fabs(a - b) <= tolerance)) fail_msg("%.17g != %.17g (tolerance %g)", a, b, tolerance);
}

/* A 4 x 3 grid (lon 0, 90, 180, 270: periodic; lat -45, 0, 45) of f. */
static const double k_lon[4] = {0, 90, 180, 270}, k_lat[3] = {-45, 0, 45};
static double k_field(double lon, double lat) { return 100 + lon / 10 + lat / 5; }
static void fill_cells(double *cells) {
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) cells[j * 4 + i] = k_field(k_lon[i], k_lat[j]);
}

/* --------------------------------------------------- netCDF test files */

static char temp_dir[256];

static int setup_files(void **state) {
    const char *base = getenv("TMPDIR");
    snprintf(temp_dir, sizeof temp_dir, "%s/unimesh_spacing_XXXXXX", base && *base ? base : "/tmp");
    if (!mkdtemp(temp_dir)) return -1;
    return setup_context(state);
}

static const char *const file_names[] = {
    "classic.nc", "nc4.nc", "float.nc", "no_cellwidth.nc", "no_lon.nc", "transposed.nc",
    "one_dim.nc", "descending.nc", "nan_cell.nc", "metres.nc", "radians.nc", "unwritten.nc",
    "truncated.nc", "truncated4.nc", "text.nc", "empty.nc", "kilometres.nc", "dup_lat.nc"};

static int teardown_files(void **state) {
    char path[512];
    for (size_t k = 0; k < sizeof file_names / sizeof *file_names; ++k) {
        snprintf(path, sizeof path, "%s/%s", temp_dir, file_names[k]);
        unlink(path);
    }
    rmdir(temp_dir);
    return teardown_context(state);
}

static const char *temp_path(const char *name) {
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", temp_dir, name);
    return path;
}

/* How to write a spacing file: the valid MPAS layout unless told otherwise. */
typedef struct {
    int format;             /* 0: classic, NC_NETCDF4 */
    nc_type cell_type;      /* 0: NC_DOUBLE */
    int omit;               /* 1: no lon variable, 2: no cellWidth variable */
    int cell_dims;          /* 0: (lat, lon), 1: (lon, lat), 2: (lat) only */
    int leave_cells_unwritten;
    const char *cell_units; /* NULL: no attribute */
    const char *lon_units;  /* NULL: no attribute */
} file_spec;

#define NC_OK(call) assert_int_equal((call), NC_NOERR)

static void write_spacing_file(const char *path, const file_spec *spec, const double *lon,
                               const double *lat, const double *cells) {
    int id, dim_lon, dim_lat, var_lon, var_lat, var_cells;
    NC_OK(nc_create(path, NC_CLOBBER | spec->format, &id));
    NC_OK(nc_def_dim(id, "lon", 4, &dim_lon));
    NC_OK(nc_def_dim(id, "lat", 3, &dim_lat));
    if (spec->omit != 1) NC_OK(nc_def_var(id, "lon", NC_DOUBLE, 1, &dim_lon, &var_lon));
    NC_OK(nc_def_var(id, "lat", NC_DOUBLE, 1, &dim_lat, &var_lat));
    if (spec->omit != 1 && spec->lon_units)
        NC_OK(nc_put_att_text(id, var_lon, "units", strlen(spec->lon_units), spec->lon_units));
    int dims[2] = {dim_lat, dim_lon};
    if (spec->cell_dims == 1) dims[0] = dim_lon, dims[1] = dim_lat;
    if (spec->omit != 2) {
        NC_OK(nc_def_var(id, "cellWidth", spec->cell_type ? spec->cell_type : NC_DOUBLE,
                         spec->cell_dims == 2 ? 1 : 2, dims, &var_cells));
        if (spec->cell_units)
            NC_OK(nc_put_att_text(id, var_cells, "units", strlen(spec->cell_units), spec->cell_units));
    }
    NC_OK(nc_enddef(id));
    if (spec->omit != 1) NC_OK(nc_put_var_double(id, var_lon, lon));
    NC_OK(nc_put_var_double(id, var_lat, lat));
    if (spec->omit != 2 && !spec->leave_cells_unwritten)
        NC_OK(nc_put_var_double(id, var_cells, cells));
    NC_OK(nc_close(id));
}

static const char *write_valid(const char *name, int format, nc_type type, const char *units) {
    double cells[12];
    fill_cells(cells);
    file_spec spec = {format, type, 0, 0, 0, units, "degrees_east"};
    const char *path = temp_path(name);
    write_spacing_file(path, &spec, k_lon, k_lat, cells);
    return path;
}

static void truncate_file(const char *path, long remove_bytes) {
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(truncate(path, st.st_size - remove_bytes), 0);
}

static void write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* --------------------------------------------------------------- tests */

static void constant_spacing(void **state) {
    um_context *ctx = ctx_of(state);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 30, &s), UM_OK);
    assert_true(eval1(s, 0, 0) == 30 && eval1(s, -180, 90) == 30 && eval1(s, 720, -90) == 30);
    um_spacing_destroy(s);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant(ctx, 0, &s), UM_ERR_INVALID_ARGUMENT, "km = 0", "> 0");
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant(ctx, -5, &s), UM_ERR_INVALID_ARGUMENT, "km = -5", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant(ctx, NAN, &s), UM_ERR_NONFINITE_INPUT, "km = nan", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant(ctx, INFINITY, &s), UM_ERR_NONFINITE_INPUT, "km = inf", NULL);
    EXPECT_ERROR(ctx, um_spacing_create_constant(ctx, 30, NULL), UM_ERR_NULL_ARGUMENT, "out", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant(NULL, 30, &s), UM_ERR_NULL_ARGUMENT, NULL, NULL);
}

/* The up-front estimate: a uniform 120 km mesh has 40,962 cells (the
 * lattice); the memory the cap judges scales with them. */
static void estimate(void **state) {
    um_context *ctx = ctx_of(state);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 120, &s), UM_OK);
    int64_t cells = 0, refine_bytes = 0, mpas_bytes = 0;
    assert_int_equal(um_spacing_estimate(s, &cells, &refine_bytes, &mpas_bytes), UM_OK);
    assert_true(cells > 39000 && cells < 43000);
    assert_true(refine_bytes >= 200 * cells);
    assert_true(mpas_bytes >= 100 * cells);
    assert_int_equal(um_spacing_estimate(s, NULL, NULL, NULL), UM_OK);
    um_spacing *fine = NULL;
    int64_t fine_cells = 0;
    assert_int_equal(um_spacing_create_constant(ctx, 60, &fine), UM_OK);
    assert_int_equal(um_spacing_estimate(fine, &fine_cells, NULL, NULL), UM_OK);
    assert_true(fine_cells > 3.9 * cells && fine_cells < 4.1 * cells);
    um_spacing_destroy(fine);
    /* The MPAS file is streamed: at 10 km (about 5.9 M cells) it adds less
     * than the mesh itself needs, and much less than the whole staggered
     * mesh (1.2 kB/cell). */
    um_spacing *ten = NULL;
    int64_t ten_cells = 0, ten_refine = 0, ten_mpas = 0;
    assert_int_equal(um_spacing_create_constant(ctx, 10, &ten), UM_OK);
    assert_int_equal(um_spacing_estimate(ten, &ten_cells, &ten_refine, &ten_mpas), UM_OK);
    assert_true(ten_mpas >= 100 * ten_cells && ten_mpas < ten_refine && ten_mpas < 400 * ten_cells);
    um_spacing_destroy(ten);
    um_spacing_destroy(s);
    EXPECT_ERROR(ctx, um_spacing_estimate(NULL, &cells, NULL, NULL), UM_ERR_NULL_ARGUMENT, NULL, NULL);
}

static void grid_spacing(void **state) {
    um_context *ctx = ctx_of(state);
    double cells[12];
    fill_cells(cells);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_grid(ctx, 4, k_lon, 3, k_lat, cells, &s), UM_OK);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) assert_true(eval1(s, k_lon[i], k_lat[j]) == k_field(k_lon[i], k_lat[j]));
    assert_close(eval1(s, 45, 22.5), k_field(45, 22.5), 1e-12);       /* bilinear */
    assert_close(eval1(s, 315, 0), (k_field(270, 0) + k_field(0, 0)) / 2, 1e-12); /* wrap cell */
    assert_close(eval1(s, -45, 0), eval1(s, 315, 0), 1e-12);          /* any lon convention */
    assert_close(eval1(s, 90, 80), k_field(90, 45), 1e-12);           /* clamped to the last row */
    um_spacing_destroy(s);
}

static void grid_bad_input(void **state) {
    um_context *ctx = ctx_of(state);
    double cells[12], lon[4], lat[3];
    um_spacing *s = NULL;
#define RESET() (fill_cells(cells), memcpy(lon, k_lon, sizeof lon), memcpy(lat, k_lat, sizeof lat))
#define GRID() um_spacing_create_grid(ctx, 4, lon, 3, lat, cells, &s)
    RESET();
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_grid(ctx, 1, lon, 3, lat, cells, &s), UM_ERR_INVALID_ARGUMENT, "n_lon = 1", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_grid(ctx, 4, lon, 0, lat, cells, &s), UM_ERR_INVALID_ARGUMENT, "n_lat = 0", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_grid(ctx, 4, lon, -3, lat, cells, &s), UM_ERR_INVALID_ARGUMENT, "n_lat = -3", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_grid(ctx, 4, NULL, 3, lat, cells, &s), UM_ERR_NULL_ARGUMENT, "lon_deg", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_grid(ctx, 4, lon, 3, NULL, cells, &s), UM_ERR_NULL_ARGUMENT, "lat_deg", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_grid(ctx, 4, lon, 3, lat, NULL, &s), UM_ERR_NULL_ARGUMENT, "cell_width_km", NULL);
    EXPECT_ERROR(ctx, um_spacing_create_grid(ctx, 4, lon, 3, lat, cells, NULL), UM_ERR_NULL_ARGUMENT, "out", NULL);
    lon[2] = 50;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_INVALID_ARGUMENT, "lon_deg[2] = 50", "descending");
    RESET(), lat[1] = -45;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_INVALID_ARGUMENT, "lat_deg[1] = -45", "duplicate");
    RESET(), lon[1] = NAN;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_NONFINITE_INPUT, "lon_deg[1] = nan", NULL);
    RESET(), lat[2] = 91;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_COORDINATE_RANGE, "lat_deg[2] = 91", NULL);
    RESET(), lon[3] = 400;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_COORDINATE_RANGE, "lon_deg spans 400", NULL);
    RESET(), cells[6] = NAN;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_NONFINITE_INPUT, "cell_width_km[6]", "lat_deg index 1, lon_deg index 2");
    RESET(), cells[11] = INFINITY;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_NONFINITE_INPUT, "cell_width_km[11] ", "inf");
    RESET(), cells[0] = 0;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_INVALID_ARGUMENT, "cell_width_km[0] ", "not > 0");
    RESET(), cells[5] = -1;
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_INVALID_ARGUMENT, "cell_width_km[5] ", "-1");
    /* A memory cap below the grid's size. */
    assert_int_equal(um_context_set_memory_cap(ctx, 64), UM_OK);
    RESET();
    EXPECT_CREATE_ERROR(ctx, s, GRID(), UM_ERR_MEMORY_CAP, "spacing grid", NULL);
    assert_int_equal(um_context_set_memory_cap(ctx, 0), UM_OK);
#undef GRID
#undef RESET
}

static void spacing_files(void **state) {
    um_context *ctx = ctx_of(state);
    double cells[12];
    fill_cells(cells);
    um_spacing *grid = NULL, *s = NULL;
    assert_int_equal(um_spacing_create_grid(ctx, 4, k_lon, 3, k_lat, cells, &grid), UM_OK);
    const char *paths[3] = {write_valid("classic.nc", 0, 0, "km"),
                            write_valid("nc4.nc", NC_NETCDF4, 0, NULL),
                            write_valid("kilometres.nc", NC_NETCDF4, 0, " Kilometres")};
    for (int k = 0; k < 3; ++k) {
        assert_int_equal(um_spacing_create_from_file(ctx, paths[k], &s), UM_OK);
        for (double lon = -180; lon <= 180; lon += 22.5)
            for (double lat = -90; lat <= 90; lat += 15)
                assert_true(eval1(s, lon, lat) == eval1(grid, lon, lat));
        um_spacing_destroy(s);
    }
    /* float32 cells: the same grid up to float rounding. */
    assert_int_equal(um_spacing_create_from_file(ctx, write_valid("float.nc", 0, NC_FLOAT, "km"), &s), UM_OK);
    assert_close(eval1(s, 10, 10), eval1(grid, 10, 10), 1e-4);
    um_spacing_destroy(s);
    um_spacing_destroy(grid);
}

/* Writes a malformed file and expects `status` naming the path and `word`. */
static void expect_file_error(um_context *ctx, const char *name, const file_spec *spec,
                              const double *lon, const double *lat, const double *cells,
                              um_status status, const char *word) {
    const char *path = temp_path(name);
    if (spec) write_spacing_file(path, spec, lon, lat, cells);
    um_spacing *s = NULL;
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_from_file(ctx, path, &s), status, path, word);
}

static void malformed_spacing_files(void **state) {
    um_context *ctx = ctx_of(state);
    double cells[12], lon[4], lat[3];
    fill_cells(cells);
    memcpy(lon, k_lon, sizeof lon);
    memcpy(lat, k_lat, sizeof lat);
    um_spacing *s = NULL;
    file_spec spec = {0, 0, 2, 0, 0, NULL, NULL};
    expect_file_error(ctx, "no_cellwidth.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "no variable 'cellWidth'");
    spec.omit = 1;
    expect_file_error(ctx, "no_lon.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "no variable 'lon'");
    spec.omit = 0, spec.cell_dims = 1;
    expect_file_error(ctx, "transposed.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "'cellWidth' has shape (4, 3) = (lon, lat)");
    spec.cell_dims = 2;
    expect_file_error(ctx, "one_dim.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "'cellWidth' has shape (3)");
    spec.cell_dims = 0;
    lon[2] = 45;
    expect_file_error(ctx, "descending.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "lon[2] = 45 is not above lon[1] = 90");
    lon[2] = 180, lat[2] = 0;
    expect_file_error(ctx, "dup_lat.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "lat[2] = 0");
    lat[2] = 45, cells[7] = NAN;
    expect_file_error(ctx, "nan_cell.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "cellWidth[7] (lat index 1, lon index 3) = nan");
    cells[7] = 5, spec.cell_units = "m";
    expect_file_error(ctx, "metres.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "units 'm'; expected km");
    spec.cell_units = NULL, spec.lon_units = "radians";
    expect_file_error(ctx, "radians.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "'lon' has units 'radians'");
    spec.lon_units = NULL, spec.leave_cells_unwritten = 1;
    expect_file_error(ctx, "unwritten.nc", &spec, lon, lat, cells, UM_ERR_FILE_FORMAT, "fill value");
    /* Truncated: classic files read the lost tail as zeros, so their length
     * is checked; netCDF-4 (HDF5) files no longer open. */
    truncate_file(write_valid("truncated.nc", 0, 0, "km"), 40);
    expect_file_error(ctx, "truncated.nc", NULL, NULL, NULL, NULL, UM_ERR_FILE_FORMAT, "the file is truncated: it has");
    truncate_file(write_valid("truncated4.nc", NC_NETCDF4, 0, "km"), 1000);
    expect_file_error(ctx, "truncated4.nc", NULL, NULL, NULL, NULL, UM_ERR_FILE_FORMAT, "not a readable netCDF file");
    write_text(temp_path("text.nc"), "lon,lat,cellWidth\n0,0,30\n");
    expect_file_error(ctx, "text.nc", NULL, NULL, NULL, NULL, UM_ERR_FILE_FORMAT, "not a readable netCDF file");
    write_text(temp_path("empty.nc"), "");
    expect_file_error(ctx, "empty.nc", NULL, NULL, NULL, NULL, UM_ERR_FILE_FORMAT, "not a readable netCDF file");
    /* Files that cannot be opened at all. */
    expect_file_error(ctx, "missing.nc", NULL, NULL, NULL, NULL, UM_ERR_IO, "no such file");
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_from_file(ctx, temp_dir, &s), UM_ERR_IO, "is a directory", NULL);
    /* A FIFO is refused, not opened (which blocked until a writer came). */
    const char *fifo = temp_path("fifo.nc");
    remove(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_from_file(ctx, fifo, &s), UM_ERR_IO, "not a regular file", NULL);
    remove(fifo);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_from_file(ctx, NULL, &s), UM_ERR_NULL_ARGUMENT, "path", NULL);
}

/* h = scale * (10 + lat / 10), NaN north of 60, -1 south of -60. */
static double user_spacing(void *user_data, double lon, double lat) {
    (void)lon;
    if (lat > 60) return NAN;
    if (lat < -60) return -1;
    return *(const double *)user_data * (10 + lat / 10);
}

static void callback_spacing(void **state) {
    um_context *ctx = ctx_of(state);
    double scale = 2;
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_callback(ctx, user_spacing, &scale, &s), UM_OK);
    assert_true(eval1(s, 10, 20) == 24);
    double lon[4] = {0, 10, 20, 30}, lat[4] = {0, 10, 70, 80}, km[4];
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 4, lon, lat, km), UM_ERR_NONFINITE_INPUT,
                 "at lon 20, lat 70 (point 2)", "h = nan");
    lat[2] = -70, lat[3] = -80;
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 4, lon, lat, km), UM_ERR_INVALID_ARGUMENT,
                 "at lon 20, lat -70 (point 2)", "not > 0");
    /* A clamp does not hide a bad value. */
    assert_int_equal(um_spacing_clamp(s, 1, 100), UM_OK);
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 4, lon, lat, km), UM_ERR_INVALID_ARGUMENT, "(point 2)", NULL);
    um_spacing_destroy(s);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_callback(ctx, NULL, &scale, &s), UM_ERR_NULL_ARGUMENT, "fn", NULL);
}

/* mesh_definition_tools.EC_CellWidthVsLat at its defaults (EC60to30). */
static double ec60to30(double lat) {
    double a = fabs(lat), eq = 1, mid = pow(30.0 / 60, 4), pole = pow(30.0 / 35, 4), d;
    if (a < 40) d = (eq - mid) * (1 + tanh((15 - a) / 6)) / 2 + mid;
    else d = (mid - pole) * (1 + tanh((73 - a) / 9)) / 2 + pole;
    return 30 / pow(d, 0.25);
}

static void preset_spacings(void **state) {
    um_context *ctx = ctx_of(state);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_preset(ctx, "QU240", &s), UM_OK);
    assert_true(eval1(s, 12, 34) == 240);
    um_spacing_destroy(s);
    assert_int_equal(um_spacing_create_preset(ctx, "EC60to30", &s), UM_OK);
    for (double lat = -90; lat <= 90; lat += 10) assert_close(eval1(s, 0, lat), ec60to30(lat), 1e-12);
    um_spacing_destroy(s);
    assert_int_equal(um_spacing_create_preset(ctx, "RRS18to6", &s), UM_OK);
    assert_close(eval1(s, 0, 0), 18, 1e-12);
    assert_close(eval1(s, 0, 90), 6, 1e-12);
    um_spacing_destroy(s);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_preset(ctx, "FOO", &s), UM_ERR_INVALID_ARGUMENT, "preset name 'FOO'", "EC<km>to<km>");
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_preset(ctx, "", &s), UM_ERR_INVALID_ARGUMENT, "preset name ''", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_preset(ctx, "QU0", &s), UM_ERR_INVALID_ARGUMENT, "'QU0'", NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_preset(ctx, NULL, &s), UM_ERR_NULL_ARGUMENT, "name", NULL);
}

/* Haversine distance in km on the library's sphere. */
static double distance_km(double lon1, double lat1, double lon2, double lat2) {
    double s1 = sin((lat2 - lat1) * DEG / 2), s2 = sin((lon2 - lon1) * DEG / 2);
    double a = s1 * s1 + cos(lat1 * DEG) * cos(lat2 * DEG) * s2 * s2;
    return 2 * 6371.22 * asin(fmin(1.0, sqrt(a)));
}

static void gradient_limiting(void **state) {
    um_context *ctx = ctx_of(state);
    enum { NX = 24, NY = 13 };
    double lon[NX], lat[NY], cells[NX * NY], km[NX * NY], qlon[NX * NY], qlat[NX * NY];
    for (int i = 0; i < NX; ++i) lon[i] = -180 + 15 * i;
    for (int j = 0; j < NY; ++j) lat[j] = -90 + 15 * j;
    for (int k = 0; k < NX * NY; ++k) {
        cells[k] = 200;
        qlon[k] = lon[k % NX], qlat[k] = lat[k / NX];
    }
    cells[6 * NX + 23] = 10; /* a fine spot at (165, 0), next to the dateline */
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_grid(ctx, NX, lon, NY, lat, cells, &s), UM_OK);
    /* Bad g leaves the spacing as it was. */
    EXPECT_ERROR(ctx, um_spacing_limit_gradient(s, 0), UM_ERR_INVALID_ARGUMENT, "g = 0", NULL);
    EXPECT_ERROR(ctx, um_spacing_limit_gradient(s, -0.1), UM_ERR_INVALID_ARGUMENT, "g = -0.1", NULL);
    EXPECT_ERROR(ctx, um_spacing_limit_gradient(s, NAN), UM_ERR_NONFINITE_INPUT, "g = nan", NULL);
    assert_int_equal(um_spacing_evaluate(s, NX * NY, qlon, qlat, km), UM_OK);
    assert_memory_equal(km, cells, sizeof cells);

    const double g = 0.02;
    assert_int_equal(um_spacing_limit_gradient(s, g), UM_OK);
    assert_int_equal(um_spacing_evaluate(s, NX * NY, qlon, qlat, km), UM_OK);
    assert_true(km[6 * NX + 23] == 10);
    /* Across the dateline the fine spot is felt: 15 degrees ~ 1668 km. */
    assert_close(km[6 * NX + 0], 10 + g * distance_km(165, 0, 180, 0), 1e-6);
    for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    int jj = j + dj, ii = (i + di + NX) % NX;
                    if (jj < 0 || jj >= NY) continue;
                    double d = distance_km(lon[i], lat[j], lon[ii], lat[jj]);
                    assert_true(fabs(km[j * NX + i] - km[jj * NX + ii]) <= g * d * (1 + 1e-9) + 1e-9);
                }
    um_spacing_destroy(s);

    /* Only grids (also inside a clamp) can be limited. */
    assert_int_equal(um_spacing_create_grid(ctx, NX, lon, NY, lat, cells, &s), UM_OK);
    assert_int_equal(um_spacing_clamp(s, 20, 150), UM_OK);
    assert_int_equal(um_spacing_limit_gradient(s, g), UM_OK);
    assert_true(eval1(s, 165, 0) == 20 && eval1(s, 0, 0) == 150);
    um_spacing_destroy(s);
    double scale = 1;
    um_spacing *others[3] = {NULL, NULL, NULL};
    assert_int_equal(um_spacing_create_constant(ctx, 30, &others[0]), UM_OK);
    assert_int_equal(um_spacing_create_preset(ctx, "EC60to30", &others[1]), UM_OK);
    assert_int_equal(um_spacing_create_callback(ctx, user_spacing, &scale, &others[2]), UM_OK);
    for (int k = 0; k < 3; ++k) {
        EXPECT_ERROR(ctx, um_spacing_limit_gradient(others[k], g), UM_ERR_INVALID_ARGUMENT, "grid spacings only", NULL);
        um_spacing_destroy(others[k]);
    }
}

static void clamping(void **state) {
    um_context *ctx = ctx_of(state);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_preset(ctx, "RRS18to6", &s), UM_OK);
    assert_int_equal(um_spacing_clamp(s, 8, 15), UM_OK);
    assert_true(eval1(s, 0, 0) == 15 && eval1(s, 0, 90) == 8);
    EXPECT_ERROR(ctx, um_spacing_clamp(s, 10, 9), UM_ERR_INVALID_ARGUMENT, "km_min = 10", "above km_max = 9");
    EXPECT_ERROR(ctx, um_spacing_clamp(s, 0, 9), UM_ERR_INVALID_ARGUMENT, "km_min = 0", NULL);
    EXPECT_ERROR(ctx, um_spacing_clamp(s, 1, INFINITY), UM_ERR_NONFINITE_INPUT, "km_max = inf", NULL);
    EXPECT_ERROR(ctx, um_spacing_clamp(s, NAN, 9), UM_ERR_NONFINITE_INPUT, "km_min = nan", NULL);
    assert_true(eval1(s, 0, 0) == 15 && eval1(s, 0, 90) == 8); /* unchanged */
    um_spacing_destroy(s);
    EXPECT_ERROR(ctx, um_spacing_clamp(NULL, 1, 2), UM_ERR_NULL_ARGUMENT, NULL, NULL);
}

static double wavy(void *user_data, double lon, double lat) {
    (void)user_data;
    return 20 + 5 * sin(3 * lon * DEG) * cos(lat * DEG);
}

static void evaluation(void **state) {
    um_context *ctx = ctx_of(state);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_preset(ctx, "EC60to30", &s), UM_OK);
    double lon[2] = {0, 1}, lat[2] = {0, 95}, km[2];
    assert_int_equal(um_spacing_evaluate(s, 0, NULL, NULL, NULL), UM_OK);
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, -1, lon, lat, km), UM_ERR_INVALID_ARGUMENT, "n = -1", NULL);
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 2, NULL, lat, km), UM_ERR_NULL_ARGUMENT, "lon_deg", NULL);
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 2, lon, NULL, km), UM_ERR_NULL_ARGUMENT, "lat_deg", NULL);
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 2, lon, lat, NULL), UM_ERR_NULL_ARGUMENT, "km_out", NULL);
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 2, lon, lat, km), UM_ERR_COORDINATE_RANGE, "lat_deg[1] = 95", NULL);
    lat[1] = 0, lon[1] = NAN;
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 2, lon, lat, km), UM_ERR_NONFINITE_INPUT, "lon_deg[1] = nan", NULL);
    lon[1] = 1, lat[1] = -INFINITY;
    EXPECT_ERROR(ctx, um_spacing_evaluate(s, 2, lon, lat, km), UM_ERR_NONFINITE_INPUT, "lat_deg[1] = -inf", NULL);
    um_spacing_destroy(s);
}

/* The same values, bit for bit, with 1 and 2 threads. */
static void evaluation_is_deterministic(void **state) {
    um_context *ctx = ctx_of(state);
    enum { N = 100000 };
    double *lon = malloc(N * sizeof *lon), *lat = malloc(N * sizeof *lat);
    double *a = malloc(N * sizeof *a), *b = malloc(N * sizeof *b);
    assert_true(lon && lat && a && b);
    for (int i = 0; i < N; ++i) lon[i] = fmod(i * 0.7548776662, 1.0) * 360 - 180,
                                lat[i] = asin(2 * fmod(i * 0.5698402910, 1.0) - 1) / DEG;
    double cells[12];
    fill_cells(cells);
    um_spacing *s[3] = {NULL, NULL, NULL};
    assert_int_equal(um_spacing_create_grid(ctx, 4, k_lon, 3, k_lat, cells, &s[0]), UM_OK);
    assert_int_equal(um_spacing_create_callback(ctx, wavy, NULL, &s[1]), UM_OK);
    assert_int_equal(um_spacing_create_preset(ctx, "RRS18to6", &s[2]), UM_OK);
    for (int k = 0; k < 3; ++k) {
        assert_int_equal(um_context_set_threads(ctx, 1), UM_OK);
        assert_int_equal(um_spacing_evaluate(s[k], N, lon, lat, a), UM_OK);
        assert_int_equal(um_context_set_threads(ctx, 2), UM_OK);
        assert_int_equal(um_spacing_evaluate(s[k], N, lon, lat, b), UM_OK);
        assert_memory_equal(a, b, N * sizeof *a);
        um_spacing_destroy(s[k]);
    }
    assert_int_equal(um_context_set_threads(ctx, 0), UM_OK);
    free(lon), free(lat), free(a), free(b);
}

static void null_destroyed_and_foreign_handles(void **state) {
    um_context *ctx = ctx_of(state);
    double lon = 0, lat = 0, km = 0;
    um_spacing_destroy(NULL);
    assert_int_equal(um_spacing_evaluate(NULL, 1, &lon, &lat, &km), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_spacing_limit_gradient(NULL, 0.1), UM_ERR_NULL_ARGUMENT);
    um_spacing *s = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 10, &s), UM_OK);
    um_spacing_destroy(s);
    um_spacing_destroy(s); /* double destroy: ignored */
    assert_int_equal(um_spacing_evaluate(s, 1, &lon, &lat, &km), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_spacing_clamp(s, 1, 2), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_spacing_limit_gradient(s, 0.1), UM_ERR_INVALID_HANDLE);
    /* A context is not a spacing, and a spacing not a context. */
    assert_int_equal(um_spacing_evaluate((const um_spacing *)ctx, 1, &lon, &lat, &km), UM_ERR_INVALID_HANDLE);
    um_spacing_destroy((um_spacing *)ctx); /* ignored: not a live spacing */
    assert_int_equal(um_context_clear_error(ctx), UM_OK);
    /* A spacing outlives its context; a destroyed context creates nothing. */
    um_context *other = NULL;
    assert_int_equal(um_context_create(&other), UM_OK);
    assert_int_equal(um_spacing_create_preset(other, "QU60", &s), UM_OK);
    um_context_destroy(other);
    assert_true(eval1(s, 1, 2) == 60);
    um_spacing_destroy(s);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant(other, 30, &s), UM_ERR_INVALID_HANDLE, NULL, NULL);
    EXPECT_CREATE_ERROR(ctx, s, um_spacing_create_constant((um_context *)&lon, 30, &s), UM_ERR_INVALID_HANDLE, NULL, NULL);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(constant_spacing),
        cmocka_unit_test(estimate),
        cmocka_unit_test(grid_spacing),
        cmocka_unit_test(grid_bad_input),
        cmocka_unit_test(spacing_files),
        cmocka_unit_test(malformed_spacing_files),
        cmocka_unit_test(callback_spacing),
        cmocka_unit_test(preset_spacings),
        cmocka_unit_test(gradient_limiting),
        cmocka_unit_test(clamping),
        cmocka_unit_test(evaluation),
        cmocka_unit_test(evaluation_is_deterministic),
        cmocka_unit_test(null_destroyed_and_foreign_handles),
    };
    return cmocka_run_group_tests_name("spacing_api", tests, setup_files, teardown_files);
}
