// The topology pass (paper section 6.4): collapse of short edges, splits
// of long ones, and the repair of vertex degrees (removal, splitting, and
// flips that turn pairs of 5-7 defects into 6s).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class Topology {
public:
    explicit Topology(MeshState &s) : s_(s) {}
    // Collapses the edges shorter than collapse_ratio h, then splits those
    // longer than split_ratio h: one scan finds both kinds (the long ones are
    // found again when a collapse changed the mesh).
    std::pair<int64_t, int64_t> collapse_and_split();
    int64_t improve_valence();
    int64_t flip_for_valence();

private:
    struct EdgeRatio {
        double ratio;
        int32_t a, b;
    };
    std::vector<EdgeRatio> edge_ratios(double below, double above) const;
    int64_t collapse_short_edges(std::vector<EdgeRatio> edges);
    int64_t split_long_edges(std::vector<EdgeRatio> edges);
    bool leaves_long_edge(const Vec3 &x, double h_x, std::initializer_list<int32_t> ends) const;
    bool leaves_short_edge(int32_t a, int32_t b) const;
    int32_t insert_between(int32_t a, int32_t b);
    bool split_vertex(int32_t v, const std::vector<int32_t> &star);
    void take_back(int32_t v, const std::vector<int32_t> &buried);
    bool relax_into_regularity(const int32_t (&quad)[4]);

    MeshState &s_;
};

}  // namespace um::optim::detail
