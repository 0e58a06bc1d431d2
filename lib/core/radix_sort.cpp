#include "core/radix_sort.hpp"

#include <algorithm>
#include <vector>

namespace um {

void radix_sort(Context &ctx, Buffer<uint64_t> &keys, int low_bit, int high_bit, uint64_t *scratch) {
    // Digits of at most 9 bits: each chunk scatters to 512 places at once,
    // which the TLB and the write-combining buffers follow. (12-bit digits,
    // one pass fewer for the construction's 36 bits, were 1.5 times slower.)
    constexpr int kMaxDigitBits = 9;
    const int bits = high_bit - low_bit;
    const int passes = (bits + kMaxDigitBits - 1) / kMaxDigitBits;
    const int digit_bits = (bits + passes - 1) / passes;
    const size_t digits = size_t(1) << digit_bits;
    constexpr int kChunks = 16;
    const size_t n = keys.size();
    auto chunk_begin = [&](int64_t c) { return n * static_cast<size_t>(c) / kChunks; };
    Buffer<uint64_t> buffer = scratch ? Buffer<uint64_t>::over(scratch, n) : Buffer<uint64_t>(n);
    std::vector<size_t> count(digits * kChunks);  // [chunk][digit]
    for (int pass = 0; pass < passes; ++pass) {
        const int shift = low_bit + pass * digit_bits;
        const uint64_t mask = (uint64_t(1) << std::min(digit_bits, high_bit - shift)) - 1;
        // Per-chunk digit counts, then each chunk scatters its keys to where
        // the same digit of the chunks before it ends.
        ctx.parallel_for(kChunks, 1, [&](int64_t c0, int64_t c1) {
            for (int64_t c = c0; c < c1; ++c) {
                size_t *cnt = &count[digits * c];
                std::fill(cnt, cnt + digits, 0);
                for (size_t i = chunk_begin(c); i < chunk_begin(c + 1); ++i) ++cnt[(keys[i] >> shift) & mask];
            }
        });
        size_t sum = 0;
        for (size_t d = 0; d < digits; ++d)
            for (int c = 0; c < kChunks; ++c) {
                const size_t here = count[digits * c + d];
                count[digits * c + d] = sum;
                sum += here;
            }
        ctx.parallel_for(kChunks, 1, [&](int64_t c0, int64_t c1) {
            for (int64_t c = c0; c < c1; ++c) {
                size_t *next = &count[digits * c];
                for (size_t i = chunk_begin(c); i < chunk_begin(c + 1); ++i)
                    buffer[next[(keys[i] >> shift) & mask]++] = keys[i];
            }
        });
        keys.swap(buffer);
    }
}

}  // namespace um
