// Engine tests of the spacing functions h(x) (lib/hfun) and of the spacing
// file reader on the shipped Mid-Atlantic file (when ../shared is there).
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <cstring>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/context.hpp"
#include "core/error.hpp"
#include "geom/sphere.hpp"
#include "hfun/feature_distance.hpp"
#include "hfun/grid.hpp"
#include "hfun/min_pyramid.hpp"
#include "hfun/presets.hpp"
#include "hfun/spacing.hpp"
#include "io/spacing_file.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using geom::Vec3;
using hfun::SpacingPtr;

namespace {

constexpr double kR = hfun::kEarthRadiusKm;
constexpr double kDeg = M_PI / 180.0;

// Runs fn, which must throw um::Error with `status` and a message holding
// every word.
void expect_error(um_status status, std::initializer_list<const char *> words,
                  const std::function<void()> &fn) {
    try {
        fn();
    } catch (const Error &e) {
        if (e.status() != status) fail_msg("status %d, expected %d: %s", e.status(), status, e.what());
        for (const char *w : words)
            if (!std::strstr(e.what(), w)) fail_msg("message '%s' lacks '%s'", e.what(), w);
        return;
    }
    fail_msg("no error; expected status %d", status);
}

void assert_close(double a, double b, double tolerance) {
    if (!(std::fabs(a - b) <= tolerance)) fail_msg("%.17g != %.17g (tolerance %g)", a, b, tolerance);
}

std::vector<double> range(double first, double step, int n) {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i) v[i] = first + step * i;
    return v;
}

// A grid of f(lon, lat) on the given axes.
std::shared_ptr<const hfun::GridSpacing> grid_of(const std::vector<double> &lon,
                                                 const std::vector<double> &lat,
                                                 const std::function<double(double, double)> &f) {
    std::vector<double> cells;
    for (double y : lat)
        for (double x : lon) cells.push_back(f(x, y));
    return std::make_shared<hfun::GridSpacing>(lon, lat, cells);
}

std::vector<Vec3> random_points(int n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::vector<Vec3> p(n);
    for (auto &q : p) q = geom::normalized({g(rng), g(rng), g(rng)});
    return p;
}

// ------------------------------------------------------------- constant

void constant_spacing_and_its_checks(void **) {
    SpacingPtr h = hfun::make_constant(30);
    for (const Vec3 &p : random_points(100, 1)) assert_true(h->km_at(p) == 30.0);
    assert_true(h->km_at_lonlat(0, 90) == 30.0);
    expect_error(UM_ERR_INVALID_ARGUMENT, {"km = 0", "> 0"}, [] { hfun::make_constant(0); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"km = -1"}, [] { hfun::make_constant(-1); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"km = nan"}, [] { hfun::make_constant(NAN); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"km = inf"}, [] { hfun::make_constant(INFINITY); });
}

// ----------------------------------------------------------------- grid

// Bilinear interpolation reproduces a linear field on a non-uniform grid,
// at the nodes exactly.
void grid_bilinear_is_exact_on_linear_fields(void **) {
    const std::vector<double> lon{-100, -97, -90, -80.5, -60}, lat{-30, -10, 0, 5, 40};
    auto f = [](double x, double y) { return 50 + 0.3 * x + 0.2 * y; };
    auto grid = grid_of(lon, lat, f);
    assert_false(grid->periodic());
    for (double y : lat)
        for (double x : lon) assert_true(grid->km_at_lonlat(x, y) == f(x, y));
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> ux(-100, -60), uy(-30, 40);
    for (int k = 0; k < 1000; ++k) {
        double x = ux(rng), y = uy(rng);
        assert_close(grid->km_at_lonlat(x, y), f(x, y), 1e-12);
        // The same through a unit vector (lon/lat recovered to ~1e-14 degrees).
        assert_close(grid->km_at(geom::unit_from_lonlat_deg(x, y)), f(x, y), 1e-9);
    }
}

// Axes whose steps differ by orders of magnitude (a fine nest in a coarse
// grid, as in regional spacing files; one with more fine steps than the
// lookup has bins): every point, random or a rounding step off a node, is
// read from its own cell (a wrong one would clamp, off the linear field).
void grid_finds_cells_on_very_uneven_axes(void **) {
    // Fine longitudes (3,000 steps of 0.01 degrees) on a few latitudes, and
    // fine latitudes (200,000 steps of 1e-5 degrees) on a few longitudes.
    std::vector<double> fine_lon{-180, -100}, fine_lat{-90, -40};
    for (int i = 1; i <= 3000; ++i) fine_lon.push_back(-100 + 0.01 * i);   // to -70
    for (int i = 1; i <= 200000; ++i) fine_lat.push_back(-40 + 1e-5 * i);  // to -38
    fine_lon.push_back(0), fine_lon.push_back(179.5);
    fine_lat.push_back(10), fine_lat.push_back(90);
    const std::vector<double> few_lon{-180, -120, 0, 150}, few_lat{-90, -45, 0, 60, 90};
    auto f = [](double x, double y) { return 500 + 0.7 * x + 0.3 * y; };
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> ux(-180, 150), uy(-90, 90), fx(-100, -70), fy(-40, -38);
    for (bool lon_is_fine : {true, false}) {
        const std::vector<double> &lon = lon_is_fine ? fine_lon : few_lon;
        const std::vector<double> &lat = lon_is_fine ? few_lat : fine_lat;
        auto grid = grid_of(lon, lat, f);
        auto check = [&](double x, double y) { assert_close(grid->km_at_lonlat(x, y), f(x, y), 1e-9); };
        auto fine = [&] { return lon_is_fine ? fx(rng) : fy(rng); };
        for (int k = 0; k < 20000; ++k) {
            check(std::min(ux(rng), lon.back()), uy(rng));
            lon_is_fine ? check(fine(), uy(rng)) : check(std::min(ux(rng), lon.back()), fine());
        }
        const std::vector<double> &axis = lon_is_fine ? lon : lat;
        for (size_t i = 0; i < axis.size(); i += lon_is_fine ? 7 : 97)
            for (double a : {std::nextafter(axis[i], -1e9), axis[i], std::nextafter(axis[i], 1e9)}) {
                if (a < axis.front() || a > axis.back()) continue;
                lon_is_fine ? check(a, uy(rng)) : check(std::min(ux(rng), lon.back()), a);
            }
    }
}

