// The mesh spacing h(x): the target edge length in km at a point of the
// sphere (DESIGN.md section 4). Every kind is an immutable object behind
// SpacingPtr, so one spacing can be read from many worker threads at once
// and shared by handles; "changing" a spacing (clamp, gradient limit) makes a
// new object, which is what lets a failed call leave the old one untouched.
//
// Kinds: constant; lon/lat grid (grid.hpp); user callback; E3SM presets
// (presets.hpp); distance to features (feature_distance.hpp); clamp;
// minimum of several.
#pragma once

#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/context.hpp"
#include "core/earth.hpp"
#include "geom/sphere.hpp"

namespace um::hfun {

// Distances in km are measured on a sphere of this radius unless a caller
// says otherwise (core/earth.hpp).
using um::kEarthRadiusKm;

// A value h may take: finite and > 0. isfinite first, so that a NaN never
// reaches an ordered comparison (which raises FE_INVALID on hosts that trap).
inline bool valid_km(double h) { return std::isfinite(h) && h > 0; }

// A point of the sphere in the form the caller has (unit vector or lon/lat in
// degrees), the other form computed once when a kind needs it: grids and
// callbacks read lon/lat, feature distances the unit vector, and a
// composition hands one Where to all its parts. Not shared between threads.
class Where {
public:
    static Where from_unit(const geom::Vec3 &u);
    static Where from_lonlat(double lon_deg, double lat_deg);

    const geom::Vec3 &unit() const;
    double lon_deg() const;  // as given, or in (-180, 180] from a unit vector
    double lat_deg() const;

private:
    mutable geom::Vec3 unit_{};
    mutable double lon_ = 0, lat_ = 0;
    mutable bool has_unit_ = false, has_lonlat_ = false;
};

class Spacing;
using SpacingPtr = std::shared_ptr<const Spacing>;

class Spacing {
public:
    virtual ~Spacing() = default;

    // h in km. Thread-safe: may be called concurrently from worker threads.
    // Built-in kinds always give a valid value; a callback may not (see
    // evaluate(), which reports that on the host thread).
    double km_at(const geom::Vec3 &unit_point) const { return at(Where::from_unit(unit_point)); }
    double km_at_lonlat(double lon_deg, double lat_deg) const {
        return at(Where::from_lonlat(lon_deg, lat_deg));
    }
    virtual double at(const Where &where) const = 0;

    // A lower bound of h over the cap of arc radius `radius` (radians) about
    // a unit point, so that the refinement sees a spacing feature narrower
    // than its triangles (a fine spot between the points it samples). A kind
    // may stop tightening the bound once it is at least `enough` (km).
    // Kinds that vary over degrees (constant, presets) and callbacks (which
    // can only be sampled) give h at the centre: the default.
    virtual double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const;

    // What this spacing is, for messages: "a constant spacing of 30 km".
    virtual std::string describe() const = 0;

    // The same spacing with |grad h| <= g (km per km) on a sphere of
    // radius_km, or nullptr when the kind cannot be limited (only grids can,
    // also inside a clamp or a minimum of grids). A grid already within the
    // bound may be returned as it is.
    virtual SpacingPtr gradient_limited(double g, double radius_km) const;
};

// Factories. Each validates its arguments and throws um::Error naming the
// argument and the value: UM_ERR_NONFINITE_INPUT for NaN/Inf,
// UM_ERR_INVALID_ARGUMENT for h <= 0 or bounds out of order.
SpacingPtr make_constant(double km);

// A C function pointer (Fortran bind(c) and ctypes can pass one) returning h
// in km at lon/lat degrees. Called from worker threads concurrently.
using SpacingCallback = double (*)(void *user_data, double lon_deg, double lat_deg);
SpacingPtr make_callback(SpacingCallback fn, void *user_data);

// h = min(max(inner, km_min), km_max). An invalid inner value (a callback's
// NaN or h <= 0) passes through unchanged so that evaluate() still sees it.
SpacingPtr make_clamp(SpacingPtr inner, double km_min, double km_max);

// h = the minimum of the parts (e.g. a background and a coastal refinement).
SpacingPtr make_minimum(std::vector<SpacingPtr> parts);

// The gradient-limited spacing; UM_ERR_INVALID_ARGUMENT when g is not finite
// and > 0 or the kind cannot be limited (the message names the kind).
SpacingPtr limit_gradient(const Spacing &spacing, double g, double radius_km = kEarthRadiusKm);

// The lowest index at which a worker found an invalid h, kept lock-free from
// any thread. Worker threads must not throw out of a user's callback path, so
// they note the index and the host thread reports after the parallel loop;
// the lowest index makes that report the same for any number of threads.
class FirstInvalid {
public:
    void note(int64_t index) noexcept {
        int64_t seen = first_.load(std::memory_order_relaxed);
        while (index < seen &&
               !first_.compare_exchange_weak(seen, index, std::memory_order_relaxed)) {
        }
    }
    bool any() const noexcept { return index() != kNone; }
    int64_t index() const noexcept { return first_.load(std::memory_order_relaxed); }

private:
    static constexpr int64_t kNone = std::numeric_limits<int64_t>::max();
    std::atomic<int64_t> first_{kNone};
};

// Throws the error for an invalid value h found at `where` (point `index`):
// UM_ERR_NONFINITE_INPUT for NaN/Inf, UM_ERR_INVALID_ARGUMENT for h <= 0.
[[noreturn]] void report_invalid(const Spacing &spacing, const Where &where, int64_t index,
                                 double km);

// Points per task of evaluate(): a callback may be slow, a grid is fast.
constexpr int64_t kEvaluateGrain = 512;

// km_out[i] = h(point_at(i)) for i in [0, n), in parallel in the context's
// arena; point_at(i) returns a Where and must be thread-safe. Each value
// depends on its point only, so the result is the same for any thread count.
// Throws (report_invalid) on the host thread for the lowest i whose value is
// invalid; km_out is then fully written but holds that invalid value.
template <class PointAt>
void evaluate(Context &ctx, const Spacing &spacing, int64_t n, PointAt &&point_at,
              double *km_out) {
    FirstInvalid bad;
    ctx.parallel_for(n, kEvaluateGrain, [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
            double h = spacing.at(point_at(i));
            km_out[i] = h;
            if (!valid_km(h)) bad.note(i);
        }
    });
    if (bad.any()) report_invalid(spacing, point_at(bad.index()), bad.index(), km_out[bad.index()]);
}

// The same at unit vectors.
void evaluate_at_points(Context &ctx, const Spacing &spacing, const std::vector<geom::Vec3> &points,
                        std::vector<double> &km_out);

}  // namespace um::hfun
