// The stopping test's summary of the mesh (optimise.cpp): min and mean of
// Q^T and Q^P over the live triangles off a regional mesh's cover, and on
// request the cosine of the largest angle. Made in blocks of triangle slots
// (reduced in parallel, combined in block order: the same sums for any
// thread count) and kept between calls: a late outer iteration changes a few
// hundred vertices, and scoring every triangle again was a twentieth of a
// coastal mesh's optimisation.
#pragma once

#include <cstdint>
#include <vector>

namespace um::optim::detail {

class MeshState;

struct Summary {
    double qt_min, qt_mean, qp_min, qp_mean;
    double largest_angle_cosine;  // of the mesh's largest angle (1 when not asked for)
};

class QualitySummary {
public:
    // A block is scored again only when its slots hold other triangles (or
    // the same ones with another cover flag) or one of their vertices
    // changed since the last call (MeshState::changed_at): what it adds to
    // the sums is then the same, bit for bit, as scoring it again.
    Summary summarise(const MeshState &s, bool with_largest_angle);

private:
    struct Partial {
        double qt_min = 2, qt_sum = 0, qp_min = 2, qp_sum = 0, largest_angle_cosine = 1;
        int64_t live = 0;
    };
    struct Block {
        Partial partial;
        uint64_t triangles = 0;  // a fingerprint of the slots' vertices and cover flags
        bool scored = false, with_angle = false;
    };
    static Partial score(const MeshState &s, int64_t first, int64_t end, bool with_largest_angle);
    static uint64_t fingerprint(const MeshState &s, int64_t first, int64_t end, int32_t since, bool &changed);

    std::vector<Block> blocks_;
    int32_t since_ = 0;  // the clock at the last call
};

}  // namespace um::optim::detail
