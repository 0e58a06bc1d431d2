// Engine tests: meshes of an ellipsoid (issue "Regional meshes and the WGS84
// ellipsoid", item 2): the surface's maps (geom/surface.hpp), the spacing in
// geodesic km (hfun/on_ellipsoid.hpp), and WGS84 meshes measured with
// GeographicLib's geodesics and polygon areas, independently of the mesher.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>

#include "core/error.hpp"
#include "core/options.hpp"
#include "dual/mpas_mesh.hpp"
#include "geom/surface.hpp"
#include "hfun/on_ellipsoid.hpp"
#include "io/geojson.hpp"
#include "mesh/refined_mesh.hpp"
#include "quality/geodesic.hpp"
#include "quality/metrics.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Surface;
using geom::Vec3;

namespace {

const Surface kWgs84 = Surface::ellipsoid(Surface::kWgs84A, Surface::kWgs84F);
const GeographicLib::Geodesic &wgs84_geodesic() { return GeographicLib::Geodesic::WGS84(); }

void the_maps_between_lonlat_and_directions(void **) {
    // On a sphere, the unit vector of the lon/lat, bit for bit.
    const Surface sphere = Surface::sphere(6371220.0);
    for (double lat : {-90.0, -33.3, 0.0, 12.5, 89.99})
        for (double lon : {-180.0, -71.2, 0.0, 45.0, 179.9}) {
            const Vec3 a = sphere.direction(lon, lat), b = geom::unit_from_lonlat_deg(lon, lat);
            assert_memory_equal(&a, &b, sizeof a);
        }
    // On WGS84: the direction of (N cos lat cos lon, N cos lat sin lon, N (1 - e^2) sin lat).
    for (double lat : {-90.0, -60.0, -1e-3, 0.0, 30.0, 45.0, 89.9, 90.0})
        for (double lon : {-179.5, -10.0, 0.0, 120.0}) {
            const Vec3 u = kWgs84.direction(lon, lat);
            double lon2, lat2;
            kWgs84.geodetic(u, lon2, lat2);
            assert_true(std::fabs(lat2 - lat) < 1e-12);
            if (std::fabs(lat) < 90) assert_true(std::fabs(std::remainder(lon2 - lon, 360.0)) < 1e-12);
            // The surface point lies on the ellipsoid x^2/a^2 + y^2/a^2 + z^2/b^2 = 1.
            const Vec3 p = kWgs84.point(u);
            const double a = kWgs84.a(), b = kWgs84.b();
            assert_true(std::fabs((p.x * p.x + p.y * p.y) / (a * a) + p.z * p.z / (b * b) - 1) < 1e-14);
            // Where MPAS puts it: the lon/lat's unit vector.
            const Vec3 s = kWgs84.sphere_unit(u), t = geom::unit_from_lonlat_deg(lon, lat);
            assert_true(geom::norm(s - t) < 1e-14);
        }
    // The geocentric latitude of the point at geodetic 45 degrees: 44.8076 (a
    // textbook value for WGS84).
    double lon, lat;
    geom::lonlat_deg_from_unit(kWgs84.direction(0, 45), lon, lat);
    assert_true(std::fabs(lat - 44.80757678) < 1e-6);
    assert_true(kWgs84.radius_along(Vec3{1, 0, 0}) == kWgs84.a());
    assert_true(std::fabs(kWgs84.radius_along(Vec3{0, 0, 1}) - 6356752.314245) < 1e-5);
    // Area and authalic radius as GeographicLib (and the literature: 6371007.181 m).
    assert_true(std::fabs(kWgs84.area_m2() / wgs84_geodesic().EllipsoidArea() - 1) < 1e-15);
    assert_true(std::fabs(kWgs84.authalic_radius_m() - 6371007.181) < 1e-3);
}

void bad_ellipsoids_are_refused(void **) {
    for (double f : {-0.001, 0.021, 0.5, std::nan("")}) {
        try {
            Surface::ellipsoid(6378137.0, f);
            fail_msg("f = %g accepted", f);
        } catch (const Error &e) {
            assert_int_equal(e.status(), UM_ERR_INVALID_ARGUMENT);
            assert_non_null(std::strstr(e.what(), "flattening f ="));
        }
    }
    for (double a : {0.0, -1.0, HUGE_VAL}) {
        try {
            Surface::ellipsoid(a, 0.003);
            fail_msg("a = %g accepted", a);
        } catch (const Error &e) {
            assert_non_null(std::strstr(e.what(), "semi-major axis a ="));
        }
    }
    // The option: the same bounds, named.
    Options options;
    try {
        options.set_real(UM_OPT_SURFACE_FLATTENING, 0.1);
        fail_msg("surface_flattening = 0.1 accepted");
    } catch (const Error &e) {
        assert_non_null(std::strstr(e.what(), "surface_flattening"));
    }
    assert_true(options.real(UM_OPT_SURFACE_FLATTENING) == 0);
}

// h in geodesic km becomes km on the sphere of radius a: a / r(u) times h.
void the_spacing_is_in_geodesic_km(void **) {
    const hfun::SpacingPtr h = hfun::make_on_ellipsoid(hfun::make_constant(100.0), kWgs84);
    assert_true(h->km_at(kWgs84.direction(30, 0)) == 100.0);  // r = a on the equator
    assert_true(std::fabs(h->km_at(Vec3{0, 0, 1}) - 100.0 / (1 - Surface::kWgs84F)) < 1e-9);
    assert_true(h->smallest_in_cap(Vec3{0, 0, 1}, 0.1, 0) == 100.0);  // a lower bound
    const hfun::SpacingPtr same = hfun::make_constant(100.0);
    assert_true(hfun::make_on_ellipsoid(same, Surface::sphere(1.0)) == same);
}

Options wgs84_options() {
    Options options;
    options.set_real(UM_OPT_SPHERE_RADIUS, Surface::kWgs84A);
    options.set_real(UM_OPT_SURFACE_FLATTENING, Surface::kWgs84F);
    return options;
}

struct EdgeRatios {
    double min = 1e300, max = 0, mean = 0;
    int64_t edges = 0, outside = 0;  // outside [0.7, 1.4]
};

// Every triangulation edge's geodesic length (GeographicLib, between the
// geodetic lon/lat of its ends) over h.
EdgeRatios geodesic_edges_over_h(const mesh::RefinedMesh &m, double h_km) {
    EdgeRatios r;
    const tri::Triangulation &tri = m.tri;
    double sum = 0;
    for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
        if (tri.is_free(t)) continue;
        for (int k = 0; k < 3; ++k) {
            if (tri.neighbour(t, k) < t) continue;
            double lon1, lat1, lon2, lat2, s12;
            m.surface.geodetic(tri.direction(tri.vertex(t, (k + 1) % 3)), lon1, lat1);
            m.surface.geodetic(tri.direction(tri.vertex(t, (k + 2) % 3)), lon2, lat2);
            wgs84_geodesic().Inverse(lat1, lon1, lat2, lon2, s12);
            const double ratio = s12 / 1000 / h_km;
            r.min = std::min(r.min, ratio), r.max = std::max(r.max, ratio);
            sum += ratio, ++r.edges;
            if (ratio < 0.7 || ratio > 1.4) ++r.outside;
        }
    }
    r.mean = sum / static_cast<double>(r.edges);
    return r;
}

