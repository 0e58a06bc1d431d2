// um_mesh entry points: the refinement stage through the C ABI.
#include <memory>

#include "capi/api.hpp"
#include "capi/objects.hpp"
#include "geom/sphere.hpp"
#include "quality/geodesic.hpp"
#include "quality/metrics.hpp"

using um::fail;
using um::capi::HandleKind;
using um::capi::MeshInUse;
using um::capi::require_handle;
using um::capi::check_base;
using um::capi::check_capacity;
using um::capi::require_pointer;

namespace {

um::Context *state_or_null(const um_mesh *m) {
    return um::capi::is_live(m, HandleKind::mesh) ? m->context.get() : nullptr;
}



// What the report measures: the mesh's spacing in radians and, for a
// regional mesh, its cells (per vertex slot; none: every cell).
struct ReportScope {
    um::refine::SpacingRadians h;
    std::vector<uint8_t> region;
    const std::vector<uint8_t> *cells() const { return region.empty() ? nullptr : &region; }
};

ReportScope report_scope(const um_mesh *m) {
    return {um::mesh::spacing_radians(*m->mesh.spacing, m->mesh.surface),
            m->mesh.regional() ? m->mesh.region_cells(*m->context) : std::vector<uint8_t>{}};
}

const um::quality::Report &quality_of(const um_mesh *m) {
    if (!m->quality) {
        const ReportScope scope = report_scope(m);
        const um::refine::SpacingRadians &h = scope.h;
        const std::vector<uint8_t> &region = scope.region;
        const std::vector<uint8_t> *cells = scope.cells();
        um::quality::Report r = um::quality::measure(*m->context, m->mesh.tri, h, &m->mesh.on_segment, cells);
        std::vector<uint8_t> ocean = m->mesh.ocean_cells();
        if (cells)
            for (size_t v = 0; v < ocean.size(); ++v) ocean[v] = region[v] ? ocean[v] : 0;
        r.ocean = um::quality::measure_ocean_edges(*m->context, m->mesh.tri, h, ocean, m->mesh.ocean_floor,
                                                   m->mesh.coastline_contacts(), m->mesh.surface);
        if (m->mesh.gamma)
            r.coastline = um::quality::measure_coastline_fidelity(m->mesh.tri, m->mesh.restricted, m->mesh.coastline_arcs(),
                                                                  h, m->mesh.boundary_beta);
        m->quality = std::move(r);
    }
    return *m->quality;
}

// quality_of(m) with, on an ellipsoid, its geodesic measures: made for the
// JSON report only (GeographicLib's geodesics cost about 4 us a cell, more
// than the rest of the report), so that um_mesh_optimise's report of the
// mesh before does not pay for them unless the caller asked for it.
const um::quality::Report &quality_with_geodesic(const um_mesh *m) {
    const um::quality::Report &r = quality_of(m);
    if (m->mesh.surface.is_sphere() || r.geodesic.measured) return r;
    const ReportScope scope = report_scope(m);
    m->quality->geodesic = um::quality::measure_geodesic(*m->context, m->mesh.tri, m->mesh.surface, scope.h, scope.cells());
    return *m->quality;
}

// The report of the mesh as it is; after um_mesh_optimise also that of the
// refined mesh and what the optimisation did.
std::string quality_json(const um_mesh *m) {
    const auto &mesh = m->mesh;
    if (!mesh.optimised) return um::quality::to_json(quality_with_geodesic(m));
    const auto &o = mesh.optimisation;
    std::string extra = um::concat(
        "\"before_optimisation\": ", um::quality::to_json(mesh.refined_quality, "  "),
        ",\n  \"optimisation\": {\"outer_iterations\": ", o.outer_iterations, ", \"moves\": ", o.moves,
        ", \"weight_updates\": ", o.weight_updates, ", \"flips\": ", o.flips,
        ", \"collapses\": ", o.collapses, ", \"splits\": ", o.splits,
        ", \"corner_vertices\": ", o.corner_vertices, ", \"gamma_vertices_removed\": ", o.gamma_vertices_removed,
        ", \"reseed_rounds\": ", o.reseed_rounds, ", \"reseeded\": ", o.reseeded,
        ", \"seconds_moves\": ", o.seconds_moves, ", \"seconds_weights\": ", o.seconds_weights,
        ", \"seconds_topology\": ", o.seconds_topology, "}");
    return um::quality::to_json(quality_with_geodesic(m), "", extra);
}

}  // namespace

