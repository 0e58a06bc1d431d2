// Engine tests: regional meshes (issue "Regional meshes and the WGS84
// ellipsoid", item 1): the domain rule (features/domain.hpp), the spacing of
// the cover outside it (hfun/region_cover.hpp), and the MPAS mesh of a
// regional mesh with its boundary layers (dual/boundary_layers.hpp).
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/options.hpp"
#include "components/cut_mesh.hpp"
#include "dual/boundary_layers.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/mpas_source.hpp"
#include "io/mpas_writer.hpp"
#include "features/domain.hpp"
#include "refine/lattice.hpp"
#include "hfun/region_cover.hpp"
#include "io/geojson.hpp"
#include "mesh/refined_mesh.hpp"
#include "quality/metrics.hpp"
#include "support/feature_parts.hpp"

// cmocka last: it defines a fail() macro.
extern "C" {
#include <cmocka.h>
}

using namespace um;
using features::Kind;
using features::Network;
using geom::Vec3;

namespace {

using Ring = testing::LinePart;

// The rings through Network::add, each with its index for its id.
um_status add_rings(Network &net, const std::vector<Ring> &rings, std::string *message = nullptr) {
    return testing::add(net, rings, message, false);
}

// A closed domain ring.
Ring ring(std::vector<double> lon, std::vector<double> lat) { return Ring{std::move(lon), std::move(lat), 1, UM_FEATURE_DOMAIN}; }

// A box of longitudes and latitudes (lon1 may exceed 180 or be below lon0:
// the ring goes east from lon0 to lon1).
Ring box(double lon0, double lon1, double lat0, double lat1) {
    return ring({lon0, lon1, lon1, lon0}, {lat0, lat0, lat1, lat1});
}

Vec3 at(double lon, double lat) { return geom::unit_from_lonlat_deg(lon, lat); }

features::Domain domain_of(const std::vector<Ring> &rings) {
    Network net;
    assert_int_equal(add_rings(net, rings), UM_OK);
    return features::Domain(features::with_domain_rings_traced(net));
}

// A box across the antimeridian, with a hole: the parity rule, and edges
// along parallels (a great arc from (160, 20) to (-160, 20) bulges to 20.6).
void a_dateline_box_with_a_hole(void **) {
    const features::Domain d = domain_of({box(160, -160, -20, 20), box(170, 175, -5, 5)});
    assert_false(d.empty());
    assert_true(d.contains(at(180, 0)));
    assert_true(d.contains(at(-170, 19.9)));
    assert_false(d.contains(at(180, 20.3)));   // inside the great arc, outside the parallel
    assert_false(d.contains(at(172, 0)));      // the hole
    assert_false(d.contains(at(150, 0)));
    assert_false(d.contains(at(0, 0)));
    assert_true(d.contains(at(176, 0)));
    // The area: the box's band less the hole's, as parallels bound them.
    auto band = [](double dlon, double lat0, double lat1) {
        return dlon * M_PI / 180 * (std::sin(lat1 * M_PI / 180) - std::sin(lat0 * M_PI / 180));
    };
    const double expected = band(40, -20, 20) - band(5, -5, 5);
    assert_true(std::fabs(d.area() - expected) < 1e-4 * expected);
    double to_ring = 0;
    d.locate(at(180, 21), &to_ring);
    assert_true(std::fabs(to_ring - M_PI / 180) < 1e-3);
}

// A ring around a pole encloses the cap (the smaller side), whichever way
// it is given.
void a_ring_around_a_pole(void **) {
    for (bool reversed : {false, true}) {
        Ring r = ring({0, 90, 180, -90}, {70, 70, 70, 70});
        if (reversed) std::reverse(r.lon.begin(), r.lon.end());
        const features::Domain d = domain_of({r});
        assert_true(d.contains(at(0, 89)));
        assert_true(d.contains(at(45, 70.5)));  // a parallel, not the chords between the corners
        assert_false(d.contains(at(45, 69.5)));
        assert_false(d.contains(at(0, -89)));
    }
}

// A ring not round a pole holds what it encloses drawn in longitude and
// latitude, whichever way it is given: a box wider than a hemisphere (its
// edges under 180 degrees of longitude each) is that box, with its hole, not
// the rest of the sphere.
void a_box_wider_than_a_hemisphere_is_that_box(void **) {
    for (bool reversed : {false, true}) {
        Ring r = ring({-170, 0, 170, 170, 0, -170}, {-70, -70, -70, 70, 70, 70});
        if (reversed) std::reverse(r.lon.begin(), r.lon.end()), std::reverse(r.lat.begin(), r.lat.end());
        const features::Domain d = domain_of({r, box(10, 20, -5, 5)});
        assert_true(d.contains(at(0, 0)));
        assert_true(d.contains(at(100, 60)));
        assert_true(d.contains(at(-169, -69)));
        assert_false(d.contains(at(15, 0)));  // the hole
        assert_false(d.contains(at(180, 0)));
        assert_false(d.contains(at(0, 80)));
        assert_false(d.contains(at(0, -80)));
        const double band = [](double dlon, double lat0, double lat1) {
            return dlon * M_PI / 180 * (std::sin(lat1 * M_PI / 180) - std::sin(lat0 * M_PI / 180));
        }(340, -70, 70);
        const double hole = 10 * M_PI / 180 * 2 * std::sin(5 * M_PI / 180);
        assert_true(std::fabs(d.area() - (band - hole)) < 1e-4 * band);
    }
}

// A box up to a pole wider than 180 degrees: its top edge runs 340 degrees
// west at the pole, so it does not go round it; the box, not the rest.
void a_box_up_to_a_pole_wider_than_180_degrees(void **) {
    const features::Domain d = domain_of({ring({-170, 0, 170, 170, -170}, {-30, -30, -30, 90, 90})});
    assert_true(d.contains(at(0, 0)));
    assert_true(d.contains(at(100, 60)));
    assert_true(d.contains(at(0, 89.9)));
    assert_false(d.contains(at(180, 0)));
    assert_false(d.contains(at(0, -60)));
    const double expected = 340 * M_PI / 180 * 1.5;
    assert_true(std::fabs(d.area() - expected) < 1e-4 * expected);
}

// A ring halving the sphere (the equator) holds the side on its left.
void the_equator_holds_the_hemisphere_on_its_left(void **) {
    for (bool reversed : {false, true}) {
        Ring r = ring({0, 90, 180, -90}, {0, 0, 0, 0});
        if (reversed) std::reverse(r.lon.begin(), r.lon.end());
        const features::Domain d = domain_of({r});
        const double north = reversed ? -1 : 1;
        assert_true(d.contains(at(30, 45 * north)));
        assert_false(d.contains(at(30, -45 * north)));
        assert_true(std::fabs(d.area() - 2 * M_PI) < 1e-9);
    }
}

// A box up to a pole: its two corners there are one point, and the edges
// beside it run along the box's meridians, not diagonally to that point.
void a_box_up_to_a_pole(void **) {
    for (double pole : {90.0, -90.0}) {
        const double s = pole > 0 ? 1 : -1;
        const features::Domain d = domain_of({ring({-10, 10, 10, -10}, {80 * s, 80 * s, pole, pole})});
        assert_true(d.contains(at(0, 89.5 * s)));
        assert_true(d.contains(at(-9.5, 85 * s)));
        assert_true(d.contains(at(9.5, 85 * s)));
        assert_false(d.contains(at(-10.5, 85 * s)));
        assert_false(d.contains(at(10.5, 85 * s)));
        const double expected = 20 * M_PI / 180 * (1 - std::sin(80 * M_PI / 180));
        assert_true(std::fabs(d.area() - expected) < 1e-4 * expected);
    }
}

// The rings add to a network, but make no domain: UM_ERR_INPUT saying `why`.
void expect_no_domain(const std::vector<Ring> &rings, const char *why) {
    Network net;
    assert_int_equal(add_rings(net, rings), UM_OK);
    try {
        features::Domain d(net);
        fail_msg("rings that should fail with \"%s\" were taken", why);
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_INPUT);
        if (!std::strstr(e.what(), why)) std::printf("said: %s\n", e.what());  // (what cmocka does not show)
        assert_non_null(std::strstr(e.what(), why));
    }
}

