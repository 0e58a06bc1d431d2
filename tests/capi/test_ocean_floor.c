/* CMocka suite: the time-step floor (UM_OPT_OCEAN_FLOOR) on planted narrow
 * features - an inlet and a strait narrower than the floor, a sea behind a
 * channel narrower than the cells - its report in the quality JSON
 * ("ocean_floor"), the passages it closes and those kept open
 * (UM_FEATURE_PASSAGE). */
#include <inttypes.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "context_fixture.h"
#include "shipped_features.h"
#include "unimesh.h"

#define H_KM 200.0
#define EARTH_KM 6371.22

static double degrees_of_km(double km) { return km / EARTH_KM * 180.0 / M_PI; }

/* Two continents (closed coastlines, counter-clockwise: land on the left):
 * the western one with an inlet 0.35 h wide and 12 degrees deep cut into
 * its east coast, the eastern one across a strait 0.3 h wide from it. */
static um_features *planted_coasts(um_context *ctx) {
    const double inlet = 0.5 * degrees_of_km(0.35 * H_KM), strait = degrees_of_km(0.3 * H_KM);
    const double lon[] = {-40, 0, 0, -12, -12, 0, 0, -40, /* west */
                          strait, 40, 40, strait /* east */};
    const double lat[] = {-20, -20, -inlet, -inlet, inlet, inlet, 20, 20, /* west */
                          -20, -20, 20, 20 /* east */};
    const int64_t offsets[] = {0, 8, 12};
    const int32_t closed[] = {1, 1}, kind[] = {UM_FEATURE_COASTLINE, UM_FEATURE_COASTLINE};
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_add(f, 12, lon, lat, 2, offsets, closed, kind, NULL), UM_OK);
    return f;
}

/* A continent (counter-clockwise) holding a sea of 20 by 16 degrees, joined
 * to the ocean east of it by a channel 0.3 h wide and 20 degrees long along
 * the equator (the sea's shore runs clockwise: land stays on the left). */
static um_features *sea_behind_a_channel(um_context *ctx) {
    const double w = 0.5 * degrees_of_km(0.3 * H_KM);
    const double lon[] = {-30, 30, 30, 10, 10, -10, -10, 10, 10, 30, 30, -30};
    const double lat[] = {-20, -20, -w, -w, -8, -8, 8, 8, w, w, 20, 20};
    const int64_t offsets[] = {0, 12};
    const int32_t closed[] = {1}, kind[] = {UM_FEATURE_COASTLINE};
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_add(f, 12, lon, lat, 1, offsets, closed, kind, NULL), UM_OK);
    return f;
}

/* The same, with a passage drawn along the channel (and one in the open
 * ocean, which keeps nothing open). */
static um_features *sea_with_a_passage(um_context *ctx) {
    um_features *f = sea_behind_a_channel(ctx);
    const double lon[] = {5, 35, 0}, lat[] = {0, 0, -40};
    const int64_t offsets[] = {0, 2, 3};
    const int32_t open[] = {0, 0}, kind[] = {UM_FEATURE_PASSAGE, UM_FEATURE_PASSAGE}, id[] = {90, 91};
    assert_int_equal(um_features_add(f, 3, lon, lat, 2, offsets, open, kind, id), UM_OK);
    return f;
}

static um_mesh *build_from(um_context *ctx, um_features *f, double floor) {
    um_spacing *h = NULL;
    um_options *o = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, H_KM, &h), UM_OK);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    if (floor >= 0) /* (else the default) */
        assert_int_equal(um_options_set_double(o, UM_OPT_OCEAN_FLOOR, floor), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, f, o, &m), UM_OK);
    assert_int_equal(um_mesh_optimise(m, o), UM_OK);
    um_options_destroy(o);
    um_features_destroy(f);
    um_spacing_destroy(h);
    return m;
}

static um_mesh *build(um_context *ctx, double floor) { return build_from(ctx, planted_coasts(ctx), floor); }

typedef struct {
    double floor, min_ratio, all_edges_min_ratio;
    int64_t ocean_edges, below_floor, regions, water_bodies, closed_passages, kept_open_cells;
    double closed_lon, closed_lat; /* the thinnest closed passage, if any */
    int64_t coast_edges, beyond_beta;  /* "coastline_fidelity" */
    double eps_mean;
} ocean_report;

static double member(const char *json, const char *key) {
    const char *at = strstr(json, "\"ocean_floor\"");
    assert_non_null(at);
    char quoted[64];
    snprintf(quoted, sizeof quoted, "\"%s\": ", key);
    at = strstr(at, quoted);
    assert_non_null(at);
    return strtod(at + strlen(quoted), NULL);
}

static char *quality_json(um_mesh *m) {
    int64_t needed = 0;
    assert_int_equal(um_mesh_quality_json(m, NULL, 0, &needed), UM_ERR_BUFFER_TOO_SMALL);
    char *json = malloc((size_t)needed);
    assert_non_null(json);
    assert_int_equal(um_mesh_quality_json(m, json, needed, &needed), UM_OK);
    return json;
}