extern "C" {

UM_API um_status um_mesh_refine(um_context *ctx, const um_spacing *spacing,
                                const um_features *features, const um_options *options,
                                um_mesh **out) {
    UM_API_BEGIN
    require_handle(ctx, HandleKind::context, "ctx");
    require_pointer(out, "out");
    *out = nullptr;
    require_handle(spacing, HandleKind::spacing, "spacing");
    if (features) require_handle(features, HandleKind::features, "features");
    if (options) require_handle(options, HandleKind::options, "options");
    um::Options defaults;
    const um::Options &opts = options ? options->values : defaults;
    std::shared_ptr<const um::features::Network> gamma;
    if (features) gamma = std::make_shared<um::features::Network>(features->network);
    auto handle = std::make_unique<um_mesh>();
    handle->context = ctx->state;
    handle->mesh = um::mesh::refine_mesh(*ctx->state, spacing->spacing, gamma, opts);
    um::capi::register_handle(handle.get(), HandleKind::mesh);
    *out = handle.release();
    return UM_OK;
    UM_API_END(um::capi::is_live(ctx, HandleKind::context) ? ctx->state.get() : nullptr)
}

UM_API um_status um_mesh_optimise(um_mesh *m, const um_options *options) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    if (options) require_handle(options, HandleKind::options, "options");
    um::Options defaults;
    const um::Options &opts = options ? options->values : defaults;
    // The report of the mesh as it is first: it is the "before". On failure
    // optimise_mesh leaves m->mesh as it was, and the caches stay valid -
    // unless even its undo ran out of memory and left the mesh empty.
    const um::quality::Report &before = quality_of(m);
    try {
        um::mesh::optimise_mesh(*m->context, m->mesh, opts, &before);
    } catch (...) {
        if (m->mesh.vertex_count() == 0) m->quality.reset(), m->release_staggered();
        throw;
    }
    m->quality.reset();
    m->release_staggered();
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API void um_mesh_destroy(um_mesh *m) {
    // Not while a call uses it (from inside that call's callback, or from
    // another thread): the mesh stays, and its context says so.
    if (um::capi::is_live(m, HandleKind::mesh) && m->in_use.load()) {
        um::capi::usage_error(m->context.get(), UM_ERR_USAGE,
                              "um_mesh_destroy: the mesh is in use by another call (this one came from inside "
                              "its callback, or from another thread); it was not destroyed");
        return;
    }
    if (um::capi::unregister_handle(m, HandleKind::mesh)) delete m;
}

UM_API um_status um_mesh_counts(const um_mesh *m, int64_t *n_vertices, int64_t *n_triangles,
                                int64_t *n_restricted_edges, int64_t *n_filtered) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    if (n_vertices) *n_vertices = m->mesh.vertex_count();
    if (n_triangles) *n_triangles = m->mesh.tri.triangle_count();
    if (n_restricted_edges) *n_restricted_edges = static_cast<int64_t>(m->mesh.restricted.size());
    if (n_filtered) *n_filtered = m->mesh.filtered;
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_copy_vertices(const um_mesh *m, double *lon_deg, double *lat_deg,
                                       int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    check_capacity(capacity, m->mesh.vertex_count(), "the vertices");
    require_pointer(lon_deg, "lon_deg");
    require_pointer(lat_deg, "lat_deg");
    for (int64_t i = 0; i < m->mesh.vertex_count(); ++i)
        m->mesh.surface.geodetic(m->mesh.tri.direction(m->mesh.slot_of_vertex[i]), lon_deg[i], lat_deg[i]);
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_copy_triangles(const um_mesh *m, int32_t base, int32_t *out,
                                        int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    check_base(base);
    const auto &tri = m->mesh.tri;
    check_capacity(capacity, 3 * int64_t(tri.triangle_count()), "the triangles");
    require_pointer(out, "out");
    for (int32_t f = 0; f < tri.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) out[3 * int64_t(f) + k] = m->mesh.vertex_of_slot[tri.vertex(f, k)] + base;
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_copy_vertex_parts(const um_mesh *m, int32_t base, int32_t *out,
                                           int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    check_base(base);
    check_capacity(capacity, m->mesh.vertex_count(), "the vertex parts");
    require_pointer(out, "out");
    for (int64_t i = 0; i < m->mesh.vertex_count(); ++i) {
        int32_t s = m->mesh.on_segment[m->mesh.slot_of_vertex[i]];
        out[i] = s < 0 ? -1 : static_cast<int32_t>(m->mesh.features_part_of_segment(s)) + base;
    }
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_copy_restricted_edges(const um_mesh *m, int32_t base,
                                               int32_t *vertices, int32_t *parts,
                                               int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    check_base(base);
    const auto &r = m->mesh.restricted;
    check_capacity(capacity, static_cast<int64_t>(r.size()), "the restricted edges");
    if (!vertices && !parts) fail(UM_ERR_NULL_ARGUMENT, "vertices and parts are both NULL");
    const auto &tri = m->mesh.tri;
    for (size_t i = 0; i < r.size(); ++i) {
        if (vertices) {
            vertices[2 * i] = m->mesh.vertex_of_slot[tri.vertex(r[i].triangle, (r[i].edge + 1) % 3)] + base;
            vertices[2 * i + 1] = m->mesh.vertex_of_slot[tri.vertex(r[i].triangle, (r[i].edge + 2) % 3)] + base;
        }
        if (parts) parts[i] = static_cast<int32_t>(m->mesh.features_part_of_segment(r[i].arc)) + base;
    }
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_copy_vertex_sides(const um_mesh *m, int32_t *out, int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    check_capacity(capacity, m->mesh.vertex_count(), "the vertex sides");
    require_pointer(out, "out");
    for (int64_t i = 0; i < m->mesh.vertex_count(); ++i)
        out[i] = static_cast<int32_t>(m->mesh.vertex_side[m->mesh.slot_of_vertex[i]]);
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_copy_triangle_sides(const um_mesh *m, int32_t *out, int64_t capacity) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    const auto &tri = m->mesh.tri;
    check_capacity(capacity, tri.triangle_count(), "the triangle sides");
    require_pointer(out, "out");
    for (int32_t f = 0; f < tri.triangle_count(); ++f)
        out[f] = static_cast<int32_t>(m->mesh.triangle_side[f]);
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_quality_json(const um_mesh *m, char *buf, int64_t capacity,
                                      int64_t *needed) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    return um::capi::copy_out_string(m->context.get(), quality_json(m), buf, capacity, needed);
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_quality_summary(const um_mesh *m, const char *metric, double *min,
                                         double *p1, double *mean, double *max) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    require_pointer(metric, "metric");
    const um::quality::Report &r = quality_of(m);
    const std::string name = metric;
    const um::quality::Summary *s = name == "area_length_ratio"    ? &r.area_length
                                    : name == "primal_dual"        ? &r.primal_dual
                                    : name == "angle_min_deg"      ? &r.angle_min
                                    : name == "angle_max_deg"      ? &r.angle_max
                                    : name == "edge_spacing_ratio" ? &r.spacing_ratio
                                    : name == "centroid_offset"    ? &r.centroid_offset
                                    : name == "dual_edge_offset"   ? &r.dual_edge_offset
                                    : name == "primal_edge_offset" ? &r.primal_edge_offset
                                    : name == "cell_spacing_ratio" ? &r.cell_spacing_ratio
                                                                   : nullptr;
    if (!s)
        fail(UM_ERR_INVALID_ARGUMENT, "metric = '", name, "' is not one of area_length_ratio, "
             "primal_dual, angle_min_deg, angle_max_deg, edge_spacing_ratio, centroid_offset, "
             "dual_edge_offset, primal_edge_offset, cell_spacing_ratio");
    if (min) *min = s->min;
    if (p1) *p1 = s->p1;
    if (mean) *mean = s->mean;
    if (max) *max = s->max;
    return UM_OK;
    UM_API_END(state_or_null(m))
}

UM_API um_status um_mesh_quality_counts(const um_mesh *m, int64_t *obtuse,
                                        int64_t *not_well_centred) {
    UM_API_BEGIN
    require_handle(m, HandleKind::mesh, "m");
    const MeshInUse in_use(m);
    const um::quality::Report &r = quality_of(m);
    if (obtuse) *obtuse = r.obtuse;
    if (not_well_centred) *not_well_centred = r.not_well_centred;
    return UM_OK;
    UM_API_END(state_or_null(m))
}

}  // extern "C"
