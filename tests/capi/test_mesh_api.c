/* CMocka suite: the refinement stage through the C ABI (um_mesh_*). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "context_fixture.h"
#include "shipped_features.h"
#include "unimesh.h"

#define DEG (M_PI / 180.0)
static const double kRadiusKm = 6371.22;

static double arc(double lon1, double lat1, double lon2, double lat2) {
    double a[3] = {cos(lat1 * DEG) * cos(lon1 * DEG), cos(lat1 * DEG) * sin(lon1 * DEG), sin(lat1 * DEG)};
    double b[3] = {cos(lat2 * DEG) * cos(lon2 * DEG), cos(lat2 * DEG) * sin(lon2 * DEG), sin(lat2 * DEG)};
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

typedef struct {
    int64_t nv, nt, nr, nf;
    double *lon, *lat;
    int32_t *tri, *vparts, *redges, *rparts, *vsides, *tsides;
} mesh_copy;

static mesh_copy copy_out(um_mesh *m) {
    mesh_copy c;
    assert_int_equal(um_mesh_counts(m, &c.nv, &c.nt, &c.nr, &c.nf), UM_OK);
    c.lon = malloc(c.nv * sizeof(double)), c.lat = malloc(c.nv * sizeof(double));
    c.tri = malloc(3 * c.nt * sizeof(int32_t)), c.vparts = malloc(c.nv * sizeof(int32_t));
    c.redges = malloc((2 * c.nr + 1) * sizeof(int32_t)), c.rparts = malloc((c.nr + 1) * sizeof(int32_t));
    c.vsides = malloc(c.nv * sizeof(int32_t)), c.tsides = malloc(c.nt * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_vertices(m, c.lon, c.lat, c.nv), UM_OK);
    assert_int_equal(um_mesh_copy_triangles(m, 0, c.tri, 3 * c.nt), UM_OK);
    assert_int_equal(um_mesh_copy_vertex_parts(m, 0, c.vparts, c.nv), UM_OK);
    assert_int_equal(um_mesh_copy_restricted_edges(m, 0, c.redges, c.rparts, c.nr), UM_OK);
    assert_int_equal(um_mesh_copy_vertex_sides(m, c.vsides, c.nv), UM_OK);
    assert_int_equal(um_mesh_copy_triangle_sides(m, c.tsides, c.nt), UM_OK);
    return c;
}

static void free_copy(mesh_copy *c) {
    free(c->lon), free(c->lat), free(c->tri), free(c->vparts), free(c->redges), free(c->rparts);
    free(c->vsides), free(c->tsides);
}

/* Every edge length in units of the (constant) spacing. */
static void edge_range(const mesh_copy *c, double h_km, double *lo, double *hi) {
    *lo = 1e300, *hi = 0;
    for (int64_t f = 0; f < c->nt; ++f)
        for (int k = 0; k < 3; ++k) {
            int32_t a = c->tri[3 * f + k], b = c->tri[3 * f + (k + 1) % 3];
            double l = arc(c->lon[a], c->lat[a], c->lon[b], c->lat[b]) * kRadiusKm / h_km;
            if (l < *lo) *lo = l;
            if (l > *hi) *hi = l;
        }
}

static void uniform_sphere(void **state) {
    um_context *ctx = *state;
    um_spacing *h = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 500.0, &h), UM_OK);
    um_mesh *m = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_OK);
    mesh_copy c = copy_out(m);
    assert_int_equal(c.nt, 2 * c.nv - 4);
    assert_int_equal(c.nr, 0);
    double lo, hi;
    edge_range(&c, 500.0, &lo, &hi);
    assert_true(lo > 0.5 && hi < 1.54);
    for (int64_t i = 0; i < c.nv; ++i) assert_int_equal(c.vparts[i], -1);
    free_copy(&c);
    um_mesh_destroy(m);
    um_spacing_destroy(h);
}

/* The bound for uniform meshes, through the C API: at 240 and 120 km
 * every edge of the refined mesh lies within [0.75, 1.35] h (the surface
 * pass leaves 2 % above 1.35 h; the relaxation moves them in). Without the
 * relaxation (refine_relax = 0) some edges are outside: the option is what
 * does it, and the cells are about as many either way. */
