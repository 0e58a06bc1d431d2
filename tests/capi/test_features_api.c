/* CMocka suite: polyarc networks (um_features) through the C ABI: every entry
 * point, every class of bad input, NULL / destroyed / foreign handles. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <cmocka.h>

#include "context_fixture.h"
#include "shipped_features.h"
#include "unimesh.h"

#define TEST_DATA(name) UNIMESH_TEST_DATA_DIR "/" name

/* The context's kept message contains `part`; clears it for the next check. */
static void expect_message(um_context *ctx, const char *part) {
    const char *m = um_context_last_error(ctx);
    if (!strstr(m, part)) printf("message \"%s\" lacks \"%s\"\n", m, part);
    assert_non_null(strstr(m, part));
    assert_int_equal(um_context_clear_error(ctx), UM_OK);
}

static void counts(const um_features *f, int64_t *parts, int64_t *points, int64_t *segments) {
    assert_int_equal(um_features_counts(f, parts, points, segments), UM_OK);
}

/* Two parts: an open river with a repeated point, a closed ring given with
 * first == last. */
static const double kLon[] = {0, 1, 1, 2, 10, 11, 11, 10};
static const double kLat[] = {0, 0, 0, 1, 10, 10, 11, 10};
static const int64_t kOffsets[] = {0, 4, 8};
static const int32_t kClosed[] = {0, 1};
static const int32_t kKind[] = {UM_FEATURE_RIVER, UM_FEATURE_COASTLINE};
static const int32_t kIds[] = {101, 202};

static void create_add_count_copy(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_non_null(f);
    int64_t np = -1, nv = -1, ns = -1;
    counts(f, &np, &nv, &ns);
    assert_true(np == 0 && nv == 0 && ns == 0);

    assert_int_equal(um_features_add(f, 8, kLon, kLat, 2, kOffsets, kClosed, kKind, kIds), UM_OK);
    counts(f, &np, &nv, &ns);
    assert_int_equal(np, 2);
    assert_int_equal(nv, 3 + 3); /* repeat and closing duplicate dropped */
    assert_int_equal(ns, 2 + 3);
    assert_int_equal(um_features_counts(f, NULL, NULL, NULL), UM_OK);

    double lon[6], lat[6];
    assert_int_equal(um_features_copy_points(f, lon, lat, 6), UM_OK);
    const double want_lon[] = {0, 1, 2, 10, 11, 11}, want_lat[] = {0, 0, 1, 10, 10, 11};
    for (int i = 0; i < 6; ++i) {
        assert_true(lon[i] == want_lon[i]);
        assert_true(lat[i] == want_lat[i]);
    }
    double only_lat[6] = {0};
    assert_int_equal(um_features_copy_points(f, NULL, only_lat, 6), UM_OK);
    assert_true(only_lat[5] == 11);

    int64_t off[3];
    int32_t closed[2], kind[2], id[2];
    assert_int_equal(um_features_copy_parts(f, off, closed, kind, id, 3), UM_OK);
    assert_true(off[0] == 0 && off[1] == 3 && off[2] == 6);
    assert_true(closed[0] == 0 && closed[1] == 1);
    assert_true(kind[0] == UM_FEATURE_RIVER && kind[1] == UM_FEATURE_COASTLINE);
    assert_true(id[0] == 101 && id[1] == 202);
    /* Without the offsets, n_parts elements are enough. */
    assert_int_equal(um_features_copy_parts(f, NULL, NULL, kind, NULL, 2), UM_OK);

    /* part_id NULL: the index in the network, counting earlier parts (the
     * ring moved: the same ring twice is refused). */
    const double lon_moved[] = {0, 1, 1, 2, 30, 31, 31, 30};
    assert_int_equal(um_features_add(f, 8, lon_moved, kLat, 2, kOffsets, kClosed, kKind, NULL), UM_OK);
    int64_t off4[5];
    int32_t id4[4];
    assert_int_equal(um_features_copy_parts(f, off4, NULL, NULL, id4, 5), UM_OK);
    assert_true(id4[2] == 2 && id4[3] == 3);
    assert_true(off4[4] == 12);

    /* An empty batch is fine. */
    const int64_t zero = 0;
    assert_int_equal(um_features_add(f, 0, NULL, NULL, 0, &zero, NULL, NULL, NULL), UM_OK);
    counts(f, &np, NULL, NULL);
    assert_int_equal(np, 4);
    um_features_destroy(f);
}

