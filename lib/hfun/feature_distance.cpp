#include "hfun/feature_distance.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"
#include "geom/arc_tree.hpp"

namespace um::hfun {

namespace {

using geom::ArcTree;
using geom::Vec3;

// The one place the distance spacing asks for a distance (radians): swap the
// structure behind it here.
double nearest_feature_distance(const ArcTree &tree, const Vec3 &p) {
    double d = 0;
    tree.nearest(p, &d);
    return d;
}

void check_ramp(const DistanceRamp &r) {
    const std::pair<const char *, double> values[] = {
        {"km_min", r.km_min}, {"km_max", r.km_max}, {"distance_km", r.distance_km}, {"rate", r.rate}};
    for (const auto &[name, v] : values)
        if (!std::isfinite(v)) fail(UM_ERR_NONFINITE_INPUT, name, " = ", v, " is not finite");
    if (r.km_min <= 0) fail(UM_ERR_INVALID_ARGUMENT, "km_min = ", r.km_min, " km is not > 0");
    if (r.km_max < r.km_min)
        fail(UM_ERR_INVALID_ARGUMENT, "km_max = ", r.km_max, " km is below km_min = ", r.km_min, " km");
    if (r.distance_km < 0)
        fail(UM_ERR_INVALID_ARGUMENT, "distance_km = ", r.distance_km, " km is negative");
    if (r.rate < 0) fail(UM_ERR_INVALID_ARGUMENT, "rate = ", r.rate, " km per km is negative");
}

Vec3 unit_point(const Vec3 &p, size_t line, size_t k) {
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(p[c]))
            fail(UM_ERR_NONFINITE_INPUT, "polyline ", line, ", point ", k, ": coordinate ", c,
                 " = ", p[c], " is not finite");
    if (p.x == 0 && p.y == 0 && p.z == 0)
        fail(UM_ERR_INVALID_ARGUMENT, "polyline ", line, ", point ", k, " is the zero vector");
    return geom::normalized(p);
}

// The edges of one polyline, repeated points skipped.
void add_edges(const std::vector<Vec3> &line, size_t index, std::vector<ArcTree::Arc> &arcs) {
    std::vector<Vec3> points;
    for (size_t k = 0; k < line.size(); ++k) {
        Vec3 u = unit_point(line[k], index, k);
        if (!points.empty()) {
            const Vec3 &prev = points.back();
            if (u.x == prev.x && u.y == prev.y && u.z == prev.z) continue;
            // Nearly opposite points: the minor arc between them is not defined.
            if (geom::dot(prev, u) < 0 && geom::norm(geom::cross(prev, u)) <= 1e-12)
                fail(UM_ERR_DEGENERATE_INPUT, "polyline ", index, ": points ", k - 1, " and ", k,
                     " are antipodal, so the arc between them is not defined");
        }
        points.push_back(u);
    }
    if (points.size() < 2)
        fail(UM_ERR_TOO_FEW_POINTS, "polyline ", index, " has ", points.size(),
             " distinct point(s); a feature line needs at least 2");
    for (size_t k = 1; k < points.size(); ++k) arcs.push_back({points[k - 1], points[k]});
}

class FeatureDistanceSpacing final : public Spacing {
public:
    FeatureDistanceSpacing(ArcTree tree, const DistanceRamp &ramp, double radius_km)
        : tree_(std::move(tree)), ramp_(ramp), radius_km_(radius_km) {}

    double at(const Where &w) const override {
        return at_distance(radius_km_ * nearest_feature_distance(tree_, w.unit()));
    }
    // h grows with the distance: its least over the cap is at the cap's
    // nearest possible distance to a feature.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double) const override {
        return at_distance(radius_km_ * std::max(0.0, nearest_feature_distance(tree_, centre) - radius));
    }
    std::string describe() const override {
        return concat("a distance-to-features spacing (", ramp_.km_min, " km within ",
                      ramp_.distance_km, " km of ", tree_.size(), " arcs, growing by ", ramp_.rate,
                      " km per km to ", ramp_.km_max, " km)");
    }

private:
    double at_distance(double d) const {
        if (d <= ramp_.distance_km) return ramp_.km_min;
        return std::min(ramp_.km_max, ramp_.km_min + ramp_.rate * (d - ramp_.distance_km));
    }

    ArcTree tree_;
    DistanceRamp ramp_;
    double radius_km_;
};

}  // namespace

DistanceRamp DistanceRamp::over_width(double km_min, double km_max, double distance_km,
                                      double width_km) {
    if (!std::isfinite(width_km) || width_km <= 0)
        fail(UM_ERR_INVALID_ARGUMENT, "width_km = ", width_km, " km is not a finite value > 0");
    return {km_min, km_max, distance_km, (km_max - km_min) / width_km};
}

SpacingPtr make_feature_distance(const std::vector<std::vector<Vec3>> &polylines,
                                 const DistanceRamp &ramp, double radius_km) {
    check_ramp(ramp);
    if (!std::isfinite(radius_km) || radius_km <= 0)
        fail(UM_ERR_INVALID_ARGUMENT, "radius_km = ", radius_km, " is not a finite value > 0");
    if (polylines.empty()) fail(UM_ERR_INVALID_ARGUMENT, "no feature polylines were given");
    std::vector<ArcTree::Arc> arcs;
    for (size_t i = 0; i < polylines.size(); ++i) add_edges(polylines[i], i, arcs);
    return std::make_shared<FeatureDistanceSpacing>(ArcTree(std::move(arcs)), ramp, radius_km);
}

}  // namespace um::hfun
