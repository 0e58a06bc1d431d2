// A stable LSD radix sort of 64-bit words by a range of their bits, in
// parallel over a fixed number of chunks, so the result is the same for any
// thread count (and, the sort being stable, fully determined by the input).
#pragma once

#include <cstdint>

#include "core/buffer.hpp"
#include "core/context.hpp"

namespace um {

// Sorts keys by bits [low_bit, high_bit) (0 <= low_bit < high_bit <= 64);
// equal digits keep their order. Uses a second buffer of keys.size() words:
// `scratch` when given, else one it allocates. (After an odd number of
// passes the sorted words are in the scratch, and keys refers to it: the
// memory keys owned is freed, and the scratch must outlive keys.)
void radix_sort(Context &ctx, Buffer<uint64_t> &keys, int low_bit, int high_bit,
                uint64_t *scratch = nullptr);

}  // namespace um