static void bad_input_is_rejected_and_changes_nothing(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_add(f, 8, kLon, kLat, 2, kOffsets, kClosed, kKind, kIds), UM_OK);

    double lon[8], lat[8];
    int64_t off[3];
    int32_t closed[2], kind[2];
#define RESET()                                                   \
    memcpy(lon, kLon, sizeof lon), memcpy(lat, kLat, sizeof lat), \
        memcpy(off, kOffsets, sizeof off), memcpy(closed, kClosed, sizeof closed), memcpy(kind, kKind, sizeof kind)
#define ADD() um_features_add(f, 8, lon, lat, 2, off, closed, kind, kIds)

    RESET(), lon[5] = NAN;
    assert_int_equal(ADD(), UM_ERR_NONFINITE_INPUT);
    expect_message(ctx, "lon_deg[5] (part 1 (part_id 202), its point 1) = nan is not finite");
    RESET(), lat[2] = -INFINITY;
    assert_int_equal(ADD(), UM_ERR_NONFINITE_INPUT);
    expect_message(ctx, "lat_deg[2] (part 0 (part_id 101), its point 2) = -inf");
    RESET(), lat[6] = 90.000001;
    assert_int_equal(ADD(), UM_ERR_COORDINATE_RANGE);
    expect_message(ctx, "lat_deg[6] (part 1 (part_id 202), its point 2) = 90.000001 is outside [-90, 90]");
    RESET(), lon[4] = lon[5] = lon[6] = lon[7] = 10, lat[4] = lat[5] = lat[6] = lat[7] = 10;
    assert_int_equal(ADD(), UM_ERR_TOO_FEW_POINTS);
    assert_int_equal(um_status_class(UM_ERR_TOO_FEW_POINTS), UM_ERR_INPUT);
    expect_message(ctx, "part 1 (part_id 202) (points 4 to 7 of lon_deg/lat_deg) has 1 distinct point (4 given)");
    RESET(), lon[1] = 180, lat[1] = 0; /* antipodal to point 0 */
    assert_int_equal(ADD(), UM_ERR_DEGENERATE_INPUT);
    expect_message(ctx, "lon_deg/lat_deg[1] (part 0 (part_id 101), its point 1) = (180, 0) is antipodal");
    RESET(), kind[1] = 8;
    assert_int_equal(ADD(), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "kind[1] = 8 is not a feature kind");
    RESET(), kind[0] = 0;
    assert_int_equal(ADD(), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "kind[0] = 0");
    RESET(), closed[1] = 2;
    assert_int_equal(ADD(), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "closed[1] = 2 is not 0 or 1");
    RESET(), off[0] = -1;
    assert_int_equal(ADD(), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "part_offsets[0] = -1 is not 0");
    RESET(), off[1] = 9;
    assert_int_equal(ADD(), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "part_offsets[1] = 9 exceeds n_points = 8");
    RESET(), off[2] = 7;
    assert_int_equal(ADD(), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "part_offsets[n_parts = 2] = 7 is not n_points = 8");
    RESET();
    assert_int_equal(um_features_add(f, -1, lon, lat, 2, off, closed, kind, NULL), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "n_points = -1 is negative");
    assert_int_equal(um_features_add(f, 8, lon, lat, -2, off, closed, kind, NULL), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "n_parts = -2 is negative");
    assert_int_equal(um_features_add(f, 8, NULL, lat, 2, off, closed, kind, NULL), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "lon_deg is NULL");
    assert_int_equal(um_features_add(f, 8, lon, NULL, 2, off, closed, kind, NULL), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "lat_deg is NULL");
    assert_int_equal(um_features_add(f, 8, lon, lat, 2, NULL, closed, kind, NULL), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "part_offsets is NULL");
    assert_int_equal(um_features_add(f, 8, lon, lat, 2, off, NULL, kind, NULL), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "closed is NULL");
    assert_int_equal(um_features_add(f, 8, lon, lat, 2, off, closed, NULL, NULL), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "kind is NULL");
    assert_int_equal(um_features_add(f, INT64_MAX, lon, lat, 2, off, closed, kind, NULL), UM_ERR_LIMIT);
    expect_message(ctx, "n_points = 9223372036854775807 exceeds the limit");
    /* The context's memory cap applies. */
    assert_int_equal(um_context_set_memory_cap(ctx, 100), UM_OK);
    assert_int_equal(ADD(), UM_ERR_MEMORY_CAP);
    expect_message(ctx, "adding the features needs about");
    assert_int_equal(um_context_set_memory_cap(ctx, 0), UM_OK);

    /* Nothing of the failed calls was kept. */
    int64_t np, nv, ns;
    counts(f, &np, &nv, &ns);
    assert_true(np == 2 && nv == 6 && ns == 5);
    RESET();
    for (int i = 4; i < 8; ++i) lon[i] += 20; /* the same ring again would be refused */
    assert_int_equal(ADD(), UM_OK);
    counts(f, &np, NULL, NULL);
    assert_int_equal(np, 4);
