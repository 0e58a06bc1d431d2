#include "geom/arc_tree.hpp"

#include <algorithm>
#include <cmath>

namespace um::geom {

namespace {
constexpr int32_t kLeafSize = 4;
}

Box arc_box(const Vec3 &a, const Vec3 &b) {
    Box box;
    box.add(a);
    box.add(b);
    // The arc bulges out of its chord by at most the sagitta
    // 1 - cos(theta/2) = 1 - sqrt(1 - (c/2)^2), c the chord (plus rounding).
    const Vec3 d = b - a;
    const double quarter_c2 = 0.25 * dot(d, d);
    box.grow(1.0 - std::sqrt(std::max(0.0, 1.0 - quarter_c2)) + 1e-15);
    return box;
}

ArcTree::ArcTree(std::vector<Arc> arcs) : arcs_(std::move(arcs)) {
    boxes_.reserve(arcs_.size());
    for (const Arc &s : arcs_) boxes_.push_back(arc_box(s.a, s.b));
    order_.resize(arcs_.size());
    for (size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int32_t>(i);
    if (!arcs_.empty()) {
        nodes_.reserve(2 * arcs_.size() / kLeafSize + 2);
        build(0, static_cast<int32_t>(arcs_.size()));
    }
    // Boxes by leaf position from now on: a leaf's boxes are read in a row.
    std::vector<Box> by_position(boxes_.size());
    for (size_t j = 0; j < order_.size(); ++j) by_position[j] = boxes_[order_[j]];
    boxes_.swap(by_position);
}

// Top-down: split at the median of box centres along the widest axis. Ties
// are broken by arc index, so the tree is the same on every run.
int32_t ArcTree::build(int32_t first, int32_t count) {
    int32_t id = static_cast<int32_t>(nodes_.size());
    nodes_.emplace_back();
    Box box;
    for (int32_t j = first; j < first + count; ++j) box.add(boxes_[order_[j]]);
    nodes_[id].box = box;
    if (count <= kLeafSize) {
        nodes_[id].first = first, nodes_[id].count = count;
        return id;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (box.hi[k] - box.lo[k] > box.hi[axis] - box.lo[axis]) axis = k;
    auto centre = [&](int32_t i) { return boxes_[i].lo[axis] + boxes_[i].hi[axis]; };
    int32_t half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half,
                     order_.begin() + first + count, [&](int32_t i, int32_t j) {
                         double ci = centre(i), cj = centre(j);
                         return ci != cj ? ci < cj : i < j;
                     });
    int32_t left = build(first, half);
    int32_t right = build(first + half, count - half);
    nodes_[id].left = left, nodes_[id].right = right;
    return id;
}

bool ArcTree::any_within(const Vec3 &p, double radius) const {
    if (!(radius > 0)) return false;
    // An arc nearer than radius has a point within that chord (shorter than
    // the arc) of p, inside p's box grown by it.
    Box box;
    box.add(p);
    box.grow(std::min(radius, 2.0) * (1 + 1e-9) + 1e-15);
    return query_until(box, [&](int32_t i) { return distance_to_arc(p, arcs_[i].a, arcs_[i].b) < radius; });
}

int32_t ArcTree::nearest(const Vec3 &p, double *distance) const {
    int32_t best = -1;
    double best_d = 1e300, best_chord2 = 1e300;
    if (nodes_.empty()) {
        if (distance) *distance = -1;
        return -1;
    }
    int32_t stack[128];
    int depth = 0;
    stack[depth++] = 0;
    while (depth > 0) {
        const Node &node = nodes_[stack[--depth]];
        // Chord distance to a box bounds the chord distance to what it holds.
        if (node.box.distance2(p) > best_chord2) continue;
        if (node.left < 0) {
            for (int32_t j = node.first; j < node.first + node.count; ++j) {
                int32_t i = order_[j];
                double d = distance_to_arc(p, arcs_[i].a, arcs_[i].b);
                if (d < best_d || (d == best_d && i < best)) {
                    best_d = d, best = i;
                    double chord = 2 * std::sin(0.5 * d);
                    best_chord2 = chord * chord * (1 + 1e-12) + 1e-300;
                }
            }
        } else {
            // Nearer child first, so the bound tightens sooner.
            int32_t a = node.left, b = node.right;
            if (nodes_[a].box.distance2(p) < nodes_[b].box.distance2(p)) std::swap(a, b);
            stack[depth++] = a;
            stack[depth++] = b;
        }
    }
    if (distance) *distance = best_d;
    return best;
}

}  // namespace um::geom
