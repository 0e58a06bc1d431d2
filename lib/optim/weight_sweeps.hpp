// The weight sweeps of Algorithm 1 (paper section 6, eq. 4-6): each vertex
// whose star staggers poorly ascends the Q^P of its worst triangle.
#pragma once

#include <cstdint>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class WeightSweeps {
public:
    explicit WeightSweeps(MeshState &s) : s_(s) {}
    // One graph-coloured sweep of weight updates; the updates taken. (After
    // the first, over those changed_near the last one's start: no other
    // can take one.)
    int64_t sweep(const StarGraph &g, bool forward);

private:
    bool update_weight(const StarGraph &g, int32_t v);

    MeshState &s_;
    SweepStart last_sweep_;
};

}  // namespace um::optim::detail
