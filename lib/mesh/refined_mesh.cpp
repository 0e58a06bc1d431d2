#include "mesh/refined_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "core/earth.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "dual/mpas_mesh.hpp"
#include "dual/mpas_source.hpp"
#include "hfun/on_ellipsoid.hpp"
#include "hfun/region_cover.hpp"
#include "refine/boundary.hpp"
#include "refine/lattice.hpp"
#include "refine/relax.hpp"
#include "refine/surface.hpp"
#include "tri/cell_walk.hpp"

namespace um::mesh {

namespace {

// Refuses a value no mesh can follow, naming where (geodetic lon/lat).
void check_spacing_km(double km, const geom::Vec3 &x, const geom::Surface &surface) {
    if (std::isfinite(km) && km > 0) return;
    double lon, lat;
    surface.geodetic(x, lon, lat);
    fail(std::isfinite(km) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT, "the spacing is ", km,
         " km at lon ", lon, ", lat ", lat, " degrees: it must be finite and > 0");
}

}  // namespace

// h in radians on the unit sphere.
refine::SpacingRadians spacing_radians(const hfun::Spacing &h, const geom::Surface &surface) {
    const double per_km = 1000.0 / surface.a();
    return [&h, per_km, surface](const geom::Vec3 &x) {
        const double km = h.km_at(x);
        check_spacing_km(km, x, surface);
        return km * per_km;
    };
}

refine::SmallestSpacingRadians smallest_spacing_radians(const hfun::Spacing &h, const geom::Surface &surface) {
    const double per_km = 1000.0 / surface.a();
    return [&h, per_km, surface](const geom::Vec3 &x, double r, double enough) {
        const double km = h.smallest_in_cap(x, r, enough / per_km);
        check_spacing_km(km, x, surface);
        return km * per_km;
    };
}

namespace {

// Four generators on (nearly) one circle give two triangles with (nearly)
// the same orthocentre: a dual edge of (almost) zero length, which MPAS and
// its checkers cannot orient. Making the vertex opposite such an edge a
// little lighter (a Laguerre weight of a few thousandths of l^2, far too
// small to hide it) keeps the edge regular with a dual edge ~1e-3 l long.
constexpr double kMinDualOverPrimal = 1e-3;

// The apexes opposite too-short dual edges among the given triangles
// (all live ones when `triangles` is empty), sorted, each once.
std::vector<int32_t> apexes_of_short_dual_edges(Context &ctx, const tri::Triangulation &tri,
                                                std::vector<int32_t> triangles) {
    if (triangles.empty())
        for (int32_t t = 0; t < tri.triangle_slots(); ++t)
            if (!tri.is_free(t)) triangles.push_back(t);
    const int64_t n = static_cast<int64_t>(triangles.size());
    std::vector<int32_t> flagged(static_cast<size_t>(n), -1);
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t t = triangles[i];
            if (tri.is_free(t)) continue;
            const geom::Vec3 ct = tri.orthocentre(t);
            for (int k = 0; k < 3; ++k) {
                const geom::Vec3 a = tri.direction(tri.vertex(t, (k + 1) % 3));
                const geom::Vec3 c = tri.direction(tri.vertex(t, (k + 2) % 3));
                const geom::Vec3 d = ct - tri.orthocentre(tri.neighbour(t, k));
                if (geom::dot(d, d) < kMinDualOverPrimal * kMinDualOverPrimal * geom::dot(a - c, a - c))
                    flagged[i] = tri.vertex(t, k);  // one per triangle is enough per pass
            }
        }
    });
    std::vector<int32_t> out;
    for (int32_t v : flagged)
        if (v >= 0) out.push_back(v);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// The cover's vertices (RefinedMesh::cover_vertices) stay as they are: no
