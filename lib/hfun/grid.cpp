#include "hfun/grid.hpp"

#include <algorithm>
#include <functional>
#include <limits>
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
    minima_ = MinPyramid(cells_, n_lat(), n_lon());
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
double GridSpacing::value(const Span &x, const Span &y) const {
    auto row = [&](int64_t j) {
        return (1 - x.t) * km_at_node(j, x.i0) + x.t * km_at_node(j, x.i1);
    };
    return (1 - y.t) * row(y.i0) + y.t * row(y.i1);
}

double GridSpacing::at(const Where &where) const {
    return value(lon_span(where.lon_deg()), lat_span(where.lat_deg()));
}

double GridSpacing::smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const {
    const geom::CapBox box = geom::cap_box(centre, radius);
    // Beyond the first and last rows h is constant in latitude.
    const double lat_lo = std::clamp(box.lat_min, lat_.front(), lat_.back());
    const double lat_hi = std::clamp(box.lat_max, lat_.front(), lat_.back());
    LonRange lons[2];
    const int n_ranges = lon_ranges(box, lons);
    double least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n_ranges; ++k) least = std::min(least, smallest_on_nodes(lat_lo, lat_hi, lons[k]));
    if (least >= enough) return least;
    least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n_ranges; ++k) least = std::min(least, smallest_in_box(lat_lo, lat_hi, lons[k]));
    return least;
}

int GridSpacing::lon_ranges(const geom::CapBox &box, LonRange out[2]) const {
    const double first = lon_.front();
    if (box.all_lon) {
        out[0] = {first, first + 360.0};
        return 1;
    }
    double from = std::fmod(box.lon_min - first, 360.0);
    if (from < 0) from += 360.0;
    from += first;
    const double to = from + (box.lon_max - box.lon_min);
    if (to <= first + 360.0) {
        out[0] = {from, to};
        return 1;
    }
    out[0] = {from, first + 360.0}, out[1] = {first, to - 360.0};
    return 2;
}

// The nodes of the grid cells holding the box: where the box passes the last
// column (the wrap gap of a periodic grid, or beyond a regional grid, which
// takes its edge columns' values there), the two edge columns too.
double GridSpacing::smallest_on_nodes(double lat_lo, double lat_hi, const LonRange &lons) const {
    const int64_t row_lo = static_cast<int64_t>(lat_index_.cell_below(lat_, lat_lo));
    const int64_t row_hi = static_cast<int64_t>(lat_index_.cell_below(lat_, lat_hi)) + 1;
    const double last = lon_.back();
    double least = std::numeric_limits<double>::infinity();
    if (lons.from <= last) {
        const int64_t col_lo = static_cast<int64_t>(lon_index_.cell_below(lon_, lons.from));
        const int64_t col_hi = static_cast<int64_t>(lon_index_.cell_below(lon_, std::min(lons.to, last))) + 1;
        least = minima_.min_over(cells_, row_lo, row_hi, col_lo, col_hi);
    }
    if (lons.to > last) {
        least = std::min(least, minima_.min_over(cells_, row_lo, row_hi, 0, 0));
        least = std::min(least, minima_.min_over(cells_, row_lo, row_hi, n_lon() - 1, n_lon() - 1));
    }
    return least;
}

// The corners of the box's pieces: the box's own corners, the grid lines
// where they cross its sides, the nodes inside it.
double GridSpacing::smallest_in_box(double lat_lo, double lat_hi, const LonRange &lons) const {
    const Span west = lon_span(lons.from), east = lon_span(lons.to);
    const Span south = lat_span(lat_lo), north = lat_span(lat_hi);
    // The grid lines strictly inside the box.
    const int64_t row_lo = std::upper_bound(lat_.begin(), lat_.end(), lat_lo) - lat_.begin();
    const int64_t row_hi = (std::lower_bound(lat_.begin(), lat_.end(), lat_hi) - lat_.begin()) - 1;
    const int64_t col_lo = std::upper_bound(lon_.begin(), lon_.end(), lons.from) - lon_.begin();
    const int64_t col_hi = (std::lower_bound(lon_.begin(), lon_.end(), lons.to) - lon_.begin()) - 1;
    double least = std::min({value(west, south), value(west, north), value(east, south), value(east, north)});
    for (int64_t r = row_lo; r <= row_hi; ++r) {
        const Span row{r, r, 0.0};
        least = std::min({least, value(west, row), value(east, row)});
    }
    for (int64_t c = col_lo; c <= col_hi; ++c) {
        const Span column{c, c, 0.0};
        least = std::min({least, value(column, south), value(column, north)});
    }
    if (row_lo <= row_hi && col_lo <= col_hi)
        least = std::min(least, minima_.min_over(cells_, row_lo, row_hi, col_lo, col_hi));
    return least;
}

