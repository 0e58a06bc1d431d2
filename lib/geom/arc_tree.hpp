// An axis-aligned bounding-box tree over great-circle arcs (the segments of
// the polyarc networks Gamma), for the dual-arc x Gamma intersection queries
// of restricted meshing (paper section 5.1) and nearest-feature distances.
// Boxes are 3-D boxes of the arcs on the unit sphere: the chord's box grown by
// the arc's sagitta, which always contains the arc.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geom/sphere.hpp"

namespace um::geom {

struct Box {
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    void add(const Vec3 &p) {
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
    void add(const Box &b) {
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
    }
    void grow(double r) {
        for (int k = 0; k < 3; ++k) lo[k] -= r, hi[k] += r;
    }
    bool overlaps(const Box &b) const {
        for (int k = 0; k < 3; ++k)
            if (lo[k] > b.hi[k] || b.lo[k] > hi[k]) return false;
        return true;
    }
    // Squared distance from p to the box (0 inside).
    double distance2(const Vec3 &p) const {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
            d2 += d * d;
        }
        return d2;
    }
};

// A box that contains the minor great arc (a, b) of unit vectors.
Box arc_box(const Vec3 &a, const Vec3 &b);

class ArcTree {
public:
    struct Arc {
        Vec3 a, b;
    };

    ArcTree() = default;
    explicit ArcTree(std::vector<Arc> arcs);

    size_t size() const { return arcs_.size(); }
    const Arc &arc(int32_t i) const { return arcs_[i]; }

    // Calls visit(i) for every arc whose box overlaps `box`, in a fixed order.
    template <class Visit>
    void query(const Box &box, Visit &&visit) const {
        query_until(box, [&](int32_t i) {
            visit(i);
            return false;
        });
    }
    // The same until visit(i) returns true; whether it did.
    template <class Visit>
    bool query_until(const Box &box, Visit &&visit) const;
    // Whether any arc's box overlaps `box` (stops at the first).
    bool any_overlaps(const Box &box) const {
        return query_until(box, [](int32_t) { return true; });
    }

    // The arc nearest to unit point p and its distance (radians); -1 when empty.
    int32_t nearest(const Vec3 &p, double *distance) const;
    // Whether some arc lies nearer than `radius` (radians) to unit point p:
    // for a tree with arcs, nearest(p, &d) and d < radius, from a box query
    // (the same distances, so the same answer) that stops at the first such
    // arc; false for an empty tree.
    bool any_within(const Vec3 &p, double radius) const;

private:
    struct Node {
        Box box;
        int32_t left = -1, right = -1;  // children; -1 for a leaf
        int32_t first = 0, count = 0;   // a leaf's range in order_
    };
    int32_t build(int32_t first, int32_t count);

    std::vector<Arc> arcs_;
    std::vector<Box> boxes_;      // by position in order_ (by arc while building)
    std::vector<int32_t> order_;
    std::vector<Node> nodes_;
};

template <class Visit>
bool ArcTree::query_until(const Box &box, Visit &&visit) const {
    if (nodes_.empty()) return false;
    int32_t stack[128];
    int depth = 0;
    stack[depth++] = 0;
    while (depth > 0) {
        const Node &node = nodes_[stack[--depth]];
        if (!node.box.overlaps(box)) continue;
        if (node.left < 0) {
            for (int32_t j = node.first; j < node.first + node.count; ++j)
                if (boxes_[j].overlaps(box) && visit(order_[j])) return true;
        } else {
            stack[depth++] = node.right;
            stack[depth++] = node.left;
        }
    }
    return false;
}

}  // namespace um::geom