void crossing_open_and_short_rings_are_refused(void **) {
    std::string message;
    expect_no_domain({ring({0, 10, 0, 10}, {0, 10, 10, 0})}, "crosses itself at lon 5, lat 5.0575149: ");  // a bow tie (to 1e-7 degree)
    expect_no_domain({box(0, 10, 0, 10), box(5, 15, 5, 15)}, "crosses domain ring 1 (id 1) at lon");
    Network net;
    Ring open = box(0, 10, 0, 10);
    open.closed = 0;
    assert_int_equal(add_rings(net, {open}, &message), UM_ERR_INPUT);
    assert_non_null(std::strstr(message.c_str(), "is open"));
    assert_int_equal(add_rings(net, {ring({0, 10}, {0, 0})}, &message), UM_ERR_INPUT);
    assert_non_null(std::strstr(message.c_str(), "at least 3"));
    assert_int_equal(net.part_count(), 0);
}

// Rings that cross, read from GeoJSON after a passage (split off Gamma,
// so Gamma's part indices are not the file's): the refinement's refusal
// names each ring's file and JSON path.
void crossing_rings_are_named_by_their_file(void **) {
    const std::string text =
        "{\"type\": \"FeatureCollection\", \"features\": ["
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"passage\"}, \"geometry\": "
        "{\"type\": \"Point\", \"coordinates\": [3, 3]}},"
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
        "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]]}},"
        "{\"type\": \"Feature\", \"properties\": {\"kind\": \"domain\"}, \"geometry\": "
        "{\"type\": \"Polygon\", \"coordinates\": [[[5, 5], [15, 5], [15, 15], [5, 15], [5, 5]]]}}]}";
    auto features = std::make_shared<Network>();
    io::read_geojson_text(text, {}, *features, "boxes.geojson");
    Context ctx;
    try {
        mesh::refine_mesh(ctx, hfun::make_constant(200), features, Options{});
        fail_msg("crossing rings were taken");
    } catch (const Error &e) {
        const char *said = "domain ring 0 (id 1, boxes.geojson: features[1].geometry.coordinates[0]) crosses domain ring 1 "
                           "(id 2, boxes.geojson: features[2].geometry.coordinates[0]) at lon 10, lat 5";
        if (!std::strstr(e.what(), said)) std::printf("said: %s\n", e.what());
        assert_non_null(std::strstr(e.what(), said));
    }
}