// -180..180 (last column repeats the first), 0..360, and cell-centred
// -176.25..176.25 all read round the dateline as one periodic field.
void grid_is_periodic_across_the_dateline(void **) {
    auto f = [](double x, double y) { return 40 + 10 * std::cos(x * kDeg) + y / 10; };
    const std::vector<double> lat = range(-60, 15, 9);
    auto a = grid_of(range(-180, 7.5, 49), lat, f);
    auto b = grid_of(range(0, 7.5, 49), lat, f);
    auto c = grid_of(range(-176.25, 7.5, 48), lat, f);
    assert_true(a->periodic() && b->periodic() && c->periodic());
    for (double y : {-70.0, -12.3, 0.0, 33.3, 59.0}) {
        for (double x : {179.9, 180.0, -180.0, -179.9, 540.0, -540.2, 0.0, 359.99, 3.75}) {
            double va = a->km_at_lonlat(x, y);
            assert_close(va, b->km_at_lonlat(x, y), 1e-12);
            assert_close(va, a->km_at_lonlat(x + 360, y), 1e-12);
        }
        // Continuous across the dateline, for every grid.
        for (auto g : {a, b, c})
            assert_close(g->km_at_lonlat(179.9999, y), g->km_at_lonlat(-179.9999, y), 1e-4);
        // The wrap cell of c: half way between its nodes at 176.25 and -176.25.
        double yy = std::min(std::max(y, -60.0), 60.0);
        assert_close(c->km_at_lonlat(180, y), f(176.25, yy), 1e-12);
        assert_close(c->km_at(geom::unit_from_lonlat_deg(-180, y)), f(176.25, yy), 1e-9);
    }
}

// A regional grid takes the value of the nearer edge column outside its range.
void regional_grid_clamps_to_the_nearer_edge(void **) {
    auto grid = grid_of({-100, -80, -60}, {0, 10}, [](double x, double) { return x + 200; });
    assert_false(grid->periodic());
    assert_true(grid->km_at_lonlat(-50, 5) == 140);   // east of -60: -60's column
    assert_true(grid->km_at_lonlat(120, 5) == 100);   // nearer to -100 going west
    assert_true(grid->km_at_lonlat(-110, 5) == 100);
    assert_true(grid->km_at_lonlat(-70, 5) == 130);
}

// Beyond the first/last latitude rows the row's value is used.
void grid_clamps_towards_the_poles(void **) {
    auto f = [](double x, double y) { return 100 + x / 10 + y; };
    auto grid = grid_of(range(-180, 30, 13), range(-80, 20, 9), f);
    assert_close(grid->km_at_lonlat(30, 85), f(30, 80), 1e-12);
    assert_close(grid->km_at_lonlat(-60, -89.5), f(-60, -80), 1e-12);
    assert_close(grid->km_at(Vec3{0, 0, 1}), f(0, 80), 1e-12);  // the pole reads lon 0
    assert_close(grid->km_at(Vec3{0, 0, -1}), f(0, -80), 1e-12);
    // A grid with pole rows of one value gives that value at the pole.
    auto full = grid_of(range(0, 45, 8), range(-90, 45, 5),
                        [](double x, double y) { return std::fabs(y) == 90 ? 7.0 : 20 + x / 100; });
    assert_true(full->km_at(Vec3{0, 0, 1}) == 7.0);
    assert_true(full->km_at_lonlat(123.4, -90) == 7.0);
}