static void uniform_edges_within_the_band(void **state) {
    um_context *ctx = *state;
    for (int i = 0; i < 2; ++i) {
        const double km = i == 0 ? 240.0 : 120.0;
        um_spacing *h = NULL;
        assert_int_equal(um_spacing_create_constant(ctx, km, &h), UM_OK);
        um_options *o = NULL;
        assert_int_equal(um_options_create(ctx, &o), UM_OK);
        /* the frontal refinement's edges (a lattice's are inside already) */
        assert_int_equal(um_options_set_int(o, UM_OPT_REFINE_LATTICE, 0), UM_OK);
        int64_t cells[2];
        for (int relax = 1; relax >= 0; --relax) {
            assert_int_equal(um_options_set_int(o, UM_OPT_REFINE_RELAX, relax), UM_OK);
            um_mesh *m = NULL;
            assert_int_equal(um_mesh_refine(ctx, h, NULL, o, &m), UM_OK);
            mesh_copy c = copy_out(m);
            double lo, hi;
            edge_range(&c, km, &lo, &hi);
            print_message("%.0f km, relax %d: %lld cells, edges %.4f..%.4f h\n", km, relax, (long long)c.nv, lo, hi);
            if (relax) assert_true(lo > 0.75 && hi < 1.35);
            else assert_true(hi > 1.35);
            cells[relax] = c.nv;
            free_copy(&c);
            um_mesh_destroy(m);
        }
        /* It moves vertices (a crowded spot may lose one): about as many cells. */
        assert_true(cells[1] <= cells[0] && cells[0] - cells[1] <= cells[0] / 1000);
        um_options_destroy(o);
        um_spacing_destroy(h);
    }
}

static void same_mesh_for_any_thread_count(void **state) {
    um_context *ctx = *state;
    um_spacing *h = NULL;
    assert_int_equal(um_spacing_create_preset(ctx, "EC60to30", &h), UM_OK);
    um_spacing *coarse = NULL;
    /* EC60to30 scaled up: clamp to keep the test quick */
    assert_int_equal(um_spacing_create_constant(ctx, 400.0, &coarse), UM_OK);
    /* At 60 km the surface pass goes by territories (the first two cases are
     * refined serially, after the seeds). */
    um_spacing *fine = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 60.0, &fine), UM_OK);
    /* Without and with features (the boundary passes and their parallel
     * searches for restricted edges). */
    um_features *f = shipped_features(ctx, 0);
    for (int with_features = 0; with_features <= 2; ++with_features) {
        mesh_copy ref = {0};
        for (int threads = 1; threads <= 3; ++threads) {
            assert_int_equal(um_context_set_threads(ctx, threads), UM_OK);
            um_mesh *m = NULL;
            assert_int_equal(um_mesh_refine(ctx, with_features == 2 ? fine : coarse, with_features ? f : NULL,
                                            NULL, &m), UM_OK);
            mesh_copy c = copy_out(m);
            if (threads == 1) {
                ref = c;
            } else {
                assert_int_equal(c.nv, ref.nv);
                assert_int_equal(c.nr, ref.nr);
                assert_memory_equal(c.lon, ref.lon, c.nv * sizeof(double));
                assert_memory_equal(c.tri, ref.tri, 3 * c.nt * sizeof(int32_t));
                assert_memory_equal(c.lat, ref.lat, c.nv * sizeof(double));
                assert_memory_equal(c.redges, ref.redges, 2 * c.nr * sizeof(int32_t));
                assert_memory_equal(c.vparts, ref.vparts, c.nv * sizeof(int32_t));
                assert_memory_equal(c.tsides, ref.tsides, c.nt * sizeof(int32_t));
                free_copy(&c);
            }
            um_mesh_destroy(m);
        }
        free_copy(&ref);
    }
    um_features_destroy(f);
    um_spacing_destroy(h);
    um_spacing_destroy(coarse);
    um_spacing_destroy(fine);
}

/* The shipped GSHHG low-resolution coastlines at 480 km: restricted edges
 * close to the coast, no edge below h/2, land and ocean told apart. (The
 * paper's bounds, without the time-step floor: it filters detail narrower
 * than 0.7 h, leaving longer restricted edges there; test_ocean_floor.) */
