// The Earth's radius every default measures with: E3SM's SHR_CONST_REARTH,
// the default of UM_OPT_SPHERE_RADIUS.
#pragma once

namespace um {

constexpr double kEarthRadiusKm = 6371.22;

}  // namespace um
