// The time-step floor (OptimiseOptions::ocean_floor): an explicit ocean
// model's time step is set by its shortest dcEdge, so no edge between two
// generators off the land (ocean or on a coastline: the cells the ocean
// mesh may take) stays shorter than floor h. Each such edge, shortest
// first, loses a vertex:
//   - neither end on Gamma: the two merge at the edge's midpoint;
//   - one end on Gamma: the other is taken out (Gamma keeps its vertices);
//   - where neither goes, in the shape phase and after the mends (where no
//     weight sweep follows to move it back), one end off Gamma is pushed
//     to just past floor h from the other (after the mends also one on
//     Gamma, slid along it as far);
//   - both on Gamma (a bend, an inlet, the two shores of a narrow channel):
//     one of them is taken out where the chord left between its
//     neighbours along Gamma passes within floor h of it (the detail
//     narrower than the floor is filtered, as the boundary refinement
//     filters detail narrower than the spacing).
// Where none of those lifts the edge, either end is taken out (off Gamma
// first), or the two merge off Gamma at the midpoint, even where Gamma then
// passes through more cells off it: the floor comes before following
// detail of Gamma narrower than it (two shores, a lake and a coast, nearer
// than the floor). With a fixed boundary, Gamma's vertices stay.
// Each pass first brings the sides of the vertices up to date
// (MeshState::refresh_sides). A
// removal is kept only if (but for that last resort) it lets Gamma into no
// more cells off it, leaves no edge longer than split_ratio h nor more
// edges below the floor around and, once the weights are tuned, adds no
// obtuse triangle and, but in the passes just before the mends (which
// re-tune the weights, and move the vertices of obtuse triangles: there the
// last resort may add those too), none not holding its orthocentre. The sweeps then
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
    // When a pass runs: in an outer iteration, after them before the mends
    // (which re-tune the weights around a triangle left off-centre), or
    // after the mends (no weight sweep follows to undo a push).
    enum class Stage { iteration, before_mends, after_mends };
    // What one pass did: vertices taken out (a change of topology), and
    // vertices pushed or slid away (moves, for the schedule's stopping test:
    // in the shape phase the sweeps may move a pushed vertex back, every
    // iteration; though a push may change the vertex's links too).
    struct Lifted {
        int64_t taken_out = 0, moved = 0;
        int64_t changes() const { return taken_out + moved; }
    };
    Lifted lift(Stage stage = Stage::iteration);
    // The edges between two generators off the land still shorter than
    // floor h (the pass's own measure: arc over h at xEdge, as the report measures it).
    int64_t count_below();

private:
    struct ShortEdge {
        double ratio;
        int32_t a, b;  // a < b
    };
    std::vector<ShortEdge> short_ocean_edges() const;
    bool lift_edge(const ShortEdge &e);
    bool lift_keeping_gamma(const ShortEdge &e);
    bool lift_at_any_cost_to_gamma(const ShortEdge &e);
    struct Before;
    Before before(std::initializer_list<int32_t> vertices) const;
    bool acceptable(const Before &b, int32_t kept) const;
    void mark_changed(const std::vector<int32_t> &link);
    void keep_moved(int32_t v, const std::vector<int32_t> &link);
    int off_centre_touching(const std::vector<int32_t> &vertices) const;
    bool merge_at_midpoint(int32_t kept, int32_t gone);
    bool take_out(int32_t v);
    bool merge_off_gamma(int32_t kept, int32_t gone);
    bool take_out_of_gamma(int32_t v);
    bool push_target(int32_t v, int32_t from, Vec3 &to) const;
    bool push_away(int32_t v, int32_t from);
    bool slide_apart(int32_t v, int32_t from);
    bool merge_along_gamma(int32_t a, int32_t b);
    bool neighbours_along_gamma(int32_t v, int32_t (&along)[2]) const;
    bool leaves_long_edge(const std::vector<int32_t> &link) const;
    double shortest_edge(int32_t v) const;

    MeshState &s_;
    int64_t moved_ = 0;          // pushes and slides kept in this pass
    double fixing_ = 0;          // the ratio of the edge being lifted
    Stage stage_ = Stage::iteration;
    bool gamma_may_spread_ = false;  // the last resort: Gamma may go into more cells
};

}  // namespace um::optim::detail
