#include "hfun/min_pyramid.hpp"

#include <algorithm>
#include <limits>

namespace um::hfun {

namespace {

// Blocks this small are read directly.
constexpr int64_t kDirectCells = 16;

}  // namespace

MinPyramid::MinPyramid(const std::vector<double> &values, int64_t rows, int64_t cols)
    : rows_(rows), cols_(cols) {
    const double *below = values.data();
    int64_t below_rows = rows, below_cols = cols;
    while (below_rows > 2 || below_cols > 2) {
        Level level;
        level.rows = (below_rows + 1) / 2, level.cols = (below_cols + 1) / 2;
        level.min.resize(static_cast<size_t>(level.rows * level.cols));
        for (int64_t r = 0; r < level.rows; ++r)
            for (int64_t c = 0; c < level.cols; ++c) {
                double m = below[(2 * r) * below_cols + 2 * c];
                const bool right = 2 * c + 1 < below_cols, down = 2 * r + 1 < below_rows;
                if (right) m = std::min(m, below[(2 * r) * below_cols + 2 * c + 1]);
                if (down) m = std::min(m, below[(2 * r + 1) * below_cols + 2 * c]);
                if (right && down) m = std::min(m, below[(2 * r + 1) * below_cols + 2 * c + 1]);
                level.min[static_cast<size_t>(r * level.cols + c)] = m;
            }
        above_.push_back(std::move(level));
        below = above_.back().min.data();
        below_rows = above_.back().rows, below_cols = above_.back().cols;
    }
}

double MinPyramid::min_over(const std::vector<double> &values, int64_t r0, int64_t r1, int64_t c0,
                            int64_t c1) const {
    double m = std::numeric_limits<double>::infinity();
    for (size_t level = 0;; ++level) {
        const double *v = level == 0 ? values.data() : above_[level - 1].min.data();
        const int64_t cols = level == 0 ? cols_ : above_[level - 1].cols;
        auto read = [&](int64_t ra, int64_t rb, int64_t ca, int64_t cb) {
            for (int64_t r = ra; r <= rb; ++r)
                for (int64_t c = ca; c <= cb; ++c) m = std::min(m, v[r * cols + c]);
        };
        // The rows and columns of the next level lying wholly inside.
        const int64_t up_r0 = (r0 + 1) / 2, up_r1 = (r1 + 1) / 2 - 1;
        const int64_t up_c0 = (c0 + 1) / 2, up_c1 = (c1 + 1) / 2 - 1;
        if (level == above_.size() || up_r0 > up_r1 || up_c0 > up_c1 ||
            (r1 - r0 + 1) * (c1 - c0 + 1) <= kDirectCells) {
            read(r0, r1, c0, c1);
            return m;
        }
        // The fringe outside them, at this level: at most one row or column a side.
        if (r0 < 2 * up_r0) read(r0, r0, c0, c1);
        if (r1 > 2 * up_r1 + 1) read(r1, r1, c0, c1);
        if (c0 < 2 * up_c0) read(2 * up_r0, 2 * up_r1 + 1, c0, c0);
        if (c1 > 2 * up_c1 + 1) read(2 * up_r0, 2 * up_r1 + 1, c1, c1);
        r0 = up_r0, r1 = up_r1, c0 = up_c0, c1 = up_c1;
    }
}

}  // namespace um::hfun
