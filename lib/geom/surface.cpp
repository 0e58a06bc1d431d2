#include "geom/surface.hpp"

#include <cmath>

#include <GeographicLib/Geodesic.hpp>

#include "core/error.hpp"

namespace um::geom {

namespace {
constexpr double kDegree = M_PI / 180.0;
}

Surface Surface::ellipsoid(double a_m, double f) {
    if (!std::isfinite(a_m) || a_m <= 0)
        fail(UM_ERR_INVALID_ARGUMENT, "the ellipsoid's semi-major axis a = ", a_m, " m is not finite and > 0");
    if (!std::isfinite(f) || f < 0 || f > kMaxFlattening)
        fail(UM_ERR_INVALID_ARGUMENT, "the ellipsoid's flattening f = ", f, " is outside [0, ", kMaxFlattening,
             "] (0 is a sphere; WGS84 has 1/298.257223563)");
    return Surface(a_m, f);
}

Vec3 Surface::direction(double lon_deg, double lat_deg) const {
    if (is_sphere()) return unit_from_lonlat_deg(lon_deg, lat_deg);
    // The ellipsoid point is (N cos(lat) cos(lon), N cos(lat) sin(lon),
    // N (1 - f)^2 sin(lat)); its direction drops N.
    double s_lat, c_lat, s_lon, c_lon;
    sincos_deg(lat_deg, s_lat, c_lat);
    sincos_deg(lon_deg, s_lon, c_lon);
    const double e = (1 - f_) * (1 - f_);
    return normalized(Vec3{c_lat * c_lon, c_lat * s_lon, e * s_lat});
}

void Surface::geodetic(Vec3 u, double &lon_deg, double &lat_deg) const {
    lonlat_deg_from_unit(u, lon_deg, lat_deg);
    if (is_sphere()) return;
    lat_deg = std::atan2(u.z, (1 - f_) * (1 - f_) * std::hypot(u.x, u.y)) / kDegree;
}

Vec3 Surface::sphere_unit(Vec3 u) const {
    if (is_sphere()) return u;
    // The direction is (cos(lat) cos(lon), cos(lat) sin(lon), (1 - f)^2 sin(lat)) scaled.
    return normalized(Vec3{u.x, u.y, u.z / ((1 - f_) * (1 - f_))});
}

double Surface::radius_along(Vec3 u) const {
    if (is_sphere()) return a_;
    const double b = this->b();
    const double q = (u.x * u.x + u.y * u.y) / (a_ * a_) + u.z * u.z / (b * b);
    return 1 / std::sqrt(q);
}

double Surface::area_m2() const {
    if (is_sphere()) return 4 * M_PI * a_ * a_;
    return GeographicLib::Geodesic(a_, f_).EllipsoidArea();
}

double Surface::authalic_radius_m() const {
    if (is_sphere()) return a_;
    return std::sqrt(area_m2() / (4 * M_PI));
}

}  // namespace um::geom
