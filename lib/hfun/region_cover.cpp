#include "hfun/region_cover.hpp"

#include <algorithm>

#include "core/text.hpp"

namespace um::hfun {

using geom::Vec3;

namespace {

class RegionCover final : public Spacing {
public:
    RegionCover(SpacingPtr inner, std::shared_ptr<const features::Domain> domain, double radius_km)
        : inner_(std::move(inner)), domain_(std::move(domain)), radius_km_(radius_km) {}

    double at(const Where &w) const override {
        const double h = inner_->at(w);
        if (!valid_km(h)) return h;
        const Vec3 &x = w.unit();
        if (domain_->distance_at_least(x) * radius_km_ >= kFullCoverKm) return std::max(h, kCoverKm);
        const features::Domain::Side side = domain_->side(x);
        if (side == features::Domain::Side::inside) return h;
        if (side == features::Domain::Side::outside) {
            const double rough = domain_->rough_distance(x);
            if (rough >= kRoughFrom) return cover(h, rough * radius_km_);
        }
        double d = 0;
        return domain_->locate(x, &d) ? h : cover(h, d * radius_km_);
    }
    // The cover grows with inner and with d, so the inner bound over the cap
    // and a lower bound of the distance over the cap bound it below: the
    // exact distance at the centre less the radius, less the rough
    // distance's error where at() may read that (only from kRoughFrom: a
    // cap near the rings keeps the exact bound, else the cover's first
    // kilometres would take the inner spacing); a cap wholly farther than
    // that bounded by the rough distance, less twice its error.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override {
        const double h = inner_->smallest_in_cap(centre, radius, enough);
        if (!valid_km(h)) return h;
        if ((domain_->distance_at_least(centre) - radius) * radius_km_ >= kFullCoverKm) return std::max(h, kCoverKm);
        const features::Domain::Side side = domain_->side(centre);
        if (side == features::Domain::Side::inside) return h;
        constexpr double error = features::Domain::rough_error();
        if (side == features::Domain::Side::outside) {
            const double rough = domain_->rough_distance(centre);
            if (rough - radius - error >= kRoughFrom) return cover(h, (rough - radius - 2 * error) * radius_km_);
        }
        double d = 0;
        if (domain_->locate(centre, &d)) return h;
        const double least = d - radius - (d + radius + error >= kRoughFrom ? error : 0.0);
        return least <= 0 ? h : cover(h, least * radius_km_);
    }
    std::string describe() const override {
        return concat(inner_->describe(), " inside the domain, growing outside it");
    }

private:
    // Beyond this distance the cover is max(inner, kCoverKm) whatever inner is.
    static constexpr double kFullCoverKm = kCoverKm / kCoverRate;
    // Farther than this from the rings (radians), the cover reads the rough
    // distance (features::Domain::rough_distance): its error moves the cover
    // there by at most kCoverRate times that error, against at least 8 times
    // as much growth.
    static constexpr double kRoughFrom = 8 * features::Domain::rough_error();
    static double cover(double h, double d_km) { return std::min(std::max(h, kCoverKm), h + kCoverRate * d_km); }

    SpacingPtr inner_;
    std::shared_ptr<const features::Domain> domain_;
    double radius_km_;
};

}  // namespace

SpacingPtr make_region_cover(SpacingPtr inner, std::shared_ptr<const features::Domain> domain, double radius_km) {
    return std::make_shared<RegionCover>(std::move(inner), std::move(domain), radius_km);
}

}  // namespace um::hfun