#undef ADD
#undef RESET
    um_features_destroy(f);
}

static void dateline_and_self_intersections_are_accepted(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    /* A ring across the antimeridian (180 and -180 the same point) and a figure eight. */
    const double lon[] = {179, -180, -179, 180, 179, 0, 2, 2, 0};
    const double lat[] = {-16, -16, -16.5, -17, -16, 0, 2, 0, 2};
    const int64_t off[] = {0, 5, 9};
    const int32_t closed[] = {1, 1}, kind[] = {UM_FEATURE_COASTLINE, UM_FEATURE_OTHER};
    assert_int_equal(um_features_add(f, 9, lon, lat, 2, off, closed, kind, NULL), UM_OK);
    int64_t np, nv, ns;
    counts(f, &np, &nv, &ns);
    assert_true(np == 2 && nv == 4 + 4 && ns == 8);
    um_features_destroy(f);
}

static void read_geojson(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("lines.geojson"), NULL, 0), UM_OK);
    int64_t np, nv, ns;
    counts(f, &np, &nv, &ns);
    assert_true(np == 13 && nv == 40 && ns == 34);
    int32_t kind[13], closed[13], id[13];
    assert_int_equal(um_features_copy_parts(f, NULL, closed, kind, id, 13), UM_OK);
    assert_true(kind[0] == UM_FEATURE_RIVER && closed[0] == 0 && id[0] == 0);
    assert_true(kind[1] == UM_FEATURE_COASTLINE && closed[1] == 1 && id[1] == 42);
    assert_true(kind[6] == UM_FEATURE_LAKE && closed[6] == 1 && id[6] == 5);

    /* A bare geometry needs a default kind; the kind property can be renamed. */
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("polygon.geojson"), NULL, 0), UM_ERR_INPUT);
    expect_message(ctx, "no default kind was given");
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("polygon.geojson"), "kind", UM_FEATURE_LAKE), UM_OK);
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("levels.geojson"), "level", 0), UM_ERR_INPUT);
    expect_message(ctx, "features[0].properties.level = 1 is not a known feature kind");
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("levels.geojson"), "level", UM_FEATURE_OTHER), UM_OK);
    counts(f, &np, NULL, NULL);
    assert_int_equal(np, 13 + 1 + 4);
    int32_t kinds[18];
    assert_int_equal(um_features_copy_parts(f, NULL, NULL, kinds, NULL, 18), UM_OK);
    assert_true(kinds[13] == UM_FEATURE_LAKE);
    assert_true(kinds[14] == UM_FEATURE_OTHER && kinds[16] == UM_FEATURE_OTHER);
    assert_true(kinds[17] == UM_FEATURE_RIVER); /* "level": "river" is a kind name */
    um_features_destroy(f);
}

