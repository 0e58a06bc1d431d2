#include "hfun/grid.hpp"

#include <algorithm>
#include <functional>
#include <queue>
#include <utility>

#include "core/error.hpp"

namespace um::hfun {

namespace {

// Slack on the 360-degree longitude span: axes written with np.arange or in
// float32 end a few ulps past 180 or 360.
constexpr double kSpanSlackDeg = 1e-6;

void check_axis(const std::vector<double> &v, const char *name, bool latitude) {
    if (v.size() < 2)
        fail(UM_ERR_INVALID_ARGUMENT, name, " has ", v.size(),
             " value(s); a grid axis needs at least 2");
    for (size_t i = 0; i < v.size(); ++i) {
        if (!std::isfinite(v[i])) fail(UM_ERR_NONFINITE_INPUT, name, "[", i, "] = ", v[i], " is not finite");
        if (latitude && std::fabs(v[i]) > 90.0)
            fail(UM_ERR_COORDINATE_RANGE, name, "[", i, "] = ", v[i], " is outside [-90, 90]");
        if (i > 0 && !(v[i] > v[i - 1]))
            fail(UM_ERR_INVALID_ARGUMENT, name, "[", i, "] = ", v[i], " is not above ", name, "[",
                 i - 1, "] = ", v[i - 1], ": ", v[i] == v[i - 1] ? "duplicate" : "descending",
                 " coordinate (the axis must be strictly increasing)");
    }
}

void check_lon_span(const std::vector<double> &lon, const char *name) {
    double span = lon.back() - lon.front();
    if (span > 360.0 + kSpanSlackDeg)
        fail(UM_ERR_COORDINATE_RANGE, name, " spans ", span, " degrees (", name, "[0] = ",
             lon.front(), " to ", name, "[", lon.size() - 1, "] = ", lon.back(),
             "), more than 360");
}

void check_cells(const std::vector<double> &cells, size_t n_lon, size_t n_lat, const GridNames &names) {
    if (cells.size() != n_lon * n_lat)
        fail(UM_ERR_INVALID_ARGUMENT, names.cells, " has ", cells.size(), " values; a grid of ",
             n_lat, " latitudes x ", n_lon, " longitudes needs ", n_lat * n_lon);
    for (size_t k = 0; k < cells.size(); ++k) {
        if (valid_km(cells[k])) continue;
        fail(std::isfinite(cells[k]) ? UM_ERR_INVALID_ARGUMENT : UM_ERR_NONFINITE_INPUT,
             names.cells, "[", k, "] (", names.lat, " index ", k / n_lon, ", ", names.lon,
             " index ", k % n_lon, ") = ", cells[k],
             std::isfinite(cells[k]) ? " km is not > 0" : " is not finite");
    }
}

// The definition AxisIndex answers by, for any x but NaN (AxisIndex gives
// 0 there): a binary search.
size_t cell_below_by_search(const std::vector<double> &v, double x) {
    const size_t last = v.size() - 2;
    size_t i = static_cast<size_t>(std::upper_bound(v.begin(), v.end(), x) - v.begin());
    return std::min(i == 0 ? 0 : i - 1, last);
}

double clamp01(double t) { return std::min(std::max(t, 0.0), 1.0); }

}  // namespace

GridSpacing::AxisIndex::AxisIndex(const std::vector<double> &v) {
    // Bins no wider than the narrowest step where that fits in kMaxBins
    // (a quarter of a megabyte), else as many as that.
    constexpr double kMaxBins = 1 << 16;
    const double span = v.back() - v.front();
    double narrowest = span;
    for (size_t i = 1; i < v.size(); ++i) narrowest = std::min(narrowest, v[i] - v[i - 1]);
    const double bins = std::min(kMaxBins, std::max(double(v.size() - 1), std::ceil(span / narrowest)));
    origin_ = v.front();
    bins_per_unit_ = bins / span;
    first_.resize(static_cast<size_t>(bins));
    for (size_t b = 0; b < first_.size(); ++b)
        first_[b] = static_cast<int32_t>(cell_below_by_search(v, origin_ + double(b) / bins_per_unit_));
}

size_t GridSpacing::AxisIndex::cell_below(const std::vector<double> &v, double x) const {
    constexpr int kMaxSteps = 8;
    const size_t last = v.size() - 2;
    const double g = (x - origin_) * bins_per_unit_;
    const double top = double(first_.size() - 1);
    const size_t bin = !(g > 0) ? 0 : static_cast<size_t>(std::min(g, top));
    // From the bin's first cell (rounding may put x just outside the bin:
    // the steps go either way).
    size_t i = static_cast<size_t>(first_[bin]);
    for (int step = 0; step < kMaxSteps; ++step) {
        if (i < last && v[i + 1] <= x) ++i;
        else if (i > 0 && v[i] > x) --i;
        else return i;
    }
    return cell_below_by_search(v, x);
}

GridSpacing::GridSpacing(std::vector<double> lon_deg, std::vector<double> lat_deg,
                         std::vector<double> cells_km, const GridNames &names)
    : lon_(std::move(lon_deg)), lat_(std::move(lat_deg)), cells_(std::move(cells_km)) {
    check_axis(lon_, names.lon, false);
    check_lon_span(lon_, names.lon);
    check_axis(lat_, names.lat, true);
    check_cells(cells_, lon_.size(), lat_.size(), names);
    lon_index_ = AxisIndex(lon_), lat_index_ = AxisIndex(lat_);
    // Round the sphere when the wrap gap is no wider than the widest step.
    double widest = 0;
    for (size_t i = 1; i < lon_.size(); ++i) widest = std::max(widest, lon_[i] - lon_[i - 1]);
    double gap = lon_.front() + 360.0 - lon_.back();
    periodic_ = gap <= widest + kSpanSlackDeg;
}

GridSpacing::Span GridSpacing::lon_span(double lon_deg) const {
    const double first = lon_.front(), last = lon_.back();
    // Into [first, first + 360): any longitude convention reads any grid
    // (fmod returns r itself when r is in range already: skipped then).
    double r = lon_deg - first;
    if (!(r >= 0 && r < 360.0)) {
        r = std::fmod(r, 360.0);
        if (r < 0) r += 360.0;
    }
    const double x = first + r;
    const int64_t n = n_lon();
    if (x <= last) {
        size_t i = lon_index_.cell_below(lon_, x);
        return {int64_t(i), int64_t(i) + 1, clamp01((x - lon_[i]) / (lon_[i + 1] - lon_[i]))};
    }
    const double gap = first + 360.0 - last;  // > 0 here, since x < first + 360
    if (periodic_) return {n - 1, 0, clamp01((x - last) / gap)};
    // Regional grid: the nearer edge column.
    return (x - last <= first + 360.0 - x) ? Span{n - 1, n - 1, 0.0} : Span{0, 0, 0.0};
}

GridSpacing::Span GridSpacing::lat_span(double lat_deg) const {
    const int64_t n = n_lat();
    if (lat_deg <= lat_.front()) return {0, 0, 0.0};
    if (lat_deg >= lat_.back()) return {n - 1, n - 1, 0.0};
    size_t j = lat_index_.cell_below(lat_, lat_deg);
    return {int64_t(j), int64_t(j) + 1, clamp01((lat_deg - lat_[j]) / (lat_[j + 1] - lat_[j]))};
}

// (1 - t) a + t b rather than a + t (b - a): exact at both nodes (t = 0, 1).
double GridSpacing::at(const Where &where) const {
    const Span x = lon_span(where.lon_deg()), y = lat_span(where.lat_deg());
    auto row = [&](int64_t j) {
        return (1 - x.t) * km_at_node(j, x.i0) + x.t * km_at_node(j, x.i1);
    };
    return (1 - y.t) * row(y.i0) + y.t * row(y.i1);
}

std::string GridSpacing::describe() const {
    return concat("a lon/lat grid spacing of ", n_lat(), " x ", n_lon(), " nodes",
                  periodic_ ? " (periodic in longitude)" : " (regional in longitude)");
}

SpacingPtr GridSpacing::gradient_limited(double g, double radius_km) const {
    auto limited = std::make_shared<GridSpacing>(*this);
    limited->limit_gradient_in_place(g, radius_km);
    return limited;
}

// The fixed point of h_i = min(h_i, h_j + g d_ij) over the 8 grid neighbours
// (across the longitude wrap when periodic; d_ij geodesic), i.e.
// h_i = min_j (h0_j + g * path length from j). It is computed in the
// label-setting (Dijkstra) order of that min-propagation: a node is final when
// it leaves the queue, so one pass reaches the fixed point, and the order
// (value, then index) makes the result the same on every run.
void GridSpacing::limit_gradient_in_place(double g, double radius_km) {
    const int64_t nx = n_lon(), ny = n_lat();
    // Node positions from per-row and per-column factors, as
    // unit_from_lonlat_deg makes them (the poles exact: cos 90 = 0).
    std::vector<double> cos_lat(ny), sin_lat(ny), cos_lon(nx), sin_lon(nx);
    for (int64_t j = 0; j < ny; ++j) geom::sincos_deg(lat_[j], sin_lat[j], cos_lat[j]);
    for (int64_t i = 0; i < nx; ++i) geom::sincos_deg(lon_[i], sin_lon[i], cos_lon[i]);
    auto node = [&](int64_t j, int64_t i) {
        return geom::Vec3{cos_lat[j] * cos_lon[i], cos_lat[j] * sin_lon[i], sin_lat[j]};
    };
    const double per_radian = g * radius_km;

    using Item = std::pair<double, int64_t>;
    std::vector<Item> initial(cells_.size());
    for (size_t k = 0; k < cells_.size(); ++k) initial[k] = {cells_[k], int64_t(k)};
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue(std::greater<Item>(),
                                                                           std::move(initial));
    while (!queue.empty()) {
        const auto [h, k] = queue.top();
        queue.pop();
        if (h > cells_[k]) continue;  // an older, larger entry of a node already lowered
        const int64_t j = k / nx, i = k % nx;
        const geom::Vec3 p = node(j, i);
        for (int64_t dj = -1; dj <= 1; ++dj) {
            const int64_t jj = j + dj;
            if (jj < 0 || jj >= ny) continue;
            for (int64_t di = -1; di <= 1; ++di) {
                int64_t ii = i + di;
                if ((dj == 0 && di == 0) || ((ii < 0 || ii >= nx) && !periodic_)) continue;
                ii = (ii + nx) % nx;
                const double candidate = h + per_radian * geom::arc_length(p, node(jj, ii));
                double &neighbour = cells_[jj * nx + ii];
                if (candidate < neighbour) {
                    neighbour = candidate;
                    queue.push({candidate, jj * nx + ii});
                }
            }
        }
    }
}

}  // namespace um::hfun