void grid_checks_name_the_array_index_and_value(void **) {
    using hfun::GridSpacing;
    const std::vector<double> lon{0, 10, 20}, lat{0, 10};
    const std::vector<double> ok(6, 5.0);
    auto with_cell = [&](int k, double v) {
        std::vector<double> c = ok;
        c[k] = v;
        return c;
    };
    expect_error(UM_ERR_INVALID_ARGUMENT, {"lon_deg has 1"},
                 [&] { (void)GridSpacing({0}, lat, {5, 5}); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"cell_width_km has 5", "needs 6"},
                 [&] { (void)GridSpacing(lon, lat, {5, 5, 5, 5, 5}); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"lon_deg[2] = 5", "descending"},
                 [&] { (void)GridSpacing({0, 10, 5}, lat, ok); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"lat_deg[1] = 0", "duplicate"},
                 [&] { (void)GridSpacing(lon, {0, 0}, ok); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"lon_deg[1] = nan"},
                 [&] { (void)GridSpacing({0, NAN, 20}, lat, ok); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"lat_deg[0] = -inf"},
                 [&] { (void)GridSpacing(lon, {-INFINITY, 0}, ok); });
    expect_error(UM_ERR_COORDINATE_RANGE, {"lat_deg[0] = -91", "[-90, 90]"},
                 [&] { (void)GridSpacing(lon, {-91, 0}, ok); });
    expect_error(UM_ERR_COORDINATE_RANGE, {"lon_deg spans 370", "more than 360"},
                 [&] { (void)GridSpacing({-10, 100, 360}, lat, ok); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"cell_width_km[4]", "lat_deg index 1", "lon_deg index 1", "nan"},
                 [&] { (void)GridSpacing(lon, lat, with_cell(4, NAN)); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"cell_width_km[5]", "inf"},
                 [&] { (void)GridSpacing(lon, lat, with_cell(5, INFINITY)); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"cell_width_km[0]", "= 0 km is not > 0"},
                 [&] { (void)GridSpacing(lon, lat, with_cell(0, 0.0)); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"cell_width_km[3]", "-2"},
                 [&] { (void)GridSpacing(lon, lat, with_cell(3, -2.0)); });
    // A 360-degree span written a few ulps long is still one turn.
    (void)GridSpacing({-180, 0, 180.0000000001}, lat, ok);
}

// -------------------------------------------------------------- presets

// EC_CellWidthVsLat of MPAS-Tools, written out here on its own: the width
// blends as density (30 / w)^4, equator -> mid-latitude below 40 degrees,
// mid-latitude -> pole above.
double ec60to30_reference(double lat) {
    const double w_eq = 30, w_mid = 60, w_pole = 35, finest = 30;
    double a = std::fabs(lat), low, high, weight;
    if (a < 40) {
        low = std::pow(finest / w_mid, 4), high = std::pow(finest / w_eq, 4);
        weight = 0.5 * (1 + std::tanh((15 - a) / 6));
    } else {
        low = std::pow(finest / w_pole, 4), high = std::pow(finest / w_mid, 4);
        weight = 0.5 * (1 + std::tanh((73 - a) / 9));
    }
    return finest * std::pow(low + weight * (high - low), -0.25);
}

void ec60to30_matches_mesh_definition_tools(void **) {
    SpacingPtr h = hfun::make_preset("EC60to30");
    for (double lat : {-90.0, -60.0, -40.5, -39.5, -15.0, 0.0, 7.0, 15.0, 30.0, 45.0, 73.0, 89.9, 90.0})
        assert_close(h->km_at_lonlat(17, lat), ec60to30_reference(lat), 1e-12);
    // The shape the name promises: ~30 km at the equator, ~60 km at
    // mid-latitudes, ~35 km at the poles.
    assert_true(h->km_at_lonlat(0, 0) > 30 && h->km_at_lonlat(0, 0) < 30.5);
    assert_true(h->km_at_lonlat(0, 39) > 55 && h->km_at_lonlat(0, 39) <= 60);
    assert_true(h->km_at_lonlat(0, 90) > 35 && h->km_at_lonlat(0, 90) < 37);
    // E3SM's newer spelling and any case give the same spacing.
    for (const char *name : {"EC30to60", "ec60TO30"})
        for (double lat : {-70.0, 0.0, 20.0, 50.0})
            assert_true(hfun::make_preset(name)->km_at_lonlat(0, lat) == h->km_at_lonlat(0, lat));
    assert_close(hfun::ec_cell_width_km(10), ec60to30_reference(10), 1e-12);
}

void rrs18to6_matches_mesh_definition_tools(void **) {
    SpacingPtr h = hfun::make_preset("RRS18to6");
    assert_close(h->km_at_lonlat(0, 0), 18, 1e-12);
    assert_close(h->km_at_lonlat(0, 90), 6, 1e-12);
    assert_close(h->km_at_lonlat(0, -90), 6, 1e-12);
    const double gamma = std::pow(6.0 / 18.0, 4);
    for (double lat : {-70.0, -45.0, 10.0, 30.0, 60.0}) {
        double s = std::sin(std::fabs(lat) * kDeg);
        assert_close(h->km_at_lonlat(5, lat), 6 / std::pow((1 - gamma) * s * s * s * s + gamma, 0.25),
                     1e-12);
        assert_true(hfun::make_preset("RRS6to18")->km_at_lonlat(5, lat) == h->km_at_lonlat(5, lat));
    }
    for (double lat = 0; lat < 90; lat += 1)
        assert_true(h->km_at_lonlat(0, lat + 1) < h->km_at_lonlat(0, lat));
}

void qu_and_unknown_preset_names(void **) {
    assert_true(hfun::make_preset("QU240")->km_at_lonlat(10, 10) == 240);
    assert_true(hfun::make_preset("qu7.5")->km_at_lonlat(10, 10) == 7.5);
    for (const char *bad : {"", "QU", "QU-5", "QU0", "QUnan", "QUinf", "QU 240", "XY60", "EC60",
                            "EC60to", "ECto30", "EC60to30x", "RRS18to-6", "RRS18x6", "QU240km"}) {
        std::string name = bad;
        expect_error(UM_ERR_INVALID_ARGUMENT, {"preset name", "QU<km>"},
                     [&] { hfun::make_preset(name); });
    }
}

// ------------------------------------------- least value over a cap