static ocean_report report_of(um_mesh *m) {
    char *json = quality_json(m);
    ocean_report r = {member(json, "floor"), member(json, "min_ratio"), member(json, "all_edges_min_ratio"),
                      (int64_t)member(json, "ocean_edges"), (int64_t)member(json, "below_floor"),
                      (int64_t)member(json, "count"), (int64_t)member(json, "water_bodies"), 0,
                      (int64_t)member(json, "cells"), 0, 0};
    const char *anchor = "\"closed_passages\": {\"count\": ";
    const char *closed = strstr(strstr(json, "\"ocean_floor\""), anchor);
    assert_non_null(closed);
    r.closed_passages = strtoll(closed + strlen(anchor), NULL, 10);
    if (r.closed_passages > 0) {
        const char *list = strstr(closed, "\"thinnest\": [[");
        assert_non_null(list);
        assert_int_equal(sscanf(list, "\"thinnest\": [[%lf, %lf", &r.closed_lon, &r.closed_lat), 2);
    }
    const char *coast = strstr(json, "\"coastline_fidelity\": ");
    assert_non_null(coast);
    assert_int_equal(sscanf(coast, "\"coastline_fidelity\": {\"beta\": %*f, \"restricted_edges\": %" SCNd64
                            ", \"eps_over_beta_h\": {\"mean\": %lf, \"max\": %*f}, \"beyond_beta\": %" SCNd64,
                            &r.coast_edges, &r.eps_mean, &r.beyond_beta), 3);
    free(json);
    return r;
}

/* Without the floor the inlet and the strait leave ocean edges well below
 * half the spacing; with the floor at 0.7 h (the default) no ocean edge is
 * below it, every triangle still holds its orthocentre, at most one in ten
 * thousand is obtuse, and the ocean (one body around the two continents) is
 * one region of the ocean mesh. */
static void the_floor_lifts_the_short_ocean_edges(void **state) {
    um_context *ctx = *state;
    um_mesh *without = build(ctx, 0.0);
    const ocean_report a = report_of(without);
    assert_true(a.floor == 0.0);
    assert_true(a.min_ratio < 0.5);
    um_mesh_destroy(without);

    um_mesh *with = build(ctx, -1);
    const ocean_report b = report_of(with);
    print_message("ocean edges: min dcEdge/h %.3f without the floor, %.3f with it (%lld of %lld below 0.7)\n",
                  a.min_ratio, b.min_ratio, (long long)b.below_floor, (long long)b.ocean_edges);
    print_message("coastline: %lld restricted edges, eps/(beta h) mean %.3f, %lld beyond beta h without the "
                  "floor; %lld, %.3f, %lld with it\n", (long long)a.coast_edges, a.eps_mean,
                  (long long)a.beyond_beta, (long long)b.coast_edges, b.eps_mean, (long long)b.beyond_beta);
    /* The cost of the floor, visible: the inlet and the strait are no longer followed. */
    assert_true(b.coast_edges > 0 && b.coast_edges < a.coast_edges);
    assert_true(b.floor == 0.7);
    assert_true(b.ocean_edges > 30000);
    assert_true(b.min_ratio >= 0.7);
    assert_int_equal(b.below_floor, 0);
    assert_true(b.all_edges_min_ratio <= b.min_ratio);
    assert_int_equal(b.regions, 1);
    int64_t obtuse = 0, off_centre = -1;
    assert_int_equal(um_mesh_quality_counts(with, &obtuse, &off_centre), UM_OK);
    assert_int_equal(off_centre, 0);
    int64_t triangles = 0;
    assert_int_equal(um_mesh_counts(with, NULL, &triangles, NULL, NULL), UM_OK);
    assert_true(obtuse * 10000 <= triangles);
    um_mesh_destroy(with);
}

/* The channel is far narrower than the cells: the mesh closes it, and the
 * report says where. A passage drawn along it keeps it open: its cells join
 * the ocean mesh, one region, their short edges counted apart. */