// edge of a kept cell has one for an apex.
int64_t separate_degenerate_dual_edges(Context &ctx, tri::Triangulation &tri, const std::vector<uint8_t> &cover) {
    int64_t changed = 0;
    std::vector<int32_t> lighten = apexes_of_short_dual_edges(ctx, tri, {});
    for (int pass = 0; pass < 4 && !lighten.empty(); ++pass) {
        std::vector<int32_t> touched;  // triangles to look at again
        for (int32_t v : lighten) {
            if (!tri.in_triangulation(v) || cover[v]) continue;
            double l2 = 1e300;  // its shortest edge, squared chord
            const geom::Vec3 x = tri.direction(v);
            for (int32_t t : tri.star(v))
                for (int k = 0; k < 3; ++k)
                    if (tri.vertex(t, k) != v) {
                        geom::Vec3 d = x - tri.direction(tri.vertex(t, k));
                        l2 = std::min(l2, geom::dot(d, d));
                    }
            tri.set_weight(v, tri.weight(v) - 4 * kMinDualOverPrimal * l2);
            ++changed;
            for (int32_t t : tri.star(v)) {
                touched.push_back(t);
                for (int k = 0; k < 3; ++k) touched.push_back(tri.neighbour(t, k));
            }
        }
        if (touched.empty()) break;  // (every apex of the cover: nothing changed; an empty list means all)
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        lighten = apexes_of_short_dual_edges(ctx, tri, touched);
    }
    return changed;
}

// Peak bytes per cell of the two stages for the memory cap's up-front check,
// with a margin. Measured by tools/bench/bench_refine: the refinement 170
// (uniform 30 km) to 225-238 (coastlines and rivers at 60 km), the whole
// pipeline 233-242 (uniform, undo snapshot included) and up to 340 on the
// coastline cases, hence the optimisation's 480; without features (no
// restricted edges, sides or guards) 231 at 10 km (tools/bench/bench_scale.py),
// hence 300.
constexpr int64_t kRefineBytesPerCell = 280;
constexpr int64_t kOptimiseBytesPerCell = 480, kOptimiseUniformBytesPerCell = 300;
constexpr double kOptimiseNewVertices = 0.125, kOptimiseNewTriangles = 0.05;  // room reserved
constexpr int kRefineRounds = 4;           // surface passes at most (each after a boundary pass)

void number_vertices(RefinedMesh &m) {
    m.vertex_of_slot.assign(static_cast<size_t>(m.tri.vertex_slots()), -1);
    m.slot_of_vertex.clear();
    m.slot_of_vertex.reserve(static_cast<size_t>(m.tri.vertex_count()));
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v)
        if (m.tri.in_triangulation(v)) {
            m.vertex_of_slot[v] = static_cast<int32_t>(m.slot_of_vertex.size());
            m.slot_of_vertex.push_back(v);
        }
}

// What every stage hands on: no degenerate dual edge, compact slots in
// Hilbert order (tri::Triangulation::reorder_spatially), vertex numbers,
// and Tri|Gamma with the sides for the triangulation as it is now.
// Gamma is every part of the caller's features but the passages, which go
// to m.passages (the one copy the mesh keeps of each part).
void split_passages(RefinedMesh &m, std::shared_ptr<const features::Network> features) {
    const bool any = features && std::any_of(features->parts().begin(), features->parts().end(),
                                             [](const features::Part &p) { return p.kind == features::Kind::passage; });
    if (!any) {
        m.gamma = std::move(features);
        return;
    }
    m.gamma = std::make_shared<features::Network>(
        features::parts_of_kind(*features, features::Kind::passage, false, &m.features_part));
    m.passages = std::make_shared<features::Network>(features::parts_of_kind(*features, features::Kind::passage, true));
}

// Gamma, the passages and the domain as the mesh uses them: split
// (split_passages), the domain rings traced along their lon/lat edges, on
// an ellipsoid each point at the direction of its geodetic lon/lat; the
// domain of those rings (none without any).
void place_gamma(RefinedMesh &m, std::shared_ptr<const features::Network> features) {
    const std::shared_ptr<const features::Network> callers = features;  // (for the rings' origins)
    split_passages(m, std::move(features));
    const bool regional = m.gamma && std::any_of(m.gamma->parts().begin(), m.gamma->parts().end(), [](const features::Part &p) {
                              return p.kind == features::Kind::domain;
                          });
    if (regional) m.gamma = std::make_shared<const features::Network>(features::with_domain_rings_traced(*m.gamma));
    if (!m.surface.is_sphere()) {
        if (m.gamma) m.gamma = std::make_shared<const features::Network>(features::on_ellipsoid(*m.gamma, m.surface.f()));
        if (m.passages)
            m.passages = std::make_shared<const features::Network>(features::on_ellipsoid(*m.passages, m.surface.f()));
    }
    if (!regional) return;
    // (Gamma's parts are the caller's but the passages, in order: the
    // traced and ellipsoidal copies keep them.)
    const features::Domain::Origin origin = [&](int64_t p) {
        return callers->domain_origin(m.features_part.empty() ? p : m.features_part[static_cast<size_t>(p)]);
    };
    auto domain = std::make_shared<const features::Domain>(*m.gamma, origin);
    if (!domain->empty()) m.domain = std::move(domain);
}

