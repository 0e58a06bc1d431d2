// The centroidal pass (centroidal.cpp): Lloyd sweeps with flips between
// them, until the generators stop moving or centroidal_sweeps.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

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
    // Per vertex slot: the clock when its step was found below
    // kCentroidalStill h; skipped while nothing around it has moved since.
    std::vector<int32_t> still_at_;
};

}  // namespace um::optim::detail
