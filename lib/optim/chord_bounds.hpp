// Bounds on the chord between the directions of two generators, read from
// their lifted points q = s x without a root: |x_a - x_b| lies within
// |q_a - q_b| -+ (|s_a - 1| + |s_b - 1|), and |s - 1| <= ||q|^2 - 1| for s > 0.
// The scans over every edge (the floor's, the collapses' and splits') keep
// the exact chord for the edges near their limits; normalising both ends of
// every edge was half of a scan's time.
#pragma once

#include <cmath>

#include "geom/sphere.hpp"

namespace um::optim {

class ChordBounds {
public:
    ChordBounds(const geom::Vec3 &qa, const geom::Vec3 &qb)
        : squared_(geom::dot(qa - qb, qa - qb)),
          slack_(std::fabs(geom::dot(qa, qa) - 1) + std::fabs(geom::dot(qb, qb) - 1)) {}
    // Each answer "surely" holds for the chord as computed from the
    // directions too: the margins (relative, and absolute for the roundings
    // of normalising, about 1e-16) are far above any rounding.
    bool surely_at_least(double limit) const {
        if (!(limit > 0)) return true;
        const double reach = (1 + kRelativeMargin) * limit + slack_ + kAbsoluteMargin;
        return squared_ >= reach * reach;
    }
    bool surely_below(double limit) const {
        const double reach = (1 - kRelativeMargin) * limit - slack_ - kAbsoluteMargin;
        return reach > 0 && squared_ <= reach * reach;
    }

private:
    static constexpr double kRelativeMargin = 1e-9, kAbsoluteMargin = 1e-14;
    double squared_, slack_;
};

}  // namespace um::optim
