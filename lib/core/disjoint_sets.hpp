// Union-find over 0..n-1 with the lowest index as each set's root, so that
// the roots (and whatever is numbered by them) do not depend on the order
// of the joins' arguments.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace um {

class DisjointSets {
public:
    explicit DisjointSets(size_t n) : parent_(n) {
        for (size_t i = 0; i < n; ++i) parent_[i] = static_cast<int32_t>(i);
    }
    int32_t root(int32_t v) {
        while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
        return v;
    }
    // Whether a and b were apart (and are now joined).
    bool join(int32_t a, int32_t b) {
        a = root(a), b = root(b);
        if (a == b) return false;
        parent_[std::max(a, b)] = std::min(a, b);
        return true;
    }

private:
    std::vector<int32_t> parent_;
};

}  // namespace um
