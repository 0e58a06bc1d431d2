// The spacing of a regional mesh (features/domain.hpp): the caller's inside
// the domain, and outside a coarse cover that grows away from the boundary,
//     h(x) = min(max(inner(x), cover_km), inner(x) + rate d(x))
// with d the distance to the domain's rings (exact near them; far outside
// the rough distance, features::Domain::rough_distance, within a few km).
// The triangulation is of the whole sphere (its hull must surround the
// centre, and the optimisation works on closed stars), so the outside is
// meshed too, but at a cost of about perimeter / (rate h) cells instead of
// the outside's area / h^2; no output holds those cells, and the
// optimisation leaves them as they are. Continuous across the rings (d = 0
// gives inner).
#pragma once

#include <memory>

#include "features/domain.hpp"
#include "hfun/spacing.hpp"

namespace um::hfun {

constexpr double kCoverRate = 0.25;     // km per km away from the domain
constexpr double kCoverKm = 1000.0;     // where the growth stops (unless inner is coarser)

// inner inside domain, the cover outside (radius_km: the sphere's, for d).
SpacingPtr make_region_cover(SpacingPtr inner, std::shared_ptr<const features::Domain> domain,
                             double radius_km = kEarthRadiusKm);

}  // namespace um::hfun
