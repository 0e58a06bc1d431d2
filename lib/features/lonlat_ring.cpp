#include "features/lonlat_ring.hpp"

#include <algorithm>
#include <cmath>

#include "core/text.hpp"

namespace um::features {

LonLatRing::LonLatRing(const double *lon, const double *lat, int64_t n) {
    std::vector<double> dlon(static_cast<size_t>(n));
    double turned = 0;
    int64_t at_pole = -1;  // the first edge from a pole point
    for (int64_t k = 0; k < n; ++k) {
        dlon[k] = std::remainder(lon[(k + 1) % n] - lon[k], 360.0);
        turned += dlon[k];
        if (at_pole < 0 && std::fabs(lat[k]) == 90) at_pole = k;
    }
    if (at_pole >= 0) dlon[at_pole] -= turned;
    lon_.resize(static_cast<size_t>(n) + 1), lat_.resize(static_cast<size_t>(n) + 1);
    lon_[0] = lon[0], lat_[0] = lat[0];
    for (int64_t k = 0; k < n; ++k) lon_[k + 1] = lon_[k] + dlon[k], lat_[k + 1] = lat[(k + 1) % n];
}

bool LonLatRing::round_a_pole() const { return std::fabs(lon_.back() - lon_.front()) > 180.0; }

double LonLatRing::twice_area() const {
    double sum = 0;
    for (size_t k = 0; k + 1 < lon_.size(); ++k) sum += lon_[k] * lat_[k + 1] - lon_[k + 1] * lat_[k];
    return sum;
}

bool LonLatRing::encloses(double lon, double lat) const {
    const double west = *std::min_element(lon_.begin(), lon_.end());
    const double x = west + std::fmod(std::fmod(lon - west, 360.0) + 360.0, 360.0);
    bool inside = false;
    for (size_t k = 0; k + 1 < lon_.size(); ++k) {
        const double x0 = lon_[k], y0 = lat_[k], x1 = lon_[k + 1], y1 = lat_[k + 1];
        if ((y0 > lat) != (y1 > lat) && x < x0 + (lat - y0) / (y1 - y0) * (x1 - x0)) inside = !inside;
    }
    return inside;
}

namespace {

// The same point of the sphere: a pole has no longitude.
bool same_place(double lon_a, double lat_a, double lon_b, double lat_b) {
    return lat_a == lat_b && (std::fabs(lat_a) == 90 || std::remainder(lon_a - lon_b, 360.0) == 0);
}

// Edges of at most this many degrees of longitude run the way they are drawn
// when read the shorter way round.
constexpr double kLongestStep = 90;

}  // namespace

bool runs_round_the_sphere(const double *lon, int64_t n) {
    for (int64_t k = 0; k < n; ++k)
        if (std::fabs(lon[(k + 1) % n] - lon[k]) >= 360) return true;
    return false;
}

namespace {

// The ring as drawn with its long edges cut (the shorter way round is then
// the way drawn), each point once: a pole's points, or the antimeridian's two
// longitudes, are one point. `pole`: the pole it reaches (0: none).
PolarCapRing cut_long_edges(const double *lon, const double *lat, int64_t n, double &pole) {
    PolarCapRing r;
    pole = 0;
    for (int64_t k = 0; k < n; ++k) {
        const int64_t j = (k + 1) % n;
        if (std::fabs(lat[k]) == 90) {
            if (pole != 0 && pole != lat[k]) return r.error = "reaches both poles (a mesh of the whole sphere takes no domain)", r;
            pole = lat[k];
        }
        auto add = [&](double x, double y) {
            if (!r.lon.empty() && same_place(r.lon.back(), r.lat.back(), x, y)) return;
            r.lon.push_back(x), r.lat.push_back(y), r.source.push_back(k);
        };
        add(lon[k], lat[k]);
        const double dlon = lon[j] - lon[k];
        const bool along_pole = std::fabs(lat[k]) == 90 && lat[j] == lat[k];
        const int64_t steps = along_pole ? 1 : static_cast<int64_t>(std::ceil(std::fabs(dlon) / kLongestStep));
        for (int64_t s = 1; s < steps; ++s) {
            const double t = static_cast<double>(s) / static_cast<double>(steps);
            add(lon[k] + t * dlon, lat[k] + t * (lat[j] - lat[k]));
        }
    }
    return r;
}

// Takes out the spikes out and back (to the pole, along the antimeridian): a
// point whose neighbours are one point goes, with one of them. In one pass
// (a stack), then round the ring's closing.
void drop_spikes(PolarCapRing &r) {
    PolarCapRing kept;
    auto same = [&](size_t a, size_t b) { return same_place(kept.lon[a], kept.lat[a], kept.lon[b], kept.lat[b]); };
    auto pop = [&] { kept.lon.pop_back(), kept.lat.pop_back(), kept.source.pop_back(); };
    for (size_t k = 0; k < r.lon.size(); ++k) {
        kept.lon.push_back(r.lon[k]), kept.lat.push_back(r.lat[k]), kept.source.push_back(r.source[k]);
        const size_t m = kept.lon.size();
        if (m >= 2 && same(m - 1, m - 2)) pop();
        else if (m >= 3 && same(m - 1, m - 3)) pop(), pop();
    }
    size_t first = 0;  // round the closing: kept[first..] is the ring
    while (kept.lon.size() - first >= 3) {
        const size_t last = kept.lon.size() - 1;
        if (same(last, first)) pop();                  // a point twice
        else if (same(last - 1, first)) pop(), pop();  // a spike at the last point
        else if (same(last, first + 1)) first += 2;    // a spike at the first
        else break;
    }
    r.lon.assign(kept.lon.begin() + static_cast<std::ptrdiff_t>(first), kept.lon.end());
    r.lat.assign(kept.lat.begin() + static_cast<std::ptrdiff_t>(first), kept.lat.end());
    r.source.assign(kept.source.begin() + static_cast<std::ptrdiff_t>(first), kept.source.end());
}

// Why the ring left is no cap round `pole` smaller than a hemisphere (empty:
// it is one): it must go once round, and the pole's side be the smaller, by
// the area in (longitude, sine of latitude) from the pole to each edge.
std::string cap_error(const PolarCapRing &r, double pole) {
    const size_t m = r.lon.size();
    double turned = 0, area = 0;
    for (size_t k = 0; k < m; ++k) {
        const size_t j = (k + 1) % m;
        const double dlon = std::remainder(r.lon[j] - r.lon[k], 360.0) * M_PI / 180;
        const double mean_sine = 0.5 * (std::sin(r.lat[k] * M_PI / 180) + std::sin(r.lat[j] * M_PI / 180));
        turned += dlon;
        area += dlon * (1 - (pole > 0 ? mean_sine : -mean_sine));
    }
    if (pole == 0 || m < 3 || std::fabs(std::fabs(turned) - 2 * M_PI) > 1e-6)
        return "does not run along one pole, to and from it along one meridian, and once round";
    if (std::fabs(area) >= 2 * M_PI)
        return concat("draws a cap round the ", pole > 0 ? "north" : "south",
                      " pole larger than a hemisphere (a ring round a pole holds the smaller side)");
    return {};
}

}  // namespace

PolarCapRing polar_cap_ring(const double *lon, const double *lat, int64_t n) {
    double pole = 0;
    PolarCapRing r = cut_long_edges(lon, lat, n, pole);
    if (!r.error.empty()) return r;
    drop_spikes(r);
    r.error = cap_error(r, pole);
    return r;
}

}  // namespace um::features