// Points spread evenly over the sphere (a Fibonacci spiral).
std::vector<Vec3> spiral(int n) {
    std::vector<Vec3> points;
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z), a = i * M_PI * (3 - std::sqrt(5.0));
        points.push_back({r * std::cos(a), r * std::sin(a), z});
    }
    return points;
}

// A polar cap as GIS tools draw one (along the pole, down the antimeridian,
// 360 degrees round and back up; either way round, with or without the
// closing point, with a coast-like edge) is the ring round the pole it
// stands for: the same domain. A band round the sphere, a cap larger than
// a hemisphere and a ring reaching both poles are refused, naming why.
void a_gis_polar_cap_is_the_ring_round_its_pole(void **) {
    const features::Domain round = domain_of({ring({180, 90, 0, -90}, {-60, -60, -60, -60})});
    std::vector<Ring> caps = {ring({-180, 180, 180, -180}, {-90, -90, -60, -60}),
                              ring({-180, 180, 180, -180, -180}, {-90, -90, -60, -60, -90}),
                              ring({-180, -180, 180, 180}, {-90, -60, -60, -90})};
    for (const Ring &cap : caps) {
        const features::Domain d = domain_of({cap});
        assert_true(std::fabs(d.area() - round.area()) < 1e-12);
        for (const Vec3 &x : spiral(2000)) assert_true(d.contains(x) == round.contains(x));
    }
    const features::Domain coast = domain_of({ring({-180, 180, 180, 90, 0, -90, -180}, {-90, -90, -70, -65, -75, -62, -70})});
    assert_true(coast.contains(at(0, -80)) && coast.contains(at(-90, -63)) && !coast.contains(at(0, -70)));
    assert_false(coast.contains(at(0, 80)));
    const features::Domain arctic = domain_of({ring({-180, 180, 180, -180}, {60, 60, 90, 90})});
    assert_true(arctic.contains(at(30, 61)) && !arctic.contains(at(30, 59)));
    const std::pair<Ring, const char *> refused[] = {
        {ring({-180, 180, 180, -180}, {-60, -60, 90, 90}), "larger than a hemisphere"},
        {ring({-180, 180, 180, -180}, {-60, -60, 60, 60}), "does not run along one pole"},
        {ring({-180, 180, 180, -180}, {-90, -90, 90, 90}), "reaches both poles"},
    };
    for (const auto &[r, why] : refused) {
        Network net;
        std::string message;
        assert_int_equal(add_rings(net, {r}, &message), UM_ERR_INPUT);
        assert_non_null(std::strstr(message.c_str(), "read as a polar cap"));
        assert_non_null(std::strstr(message.c_str(), why));
    }
}

