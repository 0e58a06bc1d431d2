#include "hfun/spacing.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"

namespace um::hfun {

// ------------------------------------------------------------------ Where

Where Where::from_unit(const geom::Vec3 &u) {
    Where w;
    w.unit_ = u;
    w.has_unit_ = true;
    return w;
}

Where Where::from_lonlat(double lon_deg, double lat_deg) {
    Where w;
    w.lon_ = lon_deg, w.lat_ = lat_deg;
    w.has_lonlat_ = true;
    return w;
}

const geom::Vec3 &Where::unit() const {
    if (!has_unit_) unit_ = geom::unit_from_lonlat_deg(lon_, lat_), has_unit_ = true;
    return unit_;
}

double Where::lon_deg() const {
    if (!has_lonlat_) geom::lonlat_deg_from_unit(unit_, lon_, lat_), has_lonlat_ = true;
    return lon_;
}

double Where::lat_deg() const {
    lon_deg();  // computes both
    return lat_;
}

// ------------------------------------------------------------------ base

SpacingPtr Spacing::gradient_limited(double, double) const { return nullptr; }

double Spacing::smallest_in_cap(const geom::Vec3 &centre, double, double) const { return km_at(centre); }

namespace {

void check_km(double km, const char *argument) {
    if (!std::isfinite(km)) fail(UM_ERR_NONFINITE_INPUT, argument, " = ", km, " km is not finite");
    if (km <= 0) fail(UM_ERR_INVALID_ARGUMENT, argument, " = ", km, " km is not > 0");
}

class ConstantSpacing final : public Spacing {
public:
    explicit ConstantSpacing(double km) : km_(km) {}
    double at(const Where &) const override { return km_; }
    std::string describe() const override { return concat("a constant spacing of ", km_, " km"); }

private:
    double km_;
};

class CallbackSpacing final : public Spacing {
public:
    CallbackSpacing(SpacingCallback fn, void *user) : fn_(fn), user_(user) {}
    double at(const Where &w) const override { return fn_(user_, w.lon_deg(), w.lat_deg()); }
    std::string describe() const override { return "the spacing callback"; }

private:
    SpacingCallback fn_;
    void *user_;
};

class ClampedSpacing final : public Spacing {
public:
    ClampedSpacing(SpacingPtr inner, double lo, double hi)
        : inner_(std::move(inner)), lo_(lo), hi_(hi) {}
    double at(const Where &w) const override {
        double h = inner_->at(w);
        if (!valid_km(h)) return h;  // let evaluate() report the inner value
        return std::min(std::max(h, lo_), hi_);
    }
    // Clamping is monotone: it keeps a lower bound one.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override {
        double h = inner_->smallest_in_cap(centre, radius, enough);
        if (!valid_km(h)) return h;
        return std::min(std::max(h, lo_), hi_);
    }
    std::string describe() const override {
        return concat(inner_->describe(), " clamped to [", lo_, ", ", hi_, "] km");
    }
    // Clamping is 1-Lipschitz, so clamp(limited grid) keeps |grad h| <= g.
    SpacingPtr gradient_limited(double g, double radius_km) const override {
        SpacingPtr limited = inner_->gradient_limited(g, radius_km);
        return limited ? std::make_shared<ClampedSpacing>(std::move(limited), lo_, hi_) : nullptr;
    }

private:
    SpacingPtr inner_;
    double lo_, hi_;
};

class MinimumSpacing final : public Spacing {
public:
    explicit MinimumSpacing(std::vector<SpacingPtr> parts) : parts_(std::move(parts)) {}
    double at(const Where &w) const override {
        double best = std::numeric_limits<double>::infinity();
        for (const auto &part : parts_) {
            double h = part->at(w);
            if (!valid_km(h)) return h;  // reported, not hidden by another part
            best = std::min(best, h);
        }
        return best;
    }
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override {
        double best = std::numeric_limits<double>::infinity();
        for (const auto &part : parts_) {
            double h = part->smallest_in_cap(centre, radius, enough);
            if (!valid_km(h)) return h;
            best = std::min(best, h);
        }
        return best;
    }
    // The minimum of g-limited parts obeys g too.
    SpacingPtr gradient_limited(double g, double radius_km) const override {
        std::vector<SpacingPtr> limited;
        for (const auto &part : parts_) {
            limited.push_back(part->gradient_limited(g, radius_km));
            if (!limited.back()) return nullptr;
        }
        return std::make_shared<MinimumSpacing>(std::move(limited));
    }
    std::string describe() const override {
        std::string text = "the minimum of (";
        for (size_t k = 0; k < parts_.size(); ++k)
            text += (k ? "; " : "") + parts_[k]->describe();
        return text + ")";
    }

private:
    std::vector<SpacingPtr> parts_;
};

}  // namespace

