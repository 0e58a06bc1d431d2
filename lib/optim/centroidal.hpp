// The centroidal pass (centroidal.cpp): Lloyd sweeps with flips between
// them, until the generators stop moving or centroidal_sweeps.
#pragma once

#include <cstdint>
#include <memory>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class Centroidal {
public:
    explicit Centroidal(MeshState &s) : s_(s) {}
    // The moves taken; graph is rebuilt when flips change the topology.
    int64_t relax_to_centroids(std::unique_ptr<StarGraph> &graph);

private:
    bool update_centroidal(const StarGraph &g, int32_t v);
    Vec3 centroid_target(const StarGraph &g, int32_t v, const Generator &here, const Ring &ring) const;

    MeshState &s_;
};

}  // namespace um::optim::detail