// What the memo answers without a search is what the search says, and most
// points away from the rings get that answer; the rough distance is within
// its error of the exact one - for a box with a hole across the
// antimeridian, a ring around a pole and a concave ring.
void the_memo_and_the_rough_distance_agree_with_the_search(void **) {
    const std::vector<std::vector<Ring>> domains = {
        {box(160, -160, -20, 20), box(170, 175, -5, 5)},
        {ring({0, 90, 180, -90}, {70, 70, 70, 70})},
        {ring({-10, 30, 30, 0, 30, 30, -10}, {0, 0, 10, 20, 30, 40, 40})},
    };
    for (const std::vector<Ring> &rings : domains) {
        const features::Domain d = domain_of(rings);
        int far = 0, answered = 0;
        for (const Vec3 &x : spiral(20000)) {
            double exact = 0;
            const bool inside = d.locate(x, &exact);
            const features::Domain::Side side = d.side(x);
            if (side != features::Domain::Side::near) assert_true(inside == (side == features::Domain::Side::inside));
            assert_true(std::fabs(d.rough_distance(x) - exact) <= features::Domain::rough_error());
            if (exact > 0.02) ++far, answered += side != features::Domain::Side::near;
        }
        print_message("memo: %d of %d points farther than 127 km answered without a search\n", answered, far);
        assert_true(answered > 0.95 * far);
    }
}

// distance_at_least answers points well inside its cap without the arc:
// at points straddling the cap's edge (from 1e-17 to 0.01 radians either
// side) it equals the arc's formula exactly, for a large and a small domain.
void the_cap_distance_is_the_arcs(void **) {
    for (const Ring &r : {box(-80, -5, 10, 65), box(-40.001, -40, 20, 20.001)}) {
        const features::Domain d = domain_of({r});
        const Vec3 c = d.cap_centre();
        const Vec3 across = geom::normalized(geom::cross(c, Vec3{0.3, -0.5, 0.8}));
        std::vector<double> offsets = {-1e-2, -1e-6, -1e-9, -1e-12, 1e-12, 1e-9, 1e-6, 1e-2};
        for (int k = -200; k <= 200; ++k) offsets.push_back(k * 1e-17);
        int inside = 0, outside = 0;
        for (double offset : offsets) {
            const double a = d.cap_radius() + offset;
            for (double scale : {1.0, 3.0}) {
                const Vec3 x = (std::cos(a) * scale) * c + (std::sin(a) * scale) * across;
                const double expected = std::max(0.0, geom::arc_length(x, c) - d.cap_radius());
                assert_true(d.distance_at_least(x) == expected);
                (expected == 0 ? inside : outside) += 1;
            }
        }
        assert_true(inside > 0 && outside > 0);
    }
}

// Inside: the caller's spacing; outside: growing at kCoverRate to kCoverKm
// (from the rough distance far from the rings, within its error);
// smallest_in_cap a lower bound of the values in the cap.
void the_cover_grows_away_from_the_domain(void **) {
    auto d = std::make_shared<const features::Domain>(domain_of({box(-40, 0, 10, 50)}));
    const hfun::SpacingPtr h = hfun::make_region_cover(hfun::make_constant(30), d);
    assert_true(h->km_at(at(-20, 30)) == 30);
    for (double lon : {0.5, 2.0, 10.0}) {
        double to_ring = 0;
        d->locate(at(lon, 30), &to_ring);
        const double d_km = to_ring * hfun::kEarthRadiusKm;
        const double error_km = hfun::kCoverRate * features::Domain::rough_error() * hfun::kEarthRadiusKm;
        assert_true(std::fabs(h->km_at(at(lon, 30)) - (30 + hfun::kCoverRate * d_km)) <= error_km);
    }
    assert_true(h->km_at(at(140, -30)) == hfun::kCoverKm);
    // Near the rings a cap's bound is the exact one (a fine mesh's cover
    // would otherwise take the inner spacing for the rough distance's error).
    const hfun::SpacingPtr fine = hfun::make_region_cover(hfun::make_constant(1), d);
    for (double lon : {0.1, 0.3}) {
        double to_ring = 0;
        d->locate(at(lon, 30), &to_ring);
        const double r = 0.001, expected = 1 + hfun::kCoverRate * (to_ring - r) * hfun::kEarthRadiusKm;
        assert_true(std::fabs(fine->smallest_in_cap(at(lon, 30), r, 1e9) - expected) < 1e-9 * expected);
    }
    for (const Vec3 &c : {at(5, 30), at(30, 30), at(-20, 55), at(100, 0), at(2.5, 30), at(0.5, 20), at(-41, 30)}) {
        const double r = 0.05, bound = h->smallest_in_cap(c, r, 1e9);
        for (int k = 0; k < 64; ++k) {
            const double a = 2 * M_PI * k / 64;
            const Vec3 t = geom::normalized(geom::cross(c, Vec3{0, 0, 1}));
            const Vec3 u = geom::cross(c, t);
            const Vec3 p = geom::normalized(std::cos(r) * c + std::sin(r) * (std::cos(a) * t + std::sin(a) * u));
            assert_true(bound <= h->km_at(p) * (1 + 1e-12));
        }
    }
}

