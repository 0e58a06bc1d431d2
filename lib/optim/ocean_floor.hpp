// The time-step floor (OptimiseOptions::ocean_floor): an explicit ocean
// model's time step is set by its shortest dcEdge, so no edge between two
// generators off the land (ocean or on a coastline: the cells the ocean
// mesh may take) stays shorter than floor h. Each such edge, shortest
// first, loses a vertex:
//   - neither end on Gamma: the two merge at the edge's midpoint;
//   - one end on Gamma: the other is taken out (Gamma keeps its vertices);
//   - both on Gamma (a bend, an inlet, the two shores of a narrow channel):
//     one of them is taken out where the chord left between its
//     neighbours along Gamma passes within floor h of it (the detail
//     narrower than the floor is filtered, as the boundary refinement
//     filters detail narrower than the spacing).
// Each pass first brings the sides of the vertices up to date
// (MeshState::refresh_sides). A
// removal is kept only if it lets Gamma into no more cells off it, leaves
// no edge longer than split_ratio h and, once the weights are tuned, adds
// no obtuse triangle and none not holding its orthocentre; the sweeps then
// re-centre the neighbours. Land and river edges may be shorter. Serial,
// one change per neighbourhood per pass, in a fixed order: deterministic.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <vector>

#include "optim/mesh_state.hpp"
#include "refine/sides.hpp"

namespace um::optim::detail {

class OceanFloor {
public:
    explicit OceanFloor(MeshState &s) : s_(s) {}
    // One pass; the vertices taken out.
    int64_t lift();
    // The edges between two generators off the land still shorter than
    // floor h (the pass's own measure: arc over h at the midpoint).
    int64_t count_below();

private:
    struct ShortEdge {
        double ratio;
        int32_t a, b;  // a < b
    };
    std::vector<ShortEdge> short_ocean_edges() const;
    bool lift_edge(const ShortEdge &e);
    struct Before;
    Before before(std::initializer_list<int32_t> vertices) const;
    bool acceptable(const Before &b, int32_t kept) const;
    void mark_changed(const std::vector<int32_t> &link);
    void keep_moved(int32_t v, const std::vector<int32_t> &link);
    int off_centre_touching(const std::vector<int32_t> &vertices) const;
    bool merge_at_midpoint(int32_t kept, int32_t gone);
    bool take_out(int32_t v);
    bool take_out_of_gamma(int32_t v);
    bool push_away(int32_t v, int32_t from);
    bool merge_along_gamma(int32_t a, int32_t b);
    bool neighbours_along_gamma(int32_t v, int32_t (&along)[2]) const;
    bool leaves_long_edge(const std::vector<int32_t> &link) const;
    double shortest_edge(int32_t v) const;

    MeshState &s_;
    double fixing_ = 0;  // the ratio of the edge being lifted
};

}  // namespace um::optim::detail
