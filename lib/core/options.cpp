#include "core/options.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/earth.hpp"
#include "core/error.hpp"
#include "geom/surface.hpp"
#include "optim/defaults.hpp"
#include "refine/bounds.hpp"

namespace um {

namespace {

constexpr double kBig = 1e300;

// One row per option: the only place an option is declared.
const OptionSpec kSpecs[] = {
    {UM_OPT_SPHERE_RADIUS, "sphere_radius", UM_OPTION_TYPE_REAL, 1e-3, 1e12, kEarthRadiusKm * 1000},
    {UM_OPT_SURFACE_FLATTENING, "surface_flattening", UM_OPTION_TYPE_REAL, 0.0, geom::Surface::kMaxFlattening, 0.0},
    {UM_OPT_REFINE_ALPHA, "refine_alpha", UM_OPTION_TYPE_REAL, 1.0, 4.0, refine::kDefaultAlpha},
    {UM_OPT_REFINE_BETA, "refine_beta", UM_OPTION_TYPE_REAL, 1e-3, 1.0, refine::kDefaultBeta},
    {UM_OPT_REFINE_RHO, "refine_rho", UM_OPTION_TYPE_REAL, 1.0, 10.0, refine::kDefaultRho},
    {UM_OPT_REFINE_TOPOLOGY_CHECK, "refine_topology_check", UM_OPTION_TYPE_INT, 0, 1, 0},
    {UM_OPT_REFINE_RELAX, "refine_relax", UM_OPTION_TYPE_INT, 0, 1, 1},
    {UM_OPT_REFINE_LATTICE, "refine_lattice", UM_OPTION_TYPE_INT, 0, 1, 1},
    {UM_OPT_SPACING_GRADIENT, "spacing_gradient", UM_OPTION_TYPE_REAL, 0.0, 10.0, refine::kDefaultSpacingGradient},
    {UM_OPT_OPTIM_OUTER_ITERATIONS, "optim_outer_iterations", UM_OPTION_TYPE_INT, 0, 1000, 20},
    {UM_OPT_OPTIM_INNER_ITERATIONS, "optim_inner_iterations", UM_OPTION_TYPE_INT, 0, 1000, 8},
    {UM_OPT_OPTIM_TOLERANCE, "optim_tolerance", UM_OPTION_TYPE_REAL, 0.0, 1.0, 1e-4},
    {UM_OPT_OPTIM_WEIGHTS, "optim_weights", UM_OPTION_TYPE_INT, 0, 1, 1},
    {UM_OPT_OPTIM_FIX_BOUNDARY, "optim_fix_boundary", UM_OPTION_TYPE_INT, 0, 1, 0},
    {UM_OPT_OPTIM_COLLAPSE_RATIO, "optim_collapse_ratio", UM_OPTION_TYPE_REAL, 0.0, 1.0, optim::kDefaultCollapseRatio},
    {UM_OPT_OPTIM_SPLIT_RATIO, "optim_split_ratio", UM_OPTION_TYPE_REAL, 1.0, kBig, optim::kDefaultSplitRatio},
    {UM_OPT_OPTIM_CORNER_VERTICES, "optim_corner_vertices", UM_OPTION_TYPE_INT, 0, 2, 1},
    {UM_OPT_OPTIM_CENTROIDAL_SWEEPS, "optim_centroidal_sweeps", UM_OPTION_TYPE_INT, 0, 1000, 8},
    {UM_OPT_OPTIM_RESEED_ROUNDS, "optim_reseed_rounds", UM_OPTION_TYPE_INT, 0, 1000, 7},
    {UM_OPT_OCEAN_FLOOR, "ocean_floor", UM_OPTION_TYPE_REAL, 0.0, 0.9, optim::kDefaultOceanFloor},
};
constexpr size_t kCount = sizeof kSpecs / sizeof kSpecs[0];

size_t index_of(um_option key) {
    for (size_t i = 0; i < kCount; ++i)
        if (kSpecs[i].key == key) return i;
    fail(UM_ERR_UNKNOWN_OPTION, "option key = ", key, " is not a known um_option");
}

void check_value(const OptionSpec &s, double value) {
    if (!std::isfinite(value) || value < s.min_value || value > s.max_value)
        fail(UM_ERR_INVALID_ARGUMENT, "option ", s.name, " = ", value, " is out of range [",
             s.min_value, ", ", s.max_value, "]");
}

void check_type(const OptionSpec &s, int32_t type) {
    if (s.type != type)
        fail(UM_ERR_OPTION_TYPE, "option ", s.name, " is ",
             s.type == UM_OPTION_TYPE_INT ? "an integer" : "a real",
             " option: use um_options_set_", s.type == UM_OPTION_TYPE_INT ? "int" : "double");
}

std::string trim(const std::string &s) {
    size_t b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

// Parses a whole string as a number in the C locale's syntax, whatever the
// host's locale is.
double parse_number(const std::string &name, const std::string &text, int32_t type) {
    const char *first = text.data(), *last = text.data() + text.size();
    if (type == UM_OPTION_TYPE_INT) {
        int64_t v = 0;
        auto r = std::from_chars(first, last, v);
        if (r.ec != std::errc() || r.ptr != last || text.empty())
            fail(UM_ERR_INVALID_ARGUMENT, "option ", name, " = '", text,
                 "' is not an integer");
        return static_cast<double>(v);
    }
    double v = 0;
    auto r = std::from_chars(first, last, v);
    if (r.ec != std::errc() || r.ptr != last || text.empty())
        fail(UM_ERR_INVALID_ARGUMENT, "option ", name, " = '", text, "' is not a number");
    return v;
}

}  // namespace

const OptionSpec &option_spec(um_option key) { return kSpecs[index_of(key)]; }

const OptionSpec *option_spec_by_name(const std::string &name) {
    for (const auto &s : kSpecs)
        if (name == s.name) return &s;
    return nullptr;
}

Options::Options() {
    values_.reserve(kCount);
    for (const auto &s : kSpecs) values_.push_back(s.default_value);
}

void Options::set_real(um_option key, double value) {
    size_t i = index_of(key);
    check_type(kSpecs[i], UM_OPTION_TYPE_REAL);
    check_value(kSpecs[i], value);
    values_[i] = value;
}

void Options::set_int(um_option key, int64_t value) {
    size_t i = index_of(key);
    check_type(kSpecs[i], UM_OPTION_TYPE_INT);
    check_value(kSpecs[i], static_cast<double>(value));
    values_[i] = static_cast<double>(value);
}

double Options::real(um_option key) const {
    size_t i = index_of(key);
    check_type(kSpecs[i], UM_OPTION_TYPE_REAL);
    return values_[i];
}

int64_t Options::integer(um_option key) const {
    size_t i = index_of(key);
    check_type(kSpecs[i], UM_OPTION_TYPE_INT);
    return static_cast<int64_t>(values_[i]);
}

void Options::set_from_string(const std::string &assignments) {
    std::vector<double> staged = values_;  // all-or-nothing
    size_t start = 0;
    while (start <= assignments.size()) {
        size_t end = assignments.find(';', start);
        if (end == std::string::npos) end = assignments.size();
        std::string item = trim(assignments.substr(start, end - start));
        start = end + 1;
        if (item.empty()) continue;
        size_t eq = item.find('=');
        if (eq == std::string::npos)
            fail(UM_ERR_INVALID_ARGUMENT, "option assignment '", item, "' has no '='");
        std::string name = trim(item.substr(0, eq)), text = trim(item.substr(eq + 1));
        const OptionSpec *s = option_spec_by_name(name);
        if (!s) fail(UM_ERR_UNKNOWN_OPTION, "option name '", name, "' is not known");
        double v = parse_number(name, text, s->type);
        check_value(*s, v);
        staged[index_of(s->key)] = v;
    }
    values_ = std::move(staged);
}

}  // namespace um
