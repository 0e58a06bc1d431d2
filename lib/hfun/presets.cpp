#include "hfun/presets.hpp"

#include <algorithm>
#include <charconv>
#include <functional>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace um::hfun {

namespace {

constexpr double kDegree = M_PI / 180.0;

// h depends on latitude only (EC, RRS).
class LatitudeProfile final : public Spacing {
public:
    LatitudeProfile(std::function<double(double)> km_at_lat, std::string description)
        : km_at_lat_(std::move(km_at_lat)), description_(std::move(description)) {}
    double at(const Where &w) const override { return km_at_lat_(w.lat_deg()); }
    std::string describe() const override { return description_; }

private:
    std::function<double(double)> km_at_lat_;
    std::string description_;
};

constexpr const char *kForms =
    "use QU<km> (e.g. QU240), EC<km>to<km> (e.g. EC60to30) or RRS<km>to<km> (e.g. RRS18to6)";

char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

bool starts_with_nocase(std::string_view text, std::string_view prefix) {
    if (text.size() < prefix.size()) return false;
    for (size_t i = 0; i < prefix.size(); ++i)
        if (lower(text[i]) != prefix[i]) return false;
    return true;
}

// A whole decimal number > 0 (from_chars: independent of the locale).
bool parse_km(std::string_view text, double &km) {
    if (text.empty()) return false;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), km);
    return error == std::errc() && end == text.data() + text.size() && valid_km(km);
}

// "<a>to<b>" -> a, b.
bool parse_pair(std::string_view text, double &a, double &b) {
    for (size_t i = 0; i + 1 < text.size(); ++i)
        if (lower(text[i]) == 't' && lower(text[i + 1]) == 'o')
            return parse_km(text.substr(0, i), a) && parse_km(text.substr(i + 2), b);
    return false;
}

[[noreturn]] void unknown(std::string_view name) {
    fail(UM_ERR_INVALID_ARGUMENT, "preset name '", name, "' is not known: ", kForms,
         "; the numbers are km > 0");
}

SpacingPtr make_ec(double fine_km, double coarse_km) {
    EcParameters p;
    p.cell_width_eq = fine_km;
    p.cell_width_mid_lat = coarse_km;
    return std::make_shared<LatitudeProfile>(
        [p](double lat) { return ec_cell_width_km(lat, p); },
        concat("the preset EC", coarse_km, "to", fine_km, " (EC_CellWidthVsLat: ", fine_km,
               " km at the equator, ", coarse_km, " km at mid-latitudes, ", p.cell_width_pole,
               " km at the poles)"));
}

SpacingPtr make_rrs(double eq_km, double pole_km) {
    return std::make_shared<LatitudeProfile>(
        [eq_km, pole_km](double lat) { return rrs_cell_width_km(lat, eq_km, pole_km); },
        concat("the preset RRS", eq_km, "to", pole_km, " (RRS_CellWidthVsLat: ", eq_km,
               " km at the equator, ", pole_km, " km at the poles)"));
}

}  // namespace

// EC_CellWidthVsLat: the resolution is blended as a "density" (min width /
// width)^4 with a tanh step between equator and mid-latitudes below
// latTransition, and another between mid-latitudes and the pole above it;
// h = min width / density^(1/4).
double ec_cell_width_km(double lat_deg, const EcParameters &p) {
    const double finest = std::min({p.cell_width_eq, p.cell_width_mid_lat, p.cell_width_pole});
    auto density = [finest](double width) { return std::pow(finest / width, 4.0); };
    const double eq = density(p.cell_width_eq), mid = density(p.cell_width_mid_lat),
                 pole = density(p.cell_width_pole);
    const double abs_lat = std::fabs(lat_deg);
    double d;
    if (abs_lat < p.lat_transition)
        d = (eq - mid) * (1.0 + std::tanh((p.lat_pos_eq - abs_lat) / p.lat_width_eq)) / 2.0 + mid;
    else
        d = (mid - pole) * (1.0 + std::tanh((p.lat_pos_pole - abs_lat) / p.lat_width_pole)) / 2.0 +
            pole;
    return finest / std::pow(d, 0.25);
}

// RRS_CellWidthVsLat: density (1 - gamma) sin^4|lat| + gamma with
// gamma = (pole / eq)^4, so h = eq at the equator and pole at the poles,
// following the latitude dependence of the Rossby radius.
double rrs_cell_width_km(double lat_deg, double cell_width_eq, double cell_width_pole) {
    const double gamma = std::pow(cell_width_pole / cell_width_eq, 4.0);
    const double s = std::sin(std::fabs(lat_deg) * kDegree);
    const double density = (1.0 - gamma) * std::pow(s, 4.0) + gamma;
    return cell_width_pole / std::pow(density, 0.25);
}

SpacingPtr make_preset(std::string_view name) {
    double a = 0, b = 0;
    if (starts_with_nocase(name, "qu")) {
        if (!parse_km(name.substr(2), a)) unknown(name);
        return make_constant(a);
    }
    // EC: the finer number is the equator's; RRS: the finer is the pole's.
    if (starts_with_nocase(name, "ec")) {
        if (!parse_pair(name.substr(2), a, b)) unknown(name);
        return make_ec(std::min(a, b), std::max(a, b));
    }
    if (starts_with_nocase(name, "rrs")) {
        if (!parse_pair(name.substr(3), a, b)) unknown(name);
        return make_rrs(std::max(a, b), std::min(a, b));
    }
    unknown(name);
}

}  // namespace um::hfun
