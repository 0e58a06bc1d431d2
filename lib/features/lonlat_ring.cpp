#include "features/lonlat_ring.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace um::features