void min_pyramid_matches_reading_every_value(void **) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (const auto &[rows, cols] : {std::pair<int64_t, int64_t>{1, 1}, {2, 3}, {7, 5}, {33, 64}, {100, 37}}) {
        std::vector<double> v(static_cast<size_t>(rows * cols));
        for (double &x : v) x = u(rng);
        const hfun::MinPyramid pyramid(v, rows, cols);
        std::uniform_int_distribution<int64_t> r(0, rows - 1), c(0, cols - 1);
        for (int trial = 0; trial < 2000; ++trial) {
            int64_t r0 = r(rng), r1 = r(rng), c0 = c(rng), c1 = c(rng);
            if (r0 > r1) std::swap(r0, r1);
            if (c0 > c1) std::swap(c0, c1);
            double least = 2;
            for (int64_t i = r0; i <= r1; ++i)
                for (int64_t j = c0; j <= c1; ++j) least = std::min(least, v[i * cols + j]);
            assert_true(pyramid.min_over(v, r0, r1, c0, c1) == least);
        }
    }
}

// A point at arc distance d (radians) from c, towards bearing b.
Vec3 offset(const Vec3 &c, double d, double b) {
    Vec3 east = geom::cross({0, 0, 1}, c);
    if (geom::norm(east) < 1e-12) east = {1, 0, 0};
    east = geom::normalized(east);
    const Vec3 north = geom::cross(c, east);
    const Vec3 t = std::cos(b) * north + std::sin(b) * east;
    return geom::normalized(std::cos(d) * c + std::sin(d) * t);
}

// No point of the cap (sampled) below the bound.
void expect_bound_below_cap(const hfun::Spacing &h, const Vec3 &c, double radius, double bound) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 4000; ++k) {
        const Vec3 p = offset(c, radius * std::sqrt(u(rng)), 2 * M_PI * u(rng));
        if (h.km_at(p) < bound * (1 - 1e-12)) fail_msg("h = %.17g in the cap, below the bound %.17g", h.km_at(p), bound);
    }
}

void grid_sees_a_spike_between_the_points_sampled(void **) {
    // 1-degree nodes, 100 km everywhere but 1 km at lon 10, lat 0.
    auto grid = grid_of(range(-180, 1, 361), range(-90, 1, 181),
                        [](double lon, double lat) { return lon == 10 && lat == 0 ? 1.0 : 100.0; });
    const double inf = std::numeric_limits<double>::infinity();
    const Vec3 beside = geom::unit_from_lonlat_deg(10.6, 0.3);  // 0.67 degrees from the node
    assert_true(grid->km_at(beside) > 50);
    assert_true(grid->smallest_in_cap(beside, 0.7 * kDeg, inf) == 1.0);
    // Beside it, the box (lat 0.25 to 1.25, lon 9.5 to 10.5) is least where
    // its south side meets lon 10: 1 * 0.75 + 100 * 0.25.
    const Vec3 north = geom::unit_from_lonlat_deg(10, 0.75);
    const double least = grid->smallest_in_cap(north, 0.5 * kDeg, inf);
    assert_close(least, 25.75, 1e-6);
    expect_bound_below_cap(*grid, north, 0.5 * kDeg, least);
    // Asked for no more than a bound below 1, the nodes of the cells touched do.
    assert_true(grid->smallest_in_cap(north, 0.5 * kDeg, 0.5) == 1.0);
    // Far from it: the background, however large the cap.
    assert_true(grid->smallest_in_cap(geom::unit_from_lonlat_deg(-100, 40), 20 * kDeg, inf) == 100.0);
    assert_true(grid->smallest_in_cap(geom::unit_from_lonlat_deg(-170, 10), 170 * kDeg, inf) == 1.0);
}

void grid_least_value_across_the_dateline_and_a_pole(void **) {
    // Cell-centred and periodic; spikes next to the wrap and next to the pole.
    auto grid = grid_of(range(-179.5, 1, 360), range(-89.5, 1, 180), [](double lon, double lat) {
        if (lon == 179.5 && lat == 0.5) return 2.0;
        if (lon == 40.5 && lat == 89.5) return 3.0;
        return 50.0;
    });
    assert_true(grid->periodic());
    const Vec3 west_of_wrap = geom::unit_from_lonlat_deg(-179.6, 0.5);
    assert_true(grid->smallest_in_cap(west_of_wrap, 1.0 * kDeg, 1e9) == 2.0);
    assert_true(grid->smallest_in_cap(west_of_wrap, 0.05 * kDeg, 1e9) > 2.0);  // the wrap cell, interpolated
    expect_bound_below_cap(*grid, west_of_wrap, 0.05 * kDeg, grid->smallest_in_cap(west_of_wrap, 0.05 * kDeg, 1e9));
    const Vec3 pole = geom::unit_from_lonlat_deg(-140, 89.8);  // the cap holds the pole
    assert_true(grid->smallest_in_cap(pole, 0.5 * kDeg, 1e9) == 3.0);
    // A regional grid takes its edge columns' values beyond it.
    auto regional = grid_of(range(0, 1, 11), range(0, 1, 11), [](double lon, double) { return lon == 10 ? 5.0 : 9.0; });
    assert_true(regional->smallest_in_cap(geom::unit_from_lonlat_deg(30, 5), 1.0 * kDeg, 1e9) == 5.0);
}