std::string GridSpacing::describe() const {
    return concat("a lon/lat grid spacing of ", n_lat(), " x ", n_lon(), " nodes",
                  periodic_ ? " (periodic in longitude)" : " (regional in longitude)");
}

SpacingPtr GridSpacing::gradient_limited(double g, double radius_km) const {
    if (!steeper_than(g, radius_km)) {
        if (SpacingPtr self = weak_from_this().lock()) return self;  // (a grid not owned by a pointer is copied)
    }
    auto limited = std::make_shared<GridSpacing>(*this);
    limited->limit_gradient_in_place(g, radius_km);
    limited->minima_ = MinPyramid(limited->cells_, n_lat(), n_lon());
    return limited;
}

// Node positions from per-row and per-column factors, as
// unit_from_lonlat_deg makes them (the poles exact: cos 90 = 0).
GridSpacing::NodePositions::NodePositions(const std::vector<double> &lon, const std::vector<double> &lat)
    : cos_lat(lat.size()), sin_lat(lat.size()), cos_lon(lon.size()), sin_lon(lon.size()) {
    for (size_t j = 0; j < lat.size(); ++j) geom::sincos_deg(lat[j], sin_lat[j], cos_lat[j]);
    for (size_t i = 0; i < lon.size(); ++i) geom::sincos_deg(lon[i], sin_lon[i], cos_lon[i]);
}

bool GridSpacing::steeper_than(double g, double radius_km) const {
    const NodePositions node(lon_, lat_);
    const int64_t nx = n_lon();
    // Every pair once: from its node of smaller index.
    for (int64_t k = 0; k < static_cast<int64_t>(cells_.size()); ++k) {
        const int64_t j = k / nx, i = k % nx;
        const geom::Vec3 p = node.at(j, i);
        bool steep = false;
        for_each_neighbour(j, i, [&](int64_t jj, int64_t ii) {
            if (steep || jj * nx + ii < k) return;
            steep = std::fabs(cells_[k] - km_at_node(jj, ii)) > g * radius_km * geom::norm(p - node.at(jj, ii));
        });
        if (steep) return true;
    }
    return false;
}

// The fixed point of h_i = min(h_i, h_j + g d_ij) over the 8 grid neighbours
// (across the longitude wrap when periodic; d_ij geodesic), i.e.
// h_i = min_j (h0_j + g * path length from j). It is computed in the
// label-setting (Dijkstra) order of that min-propagation: a node is final when
// it leaves the queue, so one pass reaches the fixed point, and the order
// (value, then index) makes the result the same on every run.
void GridSpacing::limit_gradient_in_place(double g, double radius_km) {
    const int64_t nx = n_lon();
    const NodePositions node(lon_, lat_);
    const double per_radian = g * radius_km;

    using Item = std::pair<double, int64_t>;
    std::vector<Item> initial(cells_.size());
    for (size_t k = 0; k < cells_.size(); ++k) initial[k] = {cells_[k], int64_t(k)};
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue(std::greater<Item>(),
                                                                           std::move(initial));
    while (!queue.empty()) {
        const double h = queue.top().first;  // (not a structured binding: the lambda below uses it)
        const int64_t k = queue.top().second;
        queue.pop();
        if (h > cells_[k]) continue;  // an older, larger entry of a node already lowered
        const int64_t j = k / nx, i = k % nx;
        const geom::Vec3 p = node.at(j, i);
        for_each_neighbour(j, i, [&](int64_t jj, int64_t ii) {
            const double candidate = h + per_radian * geom::arc_length(p, node.at(jj, ii));
            double &neighbour = cells_[jj * nx + ii];
            if (candidate < neighbour) {
                neighbour = candidate;
                queue.push({candidate, jj * nx + ii});
            }
        });
    }
}

}  // namespace um::hfun
