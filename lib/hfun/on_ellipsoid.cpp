#include "hfun/on_ellipsoid.hpp"

#include "core/text.hpp"

namespace um::hfun {

namespace {

class OnEllipsoid final : public Spacing {
public:
    OnEllipsoid(SpacingPtr inner, const geom::Surface &surface) : inner_(std::move(inner)), surface_(surface) {}

    // The inner kind reads the point at the same geodetic lon/lat on the
    // sphere (its lon/lat, worked out only if the kind asks: a constant does not).
    double at(const Where &w) const override {
        const geom::Vec3 &u = w.unit();
        return inner_->at(Where::from_unit(surface_.sphere_unit(u))) * (surface_.a() / surface_.radius_along(u));
    }
    // The map from directions to the sphere of geodetic lon/lat stretches arcs
    // by at most 1 / (1 - f)^2 (along meridians at the equator; parallels
    // shrink), and a / r >= 1:
    // so the inner bound over the wider cap bounds h_dir below.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override {
        const double stretch = 1 / ((1 - surface_.f()) * (1 - surface_.f()));
        return inner_->smallest_in_cap(surface_.sphere_unit(centre), radius * stretch * (1 + 1e-12) + 1e-15, enough);
    }
    std::string describe() const override { return concat(inner_->describe(), " (geodesic km on the ellipsoid)"); }

private:
    SpacingPtr inner_;
    geom::Surface surface_;
};

}  // namespace

SpacingPtr make_on_ellipsoid(SpacingPtr inner, const geom::Surface &surface) {
    if (surface.is_sphere()) return inner;
    return std::make_shared<OnEllipsoid>(std::move(inner), surface);
}

}  // namespace um::hfun