void least_value_is_below_every_value_in_the_cap(void **) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(1, 300);
    std::vector<double> lon, lat = {-88, -60, -31, -30.5, -2, 0, 1, 33, 70, 86};
    for (int i = 0; i < 40; ++i) lon.push_back(-175 + 8.7 * i + (i % 4));
    std::vector<double> cells(lon.size() * lat.size());
    for (double &c : cells) c = u(rng);
    const hfun::GridSpacing grid(lon, lat, cells);
    const std::vector<Vec3> centres = random_points(300, 23);
    for (size_t k = 0; k < centres.size(); ++k) {
        const double radius = (0.2 + 0.1 * double(k % 40)) * kDeg;
        const double least = grid.smallest_in_cap(centres[k], radius, 1e9);
        expect_bound_below_cap(grid, centres[k], radius, least);
        assert_true(least <= grid.km_at(centres[k]));
        // Near the nodes' least: never below the least of the whole grid.
        assert_true(least >= *std::min_element(cells.begin(), cells.end()));
    }
    // A distance spacing: its least over a cap is its value at the cap's
    // nearest possible distance.
    const SpacingPtr ramp = hfun::make_feature_distance({{geom::unit_from_lonlat_deg(0, 0), geom::unit_from_lonlat_deg(0, 10)}},
                                                         hfun::DistanceRamp{2, 80, 10, 0.5});
    for (size_t k = 0; k < 50; ++k) {
        const double radius = 0.05 * double(k % 10 + 1);
        const double least = ramp->smallest_in_cap(centres[k], radius, 1e9);
        expect_bound_below_cap(*ramp, centres[k], radius, least);
        assert_true(least <= ramp->km_at(centres[k]));
    }
}

void grid_within_the_gradient_is_kept_as_it_is(void **) {
    auto smooth = grid_of(range(-180, 5, 73), range(-90, 5, 37), [](double, double lat) { return 30 + 0.1 * lat; });
    // 0.1 km per degree of latitude: about 1e-3 km per km.
    assert_true(hfun::limit_gradient(*smooth, 0.01).get() == smooth.get());
    const SpacingPtr both = hfun::make_minimum({smooth, hfun::make_clamp(smooth, 10, 25)});
    assert_true(hfun::limit_gradient(*both, 0.01) != nullptr);  // a minimum of grids can be limited
    expect_error(UM_ERR_INVALID_ARGUMENT, {"grid spacings only"}, [&] {
        hfun::limit_gradient(*hfun::make_minimum({smooth, hfun::make_constant(20)}), 0.01);
    });
}

// ---------------------------------------------------- gradient limiting

// The 8 grid neighbours of node (j, i), across the wrap when periodic.
template <class Visit>
void for_each_neighbour(const hfun::GridSpacing &g, int64_t j, int64_t i, Visit visit) {
    for (int64_t dj = -1; dj <= 1; ++dj)
        for (int64_t di = -1; di <= 1; ++di) {
            int64_t jj = j + dj, ii = i + di;
            if ((!dj && !di) || jj < 0 || jj >= g.n_lat()) continue;
            if (ii < 0 || ii >= g.n_lon()) {
                if (!g.periodic()) continue;
                ii = (ii + g.n_lon()) % g.n_lon();
            }
            visit(jj, ii);
        }
}

// Haversine, independent of the library's arc_length.
double distance_km(double lon1, double lat1, double lon2, double lat2) {
    double s1 = std::sin((lat2 - lat1) * kDeg / 2), s2 = std::sin((lon2 - lon1) * kDeg / 2);
    double a = s1 * s1 + std::cos(lat1 * kDeg) * std::cos(lat2 * kDeg) * s2 * s2;
    return 2 * kR * std::asin(std::min(1.0, std::sqrt(a)));
}

void check_gradient_bound(const hfun::GridSpacing &g, double bound) {
    for (int64_t j = 0; j < g.n_lat(); ++j)
        for (int64_t i = 0; i < g.n_lon(); ++i)
            for_each_neighbour(g, j, i, [&](int64_t jj, int64_t ii) {
                double d = distance_km(g.lon_deg()[i], g.lat_deg()[j], g.lon_deg()[ii], g.lat_deg()[jj]);
                double diff = std::fabs(g.km_at_node(j, i) - g.km_at_node(jj, ii));
                if (diff > bound * d * (1 + 1e-9) + 1e-9)
                    fail_msg("|h(%ld,%ld) - h(%ld,%ld)| = %g > g d = %g", long(j), long(i), long(jj),
                             long(ii), diff, bound * d);
            });
}

void gradient_limiting_bounds_neighbour_differences(void **) {
    std::vector<double> lon, lat = range(-90, 10, 19);
    for (int i = 0; i < 36; ++i) lon.push_back(10 * i + (i % 3));  // uneven, periodic
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(5, 200);
    std::vector<double> cells(lon.size() * lat.size());
    for (double &c : cells) c = u(rng);
    cells[7 * lon.size() + 35] = 1.0;  // a deep minimum next to the wrap
    hfun::GridSpacing before(lon, lat, cells);
    assert_true(before.periodic());
    const double g = 0.01;
    SpacingPtr limited = hfun::limit_gradient(before, g);
    auto &after = dynamic_cast<const hfun::GridSpacing &>(*limited);
    check_gradient_bound(after, g);
    for (size_t k = 0; k < cells.size(); ++k) assert_true(after.cells_km()[k] <= cells[k]);
    assert_true(after.km_at_node(7, 35) == 1.0);  // the minimum stays
    assert_true(after.km_at_node(7, 0) < 1 + g * 1.0001 * distance_km(lon[35], lat[7], lon[0] + 360, lat[7]));
    for (int64_t i = 1; i < after.n_lon(); ++i) {  // one point at each pole: one value
        assert_true(after.km_at_node(0, i) == after.km_at_node(0, 0));
        assert_true(after.km_at_node(18, i) == after.km_at_node(18, 0));
    }
    // Limiting is a projection: once more changes nothing.
    SpacingPtr again = hfun::limit_gradient(after, g);
    assert_true(dynamic_cast<const hfun::GridSpacing &>(*again).cells_km() == after.cells_km());
    // The input is untouched (a new object comes out).
    assert_true(before.cells_km() == cells);
}

