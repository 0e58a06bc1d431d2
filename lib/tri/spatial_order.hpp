// Insertion order for incremental construction: biased randomised insertion
// order (BRIO) rounds, each sorted along a Hilbert curve on the cube map of
// the sphere, so that consecutive points are close (short walks, warm
// caches) while the rounds keep the early triangulation well spread.
// Deterministic: the "random" rounds come from a hash of the point index.
#pragma once

#include <cstdint>
#include <vector>

#include "core/context.hpp"
#include "geom/sphere.hpp"

namespace um::tri {

// Hilbert index (31 bits: cube face, then 14 bits per face axis) of a
// direction (need not be unit length).
uint64_t hilbert_key(const geom::Vec3 &direction);

// The insertion order of n points: a permutation of 0..n-1. direction(i)
// gives point i's direction (of any length). Runs in the context's arena;
// the result is the same for any number of threads.
// With sorted_keys, also the Hilbert index of every point in that order.
template <class DirectionFn>
std::vector<int32_t> brio_order(Context &ctx, int64_t n, DirectionFn direction,
                                std::vector<uint32_t> *sorted_keys = nullptr);

// Implementation detail shared with the template: keys are a 5-bit round
// above a 31-bit Hilbert index (36 bits); n < 2^28.
std::vector<int32_t> brio_order_from_keys(Context &ctx, std::vector<uint64_t> &keys,
                                          std::vector<uint32_t> *sorted_keys);
// The number of rounds after the first for n points, and the round of point
// `index` above its Hilbert index.
int brio_rounds(int64_t n);
uint64_t brio_round_key(int64_t index, int rounds);
// The round (0 = first) brio_order puts point `index` of n in.
int brio_round(int64_t index, int64_t n);

template <class DirectionFn>
std::vector<int32_t> brio_order(Context &ctx, int64_t n, DirectionFn direction,
                                std::vector<uint32_t> *sorted_keys) {
    std::vector<uint64_t> keys(static_cast<size_t>(n));
    const int rounds = brio_rounds(n);
    ctx.parallel_for(n, 4096, [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i)
            keys[i] = brio_round_key(i, rounds) | hilbert_key(direction(i));
    });
    return brio_order_from_keys(ctx, keys, sorted_keys);
}

}  // namespace um::tri
