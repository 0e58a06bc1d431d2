// The re-seeding of 5-7 defects (shape phase). Where the refinement's
// fronts met, the mesh keeps vertices of degree 5 and 7 (about 9 % of them
// on a uniform mesh) that no move or flip of the sweeps removes: each sits
// in a local minimum of the sweeps' objective. They are where the MPAS
// divergence, kinetic energy and TRSK errors concentrate. A round takes the
// defects that have one of the other sign nearby (a lone pentagon is a
// disclination the sphere needs: it can be moved, not removed) out with the
// rings of vertices around them and fills the holes
// again by the frontal refinement (refine_surface), which grows each hole's
// new points from the regular lattice of its rim; the shape sweeps of the
// next outer iteration relax them. Each round leaves fewer defects, the
// first one most; the schedule stops the rounds when they stop paying.
//
// Only vertices away from Gamma take part: those on it, those flagged near
// it (flag_near_gamma) and those with such a neighbour stay, so a hole's
// rim is away from Gamma as well and its new points cannot change
// Tri|Gamma. Serial, in slot order: the same for any thread count. The
// holes' new vertices take the removed ones' slots, so the slot count does
// not grow.
#pragma once

#include <cstdint>
#include <vector>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class DefectReseeding {
public:
    explicit DefectReseeding(MeshState &s) : s_(s) {}

    struct Round {
        int64_t defects = 0;   // vertices of degree other than 6 that may take part
        int64_t removed = 0;   // vertices taken out (the defects and the rings around them)
        int64_t inserted = 0;  // vertices the refinement put in the holes
    };
    // One round: the defects with `rings` rings of neighbours out, the holes
    // refilled; nothing changes when there are more than most_defects.
    // Needs flag_near_gamma of this outer iteration.
    Round reseed(int rings, int64_t most_defects);

private:
    std::vector<uint8_t> free_to_move() const;
    std::vector<int32_t> defects(const std::vector<uint8_t> &free) const;
    void add_rings(std::vector<int32_t> &vertices, int rings, const std::vector<uint8_t> &free) const;
    std::vector<int32_t> remove(const std::vector<int32_t> &vertices, std::vector<int32_t> &slots);
    int64_t refill(const std::vector<int32_t> &rim, std::vector<int32_t> &slots);

    MeshState &s_;
};

}  // namespace um::optim::detail