void gradient_limiting_needs_a_grid(void **) {
    auto grid = grid_of(range(0, 90, 4), range(-60, 60, 3), [](double x, double) { return 10 + x; });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"grid", "constant spacing of 30 km"},
                 [] { hfun::limit_gradient(*hfun::make_constant(30), 0.1); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"grid", "EC60to30"},
                 [] { hfun::limit_gradient(*hfun::make_preset("EC60to30"), 0.1); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"g = 0"}, [&] { hfun::limit_gradient(*grid, 0); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"g = -1"}, [&] { hfun::limit_gradient(*grid, -1); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"g = nan"}, [&] { hfun::limit_gradient(*grid, NAN); });
    // Through a clamp: limit inside, clamp outside.
    SpacingPtr clamped = hfun::make_clamp(grid, 20, 200);
    SpacingPtr limited = hfun::limit_gradient(*clamped, 1e-4);
    for (double x : {0.0, 45.0, 100.0, 200.0, 300.0}) {
        double h = limited->km_at_lonlat(x, 0);
        assert_true(h >= 20 && h <= 200 && h <= clamped->km_at_lonlat(x, 0));
    }
}

// ----------------------------------------------------- feature distance

// Distance (radians) from p to the minor arc (a, b), by projecting onto the
// arc's plane (written independently of lib/geom).
double reference_arc_distance(const Vec3 &p, const Vec3 &a, const Vec3 &b) {
    Vec3 n = geom::normalized(geom::cross(a, b));
    Vec3 q = p - geom::dot(p, n) * n;
    double along = std::acos(std::min(1.0, geom::dot(a, b)));
    if (geom::norm(q) > 1e-12) {
        q = geom::normalized(q);
        double qa = std::acos(std::min(1.0, geom::dot(q, a))), qb = std::acos(std::min(1.0, geom::dot(q, b)));
        if (std::fabs(qa + qb - along) < 1e-9) return std::asin(std::min(1.0, std::fabs(geom::dot(p, n))));
    }
    return std::min(std::acos(std::max(-1.0, std::min(1.0, geom::dot(p, a)))),
                    std::acos(std::max(-1.0, std::min(1.0, geom::dot(p, b)))));
}

void feature_distance_follows_the_ramp(void **) {
    std::vector<std::vector<Vec3>> lines(2);
    for (int k = 0; k <= 10; ++k) lines[0].push_back(geom::unit_from_lonlat_deg(k, 0));
    for (double lat : {30.0, 35.0, 35.0, 40.0}) lines[1].push_back(geom::unit_from_lonlat_deg(-75, lat));
    const auto ramp = hfun::DistanceRamp{2, 50, 20, 0.1};
    SpacingPtr h = hfun::make_feature_distance(lines, ramp);
    const double degree_km = kR * kDeg;
    assert_true(h->km_at_lonlat(5, 0) == 2);
    assert_true(h->km_at_lonlat(5, 0.1) == 2);  // 11 km: within d0
    assert_close(h->km_at_lonlat(5, 1), 2 + 0.1 * (degree_km - 20), 1e-9);
    assert_close(h->km_at_lonlat(12, 0), 2 + 0.1 * (2 * degree_km - 20), 1e-9);  // past the end
    assert_true(h->km_at_lonlat(180, 0) == 50);
    // Against a brute-force distance to every arc, at random points and at
    // points near the lines (where the ramp is not yet at km_max).
    std::vector<Vec3> points = random_points(2000, 7);
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> ux(-5, 15), uy(-5, 5), vx(-80, -70), vy(28, 42);
    for (int k = 0; k < 1000; ++k) {
        points.push_back(geom::unit_from_lonlat_deg(ux(rng), uy(rng)));
        points.push_back(geom::unit_from_lonlat_deg(vx(rng), vy(rng)));
    }
    for (const Vec3 &p : points) {
        double d = 10;
        for (const auto &line : lines)
            for (size_t k = 1; k < line.size(); ++k)
                if (!(line[k].x == line[k - 1].x && line[k].y == line[k - 1].y && line[k].z == line[k - 1].z))
                    d = std::min(d, reference_arc_distance(p, line[k - 1], line[k]));
        double dk = d * kR;
        double expected = dk <= 20 ? 2 : std::min(50.0, 2 + 0.1 * (dk - 20));
        assert_close(h->km_at(p), expected, 1e-7);
    }
    auto width = hfun::DistanceRamp::over_width(2, 50, 20, 480);
    assert_close(width.rate, 0.1, 1e-15);
}

