// splitmix64's finaliser: a cheap 64-bit mix whose outputs look independent
// for nearby inputs (hash keys, sampling orders and fingerprints of state).
#pragma once

#include <cstdint>

namespace um {

inline uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

}  // namespace um
