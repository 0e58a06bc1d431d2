// Capacity: releasing it, and growth for arrays that, once sized exactly, grow a few elements
// at a time: a mesh handed to the optimisation (which splits edges and
// vertices) or refined further. std::vector doubles its capacity, which at
// 10^6 cells doubles the largest arrays of the mesh for a handful of new
// vertices; this grows by an eighth instead - still geometric, so appending
// stays amortised constant time.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace um {

// Frees a container's storage now (clear() keeps its capacity).
template <class Container>
void release(Container &values) {
    Container().swap(values);
}

template <class T, class Allocator>
void reserve_for(std::vector<T, Allocator> &values, size_t needed) {
    if (needed <= values.capacity()) return;
    values.reserve(std::max(needed, values.capacity() + values.capacity() / 8 + 16));
}

}  // namespace um
