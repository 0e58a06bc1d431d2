#include "mesh/refined_mesh.hpp"

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
