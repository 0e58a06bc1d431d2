#include "optim/quality_summary.hpp"

#include <algorithm>

#include "core/splitmix.hpp"
#include "optim/mesh_state.hpp"

namespace um::optim::detail {

namespace {

// Triangle slots per block. Smaller blocks are fewer to score again (the
// changes of a late iteration lie along every coast), larger ones fewer to
// sum: on the coastlines at 30 km, 8192 left 105 of 161 blocks to score,
// 1024 left 350 of 1285, and 256 gained little more.
constexpr int64_t kBlock = 1024;

}  // namespace

QualitySummary::Partial QualitySummary::score(const MeshState &s, int64_t first, int64_t end, bool with_largest_angle) {
    Partial p;
    for (int64_t t = first; t < end; ++t) {
        const int32_t ti = static_cast<int32_t>(t);
        if (s.tri.is_free(ti) || s.touches_cover(ti)) continue;
        const Generator a = s.generator(s.tri.vertex(ti, 0)), b = s.generator(s.tri.vertex(ti, 1)),
                        c = s.generator(s.tri.vertex(ti, 2));
        const TriangleCost cost = triangle_cost(a, b, c);
        if (with_largest_angle)
            p.largest_angle_cosine = std::min(p.largest_angle_cosine, largest_angle_cosine(a.x, b.x, c.x));
        p.qt_min = std::min(p.qt_min, cost.area_length), p.qt_sum += cost.area_length;
        p.qp_min = std::min(p.qp_min, cost.primal_dual), p.qp_sum += cost.primal_dual;
        ++p.live;
    }
    return p;
}

// Each slot's vertices by id (a slot a removed vertex left may hold a new
// one) and its cover flag, bound to the slot (the sums run in slot order);
// `changed` when a vertex changed at or after `since`.
uint64_t QualitySummary::fingerprint(const MeshState &s, int64_t first, int64_t end, int32_t since, bool &changed) {
    uint64_t sum = 0;
    changed = false;
    for (int64_t t = first; t < end; ++t) {
        const int32_t ti = static_cast<int32_t>(t);
        uint64_t word = static_cast<uint64_t>(t) << 1;
        if (!s.tri.is_free(ti)) {
            for (int k = 0; k < 3; ++k) {
                const int32_t v = s.tri.vertex(ti, k);
                changed = changed || s.changed_at[v] >= since;
                word = splitmix64(word ^ static_cast<uint64_t>(static_cast<uint32_t>(s.tri.id(v))));
            }
            word ^= s.touches_cover(ti) ? 1 : 0;
        }
        sum += splitmix64(word);
    }
    return sum;
}

Summary QualitySummary::summarise(const MeshState &s, bool with_largest_angle) {
    const int32_t n = s.tri.triangle_slots();
    const int64_t n_blocks = (n + kBlock - 1) / kBlock;
    blocks_.resize(static_cast<size_t>(n_blocks));
    s.ctx.parallel_for(n_blocks, 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            Block &block = blocks_[i];
            const int64_t first = i * kBlock, end = std::min<int64_t>(n, first + kBlock);
            bool changed = false;
            const uint64_t triangles = fingerprint(s, first, end, since_, changed);
            if (block.scored && !changed && triangles == block.triangles && (block.with_angle || !with_largest_angle))
                continue;
            block.partial = score(s, first, end, with_largest_angle);
            block.triangles = triangles, block.scored = true, block.with_angle = with_largest_angle;
        }
    });
    since_ = s.clock;
    Partial all;
    for (const Block &block : blocks_) {
        const Partial &p = block.partial;
        all.qt_min = std::min(all.qt_min, p.qt_min), all.qt_sum += p.qt_sum;
        all.qp_min = std::min(all.qp_min, p.qp_min), all.qp_sum += p.qp_sum;
        if (with_largest_angle) all.largest_angle_cosine = std::min(all.largest_angle_cosine, p.largest_angle_cosine);
        all.live += p.live;
    }
    const double live = double(std::max<int64_t>(all.live, 1));
    return {all.qt_min, all.qt_sum / live, all.qp_min, all.qp_sum / live, all.largest_angle_cosine};
}

}  // namespace um::optim::detail