SpacingPtr make_constant(double km) {
    check_km(km, "km");
    return std::make_shared<ConstantSpacing>(km);
}

SpacingPtr make_callback(SpacingCallback fn, void *user_data) {
    if (!fn) fail(UM_ERR_NULL_ARGUMENT, "fn is NULL");
    return std::make_shared<CallbackSpacing>(fn, user_data);
}

SpacingPtr make_clamp(SpacingPtr inner, double km_min, double km_max) {
    if (!inner) fail(UM_ERR_NULL_ARGUMENT, "the spacing to clamp is null");
    check_km(km_min, "km_min");
    check_km(km_max, "km_max");
    if (km_min > km_max)
        fail(UM_ERR_INVALID_ARGUMENT, "km_min = ", km_min, " km is above km_max = ", km_max, " km");
    return std::make_shared<ClampedSpacing>(std::move(inner), km_min, km_max);
}

SpacingPtr make_minimum(std::vector<SpacingPtr> parts) {
    if (parts.empty()) fail(UM_ERR_INVALID_ARGUMENT, "the minimum of no spacing is not defined");
    for (size_t k = 0; k < parts.size(); ++k)
        if (!parts[k]) fail(UM_ERR_NULL_ARGUMENT, "part ", k, " of the minimum is null");
    if (parts.size() == 1) return parts[0];
    return std::make_shared<MinimumSpacing>(std::move(parts));
}

SpacingPtr limit_gradient(const Spacing &spacing, double g, double radius_km) {
    if (!std::isfinite(g)) fail(UM_ERR_NONFINITE_INPUT, "g = ", g, " is not finite");
    if (g <= 0) fail(UM_ERR_INVALID_ARGUMENT, "g = ", g, " is not > 0 (a gradient in km per km)");
    if (!std::isfinite(radius_km) || radius_km <= 0)
        fail(UM_ERR_INVALID_ARGUMENT, "radius_km = ", radius_km, " is not a finite value > 0");
    SpacingPtr limited = spacing.gradient_limited(g, radius_km);
    if (!limited)
        fail(UM_ERR_INVALID_ARGUMENT, "gradient limiting works on grid spacings only (from a "
             "lon/lat grid or a spacing file), not on ", spacing.describe());
    return limited;
}

void report_invalid(const Spacing &spacing, const Where &where, int64_t index, double km) {
    const char *what = std::isfinite(km) ? " is not > 0" : " is not finite";
    fail(std::isfinite(km) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT,
         spacing.describe(), " gave h = ", km, " km at lon ", where.lon_deg(), ", lat ",
         where.lat_deg(), " (point ", index, "); h", what);
}

void evaluate_at_points(Context &ctx, const Spacing &spacing, const std::vector<geom::Vec3> &points,
                        std::vector<double> &km_out) {
    km_out.resize(points.size());
    evaluate(ctx, spacing, static_cast<int64_t>(points.size()),
             [&](int64_t i) { return Where::from_unit(points[i]); }, km_out.data());
}

}  // namespace um::hfun