// The surface the options describe: a sphere of sphere_radius, or the
// ellipsoid of that semi-major axis and surface_flattening.
geom::Surface surface_of(const Options &options) {
    const double a = options.real(UM_OPT_SPHERE_RADIUS), f = options.real(UM_OPT_SURFACE_FLATTENING);
    return f == 0 ? geom::Surface::sphere(a) : geom::Surface::ellipsoid(a, f);
}

// how: in place after the optimisation, whose undo is then alive (a copy
// of the triangles would add to the peak there).
void finish(Context &ctx, RefinedMesh &m, const geom::ArcTree &arcs, tri::Triangulation::Reorder how) {
    separate_degenerate_dual_edges(ctx, m.tri, m.cover_vertices(ctx));
    m.on_segment.resize(static_cast<size_t>(m.tri.vertex_slots()), -1);
    const std::vector<int32_t> old_slot = m.tri.reorder_spatially(ctx, how);
    std::vector<int32_t> on_segment(old_slot.size());
    for (size_t v = 0; v < old_slot.size(); ++v) on_segment[v] = m.on_segment[old_slot[v]];
    m.on_segment.swap(on_segment);
    number_vertices(m);
    if (arcs.size() > 0) {
        m.restricted = refine::restricted_edges(ctx, m.tri, arcs);
        m.triangle_side = refine::triangle_sides(m.tri, *m.gamma, &m.restricted);
        m.vertex_side = refine::vertex_sides(m.tri, m.triangle_side, m.on_segment, *m.gamma);
    } else {
        m.restricted.clear();
        m.triangle_side.assign(static_cast<size_t>(m.tri.triangle_slots()), refine::Side::ocean);
        m.vertex_side.assign(static_cast<size_t>(m.tri.vertex_slots()), refine::Side::ocean);
    }
}

// A regional mesh needs a cell with its neighbours inside the domain.
constexpr int64_t kMinRegionCells = 7;

void require_region_cells(Context &ctx, const RefinedMesh &m) {
    const std::vector<uint8_t> kept = m.region_cells(ctx);
    const int64_t cells = std::count(kept.begin(), kept.end(), uint8_t(1));
    if (cells >= kMinRegionCells) return;
    const double km2_per_steradian = m.surface.area_m2() / (4 * M_PI) / 1e6;
    fail(UM_ERR_INPUT, "the domain (", m.domain->area() * km2_per_steradian, " km^2) holds ", cells,
         " cells at this spacing: it must be larger than the spacing (at least ", kMinRegionCells, " cells)");
}

// The triangulation the refinement starts from: the icosahedron, with the
// geodesic lattice of the spacing where the spacing is flat
// (refine::background_lattice) unless the options say no. A spacing as
// coarse as the gaps between the features (2500 km and more with the
// world's coastlines) leaves the lattice too few points away from them to
// surround the centre: then the icosahedron, which always does.
tri::Triangulation starting_triangulation(Context &ctx, const refine::SpacingRadians &hr,
                                          const geom::ArcTree &arcs, bool lattice_allowed,
                                          const features::Domain *domain) {
    if (!lattice_allowed) return refine::icosahedron(ctx);
    const std::vector<geom::Vec3> points = refine::background_lattice(ctx, hr, arcs, domain);
    tri::Triangulation tri;
    try {
        tri.build(ctx, static_cast<int64_t>(points.size()), [&](int64_t i) { return points[i]; }, nullptr);
    } catch (const Error &e) {
        if (e.status() != UM_ERR_DEGENERATE_INPUT) throw;
        return refine::icosahedron(ctx);
    }
    return tri;
}

// The spacing the mesh follows: the caller's, gradient-limited to g (> 0)
// where it is a grid steeper than that.
hfun::SpacingPtr mesh_spacing(Context &ctx, hfun::SpacingPtr h, double g, double radius_m) {
    if (!(g > 0)) return h;
    hfun::SpacingPtr limited = h->gradient_limited(g, radius_m / 1000.0);
    if (!limited || limited == h) return h;
    ctx.log(UM_LOG_INFO, concat("refine: the spacing is steeper than ", g,
                                " km per km in places: meshed gradient-limited to that (option spacing_gradient)"));
    return limited;
}

}  // namespace