static void global_coastline(void **state) {
    um_context *ctx = *state;
    um_options *no_floor = NULL;
    assert_int_equal(um_options_create(ctx, &no_floor), UM_OK);
    assert_int_equal(um_options_set_double(no_floor, UM_OPT_OCEAN_FLOOR, 0.0), UM_OK);
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_global_l.geojson", NULL, 0),
                     UM_OK);
    const double h_km = 480.0;
    um_spacing *h = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, h_km, &h), UM_OK);
    um_mesh *m = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, f, no_floor, &m), UM_OK);
    mesh_copy c = copy_out(m);
    assert_int_equal(c.nt, 2 * c.nv - 4);
    assert_true(c.nr > 100);
    double lo, hi;
    edge_range(&c, h_km, &lo, &hi);
    assert_true(lo > 0.5);
    /* restricted edges are shorter than alpha h */
    for (int64_t i = 0; i < c.nr; ++i) {
        int32_t a = c.redges[2 * i], b = c.redges[2 * i + 1];
        assert_true(arc(c.lon[a], c.lat[a], c.lon[b], c.lat[b]) * kRadiusKm < 4.0 / 3.0 * h_km);
    }
    /* sides: the middle of the Sahara is land, the middle of the Pacific ocean */
    int64_t land = 0, ocean = 0, coastal = 0;
    for (int64_t i = 0; i < c.nv; ++i) {
        land += c.vsides[i] == UM_SIDE_LAND, ocean += c.vsides[i] == UM_SIDE_OCEAN;
        coastal += c.vsides[i] == UM_SIDE_COASTAL;
        if (fabs(c.lat[i] - 23) < 4 && fabs(c.lon[i] - 15) < 6) assert_int_equal(c.vsides[i], UM_SIDE_LAND);
        if (fabs(c.lat[i]) < 8 && fabs(c.lon[i] + 150) < 10) assert_int_equal(c.vsides[i], UM_SIDE_OCEAN);
    }
    assert_true(land > 0.15 * c.nv && ocean > 0.5 * c.nv && coastal > 0);
    /* With the topology check (refine_topology_check): a few more points, at
     * the folds of Tri|Gamma (islands and inlets near the spacing). */
    um_options *o = NULL;
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    assert_int_equal(um_options_set_int(o, UM_OPT_REFINE_TOPOLOGY_CHECK, 1), UM_OK);
    assert_int_equal(um_options_set_double(o, UM_OPT_OCEAN_FLOOR, 0.0), UM_OK);
    um_mesh *checked = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, f, o, &checked), UM_OK);
    int64_t nv_checked = 0;
    assert_int_equal(um_mesh_counts(checked, &nv_checked, NULL, NULL, NULL), UM_OK);
    assert_true(nv_checked > c.nv && nv_checked < 1.05 * c.nv);
    um_mesh_destroy(checked);
    um_options_destroy(o);
    um_options_destroy(no_floor);
    free_copy(&c);
    um_mesh_destroy(m);
    um_spacing_destroy(h);
    um_features_destroy(f);
}

/* Spacings as coarse as the gaps between the world's coastlines (2500 km
 * and more) leave the geodesic lattice too few points away from them: the
 * refinement starts from the icosahedron instead, and the mesh is whole. */
static void coastlines_at_continental_spacings(void **state) {
    um_context *ctx = *state;
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_global_l.geojson", NULL, 0),
                     UM_OK);
    const double spacings_km[] = {2500.0, 4000.0, 8000.0};
    for (int k = 0; k < 3; ++k) {
        um_spacing *h = NULL;
        um_mesh *m = NULL;
        assert_int_equal(um_spacing_create_constant(ctx, spacings_km[k], &h), UM_OK);
        assert_int_equal(um_mesh_refine(ctx, h, f, NULL, &m), UM_OK);
        assert_int_equal(um_mesh_optimise(m, NULL), UM_OK);
        int64_t nv = 0, nt = 0;
        assert_int_equal(um_mesh_counts(m, &nv, &nt, NULL, NULL), UM_OK);
        assert_true(nv >= 12);
        assert_int_equal(nt, 2 * nv - 4);
        um_mesh_destroy(m);
        um_spacing_destroy(h);
    }
    um_features_destroy(f);
}