static void read_geojson_errors(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("feature.geojson"), NULL, 0), UM_OK);
    struct {
        const char *path;
        um_status status;
        const char *said;
    } cases[] = {
        {TEST_DATA("no_such_file.geojson"), UM_ERR_IO, "no_such_file.geojson' for reading"},
        {UNIMESH_TEST_DATA_DIR, UM_ERR_IO, "is a directory"},
        {TEST_DATA("bad_syntax.geojson"), UM_ERR_FILE_FORMAT, "malformed JSON at byte"},
        {TEST_DATA("truncated.geojson"), UM_ERR_FILE_FORMAT, "truncated file?"},
        {TEST_DATA("missing_coordinates.geojson"), UM_ERR_FILE_FORMAT, "features[1].geometry is a LineString with no"},
        {TEST_DATA("short_position.geojson"), UM_ERR_FILE_FORMAT, "features[0].geometry.coordinates[2] has 1 number"},
        {TEST_DATA("string_coordinate.geojson"), UM_ERR_FILE_FORMAT, "features[2].geometry.coordinates[1][1] is a string"},
        {TEST_DATA("latitude_range.geojson"), UM_ERR_COORDINATE_RANGE, "features[1].geometry.coordinates[3][1] = 90.5"},
        {TEST_DATA("unknown_kind.geojson"), UM_ERR_INPUT, "features[1].properties.kind = \"canal\""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        assert_int_equal(um_features_read_geojson(f, cases[i].path, NULL, 0), cases[i].status);
        expect_message(ctx, cases[i].said);
        int64_t np, nv;
        counts(f, &np, &nv, NULL);
        assert_true(np == 2 && nv == 5);
    }
    /* A value nested 100,000 deep (a 200 KB file) is named in the message,
     * not written out (that recursed until the stack overflowed); a FIFO is
     * refused instead of read (which blocked for ever). */
    char deep[] = "/tmp/unimesh_deep_XXXXXX";
    const int fd = mkstemp(deep);
    assert_true(fd >= 0);
    FILE *out = fdopen(fd, "w");
    fputs("{\"type\": \"FeatureCollection\", \"features\": [{\"type\": \"Feature\", \"properties\": {\"kind\": ", out);
    for (int i = 0; i < 100000; ++i) fputc('[', out);
    for (int i = 0; i < 100000; ++i) fputc(']', out);
    fputs("}, \"geometry\": {\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}}]}", out);
    fclose(out);
    assert_int_equal(um_features_read_geojson(f, deep, NULL, 0), UM_ERR_INPUT);
    expect_message(ctx, "properties.kind = an array of 1 value is not");
    remove(deep);
    char fifo[] = "/tmp/unimesh_fifo_XXXXXX";
    assert_true(mkdtemp(fifo) != NULL);
    char fifo_path[64];
    snprintf(fifo_path, sizeof fifo_path, "%s/in.geojson", fifo);
    assert_int_equal(mkfifo(fifo_path, 0600), 0);
    assert_int_equal(um_features_read_geojson(f, fifo_path, NULL, 0), UM_ERR_IO);
    expect_message(ctx, "not a regular file");
    remove(fifo_path), rmdir(fifo);
    /* With a default kind an unknown value is no error. */
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("unknown_kind.geojson"), NULL, UM_FEATURE_OTHER), UM_OK);
    assert_int_equal(um_features_read_geojson(f, NULL, NULL, 0), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "path is NULL");
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("feature.geojson"), NULL, 8), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "default_kind = 8");
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("feature.geojson"), NULL, -1), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "default_kind = -1");
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("feature.geojson"), "", 0), UM_ERR_INVALID_ARGUMENT);
    expect_message(ctx, "kind_property is empty");
    um_features_destroy(f);
}