int64_t estimated_cells(Context &ctx, const hfun::Spacing &h) {
    // Cells of spacing h cover about (sqrt(3)/2) h^2 each (hexagons of edge
    // h between generators); the sphere in 180 x 360 bands of equal angle.
    constexpr int kLat = 180, kLon = 360;
    const double radius_km = kEarthRadiusKm;
    std::vector<double> band(kLat, 0.0);
    ctx.parallel_for_with_heartbeat("refine", kLat, 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const double lat = -90 + (i + 0.5) * 180.0 / kLat;
            const double area = 2 * M_PI * radius_km * radius_km *
                                (std::sin((lat + 90.0 / kLat) * M_PI / 180) - std::sin((lat - 90.0 / kLat) * M_PI / 180)) / kLon;
            for (int j = 0; j < kLon; ++j) {
                const double km = h.km_at_lonlat(-180 + (j + 0.5) * 360.0 / kLon, lat);
                if (std::isfinite(km) && km > 0) band[i] += area / (0.8660254 * km * km);
            }
        }
    });
    double total = 0;
    for (double b : band) total += b;
    return static_cast<int64_t>(std::min(total, 1e15));
}

MeshEstimate estimate_mesh(Context &ctx, const hfun::Spacing &h) {
    MeshEstimate e;
    e.cells = estimated_cells(ctx, h);
    const int64_t cells = std::min<int64_t>(e.cells, int64_t(1) << 50);  // the products below fit int64
    e.refine_bytes = cells * std::max(kRefineBytesPerCell, kOptimiseBytesPerCell);
    // Features or not, regional or not: the larger (an estimate of the spacing
    // alone knows neither).
    e.mpas_bytes = dual::mpas_stream_bytes(cells, true, false, true);
    return e;
}

RefinedMesh refine_mesh(Context &ctx, hfun::SpacingPtr h,
                        std::shared_ptr<const features::Network> gamma, const Options &options) {
    RefinedMesh m;
    m.surface = surface_of(options);
    h = mesh_spacing(ctx, std::move(h), options.real(UM_OPT_SPACING_GRADIENT), m.radius_m());
    h = hfun::make_on_ellipsoid(std::move(h), m.surface);
    place_gamma(m, std::move(gamma));
    if (m.domain) h = hfun::make_region_cover(std::move(h), m.domain, m.radius_m() / 1000.0);
    if (ctx.memory_cap() > 0) {
        // Refused up front, before any work, when the cap cannot hold it.
        const int64_t cells = estimated_cells(ctx, *h);
        ctx.check_memory(cells * kRefineBytesPerCell, concat("a mesh of about ", cells, " cells").c_str());
    }
    m.spacing = std::move(h);
    const refine::SpacingRadians hr = spacing_radians(*m.spacing, m.surface);
    const geom::ArcTree arcs = features::segment_arc_tree(m.gamma.get());
    m.tri = starting_triangulation(ctx, hr, arcs, options.integer(UM_OPT_REFINE_LATTICE) != 0, m.domain.get());
    int32_t next_id = m.tri.vertex_slots();
    refine::BoundaryOptions bo;
    bo.alpha = options.real(UM_OPT_REFINE_ALPHA);
    bo.beta = options.real(UM_OPT_REFINE_BETA);
    m.boundary_alpha = bo.alpha, m.boundary_beta = bo.beta;
    m.ocean_floor = options.real(UM_OPT_OCEAN_FLOOR);
    std::vector<int64_t> part_of_arc;
    if (options.integer(UM_OPT_REFINE_TOPOLOGY_CHECK) != 0 && arcs.size() > 0) {
        part_of_arc.resize(arcs.size());
        for (size_t s = 0; s < arcs.size(); ++s) part_of_arc[s] = m.gamma->segment_part(static_cast<int64_t>(s));
        bo.part_of_arc = &part_of_arc;
    }
    const std::vector<uint8_t> coast_arc = m.coastline_arcs();
    if (arcs.size() > 0) bo.filter.coast_arc = &coast_arc, bo.filter.coast_filter = options.real(UM_OPT_OCEAN_FLOOR);
    refine::SurfaceOptions so;
    so.alpha = options.real(UM_OPT_REFINE_ALPHA);
    so.rho = options.real(UM_OPT_REFINE_RHO);
    so.smallest = smallest_spacing_radians(*m.spacing, m.surface);
    if (arcs.size() > 0) so.gamma = &arcs, so.on_gamma = &m.on_segment, so.filter = bo.filter;
    // Boundary then surface refinement. The surface points change dual
    // edges near Gamma, so that some restricted edges come out too long
    // again: another boundary pass mends them (looking only around the
    // surface points placed near Gamma), then a surface pass the triangles
    // it made (only around the new boundary points), until a boundary pass
    // inserts nothing - in practice after two more rounds. The last pass is
    // always a boundary pass; after kRefineRounds surface passes it ends.
    std::vector<int32_t> near_gamma;
    for (int round = 0;; ++round) {
        refine::BoundaryStats boundary;
        if (arcs.size() > 0)
            boundary = refine::refine_boundary(ctx, m.tri, hr, arcs, bo, next_id, m.on_segment,
                                               round > 0 ? &near_gamma : nullptr);
        if ((round > 0 && boundary.inserted == 0) || round == kRefineRounds) break;
        refine::SurfaceStats surface =
            refine::refine_surface(ctx, m.tri, hr, so, next_id, round > 0 ? &boundary.added : nullptr);
        next_id = surface.next_id;
        near_gamma.swap(surface.near_gamma);
    }
    if (options.integer(UM_OPT_REFINE_RELAX) != 0) {
        refine::RelaxOptions ro;
        ro.alpha = so.alpha, ro.rho = so.rho;
        if (arcs.size() > 0) ro.gamma = &arcs, ro.on_gamma = &m.on_segment;
        const refine::RelaxStats relaxed = refine::relax_edge_lengths(ctx, m.tri, hr, ro);
        ctx.log(UM_LOG_INFO, concat("refine: relaxation moved ", relaxed.moves, " vertices, removed ",
                                    relaxed.removed, " and put ", relaxed.replaced, " elsewhere; edges outside [",
                                    ro.lower, ", ", ro.upper, "] h: ", relaxed.outside_before, " -> ",
                                    relaxed.outside_after));
    }
    ctx.progress("refine tags", 0.0);  // (not from the optimisation's finish: its stage is "optimise")
    finish(ctx, m, arcs, tri::Triangulation::Reorder::copying);
    m.filtered = refine::count_bad(m.tri, m.restricted, hr, bo);
    if (m.domain) require_region_cells(ctx, m);
    return m;
}