/* The Mid-Atlantic unified case of the refinement issue: the spacing file
 * (2 km at the coast), the full-resolution coastline and rivers (17 input
 * vertices per 2-km edge, metre-long segments, rivers crossing each other
 * and the coast), about 800 k cells. No edge anywhere is shorter than h/2
 * (features below the spacing are left out, not followed); the sides are
 * ocean and land. (The paper's bounds: without the time-step floor.) */
static void midatlantic_full_resolution(void **state) {
    um_context *ctx = *state;
    um_options *no_floor = NULL;
    assert_int_equal(um_options_create(ctx, &no_floor), UM_OK);
    assert_int_equal(um_options_set_double(no_floor, UM_OPT_OCEAN_FLOOR, 0.0), UM_OK);
    um_context_set_threads(ctx, 0);
    um_spacing *h = NULL;
    um_features *f = NULL;
    assert_int_equal(um_spacing_create_from_file(ctx, UNIMESH_DATA_DIR "/midatlantic_cellwidth.nc", &h), UM_OK);
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_midatlantic_f.geojson", NULL, 0), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/rivers_midatlantic_f.geojson", NULL, 0), UM_OK);
    um_mesh *m = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, f, no_floor, &m), UM_OK);
    um_options_destroy(no_floor);
    mesh_copy c = copy_out(m);
    assert_int_equal(c.nt, 2 * c.nv - 4);
    assert_true(c.nr > 1000);
    /* h at every edge midpoint (lon/lat of the normalised chord midpoint) */
    const int64_t ne = 3 * c.nt;
    double *mlon = malloc(ne * sizeof(double)), *mlat = malloc(ne * sizeof(double)), *km = malloc(ne * sizeof(double));
    double *len = malloc(ne * sizeof(double));
    for (int64_t e = 0; e < ne; ++e) {
        const int32_t a = c.tri[e], b = c.tri[e - e % 3 + (e % 3 + 1) % 3];
        const double la = c.lat[a] * DEG, lb = c.lat[b] * DEG, oa = c.lon[a] * DEG, ob = c.lon[b] * DEG;
        const double x = cos(la) * cos(oa) + cos(lb) * cos(ob), y = cos(la) * sin(oa) + cos(lb) * sin(ob),
                     z = sin(la) + sin(lb);
        mlon[e] = atan2(y, x) / DEG, mlat[e] = atan2(z, sqrt(x * x + y * y)) / DEG;
        len[e] = arc(c.lon[a], c.lat[a], c.lon[b], c.lat[b]) * kRadiusKm;
    }
    assert_int_equal(um_spacing_evaluate(h, ne, mlon, mlat, km), UM_OK);
    double shortest = 1e300;
    for (int64_t e = 0; e < ne; ++e) shortest = fmin(shortest, len[e] / km[e]);
    assert_true(shortest > 0.5);
    /* restricted edges: shorter than alpha h at their midpoint */
    int64_t too_long = 0;
    double worst = 0;
    for (int64_t i = 0; i < c.nr; ++i) {
        const int32_t a = c.redges[2 * i], b = c.redges[2 * i + 1];
        const double la = c.lat[a] * DEG, lb = c.lat[b] * DEG, oa = c.lon[a] * DEG, ob = c.lon[b] * DEG;
        const double x = cos(la) * cos(oa) + cos(lb) * cos(ob), y = cos(la) * sin(oa) + cos(lb) * sin(ob),
                     z = sin(la) + sin(lb);
        /* h along the edge: at both ends and the middle (the refinement
         * reads it at the crossing with the feature, somewhere on the dual) */
        double qlon[3] = {c.lon[a], c.lon[b], atan2(y, x) / DEG}, qlat[3] = {c.lat[a], c.lat[b], atan2(z, sqrt(x * x + y * y)) / DEG};
        double hq[3];
        assert_int_equal(um_spacing_evaluate(h, 3, qlon, qlat, hq), UM_OK);
        const double ratio = arc(c.lon[a], c.lat[a], c.lon[b], c.lat[b]) * kRadiusKm / fmax(hq[0], fmax(hq[1], hq[2]));
        worst = fmax(worst, ratio);
        too_long += ratio >= 4.0 / 3.0;
    }
    /* The surface pass changes some dual edges near Gamma (1.5 % of the
     * restricted edges came out longer than alpha h, up to 1.5 h, when the
     * boundary pass ran only first); the boundary passes that follow it leave
     * none. */
    print_message("Mid-Atlantic: %lld cells, %lld restricted edges, %lld filtered, %lld longer than alpha h "
                  "(worst %.3f h)\n", (long long)c.nv, (long long)c.nr, (long long)c.nf, (long long)too_long, worst);
    assert_int_equal(too_long, 0);
    assert_true(worst < 4.0 / 3.0);
    int64_t land = 0, ocean = 0;
    for (int64_t i = 0; i < c.nv; ++i) land += c.vsides[i] == UM_SIDE_LAND, ocean += c.vsides[i] == UM_SIDE_OCEAN;
    assert_true(land > 0 && ocean > 0);
    free(mlon), free(mlat), free(km), free(len);
    free_copy(&c);
    um_mesh_destroy(m);
    um_features_destroy(f);
    um_spacing_destroy(h);
}