void feature_distance_checks(void **) {
    using Lines = std::vector<std::vector<Vec3>>;
    const hfun::DistanceRamp ramp{2, 50, 20, 0.1};
    const Vec3 a = geom::unit_from_lonlat_deg(0, 0), b = geom::unit_from_lonlat_deg(1, 0);
    expect_error(UM_ERR_INVALID_ARGUMENT, {"no feature"}, [&] { hfun::make_feature_distance({}, ramp); });
    expect_error(UM_ERR_TOO_FEW_POINTS, {"polyline 1", "1 distinct"},
                 [&] { hfun::make_feature_distance(Lines{{a, b}, {a, a}}, ramp); });
    expect_error(UM_ERR_DEGENERATE_INPUT, {"antipodal"},
                 [&] { hfun::make_feature_distance(Lines{{a, -1.0 * a}}, ramp); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"polyline 0, point 1"},
                 [&] { hfun::make_feature_distance(Lines{{a, Vec3{NAN, 0, 1}}}, ramp); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"zero vector"},
                 [&] { hfun::make_feature_distance(Lines{{a, Vec3{}}}, ramp); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"km_min = 0"},
                 [&] { hfun::make_feature_distance(Lines{{a, b}}, {0, 50, 20, 0.1}); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"km_max = 1", "below"},
                 [&] { hfun::make_feature_distance(Lines{{a, b}}, {2, 1, 20, 0.1}); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"rate = nan"},
                 [&] { hfun::make_feature_distance(Lines{{a, b}}, {2, 50, 20, NAN}); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"width_km = 0"},
                 [] { hfun::DistanceRamp::over_width(2, 50, 20, 0); });
}

// ---------------------------------------------------- clamp and minimum

void clamp_and_minimum(void **) {
    SpacingPtr ec = hfun::make_preset("EC60to30");
    SpacingPtr clamped = hfun::make_clamp(ec, 32, 50);
    assert_true(clamped->km_at_lonlat(0, 0) == 32);
    assert_true(clamped->km_at_lonlat(0, 39) == 50);
    assert_true(clamped->km_at_lonlat(0, 20) == ec->km_at_lonlat(0, 20));
    SpacingPtr low = hfun::make_minimum({hfun::make_constant(40), ec});
    for (double lat = -90; lat <= 90; lat += 7.5)
        assert_true(low->km_at_lonlat(3, lat) == std::min(40.0, ec->km_at_lonlat(3, lat)));
    expect_error(UM_ERR_INVALID_ARGUMENT, {"km_min = 60", "above km_max = 50"},
                 [&] { hfun::make_clamp(ec, 60, 50); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"km_min = 0"}, [&] { hfun::make_clamp(ec, 0, 50); });
    expect_error(UM_ERR_NONFINITE_INPUT, {"km_max = nan"}, [&] { hfun::make_clamp(ec, 1, NAN); });
    expect_error(UM_ERR_INVALID_ARGUMENT, {"no spacing"}, [] { hfun::make_minimum({}); });
    expect_error(UM_ERR_NULL_ARGUMENT, {"part 1"}, [&] { hfun::make_minimum({ec, nullptr}); });
}

// ---------------------------------------- callbacks and parallel evaluation

double bad_at_high_latitudes(void *user, double, double lat) {
    ++*static_cast<std::atomic<int64_t> *>(user);
    if (lat > 50) return NAN;
    if (lat < -50) return -1;
    return 10;
}

std::vector<Vec3> points_with_bad_ones(int n, const std::vector<int> &bad, double lat_of_bad) {
    std::vector<Vec3> p;
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> lon(-180, 180), lat(-45, 45);
    for (int i = 0; i < n; ++i) p.push_back(geom::unit_from_lonlat_deg(lon(rng), lat(rng)));
    for (int i : bad) p[i] = geom::unit_from_lonlat_deg(10, lat_of_bad);
    return p;
}

// Invalid callback values are reported on the host thread, for the lowest
// index, with the same message for any thread count.
void callback_errors_name_the_first_bad_point(void **) {
    std::atomic<int64_t> calls{0};
    SpacingPtr h = hfun::make_callback(bad_at_high_latitudes, &calls);
    const auto nan_points = points_with_bad_ones(20000, {12345, 777, 19000}, 60);
    std::string messages[2];
    for (int threads : {1, 2}) {
        Context ctx;
        ctx.set_threads(threads);
        std::vector<double> km;
        expect_error(UM_ERR_NONFINITE_INPUT, {"spacing callback", "h = nan", "at lon", "(point 777)"},
                     [&] { hfun::evaluate_at_points(ctx, *h, nan_points, km); });
        try {
            hfun::evaluate_at_points(ctx, *h, nan_points, km);
        } catch (const Error &e) {
            messages[threads - 1] = e.what();
        }
        // Through a clamp and a minimum the value is still reported.
        expect_error(UM_ERR_NONFINITE_INPUT, {"(point 777)"}, [&] {
            hfun::evaluate_at_points(ctx, *hfun::make_clamp(h, 1, 5), nan_points, km);
        });
        expect_error(UM_ERR_NONFINITE_INPUT, {"(point 777)"}, [&] {
            hfun::evaluate_at_points(ctx, *hfun::make_minimum({hfun::make_constant(3), h}), nan_points, km);
        });
        const auto negative = points_with_bad_ones(5000, {4000, 4999}, -70);
        expect_error(UM_ERR_INVALID_ARGUMENT, {"h = -1", "(point 4000)", "not > 0"},
                     [&] { hfun::evaluate_at_points(ctx, *h, negative, km); });
    }
    assert_string_equal(messages[0].c_str(), messages[1].c_str());
    assert_true(calls.load() > 0);
}

