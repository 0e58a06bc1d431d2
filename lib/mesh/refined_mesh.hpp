// The restricted triangulation the refinement stage hands on (paper section
// 5, issue "Geometry, spacing functions and restricted refinement"): from the
// icosahedron, boundary refinement along Gamma then surface refinement, and
// what later stages need to know about Gamma and the sides of the coastlines.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/context.hpp"
#include "core/options.hpp"
#include "features/domain.hpp"
#include "features/network.hpp"
#include "geom/surface.hpp"
#include "hfun/spacing.hpp"
#include "optim/optimise.hpp"
#include "quality/metrics.hpp"
#include "refine/bounds.hpp"
#include "refine/restricted.hpp"
#include "refine/sides.hpp"
#include "refine/surface.hpp"
#include "tri/triangulation.hpp"

namespace um::mesh {

struct RefinedMesh {
    tri::Triangulation tri;
    std::shared_ptr<const features::Network> gamma;  // may be empty
    // The caller's passages (UM_FEATURE_PASSAGE parts, split off Gamma): where
    // the ocean mesh is kept open. May be null.
    std::shared_ptr<const features::Network> passages;
    // The region of a regional mesh (the domain rings of gamma); null for a
    // mesh of the whole sphere. The triangulation still covers the sphere
    // (hfun/region_cover.hpp); region_cells() says which cells are the mesh's.
    std::shared_ptr<const features::Domain> domain;
    // Per part of gamma, its index among the caller's features (empty: the
    // same index, when no passage was split off).
    std::vector<int64_t> features_part;
    hfun::SpacingPtr spacing;                         // what it was refined to (km on the sphere of radius_m())
    // What the directions stand for (geom/surface.hpp): a sphere, or an
    // ellipsoid; spacing is then in km on the sphere of its semi-major axis
    // that the ellipsoid's geodesic h spans.
    geom::Surface surface = geom::Surface::sphere(kEarthRadiusKm * 1000);
    // The sphere's radius, or the ellipsoid's semi-major axis (sphere_radius).
    double radius_m() const { return surface.a(); }
    // Per vertex slot: the Gamma segment it was placed on, or -1.
    std::vector<int32_t> on_segment;
    // Mesh vertices are the slots in the triangulation, numbered in slot order.
    std::vector<int32_t> vertex_of_slot;  // slot -> vertex, -1 if not a vertex
    std::vector<int32_t> slot_of_vertex;
    std::vector<refine::RestrictedEdge> restricted;  // .arc is a Gamma segment index
    std::vector<refine::Side> vertex_side, triangle_side;
    int64_t filtered = 0;  // bad restricted edges left: features below the spacing
    // The boundary refinement's bounds it was refined with (refine_alpha,
    // refine_beta): the optimisation keeps the restricted edges it makes within them.
    double boundary_alpha = refine::kDefaultAlpha, boundary_beta = refine::kDefaultBeta;
    // The time-step floor it was built to (ocean_floor; the last
    // optimisation's): what the quality report counts the ocean edges against.
    double ocean_floor = 0;
    // Set by optimise_mesh: the quality of the mesh as refined, and what the
    // optimisation did.
    bool optimised = false;
    quality::Report refined_quality;
    optim::OptimiseStats optimisation;

    int64_t vertex_count() const { return static_cast<int64_t>(slot_of_vertex.size()); }
    bool regional() const { return domain != nullptr; }
    // Per vertex slot, 1 when its cell is in the mesh: every vertex of a
    // global mesh; in a regional one those inside the domain but not on its
    // rings (their cells straddle the boundary).
    std::vector<uint8_t> region_cells(Context &ctx) const;
    // Per vertex slot, 1 for a vertex of a regional mesh's cover
    // (features::Domain::in_cover; none in a global mesh).
    std::vector<uint8_t> cover_vertices(Context &ctx) const;
    // The index among the caller's features of the part of Gamma segment s.
    int64_t features_part_of_segment(int64_t s) const {
        const int64_t p = gamma->segment_part(s);
        return features_part.empty() ? p : features_part[static_cast<size_t>(p)];
    }
    // Per vertex slot, non-zero when its cell is in the ocean mesh (the MPAS
    // cellOceanMask): 1 by the rule of refine::ocean_mesh_cells, 2 when only
    // because a passage passes through it.
    std::vector<uint8_t> ocean_cells() const;
    // Per Gamma segment, 1 when it is of a closed coastline.
    std::vector<uint8_t> coastline_arcs() const;
    // Which closed coastline rings each cell touches, as (vertex slot, part
    // of gamma) pairs: the cells on a ring and the two ends of each
    // restricted edge of one (what tells water bodies apart).
    std::vector<std::pair<int32_t, int32_t>> coastline_contacts() const;
};

// Refines from the icosahedron. gamma may be null (no features); h is read
// through its km_at and checked (finite, > 0) wherever it is used; options
// give alpha, beta, rho and the sphere radius.
RefinedMesh refine_mesh(Context &ctx, hfun::SpacingPtr h,
                        std::shared_ptr<const features::Network> gamma, const Options &options);

// The weighted primal-dual optimisation (paper section 6) of a refined mesh,
// in place, with the N, M, tolerance, weight, boundary and collapse/split
// options; then the restricted edges and sides are found again for the
// moved mesh. refined_quality is the quality report of m as it is, when
// the caller has it (else it is measured here). Throws (UM_CANCELLED from
// the progress callback among others) with m exactly as it was: a snapshot
// of the triangulation (not a copy of the mesh) is kept for that.
void optimise_mesh(Context &ctx, RefinedMesh &m, const Options &options,
                   const quality::Report *refined_quality = nullptr);

// What a mesh of spacing h on the Earth is expected to need, for refusing a
// size up front: its cells (the sphere's area over the cells' area at h) and
// the peak bytes of refining and optimising it (with features: without them
// the optimisation needs less), and the bytes the MPAS mesh file's writer
// adds (it streams the file, as the copy-out makes each variable; the
// component files build the whole staggered mesh, dual::kMpasBytesPerCell).
struct MeshEstimate {
    int64_t cells = 0, refine_bytes = 0, mpas_bytes = 0;
};
MeshEstimate estimate_mesh(Context &ctx, const hfun::Spacing &h);

// The spacing in radians on the unit sphere, checked (finite, > 0) where read.
// (h in km on the sphere of the surface's radius a; errors name the
// geodetic lon/lat of the point.)
refine::SpacingRadians spacing_radians(const hfun::Spacing &h, const geom::Surface &surface);
// Its lower bound over a cap (hfun::Spacing::smallest_in_cap), checked the same way.
refine::SmallestSpacingRadians smallest_spacing_radians(const hfun::Spacing &h, const geom::Surface &surface);

}  // namespace um::mesh