namespace {

// What optimise_mesh changes, kept so that a failure or a cancellation puts
// the mesh back exactly as it was: the triangulation as a snapshot (its
// points and triangles) and on_segment, which the optimisation changes in
// place; the derived fields, which it does not read, moved aside.
struct Undo {
    tri::Triangulation::Snapshot tri;
    // on_segment as (slot, segment) for the slots on Gamma: most are not.
    std::vector<std::pair<int32_t, int32_t>> on_gamma;
    std::vector<int32_t> vertex_of_slot, slot_of_vertex;
    std::vector<refine::RestrictedEdge> restricted;
    std::vector<refine::Side> vertex_side, triangle_side;
    bool optimised;
    quality::Report refined_quality;
    optim::OptimiseStats optimisation;
};

Undo set_aside(Context &ctx, RefinedMesh &m) {
    // What can throw (the copies) before anything is moved out of m.
    Undo u;
    u.tri = m.tri.snapshot(ctx);
    for (size_t v = 0; v < m.on_segment.size(); ++v)
        if (m.on_segment[v] >= 0) u.on_gamma.push_back({static_cast<int32_t>(v), m.on_segment[v]});
    u.refined_quality = m.refined_quality;
    u.optimised = m.optimised, u.optimisation = m.optimisation;
    u.vertex_of_slot = std::move(m.vertex_of_slot), u.slot_of_vertex = std::move(m.slot_of_vertex);
    u.restricted = std::move(m.restricted);
    u.vertex_side = std::move(m.vertex_side), u.triangle_side = std::move(m.triangle_side);
    return u;
}

// Puts m back as it was. The moves first (they cannot throw); if even the
// triangulation cannot be put back (memory), m is left empty - consistent,
// every call on it answers for a mesh of no cells - and that is reported.
void put_back(RefinedMesh &m, Undo &&u) {
    m.vertex_of_slot = std::move(u.vertex_of_slot), m.slot_of_vertex = std::move(u.slot_of_vertex);
    m.restricted = std::move(u.restricted);
    m.vertex_side = std::move(u.vertex_side), m.triangle_side = std::move(u.triangle_side);
    m.optimised = u.optimised, m.refined_quality = std::move(u.refined_quality), m.optimisation = u.optimisation;
    try {
        m.tri.restore(std::move(u.tri));
        m.on_segment.assign(static_cast<size_t>(m.tri.vertex_slots()), -1);  // no larger than it was: no allocation
        for (const auto &[v, segment] : u.on_gamma) m.on_segment[v] = segment;
    } catch (...) {
        m.tri = tri::Triangulation();
        m.on_segment.clear(), m.vertex_of_slot.clear(), m.slot_of_vertex.clear(), m.restricted.clear();
        m.vertex_side.clear(), m.triangle_side.clear();
        m.filtered = 0, m.optimised = false, m.refined_quality = {}, m.optimisation = {};
        fail(UM_ERR_OUT_OF_MEMORY, "the optimisation failed and, out of memory, its undo too: the mesh "
             "is now empty (refine it again)");
    }
}

}  // namespace

