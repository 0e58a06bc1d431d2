#include "tri/spatial_order.hpp"

#include <algorithm>
#include <cmath>

#include "core/cyclic.hpp"
#include "core/radix_sort.hpp"
#include "core/splitmix.hpp"


namespace um::tri {

namespace {

constexpr int kBitsPerAxis = 14;
constexpr int kHilbertBits = 3 + 2 * kBitsPerAxis;  // face + 2 axes
static_assert(kHilbertBits == kHilbertIndexBits, "the header's count");

// Hilbert curve of order 14 by a state machine: state = orientation of the
// current sub-square; each level reads one bit of x and y, emits two bits of
// the index and moves to the orientation of the chosen quadrant. Table-driven
// so the loop has no data-dependent branches.
struct HilbertTable {
    uint8_t digit[4][4];  // [state][quadrant (x bit << 1 | y bit)]
    uint8_t next[4][4];
};

constexpr HilbertTable make_hilbert_table() {
    // Orientation 0 visits quadrants (x,y) = (0,0), (0,1), (1,1), (1,0); the
    // sub-curves in the first and last quadrants are transposed /
    // anti-transposed. States: 0 identity, 1 transpose, 2 anti-transpose,
    // 3 rotation by 180 degrees; each maps (x, y) before the lookup.
    HilbertTable t{};
    const int order0[4] = {0, 1, 3, 2};  // quadrant visited at step d = 0..3
    const int sub0[4] = {1, 0, 0, 2};    // orientation of the sub-curve at step d
    // Composition of orientations (state s applied, then sub-orientation r).
    const int compose[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
    for (int s = 0; s < 4; ++s)
        for (int q = 0; q < 4; ++q) {
            int x = q >> 1, y = q & 1, tx = x, ty = y;
            if (s == 1) tx = y, ty = x;
            if (s == 2) tx = 1 - y, ty = 1 - x;
            if (s == 3) tx = 1 - x, ty = 1 - y;
            int tq = (tx << 1) | ty;
            for (int d = 0; d < 4; ++d)
                if (order0[d] == tq) {
                    t.digit[s][q] = static_cast<uint8_t>(d);
                    t.next[s][q] = static_cast<uint8_t>(compose[s][sub0[d]]);
                }
        }
    return t;
}
constexpr HilbertTable kHilbert = make_hilbert_table();

// Levels per lookup composed from the one-level table: [state][x bits,
// y bits] -> the digits of those levels and the state after them. Two
// levels (16 entries a state) for the top of the curve, four (256) for the
// rest: fewer dependent lookups per key, and 2 KB still sit in L1.
template <int Levels>
struct HilbertTableN {
    static constexpr int kEntries = 1 << (2 * Levels);
    uint8_t digit[4][kEntries];
    uint8_t next[4][kEntries];
};

template <int Levels>
constexpr HilbertTableN<Levels> make_hilbert_table_n() {
    HilbertTableN<Levels> t{};
    for (int s = 0; s < 4; ++s)
        for (int xy = 0; xy < HilbertTableN<Levels>::kEntries; ++xy) {
            const int x = xy >> Levels, y = xy & ((1 << Levels) - 1);
            int state = s, digits = 0;
            for (int level = Levels - 1; level >= 0; --level) {
                const int q = ((x >> level) & 1) << 1 | ((y >> level) & 1);
                digits = digits * 4 + kHilbert.digit[state][q];
                state = kHilbert.next[state][q];
            }
            t.digit[s][xy] = static_cast<uint8_t>(digits);
            t.next[s][xy] = static_cast<uint8_t>(state);
        }
    return t;
}
constexpr HilbertTableN<2> kHilbert2 = make_hilbert_table_n<2>();
constexpr HilbertTableN<4> kHilbert4 = make_hilbert_table_n<4>();
static_assert(kBitsPerAxis == 2 + 3 * 4, "one two-level step, then three four-level ones");

uint64_t hilbert_2d(uint32_t x, uint32_t y) {
    int xy = static_cast<int>((x >> 12) << 2 | (y >> 12));
    uint64_t d = kHilbert2.digit[0][xy];
    int state = kHilbert2.next[0][xy];
    for (int level = 8; level >= 0; level -= 4) {
        xy = static_cast<int>(((x >> level) & 15) << 4 | ((y >> level) & 15));
        d = (d << 8) | kHilbert4.digit[state][xy];
        state = kHilbert4.next[state][xy];
    }
    return d;
}

}  // namespace

uint64_t hilbert_key(const geom::Vec3 &p) {
    // The cube face of the largest coordinate i (ties to the lower axis), and
    // the two after it as the face's axes. Selected, not branched on: the
    // face of a random point is a coin toss for the branch predictor.
    const double coord[3] = {p.x, p.y, p.z};
    const double ax = std::fabs(p.x), ay = std::fabs(p.y), az = std::fabs(p.z);
    const int x_largest = (ax >= ay) & (ax >= az), y_largest = (ay >= az) & !x_largest;
    const int i = 2 - 2 * x_largest - y_largest;
    const double m = std::max(ax, std::max(ay, az));
    const int face = i + 3 * (coord[i] <= 0);
    // The axes after and before i, cyclically.
    const double u = coord[next_of_three(i)], v = coord[prev_of_three(i)];
    if (m == 0) return 0;
    // t in [-1, 1] -> cell in [0, 2^bits - 1].
    constexpr double half_cells = 0.5 * double(1u << kBitsPerAxis);
    constexpr uint32_t last = (1u << kBitsPerAxis) - 1;
    const double scale = half_cells / m;
    auto cell = [&](double t) {
        double c = t * scale + half_cells;
        return c <= 0 ? 0u : std::min(static_cast<uint32_t>(c), last);
    };
    return (static_cast<uint64_t>(face) << (2 * kBitsPerAxis)) | hilbert_2d(cell(u), cell(v));
}

// Each round holds 8 times the points of the one before (CGAL's ratio too),
// the last round 7/8 of them. Every round sweeps the whole mesh once along
// the curve: with ratio 8 there are 4 sweeps at 10^6 points instead of the
// 11 that ratio 2 made, and bench_triangulation measured the construction
// 15-25 % faster on one thread (10^6 and 4*10^6 points), the triangles the
// same.
constexpr int kLevelBits = 3;

int brio_rounds(int64_t n) {
    // Round r (0 = first) holds about n (7/8) / 8^(R - r) points; R keeps
    // the first round at a few hundred points.
    int rounds = 0;
    // (At most 21 rounds: the shift stays below 64, the round fits 5 bits.)
    while (rounds < 21 && (n >> (kLevelBits * rounds)) > 512) ++rounds;
    return rounds;
}

uint64_t brio_round_key(int64_t index, int rounds) {
    // The level is the number of trailing one bits of a hash over
    // kLevelBits, capped at `rounds`: P(level >= k) = 8^-k. (Counted without
    // a loop: its exits are coin tosses for the branch predictor.)
    const uint64_t h = splitmix64(static_cast<uint64_t>(index));
    const int ones = ~h == 0 ? 64 : __builtin_ctzll(~h);
    const int level = std::min(ones / kLevelBits, rounds);
    const uint64_t round = static_cast<uint64_t>(rounds - level);
    return round << kHilbertBits;
}

int brio_round(int64_t index, int64_t n) {
    return static_cast<int>(brio_round_key(index, brio_rounds(n)) >> kHilbertBits);
}

void brio_sort(Context &ctx, Buffer<uint64_t> &keys, uint64_t *scratch) {
    // Pack (key, index) into one word: the key (round + Hilbert, 36 bits)
    // above the index. An LSD radix sort on the key bits is stable, so
    // equal keys keep index order: the result is fully determined by the keys.
    ctx.parallel_for(static_cast<int64_t>(keys.size()), 16384, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) keys[i] = (keys[i] << kBrioIndexBits) | uint64_t(i);
    });
    radix_sort(ctx, keys, kBrioIndexBits, 64, scratch);
}

}  // namespace um::tri