std::shared_ptr<Network> rings_network(const std::vector<Ring> &rings) {
    auto net = std::make_shared<Network>();
    assert_int_equal(add_rings(*net, rings), UM_OK);
    return net;
}

// Optimises m, checking that the cover (outside the domain, off its rings)
// is left as it is: every vertex there keeps its lifted point bit for bit,
// and no vertex the optimisation added lies in it.
void optimise_keeping_the_cover(Context &ctx, mesh::RefinedMesh &m, const Options &options) {
    std::map<int32_t, Vec3> cover;  // by vertex id
    const std::vector<uint8_t> in_cover = m.cover_vertices(ctx);
    int32_t first_new_id = 0;
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v) {
        first_new_id = std::max(first_new_id, m.tri.id(v) + 1);
        if (in_cover[v]) cover[m.tri.id(v)] = m.tri.lifted(v);
    }
    mesh::optimise_mesh(ctx, m, options, nullptr);
    const std::vector<uint8_t> cover_after = m.cover_vertices(ctx);
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v) {
        if (!m.tri.in_triangulation(v) || m.tri.id(v) < first_new_id) continue;
        assert_false(cover_after[v]);
    }
    assert_true(cover.size() > 50);
    size_t kept = 0;
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v) {
        const auto found = cover.find(m.tri.id(v));
        if (!m.tri.in_triangulation(v) || found == cover.end()) continue;
        const Vec3 &q = m.tri.lifted(v);
        assert_true(q.x == found->second.x && q.y == found->second.y && q.z == found->second.z);
        ++kept;
    }
    assert_int_equal(kept, cover.size());
}

// Rings whose corners and notches put Gamma's obtuse corners beside the
// cover (the corner passes once added vertices there and took out cover
// vertices for them): the cover stays as it is, and the cells kept have no
// obtuse triangle.
void the_cover_stays_beside_notches_and_zigzags(void **) {
    Ring zigzag = ring({}, {});
    for (int k = 0; k <= 40; ++k) zigzag.lon.push_back(0.25 * k), zigzag.lat.push_back(k % 2 ? 0.3 : 0);
    for (int k = 1; k <= 40; ++k) zigzag.lon.push_back(k % 2 ? 10.35 : 10), zigzag.lat.push_back(0.25 * k);
    for (auto [lon, lat] : {std::pair{6.0, 10.0}, {5.3, 4.0}, {5.0, 4.0}, {4.5, 10.0}, {0.0, 10.0}})
        zigzag.lon.push_back(lon), zigzag.lat.push_back(lat);
    const Ring notch = ring({-10, 30, 30, 12, 10.8, 9.2, 8, -10}, {0, 0, 40, 40, 15, 15, 40, 40});
    for (const auto &[r, km] : {std::pair{zigzag, 25.0}, {zigzag, 40.0}, {notch, 100.0}}) {
        Context ctx;
        Options options;
        mesh::RefinedMesh m = mesh::refine_mesh(ctx, hfun::make_constant(km), rings_network({r}), options);
        optimise_keeping_the_cover(ctx, m, options);
        const std::vector<uint8_t> cells = m.region_cells(ctx);
        const quality::Report q = quality::measure(ctx, m.tri, mesh::spacing_radians(*m.spacing, m.surface),
                                                   &m.on_segment, &cells);
        print_message("%.0f km: %lld triangles in the domain, %lld obtuse\n", km, static_cast<long long>(q.triangles),
                      static_cast<long long>(q.obtuse));
        assert_true(q.triangles > 100);
        assert_true(q.obtuse * 10000 <= q.triangles);  // at most 0.01 %
    }
}

