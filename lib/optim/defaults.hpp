// The optimisation's topology bounds by default, in one place: the option
// table and OptimiseOptions start from these.
#pragma once

namespace um::optim {

constexpr double kDefaultCollapseRatio = 0.5;  // collapse edges shorter than this times h
constexpr double kDefaultSplitRatio = 1.6;     // split edges longer than this times h
// No edge between two generators off the land (the ocean mesh's cells)
// shorter than this times h: an explicit ocean model's time step is set by
// its shortest dcEdge (0 turns it off; it filters coastline detail the
// boundary refinement's bounds would otherwise follow).
constexpr double kDefaultOceanFloor = 0.7;

}  // namespace um::optim
