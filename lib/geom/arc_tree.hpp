// An axis-aligned bounding-box tree over great-circle arcs (the segments of
// the polyarc networks Gamma), for the dual-arc x Gamma intersection queries
// of restricted meshing (paper section 5.1) and nearest-feature distances.
// Boxes are 3-D boxes of the arcs on the unit sphere: the chord's box grown by
// the arc's sagitta, which always contains the arc.
#pragma once

#include <array>
#include <cmath>
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
    // Whether the box comes within `margin` of the plane through the origin
    // normal to n, or reaches both sides of it.
    bool meets_plane(const Vec3 &n, double margin) const {
        double centre = 0, reach = 0;
        for (int k = 0; k < 3; ++k) {
            centre += n[k] * 0.5 * (lo[k] + hi[k]);
            reach += std::fabs(n[k]) * 0.5 * (hi[k] - lo[k]);
        }
        return std::fabs(centre) <= reach + margin;
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
    bool query_until(const Box &box, Visit &&visit) const {
        return visit_until([&](const Box &b) { return b.overlaps(box); }, visit);
    }
    // Calls visit(i) for every arc that may cross the minor great arc (a, b):
    // those whose box overlaps the arc's and comes within 1e-9 rad of its
    // great circle's plane. A box farther on one side holds no arc that
    // crosses it or touches it within arc_intersection's tolerances (1e-12
    // rad and less); the margin is far above those and the test's rounding.
    // A long arc's box holds far more arcs than its plane passes near. In a
    // fixed order.
    template <class Visit>
    void query_crossing(const Vec3 &a, const Vec3 &b, Visit &&visit) const {
        query_crossing_until(a, b, [&](int32_t i) {
            visit(i);
            return false;
        });
    }
    // The same until visit(i) returns true; whether it did.
    template <class Visit>
    bool query_crossing_until(const Vec3 &a, const Vec3 &b, Visit &&visit) const {
        const Box box = arc_box(a, b);
        const Vec3 n = cross(a, b);
        const double margin = 1e-9 * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
        return visit_until([&](const Box &c) { return c.overlaps(box) && c.meets_plane(n, margin); }, visit);
    }
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
    // visit(i) for the arcs in the boxes (of nodes, then arcs) that `test`
    // accepts, until it returns true; whether it did.
    template <class Test, class Visit>
    bool visit_until(Test &&test, Visit &&visit) const;

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

template <class Test, class Visit>
bool ArcTree::visit_until(Test &&test, Visit &&visit) const {
    if (nodes_.empty()) return false;
    int32_t stack[128];
    int depth = 0;
    stack[depth++] = 0;
    while (depth > 0) {
        const Node &node = nodes_[stack[--depth]];
        if (!test(node.box)) continue;
        if (node.left < 0) {
            for (int32_t j = node.first; j < node.first + node.count; ++j)
                if (test(boxes_[j]) && visit(order_[j])) return true;
        } else {
            stack[depth++] = node.right;
            stack[depth++] = node.left;
        }
    }
    return false;
}

}  // namespace um::geom
