// The structs behind the engine-object handles of the C ABI, in one place so
// that an entry point taking several kinds (um_mesh_refine) can see them all.
// Each holds a share of its context's state, so it outlives the context.
#pragma once

#include <memory>
#include <optional>

#include "capi/api.hpp"
#include "dual/mpas_mesh.hpp"
#include "features/network.hpp"
#include "hfun/spacing.hpp"
#include "mesh/refined_mesh.hpp"
#include "quality/metrics.hpp"
#include "tri/triangulation.hpp"

struct um_triangulation {
    um::ContextPtr context;
    um::tri::Triangulation tri;
};

struct um_spacing {
    um::ContextPtr context;
    um::hfun::SpacingPtr spacing;
};

struct um_features {
    um::ContextPtr context;
    um::features::Network network;
};

struct um_mesh {
    um::ContextPtr context;
    um::mesh::RefinedMesh mesh;
    // The quality report of `mesh`, measured on first request and kept until
    // the mesh changes (the quality calls are const; one host thread at a
    // time per context makes the cache safe).
    mutable std::optional<um::quality::Report> quality;
    // The MPAS staggered mesh of `mesh`, built on the first copy-out and kept
    // until released or the mesh changes.
    mutable std::unique_ptr<um::dual::MpasMesh> mpas;
};