double smooth_callback(void *, double lon, double lat) {
    return 20 + 5 * std::sin(3 * lon * kDeg) * std::cos(lat * kDeg);
}

void evaluation_is_the_same_for_one_and_two_threads(void **) {
    std::vector<std::vector<Vec3>> lines{{geom::unit_from_lonlat_deg(-76, 36), geom::unit_from_lonlat_deg(-75, 39),
                                          geom::unit_from_lonlat_deg(-74, 41)}};
    auto grid = grid_of(range(-180, 2.5, 145), range(-90, 2.5, 73),
                        [](double x, double y) { return 30 + 0.1 * x + 0.05 * y * std::sin(x); });
    const std::vector<SpacingPtr> kinds{
        grid,
        hfun::limit_gradient(*grid, 0.002),
        hfun::make_preset("EC60to30"),
        hfun::make_preset("RRS18to6"),
        hfun::make_feature_distance(lines, {1, 60, 10, 0.05}),
        hfun::make_callback(smooth_callback, nullptr),
        hfun::make_minimum({hfun::make_preset("EC60to30"), hfun::make_feature_distance(lines, {1, 60, 10, 0.05})}),
    };
    const auto points = random_points(50000, 11);
    Context one, two;
    one.set_threads(1);
    two.set_threads(2);
    for (const auto &h : kinds) {
        std::vector<double> a, b;
        hfun::evaluate_at_points(one, *h, points, a);
        hfun::evaluate_at_points(two, *h, points, b);
        assert_memory_equal(a.data(), b.data(), a.size() * sizeof(double));
        for (double v : a) assert_true(hfun::valid_km(v));
    }
}

// ------------------------------------------------- the shipped data file

// The Mid-Atlantic spacing file of shared/data (README: 1505 x 1096 nodes,
// lon -180..180 and lat -90..90, h from 1 to 31 km). Skipped when the data
// folder is not beside the project.
void shipped_midatlantic_file(void **) {
    // skip() jumps out of the function: decide before any object needing a
    // destructor exists.
    if (!std::filesystem::exists(UNIMESH_SHARED_DATA "/midatlantic_cellwidth.nc")) {
        print_message("skipped: %s is not there\n", UNIMESH_SHARED_DATA "/midatlantic_cellwidth.nc");
        skip();
    }
    const std::string path = std::string(UNIMESH_SHARED_DATA) + "/midatlantic_cellwidth.nc";
    Context ctx;
    auto grid = io::read_spacing_file(path, ctx);
    assert_int_equal(grid->n_lon(), 1505);
    assert_int_equal(grid->n_lat(), 1096);
    assert_true(grid->periodic());
    const auto &cells = grid->cells_km();
    assert_true(*std::min_element(cells.begin(), cells.end()) == 1.0);
    assert_close(*std::max_element(cells.begin(), cells.end()), 31.0, 1e-9);
    assert_close(grid->km_at_lonlat(100, -30), 31, 1e-9);  // far from the Mid-Atlantic lines
    assert_true(grid->km_at_lonlat(-76.1, 38.3) < 2);       // Chesapeake Bay, on the coast
    assert_close(grid->km_at_lonlat(180, 10), grid->km_at_lonlat(-180, 10), 1e-12);
    std::vector<double> km;
    hfun::evaluate_at_points(ctx, *grid, random_points(10000, 3), km);
    for (double v : km) assert_true(v >= 1 && v <= 31 + 1e-9);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(constant_spacing_and_its_checks),
        cmocka_unit_test(grid_bilinear_is_exact_on_linear_fields),
        cmocka_unit_test(grid_is_periodic_across_the_dateline),
        cmocka_unit_test(grid_finds_cells_on_very_uneven_axes),
        cmocka_unit_test(regional_grid_clamps_to_the_nearer_edge),
        cmocka_unit_test(grid_clamps_towards_the_poles),
        cmocka_unit_test(grid_checks_name_the_array_index_and_value),
        cmocka_unit_test(ec60to30_matches_mesh_definition_tools),
        cmocka_unit_test(rrs18to6_matches_mesh_definition_tools),
        cmocka_unit_test(qu_and_unknown_preset_names),
        cmocka_unit_test(min_pyramid_matches_reading_every_value),
        cmocka_unit_test(grid_sees_a_spike_between_the_points_sampled),
        cmocka_unit_test(grid_least_value_across_the_dateline_and_a_pole),
        cmocka_unit_test(least_value_is_below_every_value_in_the_cap),
        cmocka_unit_test(grid_within_the_gradient_is_kept_as_it_is),
        cmocka_unit_test(gradient_limiting_bounds_neighbour_differences),
        cmocka_unit_test(gradient_limiting_needs_a_grid),
        cmocka_unit_test(feature_distance_follows_the_ramp),
        cmocka_unit_test(feature_distance_checks),
        cmocka_unit_test(clamp_and_minimum),
        cmocka_unit_test(callback_errors_name_the_first_bad_point),
        cmocka_unit_test(evaluation_is_the_same_for_one_and_two_threads),
        cmocka_unit_test(shipped_midatlantic_file),
    };
    return cmocka_run_group_tests_name("spacing", tests, nullptr, nullptr);
}