static void bad_input(void **state) {
    um_context *ctx = *state;
    um_spacing *h = NULL;
    um_mesh *m = (um_mesh *)&h;
    assert_int_equal(um_mesh_refine(ctx, NULL, NULL, NULL, &m), UM_ERR_NULL_ARGUMENT);
    assert_null(m);
    assert_int_equal(um_mesh_refine(ctx, (um_spacing *)ctx, NULL, NULL, &m), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_spacing_create_constant(ctx, 800.0, &h), UM_OK);
    assert_int_equal(um_mesh_refine(NULL, h, NULL, NULL, &m), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_mesh_refine(ctx, h, (um_features *)h, NULL, &m), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_OK);
    int64_t nv;
    assert_int_equal(um_mesh_counts(m, &nv, NULL, NULL, NULL), UM_OK);
    double lon[4], lat[4];
    assert_int_equal(um_mesh_copy_vertices(m, lon, lat, 4), UM_ERR_BUFFER_TOO_SMALL);
    int32_t *tri = malloc(3 * 2 * nv * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_triangles(m, 5, tri, 6 * nv), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_mesh_copy_restricted_edges(m, 0, NULL, NULL, 0), UM_ERR_NULL_ARGUMENT);
    free(tri);
    um_mesh_destroy(m);
    um_mesh_destroy(m);
    assert_int_equal(um_mesh_counts(m, &nv, NULL, NULL, NULL), UM_ERR_INVALID_HANDLE);
    um_spacing_destroy(h);
}

/* A regional mesh through the C ABI: a domain ring across the antimeridian;
 * its MPAS mesh holds the cells inside only, with the boundary layers, and
 * its JIGSAW file and river report are the domain's. */