// The dateline box at 150 km: every cell inside, the layers, no obtuse
// triangle, and the same mesh on one and two threads.
void a_regional_mesh_of_a_dateline_box(void **) {
    std::vector<dual::MpasMesh> meshes;
    for (int threads : {1, 2}) {
        Context ctx;
        ctx.set_threads(threads);
        Options options;
        mesh::RefinedMesh m = mesh::refine_mesh(ctx, hfun::make_constant(150), rings_network({box(160, -160, -20, 20)}), options);
        assert_true(m.regional());
        optimise_keeping_the_cover(ctx, m, options);
        meshes.push_back(dual::build_mpas_mesh(ctx, m));
        const std::vector<uint8_t> cells = m.region_cells(ctx);
        const quality::Report r = quality::measure(ctx, m.tri, mesh::spacing_radians(*m.spacing, m.surface),
                                                   &m.on_segment, &cells);
        assert_true(r.triangles > 0);
        assert_int_equal(r.obtuse, 0);
    }
    const dual::MpasMesh &mpas = meshes[0];
    print_message("dateline box at 150 km: %d cells\n", mpas.n_cells);
    // 1.94e7 km^2 / (0.866 * 150^2 km^2) = 995 cells, less the rings' and the gaps'.
    assert_true(mpas.n_cells > 700 && mpas.n_cells < 1100);
    const features::Domain d = domain_of({box(160, -160, -20, 20)});
    for (int32_t c = 0; c < mpas.n_cells; ++c)
        assert_true(d.contains((1 / mpas.radius_m) * Vec3{mpas.x_cell[c], mpas.y_cell[c], mpas.z_cell[c]}));
    for (int32_t v = 0; v < mpas.n_vertices; ++v)
        assert_true(d.contains((1 / mpas.radius_m) * Vec3{mpas.x_vertex[v], mpas.y_vertex[v], mpas.z_vertex[v]}));
    // Layers: 7 exactly where a neighbour is missing; neighbours one apart
    // (or both interior); every layer present.
    std::vector<int> per_layer(8, 0);
    const size_t w = static_cast<size_t>(mpas.max_edges);
    for (int32_t c = 0; c < mpas.n_cells; ++c) {
        const int32_t layer = mpas.bdy_mask_cell[c];
        ++per_layer[layer];
        bool missing = false;
        for (int32_t j = 0; j < mpas.n_edges_on_cell[c]; ++j) {
            const int32_t n = mpas.cells_on_cell[c * w + j];
            if (n == dual::kNone) {
                missing = true;
                continue;
            }
            assert_true(std::abs(layer - mpas.bdy_mask_cell[n]) <= 1);
        }
        assert_true(missing == (layer == dual::kBoundaryLayers));
    }
    for (int k = 0; k <= 7; ++k) assert_true(per_layer[k] > 0);
    for (int32_t e = 0; e < mpas.n_edges; ++e) {
        const int32_t c1 = mpas.cells_on_edge[2 * e], c2 = mpas.cells_on_edge[2 * e + 1];
        const int32_t least = std::min(c1 == dual::kNone ? 7 : mpas.bdy_mask_cell[c1], c2 == dual::kNone ? 7 : mpas.bdy_mask_cell[c2]);
        assert_int_equal(mpas.bdy_mask_edge[e], least);
    }
    const dual::MpasMesh &other = meshes[1];
    assert_int_equal(mpas.n_cells, other.n_cells);
    assert_true(mpas.x_cell == other.x_cell && mpas.cells_on_cell == other.cells_on_cell &&
                mpas.weights_on_edge == other.weights_on_edge && mpas.bdy_mask_cell == other.bdy_mask_cell);
}

