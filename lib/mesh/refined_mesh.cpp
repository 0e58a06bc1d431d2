#include "mesh/refined_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "refine/boundary.hpp"
#include "refine/surface.hpp"

namespace um::mesh {

// h in radians on the unit sphere, refusing values no mesh can follow.
refine::SpacingRadians spacing_radians(const hfun::Spacing &h, double radius_m) {
    const double per_km = 1000.0 / radius_m;
    return [&h, per_km](const geom::Vec3 &x) {
        double km = h.km_at(x);
        if (!std::isfinite(km) || km <= 0) {
            double lon, lat;
            geom::lonlat_deg_from_unit(x, lon, lat);
            fail(std::isfinite(km) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT,
                 "the spacing is ", km, " km at lon ", lon, ", lat ", lat,
                 " degrees: it must be finite and > 0");
        }
        return km * per_km;
    };
}

namespace {

// Four generators on (nearly) one circle give two triangles with (nearly)
// the same orthocentre: a dual edge of (almost) zero length, which MPAS and
// its checkers cannot orient. Making the vertex opposite such an edge a
// little lighter (a Laguerre weight of a few thousandths of l^2, far too
// small to hide it) keeps the edge regular with a dual edge ~1e-3 l long.
// Returns how many vertices were reweighted.
int64_t separate_degenerate_dual_edges(tri::Triangulation &tri) {
    constexpr double kMinDualOverPrimal = 1e-3;
    int64_t changed = 0;
    for (int pass = 0; pass < 4; ++pass) {
        std::vector<int32_t> lighten;
        for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
            if (tri.is_free(t)) continue;
            const geom::Vec3 ct = tri.orthocentre(t);
            for (int k = 0; k < 3; ++k) {
                const int32_t u = tri.neighbour(t, k);
                if (u < t) continue;
                const double l = geom::arc_length(tri.direction(tri.vertex(t, (k + 1) % 3)),
                                                  tri.direction(tri.vertex(t, (k + 2) % 3)));
                if (geom::arc_length(ct, tri.orthocentre(u)) < kMinDualOverPrimal * l)
                    lighten.push_back(tri.vertex(t, k));
            }
        }
        if (lighten.empty()) break;
        std::sort(lighten.begin(), lighten.end());
        lighten.erase(std::unique(lighten.begin(), lighten.end()), lighten.end());
        for (int32_t v : lighten) {
            if (!tri.in_triangulation(v)) continue;
            double l = 0;  // its shortest edge
            const geom::Vec3 x = tri.direction(v);
            for (int32_t t : tri.star(v))
                for (int k = 0; k < 3; ++k)
                    if (tri.vertex(t, k) != v) {
                        double d = geom::arc_length(x, tri.direction(tri.vertex(t, k)));
                        l = l == 0 ? d : std::min(l, d);
                    }
            tri.set_weight(v, tri.weight(v) - 4 * kMinDualOverPrimal * l * l);
            ++changed;
        }
    }
    return changed;
}

void number_vertices(RefinedMesh &m) {
    m.vertex_of_slot.assign(static_cast<size_t>(m.tri.vertex_slots()), -1);
    m.slot_of_vertex.clear();
    for (int32_t v = 0; v < m.tri.vertex_slots(); ++v)
        if (m.tri.in_triangulation(v)) {
            m.vertex_of_slot[v] = static_cast<int32_t>(m.slot_of_vertex.size());
            m.slot_of_vertex.push_back(v);
        }
}

}  // namespace

RefinedMesh refine_mesh(Context &ctx, hfun::SpacingPtr h,
                        std::shared_ptr<const features::Network> gamma, const Options &options) {
    RefinedMesh m;
    m.radius_m = options.real(UM_OPT_SPHERE_RADIUS);
    m.gamma = std::move(gamma);
    m.spacing = std::move(h);
    const refine::SpacingRadians hr = spacing_radians(*m.spacing, m.radius_m);
    m.tri = refine::icosahedron(ctx);
    int32_t next_id = 12;

    geom::ArcTree arcs;
    if (m.gamma && m.gamma->segment_count() > 0) {
        std::vector<geom::ArcTree::Arc> list;
        list.reserve(static_cast<size_t>(m.gamma->segment_count()));
        for (int64_t s = 0; s < m.gamma->segment_count(); ++s)
            list.push_back({m.gamma->segment_a(s), m.gamma->segment_b(s)});
        arcs = geom::ArcTree(std::move(list));
        refine::BoundaryOptions bo;
        bo.alpha = options.real(UM_OPT_REFINE_ALPHA);
        bo.beta = options.real(UM_OPT_REFINE_BETA);
        refine::BoundaryStats stats = refine::refine_boundary(ctx, m.tri, hr, arcs, bo, next_id,
                                                              m.on_segment);
        m.filtered = stats.filtered;
    }
    refine::SurfaceOptions so;
    so.alpha = options.real(UM_OPT_REFINE_ALPHA);
    so.rho = options.real(UM_OPT_REFINE_RHO);
    if (arcs.size() > 0) so.gamma = &arcs, so.on_gamma = &m.on_segment;
    refine::refine_surface(ctx, m.tri, hr, so, next_id);
    separate_degenerate_dual_edges(m.tri);
    m.tri.compact();
    m.on_segment.resize(static_cast<size_t>(m.tri.vertex_slots()), -1);
    number_vertices(m);

    if (arcs.size() > 0) {
        m.restricted = refine::restricted_edges(ctx, m.tri, arcs);
        m.triangle_side = refine::triangle_sides(m.tri, *m.gamma);
        m.vertex_side = refine::vertex_sides(m.tri, m.triangle_side, m.on_segment, *m.gamma);
    } else {
        m.triangle_side.assign(static_cast<size_t>(m.tri.triangle_slots()), refine::Side::ocean);
        m.vertex_side.assign(static_cast<size_t>(m.tri.vertex_slots()), refine::Side::ocean);
    }
    return m;
}

}  // namespace um::mesh