static void regional_mesh(void **state) {
    um_context *ctx = *state;
    const double lon[4] = {150, -150, -150, 150}, lat[4] = {-30, -30, 30, 30};
    const int64_t offsets[2] = {0, 4};
    const int32_t closed = 1, kind = UM_FEATURE_DOMAIN;
    um_features *f = NULL;
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_add(f, 4, lon, lat, 1, offsets, &closed, &kind, NULL), UM_OK);
    assert_int_equal(um_spacing_create_constant(ctx, 300.0, &h), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, f, NULL, &m), UM_OK);
    assert_int_equal(um_mesh_optimise(m, NULL), UM_OK);
    int64_t nv = 0, cells = 0, edges = 0, vertices = 0, max_edges = 0;
    assert_int_equal(um_mesh_counts(m, &nv, NULL, NULL, NULL), UM_OK);
    assert_int_equal(um_mesh_mpas_dimensions(m, &cells, &edges, &vertices, &max_edges), UM_OK);
    assert_true(cells > 100 && cells < nv);
    double *lat_cell = malloc(cells * sizeof(double)), *lon_cell = malloc(cells * sizeof(double));
    int32_t *layer = malloc(cells * sizeof(int32_t));
    assert_int_equal(um_mesh_copy_mpas_real(m, "latCell", lat_cell, cells), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_real(m, "lonCell", lon_cell, cells), UM_OK);
    assert_int_equal(um_mesh_copy_mpas_int(m, "bdyMaskCell", 0, layer, cells), UM_OK);
    int per_layer[8] = {0};
    for (int64_t c = 0; c < cells; ++c) {
        const double east = fmod(lon_cell[c] / DEG + 360.0, 360.0);
        assert_true(fabs(lat_cell[c] / DEG) < 30 && east > 150 && east < 210);
        assert_true(layer[c] >= 0 && layer[c] <= 7);
        ++per_layer[layer[c]];
    }
    for (int k = 0; k < 8; ++k) assert_true(per_layer[k] > 0);
    /* The JIGSAW file: the MPAS mesh's cells and the triangles between them. */
    assert_int_equal(um_mesh_write_jigsaw(m, "test_mesh_api_regional.msh"), UM_OK);
    FILE *msh = fopen("test_mesh_api_regional.msh", "r");
    assert_non_null(msh);
    char line[256];
    long long points = -1, triangles = -1;
    while (fgets(line, sizeof line, msh)) sscanf(line, "POINT=%lld", &points), sscanf(line, "TRIA3=%lld", &triangles);
    fclose(msh);
    remove("test_mesh_api_regional.msh");
    assert_int_equal(points, cells);
    assert_true(triangles > 0 && triangles < vertices);
    /* Its river report is of the domain (no rivers here: none routed). */
    char report[512];
    int64_t needed = 0;
    assert_int_equal(um_mesh_river_report_json(m, report, sizeof report, &needed), UM_OK);
    assert_non_null(strstr(report, "\"river_cells\": 0"));
    assert_non_null(strstr(report, "\"boundary_outlets\": 0"));
    free(lat_cell), free(lon_cell), free(layer);
    um_mesh_destroy(m);
    um_spacing_destroy(h);
    um_features_destroy(f);
}

/* The WGS84 ellipsoid through the options: a flattening out of range is
 * refused by name; the MPAS cells' areas add up to the ellipsoid's. */
static void wgs84_mesh(void **state) {
    um_context *ctx = *state;
    um_options *opts = NULL;
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_options_create(ctx, &opts), UM_OK);
    assert_int_equal(um_options_set_double(opts, UM_OPT_SURFACE_FLATTENING, 0.5), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "surface_flattening"));
    assert_int_equal(um_options_set_double(opts, UM_OPT_SPHERE_RADIUS, 6378137.0), UM_OK);
    assert_int_equal(um_options_set_double(opts, UM_OPT_SURFACE_FLATTENING, 1 / 298.257223563), UM_OK);
    assert_int_equal(um_spacing_create_constant(ctx, 480.0, &h), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, NULL, opts, &m), UM_OK);
    assert_int_equal(um_mesh_optimise(m, opts), UM_OK);
    int64_t cells = 0, edges = 0, vertices = 0, max_edges = 0;
    assert_int_equal(um_mesh_mpas_dimensions(m, &cells, &edges, &vertices, &max_edges), UM_OK);
    double *area = malloc(cells * sizeof(double)), sum = 0;
    assert_int_equal(um_mesh_copy_mpas_real(m, "areaCell", area, cells), UM_OK);
    for (int64_t c = 0; c < cells; ++c) sum += area[c];
    assert_true(fabs(sum / 5.100656217240886e14 - 1) < 1e-10);
    free(area);
    um_mesh_destroy(m);
    um_spacing_destroy(h);
    um_options_destroy(opts);
}

static double nan_south(void *user, double lon, double lat) {
    (void)user, (void)lon;
    return lat < -60 ? NAN : 900.0;
}

static void spacing_callback_failure_names_the_point(void **state) {
    um_context *ctx = *state;
    um_spacing *h = NULL;
    assert_int_equal(um_spacing_create_callback(ctx, nan_south, NULL, &h), UM_OK);
    um_mesh *m = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_ERR_NONFINITE_INPUT);
    assert_null(m);
    assert_non_null(strstr(um_context_last_error(ctx), "spacing"));
    assert_non_null(strstr(um_context_last_error(ctx), "lat"));
    /* The same point named for any number of threads. */
    char first[1024];
    snprintf(first, sizeof first, "%s", um_context_last_error(ctx));
    for (int32_t threads = 1; threads <= 3; threads += 2) {
        assert_int_equal(um_context_set_threads(ctx, threads), UM_OK);
        assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_ERR_NONFINITE_INPUT);
        assert_string_equal(um_context_last_error(ctx), first);
    }
    assert_int_equal(um_context_set_threads(ctx, 0), UM_OK);
    um_spacing_destroy(h);
}