// A domain of a millionth of the sphere at 1 km (the whole sphere's lattice
// would pass the triangulation's 2^28 points) still starts from the relaxed
// lattice placed around it: every cell away from the boundary a hexagon
// (from the icosahedron, 6-21 % of them were not, on boxes of 1-4 degrees).
void a_small_fine_domain_starts_from_the_lattice(void **) {
    Context ctx;
    ctx.set_threads(2);
    Options options;
    mesh::RefinedMesh m =
        mesh::refine_mesh(ctx, hfun::make_constant(1), rings_network({box(-40, -39.7, 20, 20.3)}), options);
    optimise_keeping_the_cover(ctx, m, options);
    const dual::MpasMesh mpas = dual::build_mpas_mesh(ctx, m);
    int32_t interior = 0, not_hexagons = 0;
    for (int32_t c = 0; c < mpas.n_cells; ++c)
        if (mpas.bdy_mask_cell[c] == 0) ++interior, not_hexagons += mpas.n_edges_on_cell[c] != 6;
    print_message("0.3 x 0.3 degree box at 1 km: %d cells, %d away from the boundary, %d of them not hexagons\n",
                  mpas.n_cells, interior, not_hexagons);
    assert_true(interior > 200);
    assert_int_equal(not_hexagons, 0);
}

// A domain's lattice that would not fit the memory cap gives way to the
// icosahedron's corners (a long thin domain's cap holds many times its
// points); without a cap, the same domain gets its lattice.
void a_domain_lattice_stays_within_the_memory_cap(void **) {
    const features::Domain strip = domain_of({box(-60, 20, 40, 41)});
    const refine::SpacingRadians h = [](const Vec3 &) { return 20.0 / 6371.0; };
    const geom::ArcTree none;
    Context ctx;
    const size_t uncapped = refine::background_lattice(ctx, h, none, &strip).size();
    ctx.set_memory_cap(int64_t(1) << 20);
    const size_t capped = refine::background_lattice(ctx, h, none, &strip).size();
    print_message("a strip of 80 x 1 degrees at 20 km: %zu lattice points kept, %zu under a 1 MiB cap\n", uncapped,
                  capped);
    assert_true(uncapped > 1000);
    assert_true(capped <= 12);
}

