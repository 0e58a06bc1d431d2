// Insertion order for incremental construction: biased randomised insertion
// order (BRIO) rounds, each sorted along a Hilbert curve on the cube map of
// the sphere, so that consecutive points are close (short walks, warm
// caches) while the rounds keep the early triangulation well spread.
// Deterministic: the "random" rounds come from a hash of the point index.
#pragma once

#include <cstdint>
#include <vector>

#include "core/buffer.hpp"
#include "core/context.hpp"
#include "core/error.hpp"
#include "geom/sphere.hpp"

namespace um::tri {

// Hilbert index (31 bits: cube face, then 14 bits per face axis) of a
// direction (need not be unit length).
uint64_t hilbert_key(const geom::Vec3 &direction);

// The insertion order of n points as sorted words, one per point: its
// round and Hilbert index (brio_hilbert) above its index (brio_point),
// ascending. direction(i) gives point i's direction (of any length). Runs
// in the context's arena; the result is the same for any number of threads.
// (Words, not a permutation and a list of keys: the construction reads
// both from the one array, and at 10^6 points each array it does not
// allocate saves it some 1,000 page faults.)
// `room`, when given, holds 2n words for the words and the sort's buffer
// (the Buffer returned is then over part of it), else they are allocated.
template <class DirectionFn>
Buffer<uint64_t> brio_words(Context &ctx, int64_t n, DirectionFn direction, uint64_t *room = nullptr);
constexpr int kBrioIndexBits = 28;  // n <= 2^28 (check_brio_count)
// Throws UM_ERR_LIMIT unless 0 <= n <= 2^28: point indices fit the bits
// below the key.
inline void check_brio_count(int64_t n) {
    if (n < 0 || n > (int64_t(1) << kBrioIndexBits))
        fail(UM_ERR_LIMIT, n, " points to order; at most 2^", kBrioIndexBits);
}
inline int32_t brio_point(uint64_t word) {
    return static_cast<int32_t>(word & ((uint64_t(1) << kBrioIndexBits) - 1));
}
constexpr int kHilbertIndexBits = 31;  // hilbert_key's
inline uint32_t brio_hilbert(uint64_t word) {
    return static_cast<uint32_t>((word >> kBrioIndexBits) & ((uint64_t(1) << kHilbertIndexBits) - 1));
}

// Implementation detail shared with the template: keys are a 5-bit round
// above a 31-bit Hilbert index (36 bits); sorts the words made from them.
void brio_sort(Context &ctx, Buffer<uint64_t> &keys, uint64_t *scratch);
// The number of rounds after the first for n points, and the round of point
// `index` above its Hilbert index.
int brio_rounds(int64_t n);
uint64_t brio_round_key(int64_t index, int rounds);
// The round (0 = first) brio_words puts point `index` of n in.
int brio_round(int64_t index, int64_t n);

template <class DirectionFn>
Buffer<uint64_t> brio_words(Context &ctx, int64_t n, DirectionFn direction, uint64_t *room) {
    check_brio_count(n);
    Buffer<uint64_t> keys = room ? Buffer<uint64_t>::over(room, static_cast<size_t>(n))
                                 : Buffer<uint64_t>(static_cast<size_t>(n));
    const int rounds = brio_rounds(n);
    ctx.parallel_for(n, 4096, [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i)
            keys[i] = brio_round_key(i, rounds) | hilbert_key(direction(i));
    });
    brio_sort(ctx, keys, room ? room + n : nullptr);
    return keys;
}

}  // namespace um::tri