// The MPAS mesh's cells as geodesic polygons on WGS84 through its vertices'
// geodetic lat/lon: their areas (GeographicLib) and areaCell, each summed.
void expect_cells_tile_the_ellipsoid(Context &ctx, const mesh::RefinedMesh &m) {
    const dual::MpasMesh mpas = dual::build_mpas_mesh(ctx, m);
    assert_true(mpas.ellipsoid_f == Surface::kWgs84F && mpas.ellipsoid_a_m == Surface::kWgs84A);
    assert_true(mpas.radius_m == kWgs84.authalic_radius_m());
    const double area = wgs84_geodesic().EllipsoidArea();
    double geodesic_sum = 0, area_cell_sum = 0;
    const size_t w = static_cast<size_t>(mpas.max_edges);
    for (int32_t c = 0; c < mpas.n_cells; ++c) {
        GeographicLib::PolygonArea polygon(wgs84_geodesic());
        for (int j = 0; j < mpas.n_edges_on_cell[c]; ++j) {
            const int32_t v = mpas.vertices_on_cell[w * c + j];  // 0-based in memory
            polygon.AddPoint(mpas.lat_vertex[v] * 180 / M_PI, mpas.lon_vertex[v] * 180 / M_PI);
        }
        double perimeter, cell_area;
        polygon.Compute(false, true, perimeter, cell_area);  // counter-clockwise: positive
        assert_true(cell_area > 0);
        geodesic_sum += cell_area;
        area_cell_sum += mpas.area_cell[c];
    }
    print_message("cells' geodesic areas / the ellipsoid's - 1 = %.2e; areaCell's: %.2e\n", geodesic_sum / area - 1,
                  area_cell_sum / area - 1);
    assert_true(std::fabs(geodesic_sum / area - 1) < 1e-10);
    assert_true(std::fabs(area_cell_sum / area - 1) < 1e-10);
}

