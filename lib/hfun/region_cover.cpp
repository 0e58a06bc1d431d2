#include "hfun/region_cover.hpp"

#include <algorithm>

#include "core/text.hpp"

namespace um::hfun {

namespace {

class RegionCover final : public Spacing {
public:
    RegionCover(SpacingPtr inner, std::shared_ptr<const features::Domain> domain, double radius_km)
        : inner_(std::move(inner)), domain_(std::move(domain)), radius_km_(radius_km) {}

    double at(const Where &w) const override {
        const double h = inner_->at(w);
        if (!valid_km(h) || domain_->deep_inside(w.unit())) return h;
        if (domain_->distance_at_least(w.unit()) * radius_km_ >= kFullCoverKm) return std::max(h, kCoverKm);
        double d = 0;
        return domain_->locate(w.unit(), &d) ? h : cover(h, d * radius_km_);
    }
    // The cover grows with inner and with d, so the inner bound over the cap
    // and the cap's least distance to the rings bound it below.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override {
        const double h = inner_->smallest_in_cap(centre, radius, enough);
        if (!valid_km(h)) return h;
        if ((domain_->distance_at_least(centre) - radius) * radius_km_ >= kFullCoverKm) return std::max(h, kCoverKm);
        double d = 0;
        if (domain_->locate(centre, &d)) return h;
        return d <= radius ? h : cover(h, (d - radius) * radius_km_);
    }
    std::string describe() const override {
        return concat(inner_->describe(), " inside the domain, growing outside it");
    }

private:
    // Beyond this distance the cover is max(inner, kCoverKm) whatever inner is.
    static constexpr double kFullCoverKm = kCoverKm / kCoverRate;
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
