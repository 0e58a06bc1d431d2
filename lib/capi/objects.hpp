// The structs behind the engine-object handles of the C ABI, in one place so
// that an entry point taking several kinds (um_mesh_refine) can see them all.
// Each holds a share of its context's state, so it outlives the context.
#pragma once

#include "capi/api.hpp"
#include "features/network.hpp"
#include "hfun/spacing.hpp"
#include "mesh/refined_mesh.hpp"
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
};