/* A slow spacing callback (200 us a call) does not keep cancel out: the
 * refinement reports progress every quarter of a second whatever its
 * steps cost. The 240 km refinement takes some 60,000 calls (12 s); a
 * cancel asked for at the first report of a refinement stage after 2,000
 * calls (so a report made during its work, not at its start) ends it after
 * a few thousand. */
typedef struct {
    long calls;
    int reports;
    int fast;  /* while set, calls are neither slow nor counted */
} slow_run;

static double slow_spacing(void *user, double lon, double lat) {
    (void)lon, (void)lat;
    slow_run *run = user;
    if (run->fast) return 240.0;
    ++run->calls;
    struct timespec pause = {0, 200000};
    nanosleep(&pause, NULL);
    return 240.0;
}

static int32_t cancel_after_2000_calls(void *user, const char *stage, double fraction) {
    (void)fraction;
    slow_run *run = user;
    const int refining = strncmp(stage, "refine ", 7) == 0;
    run->reports += refining;
    return refining && run->calls > 2000;
}

static void a_slow_spacing_callback_can_be_cancelled(void **state) {
    um_context *ctx = *state;
    slow_run run = {0, 0, 0};
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_callback(ctx, slow_spacing, &run, &h), UM_OK);
    assert_int_equal(um_context_set_progress(ctx, cancel_after_2000_calls, &run), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_CANCELLED);
    assert_null(m);
    print_message("spacing calls before the cancel took: %ld\n", run.calls);
    assert_true(run.calls < 20000);
    assert_int_equal(um_context_set_progress(ctx, NULL, NULL), UM_OK);
    um_context_clear_error(ctx);
    um_spacing_destroy(h);
}

/* The same for the optimisation, whose every outer iteration reads h at
 * every vertex, and for the quality measures around it: a spacing that
 * turns slow once the mesh is refined is cancelled within one block of the
 * quality measure (32,768 edges, one call each: the whole 240 km mesh),
 * not after the 200,000 calls the optimisation makes. */
static int32_t cancel_optimise_after_500_calls(void *user, const char *stage, double fraction) {
    (void)fraction;
    const slow_run *run = user;
    return (strcmp(stage, "optimise") == 0 || strcmp(stage, "quality") == 0) && run->calls > 500;
}

static void a_slow_spacing_callback_can_cancel_the_optimisation(void **state) {
    um_context *ctx = *state;
    slow_run run = {0, 0, 1};
    um_spacing *h = NULL;
    um_mesh *m = NULL;
    assert_int_equal(um_spacing_create_callback(ctx, slow_spacing, &run, &h), UM_OK);
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_OK);
    run.fast = 0;
    assert_int_equal(um_context_set_progress(ctx, cancel_optimise_after_500_calls, &run), UM_OK);
    assert_int_equal(um_mesh_optimise(m, NULL), UM_CANCELLED);
    print_message("spacing calls before the optimisation's cancel took: %ld\n", run.calls);
    assert_true(run.calls < 40000);
    assert_int_equal(um_context_set_progress(ctx, NULL, NULL), UM_OK);
    um_context_clear_error(ctx);
    um_mesh_destroy(m);
    um_spacing_destroy(h);
}

