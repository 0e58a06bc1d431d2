// The optimisation's topology bounds by default, in one place: the option
// table and OptimiseOptions start from these.
#pragma once

namespace um::optim {

constexpr double kDefaultCollapseRatio = 0.5;  // collapse edges shorter than this times h
constexpr double kDefaultSplitRatio = 1.6;     // split edges longer than this times h

}  // namespace um::optim
