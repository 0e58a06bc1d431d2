// The smallest value over a block of rows and columns of a row-major 2-D
// array, in time proportional to the block's perimeter rather than its area:
// levels of 2 x 2 minima (each a quarter of the one below, a third of the
// array's size in all), the block covered by the largest aligned squares
// that fit, its fringe read at the levels below. Grid spacings use it to see
// a spacing feature inside a triangle of any size (grid.hpp).
#pragma once

#include <cstdint>
#include <vector>

namespace um::hfun {

class MinPyramid {
public:
    MinPyramid() = default;
    // The levels above `values` (rows x cols, row-major), which the
    // pyramid does not keep: queries take the same array again.
    MinPyramid(const std::vector<double> &values, int64_t rows, int64_t cols);

    // min of values[r * cols + c] for r in [r0, r1], c in [c0, c1]
    // (inclusive, within the array, not empty).
    double min_over(const std::vector<double> &values, int64_t r0, int64_t r1, int64_t c0,
                    int64_t c1) const;

private:
    struct Level {
        int64_t rows = 0, cols = 0;
        std::vector<double> min;
    };
    int64_t rows_ = 0, cols_ = 0;
    std::vector<Level> above_;  // above_[k] halves above_[k - 1] (the array for k = 0)
};

}  // namespace um::hfun
