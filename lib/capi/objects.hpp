// The structs behind the engine-object handles of the C ABI, in one place so
// that an entry point taking several kinds (um_mesh_refine) can see them all.
// Each holds a share of its context's state, so it outlives the context.
#pragma once

#include <atomic>
#include <memory>
#include <optional>

#include "capi/api.hpp"
#include "dual/mpas_source.hpp"
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
    // The source of the MPAS staggered mesh of `mesh` (its numbering and
    // tags), made on the first copy-out and kept until released or the mesh
    // changes; each variable is made from it when it is copied out.
    mutable std::unique_ptr<um::dual::MpasSource> mpas;
    const um::dual::MpasSource &staggered() const {
        if (!mpas) {
            context->check_memory(um::dual::mpas_copy_out_bytes(mesh.vertex_count(), mesh.gamma != nullptr,
                                                                !mesh.surface.is_sphere(), mesh.regional()),
                                  "the MPAS copy-out");
            mpas = std::make_unique<um::dual::MpasSource>(*context, mesh);
        }
        return *mpas;
    }
    void release_staggered() const { mpas.reset(); }
    // Set while a call uses the mesh: a call on it from inside another's
    // callback (progress, log, a spacing callback) or from a second thread
    // gets UM_ERR_USAGE instead of a mesh that changes or vanishes under
    // the first.
    mutable std::atomic<bool> in_use{false};
};

namespace um::capi {

// Claims a mesh for the call in scope; throws UM_ERR_USAGE when another
// call holds it.
class MeshInUse {
public:
    explicit MeshInUse(const um_mesh *m) : m_(m) {
        if (m_->in_use.exchange(true))
            fail(UM_ERR_USAGE, "the mesh is in use by another call (this one came from inside its progress, "
                               "log or spacing callback, or from another thread): one call at a time per mesh");
    }
    ~MeshInUse() { m_->in_use.store(false); }
    MeshInUse(const MeshInUse &) = delete;
    MeshInUse &operator=(const MeshInUse &) = delete;

private:
    const um_mesh *m_;
};

}  // namespace um::capi
