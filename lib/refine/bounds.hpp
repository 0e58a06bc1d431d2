// The refinement's bounds by default (paper section 5), in one place: the
// option table and every struct that carries them start from these.
#pragma once

namespace um::refine {

constexpr double kDefaultAlpha = 4.0 / 3.0;  // edges and sizes below alpha h
constexpr double kDefaultBeta = 0.2;         // restricted edges within beta h of Gamma
constexpr double kDefaultRho = 1.05;         // radius-edge ratio below rho

}  // namespace um::refine
