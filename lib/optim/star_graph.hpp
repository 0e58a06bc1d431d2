// The vertex graph the sweeps walk (paper Algorithm 1, DESIGN.md section 4):
// per vertex its link (the neighbours, counter-clockwise seen from outside),
// so that its star is the fan (v, link[k], link[k+1]); and a greedy colouring
// in vertex-slot order such that no two vertices of one colour share a
// triangle. Within a colour, updates touch disjoint stars and read only
// vertices of other colours, so they can run in parallel and give the same
// result for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "tri/triangulation.hpp"

namespace um::optim {

// out[v] = the number of triangles around vertex slot v (0 off the
// triangulation), for every slot, star by star in parallel.
void write_degrees(Context &ctx, const tri::Triangulation &tri, int32_t *out);
inline std::vector<int32_t> vertex_degrees(Context &ctx, const tri::Triangulation &tri) {
    std::vector<int32_t> degree(static_cast<size_t>(tri.vertex_slots()));
    write_degrees(ctx, tri, degree.data());
    return degree;
}

class StarGraph {
public:
    // Links of every vertex in the triangulation (hidden and removed slots
    // get an empty link).
    StarGraph(Context &ctx, const tri::Triangulation &tri);

    int32_t vertex_slots() const { return static_cast<int32_t>(offset_.size()) - 1; }
    int32_t degree(int32_t v) const { return static_cast<int32_t>(offset_[v + 1] - offset_[v]); }
    const int32_t *link(int32_t v) const { return link_.data() + offset_[v]; }

    // Greedy colouring in slot order: each vertex takes the smallest colour
    // none of its neighbours has. colours()[c] lists the vertices of colour c
    // in ascending slot order.
    const std::vector<std::vector<int32_t>> &colours() const { return colours_; }

private:
    void colour();

    std::vector<int64_t> offset_;  // vertex_slots + 1; 64-bit: 3 x triangles passes 2^31 at 358 M vertices
    std::vector<int32_t> link_;
    std::vector<std::vector<int32_t>> colours_;
};

}  // namespace um::optim
