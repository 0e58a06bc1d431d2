// The mends after the schedule (mends.cpp): joint searches over the weights
// and positions of a triangle's vertices (or a flip of one of its edges)
// for the triangles not holding their orthocentre and the obtuse ones,
// which moving one vertex at a time cannot mend.
#pragma once

#include <cstdint>
#include <vector>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class Mends {
public:
    explicit Mends(MeshState &s) : s_(s) {}
    // What a mend keeps: no Q^P below qp; where vertices move, no Q^T below
    // qt and no angle larger than the one of cosine largest_angle_cosine.
    struct MendFloors {
        double qp = 0, qt = 0, largest_angle_cosine = -1;
    };
    // What a mend met and mended (slid: of those, with a vertex sliding
    // along Gamma).
    struct Mended {
        int64_t met = 0, mended = 0, slid = 0, flipped = 0;
        MendFloors floors;  // what it kept (from a summary, made only when it met any)
    };
    // keep_obtuse: its moves may not add obtuse triangles (after the obtuse mend).
    Mended mend_off_centre_triangles(bool keep_obtuse);
    Mended mend_obtuse_triangles();

private:
    // The floors from a fresh summary: the mesh's least Q^P (or kMendQpFloor,
    // when `qp_floor` and that is lower), least Q^T and largest angle.
    MendFloors mend_floors(bool qp_floor);
    struct Candidate {  // a generator a vertex may take, and its segment of Gamma
        Generator g;
        int32_t segment;
    };
    std::vector<Candidate> mend_candidates(int32_t v, int steps, int slides, bool off_gamma_moves = false) const;
    // What a joint search lowers: the triangles not holding their
    // orthocentre (also without adding obtuse ones), or the obtuse ones
    // (then without adding to the former).
    enum class MendGoal { off_centre, off_centre_keeping_obtuse, obtuse };
    // The off-centre and obtuse triangles around, counted before a flip
    // that left the mesh as it is not regular (mend_by_flip): what a joint
    // search after it must beat, instead of the counts as they are.
    struct Baseline {
        int off_centre, obtuse;
        int gamma_crossings;  // stars_gamma_crossings of the quad before the flip
    };
    struct JointSearch;
    bool mend_jointly(const int32_t *v, int n, const std::vector<Candidate> *candidates, const MendFloors &floors,
                      bool moves, MendGoal goal = MendGoal::off_centre, const Baseline *baseline = nullptr);
    bool mend_by_flip(int32_t &t, int k, const MendFloors &floors, MendGoal goal);
    // out counts the slides and flips that mended t.
    bool mend_off_centre_triangle(int32_t t, const MendFloors &floors, MendGoal moving, Mended &out);

    MeshState &s_;
};

}  // namespace um::optim::detail
