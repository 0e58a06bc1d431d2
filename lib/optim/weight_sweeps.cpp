#include "optim/weight_sweeps.hpp"

#include <algorithm>
#include <cmath>

namespace um::optim::detail {

namespace {

// Stars whose worst staggering score is at least this keep their weights
// (the centroidal pass keeps Q^P at 0.99 where the shape phase reached it,
// so in the bulk few stars are below). An ascent lifts the worst triangle
// only kWeightedMargin past the threshold, not to its star's mean as eq. 6
// would: a larger weight moves xEdge further off the primal midpoint.
constexpr double kWeightedBelow = 0.99;
constexpr double kWeightedMargin = 0.001;

}  // namespace

int64_t WeightSweeps::sweep(const StarGraph &g, bool forward) {
    std::vector<uint8_t> near = last_sweep_.next(s_, g);
    return s_.sweep(g, forward, nullptr, [&](const StarGraph &g, int32_t v) { return update_weight(g, v); },
                    near.empty() ? nullptr : &near);
}

// Eq. 4-6: ascend the Q^P of the worst adjacent triangle, starting from the
// first-order step that would lift it to the star's mean (here: just past
// the threshold).
bool WeightSweeps::update_weight(const StarGraph &g, int32_t v) {
    if (g.degree(v) < 3) return false;
    if (s_.nothing_changed_since(g, v, s_.weight_failed_at[v])) return false;
    Ring ring;
    if (!s_.gather_ring(g, v, ring)) return false;
    const int m = ring.m;
    const Generator here = s_.generator(v);
    // The worst triangle by the staggering score; the step from plain Q^P
    // (eq. 6 aims the worst Q^P at the star's mean Q^P).
    LocalQuality before;
    double sum = 0, sum_qp = 0, worst_qp = 0;
    int worst_k = 0;
    for (int k = 0; k < m; ++k) {
        const Generator &a = ring.at(k), &b = ring.after(k);
        double qp = 0;
        const double q = staggering_score(here, a, b, &qp);
        if (q < before.worst) before.worst = q, worst_k = k, worst_qp = qp;
        sum += q, sum_qp += qp;
    }
    before.mean = sum / m;
    // Weights move xEdge off the primal midpoint, which the curl feels, and
    // gain the divergence little: only stars whose worst triangle staggers
    // poorly get them; the bulk stays a Voronoi (power with equal weights)
    // diagram of centroidal generators.
    if (before.worst >= kWeightedBelow) {
        s_.weight_failed_at[v] = s_.clock;
        return false;
    }
    const double slope =
        primal_dual_weight_derivative(here, ring.at(worst_k), ring.after(worst_k));
    // A star with a triangle that does not hold its orthocentre (a negative
    // score) gets eq. 6's whole step: holding it matters more than the curl.
    const double target = before.worst < 0 ? sum_qp / m : std::min(sum_qp / m, kWeightedBelow + kWeightedMargin);
    const double gain = target - worst_qp;
    if (slope != 0 && gain > 0) {
        const double w = 2.0 * (1.0 - 1.0 / here.s);
        // A weight may not let Gamma into more cells off it around v (counted once, when first needed).
        const bool guarded = !s_.near_gamma.empty() && s_.near_gamma[v];
        int crossings = -1;
        double dw = gain / slope;  // eq. 6
        for (int i = 0; i <= kHalvings; ++i, dw *= 0.5) {
            Generator weighted = here;
            weighted.s = tri::lifted_scale(w + dw);
            if (!(weighted.s > 0) || !std::isfinite(weighted.s)) continue;
            const LocalQuality now = ring_quality<false>(ring, weighted, before.worst + s_.gain, worst_k);
            if (!(now.worst > before.worst + s_.gain)) continue;
            if (!star_is_valid(ring, weighted)) continue;
            if (crossings < 0) crossings = guarded ? s_.gamma_crossings(v, ring, g.link(v), here) : 0;
            if (guarded && s_.gamma_crossings(v, ring, g.link(v), weighted) > crossings) continue;
            s_.set_generator(v, weighted);
            s_.changed_at[v] = s_.clock;
            return true;
        }
    }
    s_.weight_failed_at[v] = s_.clock;
    return false;
}

}  // namespace um::optim::detail