void optimise_mesh(Context &ctx, RefinedMesh &m, const Options &options,
                   const quality::Report *refined_quality) {
    ctx.check_memory(m.vertex_count() * (m.gamma ? kOptimiseBytesPerCell : kOptimiseUniformBytesPerCell),
                     concat("optimising a mesh of ", m.vertex_count(), " cells").c_str());
    const refine::SpacingRadians hr = spacing_radians(*m.spacing, m.surface);
    const std::vector<uint8_t> region = m.regional() && !refined_quality ? m.region_cells(ctx) : std::vector<uint8_t>{};
    const quality::Report before = refined_quality ? *refined_quality
                                                   : quality::measure(ctx, m.tri, hr, &m.on_segment,
                                                                      region.empty() ? nullptr : &region);
    optim::OptimiseOptions o;
    o.outer_iterations = static_cast<int>(options.integer(UM_OPT_OPTIM_OUTER_ITERATIONS));
    o.inner_iterations = static_cast<int>(options.integer(UM_OPT_OPTIM_INNER_ITERATIONS));
    o.tolerance = options.real(UM_OPT_OPTIM_TOLERANCE);
    o.weights = options.integer(UM_OPT_OPTIM_WEIGHTS) != 0;
    o.fix_boundary = options.integer(UM_OPT_OPTIM_FIX_BOUNDARY) != 0;
    o.collapse_ratio = options.real(UM_OPT_OPTIM_COLLAPSE_RATIO);
    o.split_ratio = options.real(UM_OPT_OPTIM_SPLIT_RATIO);
    o.ocean_floor = options.real(UM_OPT_OCEAN_FLOOR);
    o.corner_vertices = options.integer(UM_OPT_OPTIM_CORNER_VERTICES) != 0;
    o.corner_cells_clear = options.integer(UM_OPT_OPTIM_CORNER_VERTICES) == 2;
    o.centroidal_sweeps = static_cast<int>(options.integer(UM_OPT_OPTIM_CENTROIDAL_SWEEPS));
    o.reseed_rounds = static_cast<int>(options.integer(UM_OPT_OPTIM_RESEED_ROUNDS));
    o.refill_alpha = options.real(UM_OPT_REFINE_ALPHA), o.refill_rho = options.real(UM_OPT_REFINE_RHO);
    o.gamma_alpha = m.boundary_alpha, o.gamma_beta = m.boundary_beta;
    // The optimisation inserts a few per cent of new vertex slots (splits)
    // and, as it also removes about as many vertices (collapses), needs few
    // new triangle slots: their room first, while neither the undo nor the
    // optimiser's state is allocated.
    m.tri.reserve_extra(ctx, kOptimiseNewVertices, kOptimiseNewTriangles);
    Undo undo = set_aside(ctx, m);
    try {
        m.refined_quality = before;
        // (The sides finish found for this triangulation, set aside with it.)
        const bool sides_known = undo.vertex_side.size() == static_cast<size_t>(m.tri.vertex_slots());
        m.optimisation = optim::optimise(ctx, m.tri, m.on_segment, m.gamma.get(), hr, o, m.domain.get(),
                                         sides_known ? &undo.vertex_side : nullptr);
        m.optimised = true, m.ocean_floor = o.ocean_floor;
        finish(ctx, m, features::segment_arc_tree(m.gamma.get()), tri::Triangulation::Reorder::in_place);
        if (m.domain) require_region_cells(ctx, m);  // (the mesh is put back if not)
    } catch (...) {
        put_back(m, std::move(undo));
        throw;
    }
}

