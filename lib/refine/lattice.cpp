#include "refine/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "tri/spatial_order.hpp"

namespace um::refine {

using geom::Vec3;

int64_t lattice_frequency(double spacing, int64_t max_points) {
    if (!(spacing > 0)) return 0;
    const double hexagons = 4 * M_PI / (0.8660254037844386 * spacing * spacing);
    const double n = std::round(std::sqrt(std::max(0.0, hexagons - 2) / 10));
    if (n > std::sqrt(static_cast<double>(max_points) / 10)) return 0;
    return std::max<int64_t>(1, static_cast<int64_t>(n));
}

namespace {

constexpr double kFlat = 0.01;            // relative spread of h that counts as one value
constexpr int64_t kSampleFrequency = 64;  // 40,962 samples for the coarsest spacing
constexpr int kProbes = 6;                // around each lattice point, at distance h0
constexpr double kGammaClearance = 1.0;   // in units of h0
constexpr const char *kStage = "refine lattice";  // progress (the spacing may be a slow callback)

// Over the sphere, or over the samples inside the domain (and the cap's
// centre when inside); 0 (no lattice) when none is.
double coarsest_spacing(Context &ctx, const SpacingRadians &h, const features::Domain *domain) {
    std::vector<Vec3> samples = geodesic_lattice(kSampleFrequency);
    if (domain) {
        samples.erase(std::remove_if(samples.begin(), samples.end(), [&](const Vec3 &p) { return !domain->contains(p); }),
                      samples.end());
        if (domain->contains(domain->cap_centre())) samples.push_back(domain->cap_centre());
        if (samples.empty()) return 0;  // a domain between the samples: no lattice
    }
    std::vector<double> value(samples.size());
    ctx.parallel_for_with_heartbeat(kStage, static_cast<int64_t>(samples.size()), 16, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) value[i] = h(samples[i]);
    });
    return *std::max_element(value.begin(), value.end());
}

// Whether h is h0 (within kFlat) at p and at kProbes points h0 around it.
bool flat_around(const SpacingRadians &h, const Vec3 &p, double h0) {
    auto flat = [&](const Vec3 &q) { return std::fabs(h(q) - h0) <= kFlat * h0; };
    if (!flat(p)) return false;
    const Vec3 axis = std::fabs(p.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
    const Vec3 e1 = geom::normalized(geom::cross(p, axis)), e2 = geom::cross(p, e1);
    for (int k = 0; k < kProbes; ++k) {
        const double angle = 2 * M_PI * k / kProbes;
        const Vec3 q = std::cos(h0) * p + std::sin(h0) * (std::cos(angle) * e1 + std::sin(angle) * e2);
        if (!flat(geom::normalized(q))) return false;
    }
    return true;
}

}  // namespace

std::vector<Vec3> background_lattice(Context &ctx, const SpacingRadians &h, const geom::ArcTree &gamma,
                                     const features::Domain *domain) {
    const double h0 = coarsest_spacing(ctx, h, domain);
    // (Relaxed, and placed, only around a domain that a cap smaller than a
    // hemisphere holds: the corners first, then the points around the cap.)
    const std::optional<Cap> cap =
        domain && domain->cap_radius() < M_PI / 2 ? std::optional<Cap>(Cap{domain->cap_centre(), domain->cap_radius()})
                                                  : std::nullopt;
    // No larger lattice than one triangulation build takes: the whole
    // sphere's (above that, 1.48 km uniform and finer, the refinement starts
    // from the icosahedron), or what a cap's placement holds; and a domain's
    // also within the memory cap (its finest level's points twice, the
    // relaxation's two buffers, a quarter more for the level before, and its
    // flags: a long thin domain's cap holds many times the domain's points).
    const int64_t most = int64_t{1} << tri::kBrioIndexBits;
    int64_t n = lattice_frequency(h0, cap ? std::numeric_limits<int64_t>::max() : most);
    if (cap) {
        const double held = lattice_region_points(n, *cap);
        const double bytes = held * (2.25 * sizeof(Vec3) + 2);
        const bool too_big = ctx.memory_cap() > 0 && bytes > static_cast<double>(ctx.memory_cap());
        if (held > static_cast<double>(most) || too_big) n = 0;
    }
    const int64_t frequency = std::max<int64_t>(n, 1);
    std::vector<Vec3> points;
    if (cap)
        points = relaxed_lattice_region(ctx, frequency, *cap).points;
    else
        points = relaxed_geodesic_lattice(ctx, frequency);
    std::vector<uint8_t> keep(points.size(), 0);
    ctx.parallel_for_with_heartbeat(kStage, static_cast<int64_t>(points.size()), 16, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            if (domain && i >= 12 && !domain->contains(points[i])) continue;  // not kept: the cover's
            const bool near_gamma = gamma.any_within(points[i], kGammaClearance * h0);
            const bool flat = n > 0 && !(i >= 12 && near_gamma) && (!domain || i >= 12 || domain->contains(points[i])) &&
                              flat_around(h, points[i], h0);
            // A corner stays where the lattice does not reach (the
            // icosahedron's start there), unless the lattice has a band
            // along Gamma there.
            keep[i] = i < 12 ? !(flat && near_gamma) : flat && !near_gamma;
        }
    });
    size_t kept = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (keep[i]) points[kept++] = points[i];
    points.resize(kept);
    return points;
}

}  // namespace um::refine
