// The centroidal pass (issue "Meshes that make the MPAS operators accurate"):
// Lloyd iterations that move every generator to the centroid of its power
// cell under the density rho = h^-4 (the spacing of a centroidal Voronoi
// tessellation, Du, Faber and Gunzburger 1999; Ringler et al. 2008 for MPAS).
// The MPAS operators' errors sit where cells are far from centroidal: the
// divergence and kinetic energy feel how far xEdge is from the middle of the
// dual edge, and TRSK how far the generators are from the cells' centroids.
//
// Unlike the shape sweeps, a Lloyd step is taken whenever it keeps the star
// valid and its triangles within bounds of shape and staggering: the bulk
// keeps converging instead of freezing once the worst star is good.
#include <algorithm>
#include <cmath>

#include "core/growth.hpp"
#include "core/text.hpp"

#include "geom/predicates.hpp"
#include "optim/centroidal.hpp"

namespace um::optim::detail {

namespace {

// Flips restore regularity after every kCentroidalFlipEvery Lloyd sweeps
// (alternately forward and backward over the colours). The sweeps' number
// is an option (optim_centroidal_sweeps): on the uniform 120 km mesh 8 take
// the centroid offset where 128 do (tools/bench/HISTORY.md); Lloyd's slow
// global drift after that changes no operator error.
constexpr int kCentroidalFlipEvery = 4;
// A generator this close to its centroid (in h) stays where it is, and is
// not looked at again until something around it moves: in the later sweeps
// most of the mesh is still (a thousandth of h is far below the centroid
// offsets that matter, a few thousandths of the cell's size).
constexpr double kCentroidalStill = 1e-3;
// A step may not take a triangle of its star below Q^T = kLloydQt or past
// the angle kLloydAngle (degrees), nor further past them than the star's
// worst triangle was: the mesh keeps the worst-case shape the issue asks
// for (Q^T >= 0.92, angles <= 82 degrees) with a margin, and the bulk is
// free to become centroidal. Bounds nearer the targets than the shape
// score's single floor: at 120 km, a floor of 0.95 on the shape score left
// the centroid offset at 0.0099 and TRSK at 2.6e-2, one of 0.94 at 0.0070
// and 1.85e-2.
constexpr double kLloydQt = 0.925;
constexpr double kLloydAngle = 81.0;
// Nor below this Q^P: the staggering the shape phase reached stays without
// weights, which would move xEdge off the primal midpoints (the curl).
constexpr double kLloydQp = 0.99;
// Nor take a spoke below kLloydShortest of the spacing, or shorter than it
// was if it was already: the model's time step goes by the shortest edge,
// and Lloyd's steps squeeze the spokes of the lattice's pentagons (uniform
// 30 km: the shortest edge 0.84 h before the pass, 0.81 h after it without
// this bound).
constexpr double kLloydShortest = 0.85;
constexpr int kCentroidalHalvings = 6;

// The integral of X over the spherical triangle's part that the edge (p, q)
// closes, as in the vector-area identity: for a spherical polygon, the
// integral of X over it is half the sum over its edges of the arc length
// times the unit normal of the edge's plane. The arc over its sine,
// asin(s) / s, by its series in s = sin(theta) below 0.1 (the next term is
// 5e-8 relative there), atan2 above: the Lloyd targets spend most of their time
// here otherwise.
Vec3 edge_moment(const Vec3 &p, const Vec3 &q) {
    const Vec3 n = geom::cross(p, q);
    const double sin2 = geom::dot(n, n);
    if (!(sin2 > 0)) return {};
    const double arc_over_sin = sin2 < 0.01 && geom::dot(p, q) > 0
                                    ? 1 + sin2 * (1.0 / 6 + sin2 * (3.0 / 40))
                                    : std::atan2(std::sqrt(sin2), geom::dot(p, q)) / std::sqrt(sin2);
    return (0.5 * arc_over_sin) * n;
}

// How far the star of v at `centre` is inside the Lloyd steps' bounds: the
// least over its triangles of min(Q^T - kLloydQt, cos(largest angle) -
// cos(kLloydAngle), Q^P - kLloydQp), negative when a triangle is past one.
// Stops as soon as it is below `floor` (the cheap shape terms first: Q^P
// costs an orthocentre).
double lloyd_margin(const Ring &ring, const Generator &centre, double floor = -kInfinity) {
    static const double cos_limit = std::cos(kLloydAngle * M_PI / 180);
    double margin = kInfinity;
    for (int k = 0; k < ring.m && margin >= floor; ++k) {
        const Vec3 &a = centre.x, &b = ring.at(k).x, &c = ring.after(k).x;
        margin = std::min({margin, area_length_ratio(a, b, c) - kLloydQt, largest_angle_cosine(a, b, c) - cos_limit});
    }
    for (int k = 0; k < ring.m && margin >= floor; ++k)
        margin = std::min(margin, primal_dual(centre, ring.at(k), ring.after(k)) - kLloydQp);
    return margin;
}

// Whether v at `to` keeps each spoke (the chord to ring vertex k) at least
// least[k] long.
bool keeps_spokes(const Ring &ring, const Vec3 &to, const double *least) {
    for (int k = 0; k < ring.m; ++k)
        if (geom::norm(to - ring.at(k).x) < least[k]) return false;
    return true;
}

}  // namespace

// The centroid of v's power cell (the polygon of its star's orthocentres),
// fanned from the generator, each fan triangle weighted by the density at
// its spoke: rho = (mean h of v and the spoke's far end)^-4. Exact on the
// sphere for a constant density (the spokes' moments cancel).
Vec3 Centroidal::centroid_target(const StarGraph &g, int32_t v, const Generator &c, const Ring &ring) const {
    const int32_t *link = g.link(v);
    const int m = ring.m;
    const Vec3 q = c.lifted();
    Vec3 ortho[Ring::kMax];
    for (int k = 0; k < m; ++k)
        ortho[k] = geom::normalized(geom::cross(ring.q[k] - q, ring.q[k + 1 == m ? 0 : k + 1] - q));
    // Fan triangle k: (x, ortho[k - 1], ortho[k]) around the spoke to link[k].
    Vec3 sum{};
    Vec3 spoke_prev = edge_moment(c.x, ortho[m - 1]);
    for (int k = 0; k < m; ++k) {
        const Vec3 spoke = edge_moment(c.x, ortho[k]);
        const Vec3 moment = spoke_prev + edge_moment(ortho[k == 0 ? m - 1 : k - 1], ortho[k]) - spoke;
        const double h = 0.5 * (static_cast<double>(s_.h_at[v]) + static_cast<double>(s_.h_at[link[k]]));
        const double h2 = h * h;
        sum = sum + (1.0 / (h2 * h2)) * moment;
        spoke_prev = spoke;
    }
    return geom::normalized(sum);
}

// A Lloyd step of v, halved until the star stays valid, keeps Gamma where
// it was and stays within the Lloyd bounds (lloyd_margin at least 0, or
// what it was). True when v moved by more than kCentroidalStill h.
bool Centroidal::update_centroidal(const StarGraph &g, int32_t v) {
    // Vertices on Gamma stay where the shape phase put them: they carry the
    // restricted edges, and a cell cut by a coastline is not meant to be
    // centroidal.
    if (g.degree(v) < 3 || s_.on_segment[v] >= 0) return false;
    if (s_.nothing_changed_since(g, v, still_at_[v])) return false;
    Ring ring;
    if (!s_.gather_ring(g, v, ring)) return false;
    const Generator here = s_.generator(v);
    const Vec3 target = centroid_target(g, v, here, ring);
    const double still = kCentroidalStill * static_cast<double>(s_.h_at[v]);
    if (!(geom::norm(target - here.x) > still)) {
        still_at_[v] = s_.clock;
        return false;
    }
    const double floor = std::min(0.0, lloyd_margin(ring, here));
    const bool guarded = !s_.near_gamma.empty() && s_.near_gamma[v];
    int crossings = -1;
    const double slack = s_.floor_slack(v, ring, g.link(v));
    // Each spoke's least length: kLloydShortest of its spacing, or what it
    // is if already shorter.
    double least_spoke[Ring::kMax];
    for (int k = 0; k < ring.m; ++k) {
        const double h = 0.5 * (static_cast<double>(s_.h_at[v]) + static_cast<double>(s_.h_at[g.link(v)[k]]));
        least_spoke[k] = std::min(kLloydShortest * h, geom::norm(here.x - ring.at(k).x));
    }
    double step = 1;
    for (int i = 0; i <= kCentroidalHalvings; ++i, step *= 0.5) {
        Generator moved = here;
        moved.x = geom::normalized((1 - step) * here.x + step * target);
        if (lloyd_margin(ring, moved, floor) < floor || !keeps_spokes(ring, moved.x, least_spoke)) continue;
        if (!star_is_valid(ring, moved) || !s_.move_keeps_floor(v, moved.x, slack, ring, g.link(v))) continue;
        if (guarded) {
            if (crossings < 0) crossings = s_.gamma_crossings(v, ring, g.link(v), here);
            if (s_.gamma_crossings(v, ring, g.link(v), moved) > crossings) continue;
        }
        s_.set_generator(v, moved);
        s_.h_at[v] = static_cast<float>(s_.h(moved.x));
        s_.changed_at[v] = s_.clock;
        return true;
    }
    still_at_[v] = s_.clock;  // no step fits: as still as one that need not move
    return false;
}

int64_t Centroidal::relax_to_centroids(std::unique_ptr<StarGraph> &graph) {
    int64_t total = 0;
    int32_t since = s_.clock;
    still_at_.assign(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    for (int i = 0; i < s_.options.centroidal_sweeps; ++i) {
        if (i % kCentroidalFlipEvery == 0) s_.flag_near_gamma();
        auto t0 = Clock::now();
        const int64_t moved =
            s_.sweep(*graph, i % 2 == 0, nullptr, [&](const StarGraph &g, int32_t v) { return update_centroidal(g, v); });
        s_.stats.seconds_moves += seconds_since(t0);
        total += moved;
        const bool last = moved == 0 || i + 1 == s_.options.centroidal_sweeps;
        if (i % kCentroidalFlipEvery == kCentroidalFlipEvery - 1 || last) {
            t0 = Clock::now();
            int64_t flips = s_.restore_regularity(since);
            s_.stats.flips += flips;
            if (flips > 0) s_.rebuild_graph(graph);
            ++s_.clock;
            since = s_.clock;
            s_.stats.seconds_topology += seconds_since(t0);
            s_.ctx.log(UM_LOG_DEBUG, concat("optimise: centroidal sweep ", i + 1, ": ", moved, " moved, ", flips, " flips"));
        }
        if (moved == 0) break;
    }
    release(still_at_);
    return total;
}

}  // namespace um::optim::detail