std::vector<uint8_t> RefinedMesh::cover_vertices(Context &ctx) const {
    const int32_t n = tri.vertex_slots();
    std::vector<uint8_t> cover(static_cast<size_t>(n), 0);
    if (!domain) return cover;
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t v = static_cast<int32_t>(i);
            const int32_t s = static_cast<size_t>(v) < on_segment.size() ? on_segment[v] : -1;
            cover[v] = tri.in_triangulation(v) && domain->in_cover(tri.direction(v), s);
        }
    });
    return cover;
}

std::vector<uint8_t> RefinedMesh::region_cells(Context &ctx) const {
    const int32_t n = tri.vertex_slots();
    std::vector<uint8_t> kept(static_cast<size_t>(n), 0);
    if (!domain) {
        for (int32_t v = 0; v < n; ++v) kept[v] = tri.in_triangulation(v);
        return kept;
    }
    // A cell beside one of the cover reaches beyond the ring (where the
    // ring's vertices leave a gap): the cells kept are those of vertices
    // inside with no vertex of the cover in their stars, so that each lies
    // within the domain.
    const std::vector<uint8_t> cover = cover_vertices(ctx);
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int32_t v = static_cast<int32_t>(b); v < e; ++v) {
            const int32_t s = static_cast<size_t>(v) < on_segment.size() ? on_segment[v] : -1;
            if (!tri.in_triangulation(v) || cover[v] || domain->is_ring_segment(s)) continue;
            bool enclosed = true;
            tri.for_each_in_star(v, [&](int32_t t) {
                for (int k = 0; k < 3; ++k) enclosed = enclosed && !cover[tri.vertex(t, k)];
            });
            kept[v] = enclosed;
        }
    });
    return kept;
}

std::vector<uint8_t> RefinedMesh::ocean_cells() const {
    std::vector<uint8_t> ocean = refine::ocean_mesh_cells(tri, vertex_side, triangle_side);
    if (!passages) return ocean;
    int32_t at = -1;  // where the last walk ended: the next starts there
    auto keep_open = [&](int32_t v) {
        if (v >= 0 && !ocean[v]) ocean[v] = 2;
        if (v >= 0) at = v;
    };
    for (const features::Part &p : passages->parts()) {
        if (p.n_segments == 0) keep_open(tri::cell_holding(tri, passages->point(p.first_point), at));
        for (int64_t s = p.first_segment; s < p.first_segment + p.n_segments; ++s)
            for (int32_t v : tri::cells_along_arc(tri, passages->segment_a(s), passages->segment_b(s), at))
                keep_open(v);
    }
    return ocean;
}

std::vector<uint8_t> RefinedMesh::coastline_arcs() const {
    std::vector<uint8_t> coast(static_cast<size_t>(gamma ? gamma->segment_count() : 0));
    for (size_t s = 0; s < coast.size(); ++s)
        coast[s] = refine::is_closed_coastline(gamma->part(gamma->segment_part(static_cast<int64_t>(s))));
    return coast;
}

std::vector<std::pair<int32_t, int32_t>> RefinedMesh::coastline_contacts() const {
    std::vector<std::pair<int32_t, int32_t>> contacts;
    if (!gamma) return contacts;
    auto ring_of = [&](int64_t segment) {
        const int64_t p = gamma->segment_part(segment);
        return refine::is_closed_coastline(gamma->part(p)) ? static_cast<int32_t>(p) : -1;
    };
    for (int32_t v = 0; v < static_cast<int32_t>(on_segment.size()); ++v)
        if (on_segment[v] >= 0 && tri.in_triangulation(v) && ring_of(on_segment[v]) >= 0)
            contacts.push_back({v, ring_of(on_segment[v])});
    for (const refine::RestrictedEdge &e : restricted) {
        const int32_t ring = ring_of(e.arc);
        if (ring < 0) continue;
        contacts.push_back({tri.vertex(e.triangle, (e.edge + 1) % 3), ring});
        contacts.push_back({tri.vertex(e.triangle, (e.edge + 2) % 3), ring});
    }
    return contacts;
}

}  // namespace um::mesh