// A regional mesh's rows (the region's elements of the whole numbering,
// made a block at a time) are the whole triangulation's MPAS mesh cut to the
// region by the component meshes' cut (components/cut_mesh.hpp), the same
// way whatever the block size of the file.
void a_regional_mesh_is_the_whole_mesh_cut(void **) {
    Context ctx;
    Options options;
    mesh::RefinedMesh m = mesh::refine_mesh(ctx, hfun::make_constant(300), rings_network({box(160, -160, -20, 20)}), options);
    optimise_keeping_the_cover(ctx, m, options);
    const dual::MpasMesh regional = dual::build_mpas_mesh(ctx, m);
    dual::MpasMeshInput input;
    input.slot_of_vertex = m.slot_of_vertex, input.radius_m = m.surface.authalic_radius_m();
    const dual::MpasMesh whole = dual::build_mpas_mesh(ctx, m.tri, input);
    const std::vector<uint8_t> region = m.region_cells(ctx);
    std::vector<uint8_t> keep(static_cast<size_t>(whole.n_cells));
    for (int32_t c = 0; c < whole.n_cells; ++c) keep[c] = region[m.slot_of_vertex[whole.cell_source_vertex[c]]];
    const dual::MpasMesh cut = components::cut_mesh(ctx, whole, keep);
    assert_true(cut.n_cells < whole.n_cells);
    assert_int_equal(regional.n_cells, cut.n_cells);
    assert_int_equal(regional.n_edges, cut.n_edges);
    assert_int_equal(regional.n_vertices, cut.n_vertices);
    assert_int_equal(regional.max_edges, cut.max_edges);
    assert_true(regional.x_cell == cut.x_cell && regional.y_cell == cut.y_cell && regional.z_cell == cut.z_cell &&
                regional.lat_cell == cut.lat_cell && regional.lon_cell == cut.lon_cell &&
                regional.area_cell == cut.area_cell && regional.mesh_density == cut.mesh_density);
    assert_true(regional.edges_on_cell == cut.edges_on_cell && regional.vertices_on_cell == cut.vertices_on_cell &&
                regional.cells_on_cell == cut.cells_on_cell && regional.n_edges_on_cell == cut.n_edges_on_cell);
    assert_true(regional.cells_on_edge == cut.cells_on_edge && regional.vertices_on_edge == cut.vertices_on_edge);
    assert_true(regional.x_edge == cut.x_edge && regional.y_edge == cut.y_edge && regional.z_edge == cut.z_edge &&
                regional.lat_edge == cut.lat_edge && regional.lon_edge == cut.lon_edge &&
                regional.dc_edge == cut.dc_edge && regional.dv_edge == cut.dv_edge &&
                regional.angle_edge == cut.angle_edge);
    assert_true(regional.x_vertex == cut.x_vertex && regional.y_vertex == cut.y_vertex &&
                regional.z_vertex == cut.z_vertex && regional.lat_vertex == cut.lat_vertex &&
                regional.lon_vertex == cut.lon_vertex);
    assert_true(regional.cells_on_vertex == cut.cells_on_vertex && regional.edges_on_vertex == cut.edges_on_vertex &&
                regional.kite_areas_on_vertex == cut.kite_areas_on_vertex &&
                regional.area_triangle == cut.area_triangle && regional.boundary_vertex == cut.boundary_vertex);
    // The weights from the same kites, dvEdge and dcEdge in the same order: the same bits.
    assert_true(regional.n_edges_on_edge == cut.n_edges_on_edge && regional.edges_on_edge == cut.edges_on_edge &&
                regional.weights_on_edge == cut.weights_on_edge);
    // Edges turned round (their first cell outside in the whole numbering)
    // are among them: a row's first cell is always the region's.
    int64_t turned = 0;
    for (int32_t e = 0; e < cut.n_edges; ++e) {
        assert_true(regional.cells_on_edge[2 * e] != dual::kNone);
        turned += whole.cells_on_edge[2 * int64_t(cut.base_edge[e])] != cut.base_cell[regional.cells_on_edge[2 * e]];
    }
    assert_true(turned > 0);
    // The file in blocks of a few rows, of one row and whole: the same bytes.
    const std::string path = std::string(UNIMESH_TEST_OUTPUT_DIR) + "/test_regional.nc";
    auto bytes = [&] {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    io::write_mpas_mesh(regional, path, io::MpasWriteOptions{});
    const std::string expected = bytes();
    for (int threads : {1, 3}) {
        Context streaming;
        streaming.set_threads(threads);
        const dual::MpasSource source(streaming, m);
        for (int64_t rows : {int64_t(1), int64_t(97)}) {
            io::MpasWriteOptions o;
            o.block_rows = rows;
            io::write_mpas_mesh(streaming, source, path, o);
            assert_true(bytes() == expected);
        }
    }
    std::remove(path.c_str());
}

void a_domain_smaller_than_the_spacing_is_refused(void **) {
    Context ctx;
    try {
        mesh::refine_mesh(ctx, hfun::make_constant(100), rings_network({box(10, 10.5, 10, 10.5)}), Options{});
        fail_msg("a domain of half a degree was meshed at 100 km");
    } catch (const Error &e) {
        assert_int_equal(e.status(), UM_ERR_INPUT);
        assert_non_null(std::strstr(e.what(), "larger than the spacing"));
    }
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_dateline_box_with_a_hole),
        cmocka_unit_test(a_ring_around_a_pole),
        cmocka_unit_test(a_gis_polar_cap_is_the_ring_round_its_pole),
        cmocka_unit_test(a_box_wider_than_a_hemisphere_is_that_box),
        cmocka_unit_test(a_box_up_to_a_pole),
        cmocka_unit_test(a_box_up_to_a_pole_wider_than_180_degrees),
        cmocka_unit_test(a_small_fine_domain_starts_from_the_lattice),
        cmocka_unit_test(a_domain_lattice_stays_within_the_memory_cap),
        cmocka_unit_test(the_equator_holds_the_hemisphere_on_its_left),
        cmocka_unit_test(crossing_open_and_short_rings_are_refused),
        cmocka_unit_test(crossing_rings_are_named_by_their_file),
        cmocka_unit_test(the_memo_and_the_rough_distance_agree_with_the_search),
        cmocka_unit_test(the_cap_distance_is_the_arcs),
        cmocka_unit_test(the_cover_grows_away_from_the_domain),
        cmocka_unit_test(a_regional_mesh_of_a_dateline_box),
        cmocka_unit_test(a_regional_mesh_is_the_whole_mesh_cut),
        cmocka_unit_test(the_cover_stays_beside_notches_and_zigzags),
        cmocka_unit_test(a_domain_smaller_than_the_spacing_is_refused),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