static void copy_out_errors(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_add(f, 8, kLon, kLat, 2, kOffsets, kClosed, kKind, kIds), UM_OK);
    double lon[6], lat[6];
    int64_t off[3];
    int32_t kind[3];
    assert_int_equal(um_features_copy_points(f, lon, lat, 5), UM_ERR_BUFFER_TOO_SMALL);
    expect_message(ctx, "capacity = 5 is below the 6 elements the points needs");
    assert_int_equal(um_features_copy_points(f, lon, lat, -1), UM_ERR_BUFFER_TOO_SMALL);
    expect_message(ctx, "capacity = -1");
    assert_int_equal(um_features_copy_points(f, NULL, NULL, 6), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "lon_deg and lat_deg are both NULL");
    assert_int_equal(um_features_copy_parts(f, off, NULL, kind, NULL, 2), UM_ERR_BUFFER_TOO_SMALL);
    expect_message(ctx, "part_offsets (n_parts + 1)");
    assert_int_equal(um_features_copy_parts(f, NULL, NULL, kind, NULL, 1), UM_ERR_BUFFER_TOO_SMALL);
    expect_message(ctx, "capacity = 1 is below the 2 elements");
    assert_int_equal(um_features_copy_parts(f, NULL, NULL, NULL, NULL, 3), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "all NULL");
    /* An empty network copies nothing, with any buffers. */
    um_features *empty = NULL;
    assert_int_equal(um_features_create(ctx, &empty), UM_OK);
    int64_t first = -7;
    assert_int_equal(um_features_copy_parts(empty, &first, NULL, NULL, NULL, 1), UM_OK);
    assert_true(first == 0);
    assert_int_equal(um_features_copy_points(empty, lon, NULL, 0), UM_OK);
    um_features_destroy(empty);
    um_features_destroy(f);
}

static void null_destroyed_and_foreign_handles(void **state) {
    um_context *ctx = *state;
    int64_t n = 0;
    double x[2] = {0, 1};
    int64_t off[2] = {0, 2};
    int32_t i32[1] = {UM_FEATURE_RIVER}, zero[1] = {0};
    um_features *f = (um_features *)&n; /* never created */
    assert_int_equal(um_features_create(NULL, &f), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_features_create(ctx, NULL), UM_ERR_NULL_ARGUMENT);
    expect_message(ctx, "out is NULL");
    assert_int_equal(um_features_create((um_context *)&n, &f), UM_ERR_INVALID_HANDLE);
    assert_null(f);

    assert_int_equal(um_features_add(NULL, 2, x, x, 1, off, zero, i32, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_features_read_geojson(NULL, TEST_DATA("feature.geojson"), NULL, 0), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_features_counts(NULL, &n, &n, &n), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_features_copy_points(NULL, x, x, 2), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_features_copy_parts(NULL, off, zero, i32, zero, 2), UM_ERR_NULL_ARGUMENT);
    um_features_destroy(NULL);

    /* A handle of another kind. */
    um_options *o = NULL;
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    /* (no message: a foreign handle has no context to record it in) */
    assert_int_equal(um_features_counts((const um_features *)o, &n, NULL, NULL), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_features_add((um_features *)ctx, 2, x, x, 1, off, zero, i32, NULL), UM_ERR_INVALID_HANDLE);
    um_features_destroy((um_features *)o); /* not a features handle: ignored */
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_ALPHA, 1.2), UM_OK);
    um_options_destroy(o);

    /* Destroyed, twice, then used. */
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    um_features_destroy(f);
    um_features_destroy(f);
    assert_int_equal(um_features_add(f, 2, x, x, 1, off, zero, i32, NULL), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_features_read_geojson(f, TEST_DATA("feature.geojson"), NULL, 0), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_features_counts(f, &n, &n, &n), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_features_copy_points(f, x, x, 2), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_features_copy_parts(f, off, zero, i32, zero, 2), UM_ERR_INVALID_HANDLE);

    /* The network outlives its context. */
    um_context *other = NULL;
    assert_int_equal(um_context_create(&other), UM_OK);
    assert_int_equal(um_features_create(other, &f), UM_OK);
    um_context_destroy(other);
    assert_int_equal(um_features_add(f, 2, x, x, 1, off, zero, i32, NULL), UM_OK);
    assert_int_equal(um_features_add(f, 2, x, x, 1, off, i32, zero, NULL), UM_ERR_INVALID_ARGUMENT);
    counts(f, &n, NULL, NULL);
    assert_int_equal(n, 1);
    um_features_destroy(f);
}

