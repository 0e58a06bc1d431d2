// The shape sweeps of Algorithm 1 (paper section 6, eq. 7-8): each vertex
// moves towards the ODT target of its star (or the centre of its link) when
// that is BETTER, and once the sweeps slow down, the poor stars get a
// compass search (polish_poor_stars).
#pragma once

#include <cstdint>
#include <vector>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class ShapeSweeps {
public:
    explicit ShapeSweeps(MeshState &s) : s_(s) {}
    // One graph-coloured sweep of moves over every vertex; the moves taken.
    // (After the first, over those changed_near the last one's start: no
    // other can move.)
    int64_t sweep(const StarGraph &g, bool forward);
    // The same over the vertices near Gamma only (MeshState::near_gamma;
    // none without Gamma).
    int64_t sweep_near_gamma(const StarGraph &g, bool forward) {
        return s_.near_gamma.empty() ? 0 : moves(g, forward, &s_.near_gamma);
    }
    // Whether an outer iteration of `changes` updates has slowed down enough
    // for the compass polish.
    bool wants_polish(int64_t changes) const;
    int64_t polish_poor_stars(const StarGraph &g);

private:
    // Over every vertex, or only over those flagged in *only (and `near`:
    // MeshState::sweep).
    int64_t moves(const StarGraph &g, bool forward, const std::vector<uint8_t> *only,
                  std::vector<uint8_t> *near = nullptr);
    bool update_position(const StarGraph &g, int32_t v);
    struct MoveTrial;
    bool move_to_targets(MoveTrial &trial);
    bool move_by_compass(MoveTrial &trial);
    bool move_along_gamma(MoveTrial &trial);
    // The ODT target of a move of v (at `here`, link `ring` from the graph).
    Vec3 odt_target(const StarGraph &g, int32_t v, const Generator &here, const Ring &ring) const;

    MeshState &s_;
    double poor_star_ = -kInfinity;  // stars scoring below get the compass search
    SweepStart last_sweep_;
};

}  // namespace um::optim::detail
