#include "optim/star_graph.hpp"

#include <algorithm>

namespace um::optim {

void write_degrees(Context &ctx, const tri::Triangulation &tri, int32_t *out) {
    ctx.parallel_for(tri.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            int32_t degree = 0;
            tri.for_each_in_star(static_cast<int32_t>(v), [&](int32_t) { ++degree; });
            out[v] = degree;
        }
    });
}

StarGraph::StarGraph(Context &ctx, const tri::Triangulation &tri) {
    const int32_t n = tri.vertex_slots();
    std::vector<int32_t> degree(static_cast<size_t>(n));
    write_degrees(ctx, tri, degree.data());
    offset_.assign(static_cast<size_t>(n) + 1, 0);
    for (int32_t v = 0; v < n; ++v) offset_[v + 1] = offset_[v] + degree[v];
    link_.assign(static_cast<size_t>(offset_[n]), -1);
    // Walk each star once, counter-clockwise (what Triangulation::star gives).
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            if (!tri.in_triangulation(static_cast<int32_t>(v))) continue;
            int32_t *out = link_.data() + offset_[v];
            tri.for_each_neighbour(static_cast<int32_t>(v), [&](int32_t w) { *out++ = w; });
        }
    });
    colour();
}

void StarGraph::colour() {
    const int32_t n = vertex_slots();
    std::vector<int32_t> colour_of(static_cast<size_t>(n), -1);
    std::vector<int32_t> seen_by;  // seen_by[c] == v: a neighbour of v has colour c
    for (int32_t v = 0; v < n; ++v) {
        if (degree(v) == 0) continue;
        for (int k = 0; k < degree(v); ++k) {
            int32_t c = colour_of[link(v)[k]];
            if (c < 0) continue;
            if (c >= static_cast<int32_t>(seen_by.size())) seen_by.resize(c + 1, -1);
            seen_by[c] = v;
        }
        int32_t c = 0;
        while (c < static_cast<int32_t>(seen_by.size()) && seen_by[c] == v) ++c;
        colour_of[v] = c;
    }
    // The lists sized exactly (growing them by push_back would hold up to
    // twice their size at the moment memory peaks), each in slot order.
    std::vector<int32_t> count;
    for (int32_t c : colour_of)
        if (c >= 0) {
            if (c >= static_cast<int32_t>(count.size())) count.resize(c + 1, 0);
            ++count[c];
        }
    colours_.resize(count.size());
    for (size_t c = 0; c < count.size(); ++c) colours_[c].reserve(static_cast<size_t>(count[c]));
    for (int32_t v = 0; v < n; ++v)
        if (colour_of[v] >= 0) colours_[colour_of[v]].push_back(v);
}

}  // namespace um::optim
