// The refinement's bounds by default (paper section 5), in one place: the
// option table and every struct that carries them start from these.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace um::refine {

constexpr double kDefaultAlpha = 4.0 / 3.0;  // edges and sizes below alpha h
constexpr double kDefaultBeta = 0.2;         // restricted edges within beta h of Gamma
constexpr double kDefaultRho = 1.05;         // radius-edge ratio below rho
// A grid spacing steeper than this (km per km) is meshed gradient-limited to
// it: about the steepest grading the optimised meshes keep.
constexpr double kDefaultSpacingGradient = 0.25;

// The shortest edge, over h, a refinement may make with a new vertex:
// `filter`, and for a vertex on an arc flagged in coast_arc (when given:
// the closed coastlines, whose vertices the ocean mesh's cells have) at
// least coast_filter (the time-step floor: the detail of the coastline
// narrower than that is filtered).
struct InsertionFilter {
    double filter = 0.5;
    const std::vector<uint8_t> *coast_arc = nullptr;
    double coast_filter = 0.5;
    double on_arc(int64_t arc) const {
        return coast_arc && arc >= 0 && (*coast_arc)[static_cast<size_t>(arc)] ? std::max(filter, coast_filter) : filter;
    }
};

}  // namespace um::refine
