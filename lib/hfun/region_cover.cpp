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
    // and a lower bound of the distance over the cap (less the rough
    // distance's error, which at() may read) bound it below.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override {
        const double h = inner_->smallest_in_cap(centre, radius, enough);
        if (!valid_km(h)) return h;
        if ((domain_->distance_at_least(centre) - radius) * radius_km_ >= kFullCoverKm) return std::max(h, kCoverKm);
        const features::Domain::Side side = domain_->side(centre);
        if (side == features::Domain::Side::inside) return h;
        double d = 0;
        if (side == features::Domain::Side::outside) {
            d = domain_->rough_distance(centre) - features::Domain::rough_error();
        } else if (domain_->locate(centre, &d)) {
            return h;
        }
        const double least = d - radius - features::Domain::rough_error();
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
    // there by at most kCoverRate times 28 km, against at least 8 times that.
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
