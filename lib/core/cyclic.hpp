// The next and previous of the indices 0, 1, 2 taken cyclically (a
// triangle's corners, a vector's axes), from bit tables rather than
// conditionals: the compiler turns those into branches, and in the
// insertion's walk and cavity search they are mispredicted often.
#pragma once

namespace um {

inline int next_of_three(int k) { return (0x09 >> (2 * k)) & 3; }  // 0 -> 1, 1 -> 2, 2 -> 0
inline int prev_of_three(int k) { return (0x12 >> (2 * k)) & 3; }  // 0 -> 2, 1 -> 0, 2 -> 1

}  // namespace um