static void a_closed_channel_is_reported_and_a_passage_keeps_it_open(void **state) {
    um_context *ctx = *state;
    um_mesh *closed = build_from(ctx, sea_behind_a_channel(ctx), -1);
    const ocean_report a = report_of(closed);
    um_mesh_destroy(closed);
    print_message("closed: %lld regions, %lld water bodies, %lld closed passages (thinnest at %.2f, %.2f)\n",
                  (long long)a.regions, (long long)a.water_bodies, (long long)a.closed_passages, a.closed_lon,
                  a.closed_lat);
    assert_int_equal(a.regions, 2);
    assert_int_equal(a.water_bodies, 1);
    assert_int_equal(a.closed_passages, 1);
    assert_true(a.closed_lon > 8 && a.closed_lon < 32 && fabs(a.closed_lat) < 3);
    assert_int_equal(a.kept_open_cells, 0);

    um_mesh *kept = build_from(ctx, sea_with_a_passage(ctx), -1);
    const ocean_report b = report_of(kept);
    print_message("kept open: %lld regions, %lld closed passages, %lld cells kept open, %lld below the floor "
                  "outside them\n", (long long)b.regions, (long long)b.closed_passages,
                  (long long)b.kept_open_cells, (long long)b.below_floor);
    assert_int_equal(b.regions, 1);
    assert_int_equal(b.water_bodies, 1);
    assert_int_equal(b.closed_passages, 0);
    assert_true(b.kept_open_cells >= 3);
    assert_int_equal(b.below_floor, 0);
    /* The passages are not features of the mesh: no vertex on them. */
    int64_t n = 0;
    assert_int_equal(um_mesh_counts(kept, &n, NULL, NULL, NULL), UM_OK);
    int32_t *parts = malloc((size_t)n * sizeof(int32_t));
    assert_non_null(parts);
    assert_int_equal(um_mesh_copy_vertex_parts(kept, 0, parts, n), UM_OK);
    for (int64_t v = 0; v < n; ++v) assert_true(parts[v] == -1 || parts[v] == 0);
    free(parts);
    um_mesh_destroy(kept);
}

static void copy_points(um_mesh *m, double **lon, double **lat, int64_t *n) {
    assert_int_equal(um_mesh_counts(m, n, NULL, NULL, NULL), UM_OK);
    *lon = malloc((size_t)*n * sizeof(double)), *lat = malloc((size_t)*n * sizeof(double));
    assert_non_null(*lon), assert_non_null(*lat);
    assert_int_equal(um_mesh_copy_vertices(m, *lon, *lat, *n), UM_OK);
}

/* The floor's removals are serial and ordered, and so is the walk that
 * keeps the passages open: the same mesh and the same report (the cells
 * kept open, the closed passages) for 1 and 2 threads. */
static void the_floor_is_bit_identical_for_any_thread_count(void **state) {
    um_context *ctx = *state;
    for (int planted = 0; planted < 2; ++planted) {
        double *lon[2], *lat[2];
        int64_t n[2];
        char *json[2];
        for (int run = 0; run < 2; ++run) {
            assert_int_equal(um_context_set_threads(ctx, run + 1), UM_OK);
            um_mesh *m = planted == 0 ? build(ctx, 0.7) : build_from(ctx, sea_with_a_passage(ctx), 0.7);
            copy_points(m, &lon[run], &lat[run], &n[run]);
            json[run] = quality_json(m);
            um_mesh_destroy(m);
        }
        assert_int_equal(n[0], n[1]);
        assert_memory_equal(lon[0], lon[1], (size_t)n[0] * sizeof(double));
        assert_memory_equal(lat[0], lat[1], (size_t)n[0] * sizeof(double));
        /* (The report's seconds differ: its ocean sections are compared.) */
        for (int run = 0; run < 2; ++run) {
            char *from = strstr(json[run], "\"ocean_floor\""), *to = strstr(json[run], "\"before_optimisation\"");
            assert_non_null(from), assert_non_null(to);
            *to = '\0';
            memmove(json[run], from, strlen(from) + 1);
        }
        assert_string_equal(json[0], json[1]);
        for (int run = 0; run < 2; ++run) free(lon[run]), free(lat[run]), free(json[run]);
    }
    assert_int_equal(um_context_set_threads(ctx, 0), UM_OK);
}

/* On the shipped coastlines and rivers the floor holds by the report's own
 * sides (refine::vertex_sides): at 64 km a vertex the passes had made beside
 * the Black Sea's coast kept a land neighbour's side, though its triangles
 * were all on the ocean side, and the report found an ocean edge at 0.65 h
 * that the pass had taken for a land one. */
static void the_floor_holds_by_the_reports_sides(void **state) {
    um_context *ctx = *state;
    um_features *f = shipped_features(ctx, 1);
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 64.0, &h), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, f, NULL, &m), UM_OK);
    assert_int_equal(um_mesh_optimise(m, NULL), UM_OK);
    const ocean_report r = report_of(m);
    print_message("coast + rivers 64 km: min dcEdge/h %.3f over %lld ocean edges, %lld below the floor\n",
                  r.min_ratio, (long long)r.ocean_edges, (long long)r.below_floor);
    assert_true(r.ocean_edges > 250000);
    assert_int_equal(r.below_floor, 0);
    assert_true(r.min_ratio >= 0.7);
    um_mesh_destroy(m);
    um_features_destroy(f);
    um_spacing_destroy(h);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_floor_lifts_the_short_ocean_edges),
        cmocka_unit_test(a_closed_channel_is_reported_and_a_passage_keeps_it_open),
        cmocka_unit_test(the_floor_holds_by_the_reports_sides),
        cmocka_unit_test(the_floor_is_bit_identical_for_any_thread_count),
    };
    return cmocka_run_group_tests(tests, setup_context, teardown_context);
}
