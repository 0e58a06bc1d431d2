// Spacing on a rectilinear lon/lat grid: the cellWidth(lat, lon) convention
// of the MPAS mesh tools (cell widths in km, lon and lat in degrees, each
// axis strictly increasing but not necessarily uniform), read by bilinear
// interpolation in lon/lat.
//
// Longitude. The grid is periodic when it goes round the sphere: when the
// wrap gap lon[0] + 360 - lon[last] is no wider than its widest step. That
// covers -180..180 and 0..360 with a repeated last column (gap 0: the two
// columns are one meridian), cell-centred -179.5..179.5 (gap = one step), and
// any longitude convention, since a query longitude is first brought into
// [lon[0], lon[0] + 360). A regional grid (wider gap) takes the value of the
// nearer edge column outside its range.
// Latitude. Beyond the first/last row (near the poles when the grid stops
// short of them) the row is used: h is clamped, not extrapolated.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hfun/min_pyramid.hpp"
#include "hfun/spacing.hpp"

namespace um::hfun {

// The names of the three arrays in messages (C API arguments or the
// variables of a spacing file).
struct GridNames {
    const char *lon = "lon_deg";
    const char *lat = "lat_deg";
    const char *cells = "cell_width_km";
};

class GridSpacing final : public Spacing, public std::enable_shared_from_this<GridSpacing> {
public:
    // cells has lat.size() rows of lon.size() values (lon fastest). Throws
    // um::Error naming the array, index and value: UM_ERR_INVALID_ARGUMENT
    // for fewer than 2 values on an axis, a cell count that does not match,
    // coordinates not strictly increasing, cells <= 0;
    // UM_ERR_NONFINITE_INPUT for NaN/Inf; UM_ERR_COORDINATE_RANGE for
    // |lat| > 90 or longitudes spanning more than 360 degrees.
    GridSpacing(std::vector<double> lon_deg, std::vector<double> lat_deg,
                std::vector<double> cells_km, const GridNames &names = {});

    double at(const Where &where) const override;
    double km_at_node(int64_t lat_index, int64_t lon_index) const {
        return cells_[static_cast<size_t>(lat_index * n_lon() + lon_index)];
    }
    // The least value over the cap's lon/lat box (geom::cap_box): exact for
    // the box, since between grid lines h is bilinear in lon and lat and so
    // least at a corner of the box's pieces. First the nodes of the grid
    // cells the box touches (a looser bound), enough away from features.
    double smallest_in_cap(const geom::Vec3 &centre, double radius, double enough) const override;
    std::string describe() const override;
    SpacingPtr gradient_limited(double g, double radius_km) const override;

    int64_t n_lon() const { return static_cast<int64_t>(lon_.size()); }
    int64_t n_lat() const { return static_cast<int64_t>(lat_.size()); }
    const std::vector<double> &lon_deg() const { return lon_; }
    const std::vector<double> &lat_deg() const { return lat_; }
    const std::vector<double> &cells_km() const { return cells_; }
    bool periodic() const { return periodic_; }

private:
    // The cell of a strictly increasing axis holding x: the last i <= size - 2
    // with v[i] <= x (0 if none). Equal-width bins over the axis remember
    // the cell at their start, so a lookup takes a step or two from there
    // on any axis, uniform or not (a binary search only past kMaxSteps).
    class AxisIndex {
    public:
        AxisIndex() = default;
        explicit AxisIndex(const std::vector<double> &v);
        size_t cell_below(const std::vector<double> &v, double x) const;

    private:
        double origin_ = 0, bins_per_unit_ = 0;
        std::vector<int32_t> first_;  // per bin
    };
    // Interpolation along one axis: value = (1 - t) v[i0] + t v[i1].
    struct Span {
        int64_t i0, i1;
        double t;
    };
    Span lon_span(double lon_deg) const;
    Span lat_span(double lat_deg) const;
    double value(const Span &x, const Span &y) const;
    // A stretch of longitudes [from, to] in the grid's frame
    // [lon[0], lon[0] + 360], from <= to.
    struct LonRange {
        double from, to;
    };
    int lon_ranges(const geom::CapBox &box, LonRange out[2]) const;
    double smallest_on_nodes(double lat_lo, double lat_hi, const LonRange &lons) const;
    double smallest_in_box(double lat_lo, double lat_hi, const LonRange &lons) const;
    // Replaces the cells with the largest values <= them whose differences
    // between grid neighbours obey |h_i - h_j| <= g * distance(i, j).
    void limit_gradient_in_place(double g, double radius_km);
    // The unit vectors of the nodes, from per-row and per-column factors.
    struct NodePositions {
        NodePositions(const std::vector<double> &lon, const std::vector<double> &lat);
        geom::Vec3 at(int64_t j, int64_t i) const {
            return {cos_lat[j] * cos_lon[i], cos_lat[j] * sin_lon[i], sin_lat[j]};
        }
        std::vector<double> cos_lat, sin_lat, cos_lon, sin_lon;
    };
    // visit(jj, ii) for the 8 grid neighbours of node (j, i), across the
    // longitude wrap when periodic.
    template <class Visit>
    void for_each_neighbour(int64_t j, int64_t i, Visit visit) const {
        const int64_t nx = n_lon(), ny = n_lat();
        for (int64_t jj = j - 1; jj <= j + 1; ++jj) {
            if (jj < 0 || jj >= ny) continue;
            for (int64_t ii = i - 1; ii <= i + 1; ++ii) {
                if ((jj == j && ii == i) || ((ii < 0 || ii >= nx) && !periodic_)) continue;
                visit(jj, (ii + nx) % nx);
            }
        }
    }
    // Whether some grid neighbours differ by more than g times their chord
    // (below the arc: a grid that passes needs no limiting).
    bool steeper_than(double g, double radius_km) const;

    std::vector<double> lon_, lat_, cells_;
    AxisIndex lon_index_, lat_index_;
    MinPyramid minima_;  // of cells_
    bool periodic_ = false;
};

}  // namespace um::hfun