static void shipped_data(void **state) {
    um_context *ctx = *state;
    um_features *f = shipped_features(ctx, 1);
    int64_t np, nv, ns;
    counts(f, &np, &nv, &ns);
    /* 813 closed shorelines (44,103 positions, closing ones stored once) and
     * 1,285 open rivers (16,512 positions). */
    assert_int_equal(np, 813 + 1285);
    assert_int_equal(nv, (44103 - 813) + 16512);
    assert_int_equal(ns, (44103 - 813) + (16512 - 1285));
    um_features_destroy(f);
}

/* A closed ring given twice - again in a later call, in the same call,
 * from another start or the other way round - is refused (the sides count
 * the rings around a point: two copies cancel, and all land became ocean),
 * leaving the features as they were; an open line given twice is not a
 * ring and stays allowed. */
static void repeated_rings_are_refused(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_add(f, 8, kLon, kLat, 2, kOffsets, kClosed, kKind, NULL), UM_OK);
    assert_int_equal(um_features_add(f, 8, kLon, kLat, 2, kOffsets, kClosed, kKind, NULL), UM_ERR_INPUT);
    expect_message(ctx, "is the same closed ring as part 1 read before");
    /* The same ring from its third point, the other way round, twice in one call. */
    const double lon[] = {11, 11, 10, 10, 11, 11};
    const double lat[] = {10, 11, 10, 10, 11, 10};
    const int64_t offsets[] = {0, 3, 6};
    const int32_t closed[] = {1, 1}, kind[] = {UM_FEATURE_LAKE, UM_FEATURE_LAKE};
    um_features *g = NULL;
    assert_int_equal(um_features_create(ctx, &g), UM_OK);
    assert_int_equal(um_features_add(g, 6, lon, lat, 2, offsets, closed, kind, NULL), UM_ERR_INPUT);
    expect_message(ctx, "the same closed ring as part 0");
    assert_int_equal(um_features_add(g, 3, lon, lat, 1, offsets, closed, kind, NULL), UM_OK);
    assert_int_equal(um_features_add(f, 3, lon, lat, 1, offsets, closed, kind, NULL), UM_ERR_INPUT);
    int64_t np, nv;
    counts(f, &np, &nv, NULL);
    assert_true(np == 2);
    const int32_t open[] = {0};
    assert_int_equal(um_features_add(f, 3, kLon, kLat, 1, offsets, open, kind, NULL), UM_OK);
    assert_int_equal(um_features_add(f, 3, kLon, kLat, 1, offsets, open, kind, NULL), UM_OK);
    um_features_destroy(g);
    um_features_destroy(f);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(create_add_count_copy, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(repeated_rings_are_refused, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(bad_input_is_rejected_and_changes_nothing, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(dateline_and_self_intersections_are_accepted, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(read_geojson, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(read_geojson_errors, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(copy_out_errors, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(null_destroyed_and_foreign_handles, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(shipped_data, setup_context, teardown_context),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