static void quality_report(void **state) {
    um_context *ctx = *state;
    um_spacing *h = NULL;
    assert_int_equal(um_spacing_create_constant(ctx, 400.0, &h), UM_OK);
    um_mesh *m = NULL;
    assert_int_equal(um_mesh_refine(ctx, h, NULL, NULL, &m), UM_OK);
    double mn, p1, mean, mx;
    assert_int_equal(um_mesh_quality_summary(m, "area_length_ratio", &mn, &p1, &mean, &mx), UM_OK);
    /* spherical triangles have a little more area than flat ones: just above 1 */
    assert_true(mn > 0.5 && mx < 1.01 && mean > 0.9);
    /* radius-edge < 1.05 bounds the smallest angle by asin(1 / 2.1) = 28.4 degrees */
    assert_int_equal(um_mesh_quality_summary(m, "angle_min_deg", &mn, &p1, &mean, &mx), UM_OK);
    assert_true(mn > 28.0 && mx < 60.5);
    assert_int_equal(um_mesh_quality_summary(m, "primal_dual", &mn, NULL, &mean, &mx), UM_OK);
    assert_true(mn > 0 && mx <= 1.0 + 1e-12 && mean > 0.9);
    assert_int_equal(um_mesh_quality_summary(m, "edge_spacing_ratio", &mn, NULL, &mean, &mx), UM_OK);
    assert_true(mn >= 0.5 && mx < 1.54 && fabs(mean - 1.0) < 0.1);
    /* The operator diagnostics: offsets are >= 0, ordered min <= p1 <= mean
     * <= max; on a refined (Voronoi) mesh xEdge is the edge midpoint. */
    const char *offsets[] = {"centroid_offset", "dual_edge_offset", "primal_edge_offset"};
    for (int i = 0; i < 3; ++i) {
        mn = p1 = mean = mx = -1;
        assert_int_equal(um_mesh_quality_summary(m, offsets[i], &mn, &p1, &mean, &mx), UM_OK);
        assert_true(mn >= 0 && mn <= p1 && p1 <= mean && mean <= mx);
    }
    assert_int_equal(um_mesh_quality_summary(m, "centroid_offset", NULL, NULL, &mean, &mx), UM_OK);
    assert_true(mean > 0 && mx < 0.5);
    assert_int_equal(um_mesh_quality_summary(m, "primal_edge_offset", NULL, NULL, NULL, &mx), UM_OK);
    assert_true(mx < 1e-9);
    assert_int_equal(um_mesh_quality_summary(m, "cell_spacing_ratio", &mn, &p1, &mean, &mx), UM_OK);
    assert_true(mn >= 0.5 && mn <= p1 && mx < 1.54 && fabs(mean - 1.0) < 0.1);
    int64_t obtuse = -1, bad = -1;
    assert_int_equal(um_mesh_quality_counts(m, &obtuse, &bad), UM_OK);
    assert_true(obtuse >= 0 && bad >= 0 && bad <= obtuse);
    int64_t needed = 0;
    assert_int_equal(um_mesh_quality_json(m, NULL, 0, &needed), UM_ERR_BUFFER_TOO_SMALL);
    char *json = malloc(needed);
    assert_int_equal(um_mesh_quality_json(m, json, needed, NULL), UM_OK);
    assert_non_null(strstr(json, "\"primal_dual\""));
    assert_non_null(strstr(json, "\"not_well_centred\""));
    const char *diagnostics = strstr(json, "\"operator_diagnostics\": {");
    assert_non_null(diagnostics);
    assert_non_null(strstr(diagnostics, "\"centroid_offset\": {\"rms\": "));
    assert_non_null(strstr(diagnostics, "\"dual_edge_offset\": {\"rms\": "));
    assert_non_null(strstr(diagnostics, "\"primal_edge_offset\": {\"rms\": "));
    assert_non_null(strstr(diagnostics, "\"cell_spacing_ratio\": {\"min\": "));
    assert_non_null(strstr(diagnostics, "\"std\": "));
    free(json);
    assert_int_equal(um_mesh_quality_summary(m, "nonsense", &mn, NULL, NULL, NULL), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "nonsense"));
    assert_non_null(strstr(um_context_last_error(ctx), "cell_spacing_ratio"));
    um_mesh_destroy(m);
    um_spacing_destroy(h);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(uniform_sphere, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(uniform_edges_within_the_band, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(same_mesh_for_any_thread_count, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(global_coastline, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(coastlines_at_continental_spacings, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(midatlantic_full_resolution, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(bad_input, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(regional_mesh, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(wgs84_mesh, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(spacing_callback_failure_names_the_point, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(a_slow_spacing_callback_can_cancel_the_optimisation, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(a_slow_spacing_callback_can_be_cancelled, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(quality_report, setup_context, teardown_context),
    };
    return cmocka_run_group_tests_name("mesh_api", tests, NULL, NULL);
}