void a_uniform_wgs84_mesh_at_120_km(void **) {
    Context ctx;
    ctx.set_threads(2);
    const Options options = wgs84_options();
    mesh::RefinedMesh m = mesh::refine_mesh(ctx, hfun::make_constant(120.0), nullptr, options);
    mesh::optimise_mesh(ctx, m, options);
    const EdgeRatios r = geodesic_edges_over_h(m, 120.0);
    print_message("WGS84 120 km: %lld edges, geodesic length / h min %.4f mean %.4f max %.4f\n",
                  (long long)r.edges, r.min, r.mean, r.max);
    assert_true(r.min > 0.8 && r.max < 1.1 && std::fabs(r.mean - 1) < 0.005 && r.outside == 0);
    expect_cells_tile_the_ellipsoid(ctx, m);
    // The quality report's geodesic measures: the same edges, and the power
    // cells' areas tiling the ellipsoid; the same bits on one thread.
    const refine::SpacingRadians h = mesh::spacing_radians(*m.spacing, m.surface);
    const quality::Report::Geodesic g = quality::measure_geodesic(ctx, m.tri, m.surface, h);
    assert_true(g.measured && g.edges == r.edges && g.cells == m.vertex_count());
    assert_true(std::fabs(g.length_over_h_min - r.min) < 1e-12 && std::fabs(g.length_over_h_max - r.max) < 1e-12);
    assert_true(std::fabs(g.length_over_h_mean - r.mean) < 1e-12);
    assert_true(std::fabs(g.cell_area_m2 / g.surface_area_m2 - 1) < 1e-10);
    Context one;
    one.set_threads(1);
    const quality::Report::Geodesic g1 = quality::measure_geodesic(one, m.tri, m.surface, h);
    assert_memory_equal(&g1.length_over_h_mean, &g.length_over_h_mean, sizeof(double));
    assert_memory_equal(&g1.cell_area_m2, &g.cell_area_m2, sizeof(double));
}

void a_coastal_wgs84_mesh_at_60_km(void **) {
    auto gamma = std::make_shared<features::Network>();
    io::read_geojson_file(UNIMESH_DATA_DIR "/coast_global_l.geojson", {}, *gamma);
    Context ctx;
    ctx.set_threads(2);
    const Options options = wgs84_options();
    mesh::RefinedMesh m = mesh::refine_mesh(ctx, hfun::make_constant(60.0), gamma, options);
    mesh::optimise_mesh(ctx, m, options);
    // The coastline's points lie on the mesh's Gamma at their geodetic lon/lat.
    double lon, lat;
    m.surface.geodetic(m.gamma->point(0), lon, lat);
    assert_true(std::fabs(lon - gamma->lon_deg(0)) < 1e-9 && std::fabs(lat - gamma->lat_deg(0)) < 1e-9);
    const EdgeRatios r = geodesic_edges_over_h(m, 60.0);
    const quality::Report q = quality::measure(ctx, m.tri, {}, &m.on_segment);
    print_message("WGS84 60 km + coast_global_l: %lld edges, geodesic length / h min %.4f mean %.4f max %.4f, "
                  "%lld outside [0.7, 1.4]; %lld obtuse of %lld triangles\n",
                  (long long)r.edges, r.min, r.mean, r.max, (long long)r.outside, (long long)q.obtuse,
                  (long long)q.triangles);
    // As on the sphere: short and long edges only along the coastlines, where
    // the restricted edges set them. The longest join two coastline vertices
    // across an inlet or a channel (no split takes an edge between two
    // vertices on Gamma); on the sphere's coastal meshes at 50 to 240 km they
    // reach 1.6 to 1.94 h.
    assert_true(r.min > 0.2 && r.max < 2.0 && std::fabs(r.mean - 1) < 0.01 && r.outside * 100 < r.edges);
    assert_true(q.obtuse * 10000 <= q.triangles);  // 0.01 %
    expect_cells_tile_the_ellipsoid(ctx, m);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_maps_between_lonlat_and_directions),
        cmocka_unit_test(bad_ellipsoids_are_refused),
        cmocka_unit_test(the_spacing_is_in_geodesic_km),
        cmocka_unit_test(a_uniform_wgs84_mesh_at_120_km),
        cmocka_unit_test(a_coastal_wgs84_mesh_at_60_km),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
