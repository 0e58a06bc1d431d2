#include "optim/shape_sweeps.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "core/growth.hpp"
#include "optim/slide.hpp"

namespace um::optim::detail {

namespace {

// Targets closer than this (in units of h) are not searched towards.
constexpr double kShortestMove = 1e-4;

// Once an outer iteration of the shape phase moves fewer than kPolishAfter
// vertices per vertex, the stars whose worst shape score is within
// kPoorMargin of the mesh's worst (and below kPoorStar), and every star with
// a triangle scoring below kObtuseOffset (every obtuse one, and acute ones
// with Q^T below it), get serial rounds
// of sweeps with a compass search (polish_poor_stars): the two targets leave
// a few stars poor, the mesh's worst triangle among them, and beside Gamma
// many triangles just past a right angle (on the coastline case at 60 km
// this takes the obtuse share from 0.50 to 0.38 % and the triangles not
// holding their orthocentre from 13 to 4).
constexpr double kPoorStar = 0.95;
constexpr double kPoorMargin = 0.05;
constexpr double kPolishAfter = 0.5;
constexpr int kPolishRounds = 4;
constexpr int kCompassDirections = 16;
// (cos, sin) of direction d of the compass, computed once.
std::pair<double, double> compass_direction(int d) {
    static const auto table = [] {
        std::array<std::pair<double, double>, kCompassDirections> t{};
        for (int i = 0; i < kCompassDirections; ++i)
            t[i] = {std::cos(2 * M_PI * i / kCompassDirections), std::sin(2 * M_PI * i / kCompassDirections)};
        return t;
    }();
    return table[d];
}
constexpr int kCompassSteps = 5;  // h / 4, h / 8, ...: the compass step halved

}  // namespace

int64_t ShapeSweeps::sweep(const StarGraph &g, bool forward) {
    std::vector<uint8_t> near = last_sweep_.next(s_, g);
    return moves(g, forward, nullptr, near.empty() ? nullptr : &near);
}

int64_t ShapeSweeps::moves(const StarGraph &g, bool forward, const std::vector<uint8_t> *only,
                           std::vector<uint8_t> *near) {
    return s_.sweep(g, forward, only, [&](const StarGraph &g, int32_t v) { return update_position(g, v); }, near);
}

bool ShapeSweeps::wants_polish(int64_t changes) const {
    return s_.options.inner_iterations > 0 && changes < kPolishAfter * static_cast<double>(s_.tri.vertex_count());
}

int64_t ShapeSweeps::polish_poor_stars(const StarGraph &g) {
    std::vector<double> score(static_cast<size_t>(s_.tri.triangle_slots()), kInfinity);
    s_.ctx.parallel_for(s_.tri.triangle_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t)
            if (!s_.tri.is_free(static_cast<int32_t>(t)) && !s_.touches_cover(static_cast<int32_t>(t)))
                score[t] = shape_score(s_.tri.direction(s_.tri.vertex(t, 0)), s_.tri.direction(s_.tri.vertex(t, 1)),
                                       s_.tri.direction(s_.tri.vertex(t, 2)));
    });
    const double worst = *std::min_element(score.begin(), score.end());
    poor_star_ = std::max(kObtuseOffset, std::min(kPoorStar, worst + kPoorMargin));
    std::vector<uint8_t> poor(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    for (int32_t t = 0; t < s_.tri.triangle_slots(); ++t)
        if (score[t] < poor_star_)
            for (int k = 0; k < 3; ++k) {
                const int32_t v = s_.tri.vertex(t, k);
                poor[v] = 1;
                s_.move_failed_at[v] = 0;  // a new search: failures without it do not count
            }
    release(score);
    int64_t moved = 0;
    for (int round = 0; round < kPolishRounds; ++round) {
        const int64_t now = moves(g, round % 2 == 0, &poor);
        moved += now;
        if (now == 0) break;
    }
    poor_star_ = -kInfinity;
    return moved;
}

// Eq. 7-8: the mean of the star's orthocentres weighted by spacing-weighted
// areas A_j / hbar_j^2.
Vec3 ShapeSweeps::odt_target(const StarGraph &g, int32_t v, const Generator &c, const Ring &ring) const {
    const int32_t *link = g.link(v);
    const int m = ring.m;
    Vec3 sum{};
    for (int k = 0; k < m; ++k) {
        const Generator &a = ring.at(k), &b = ring.after(k);
        const double area = 0.5 * geom::norm(geom::cross(a.x - c.x, b.x - c.x));
        const double hbar = (s_.h_at[v] + s_.h_at[link[k]] + s_.h_at[link[k + 1 == m ? 0 : k + 1]]) / 3;
        const Vec3 ortho =
            geom::normalized(geom::cross(a.lifted() - c.lifted(), b.lifted() - c.lifted()));
        sum = sum + (area / (hbar * hbar)) * ortho;
    }
    return geom::normalized(sum);
}
// A move of one vertex under trial: its star as it is and what a move must
// beat (BETTER than `before`, Gamma entering no more cells off it).
struct ShapeSweeps::MoveTrial {
    // (Not an aggregate: the ring is left uninitialised, as gather_ring fills it.)
    MoveTrial(MeshState &s, const StarGraph &g, int32_t v, bool on_gamma) : s(s), g(g), v(v), on_gamma(on_gamma) {}
    MeshState &s;
    const StarGraph &g;
    int32_t v;
    bool on_gamma;
    Ring ring;
    Generator here;
    LocalQuality before;
    // A move may not let Gamma into more cells off it around v (the count
    // as it is taken once, when a trial first gets this far).
    bool guarded = false;
    int crossings = -1;

    // The floor's slack (MeshState::floor_slack), taken once (NaN: not yet).
    double slack = std::numeric_limits<double>::quiet_NaN();
    bool keeps_floor(const Generator &moved) {
        if (std::isnan(slack)) slack = s.floor_slack(v, ring, g.link(v));
        return s.move_keeps_floor(v, moved.x, slack, ring, g.link(v));
    }

    bool keeps_gamma(const Generator &moved) {
        if (!guarded) return true;
        if (crossings < 0) crossings = s.gamma_crossings(v, ring, g.link(v), here);
        return s.gamma_crossings(v, ring, g.link(v), moved) <= crossings;
    }
    void take(const Generator &moved, int64_t segment) {
        s.set_generator(v, moved);
        s.on_segment[v] = static_cast<int32_t>(segment);
        s.h_at[v] = static_cast<float>(s.h(moved.x));
        s.changed_at[v] = s.clock;
    }
    // Tries the move to x (slid onto Gamma when v is on it); true if taken.
    bool try_move(const Vec3 &x) {
        Generator moved = here;
        moved.x = x;
        int64_t segment = s.on_segment[v];
        if (on_gamma) {
            PointOnGamma p = slide_along(*s.gamma, segment, moved.x);
            moved.x = p.x, segment = p.segment;
        }
        // The cheaper test first: most trials fail on quality.
        if (!better(ring_quality<true>(ring, moved, before.worst, before.worst_k), before, s.gain)) return false;
        if (!star_is_valid(ring, moved) || !keeps_gamma(moved) || !keeps_floor(moved)) return false;
        take(moved, segment);
        return true;
    }
};

// Eq. 7: towards the ODT target with halving steps, taken at the first step
// that is BETTER. When none is (the worst triangle of the star is not the
// one the ODT step helps), the same search towards the centre of the link
// polygon, which evens the star's triangles out.
bool ShapeSweeps::update_position(const StarGraph &g, int32_t v) {
    const bool on_gamma = s_.on_segment[v] >= 0;
    if (g.degree(v) < 3 || (on_gamma && (s_.options.fix_boundary || !s_.gamma))) return false;
    if (s_.nothing_changed_since(g, v, s_.move_failed_at[v])) return false;
    MoveTrial trial(s_, g, v, on_gamma);
    if (!s_.gather_ring(g, v, trial.ring)) return false;
    trial.here = s_.generator(v);
    trial.before = ring_quality<true>(trial.ring, trial.here, -kInfinity);
    trial.guarded = !s_.near_gamma.empty() && s_.near_gamma[v];
    if (move_to_targets(trial)) return true;
    if (!on_gamma && trial.before.worst < poor_star_ && move_by_compass(trial)) return true;
    if (on_gamma && move_along_gamma(trial)) return true;
    s_.move_failed_at[v] = s_.clock;
    return false;
}

bool ShapeSweeps::move_to_targets(MoveTrial &trial) {
    const Ring &ring = trial.ring;
    const Generator &here = trial.here;
    Vec3 link_sum{};
    for (int k = 0; k < ring.m; ++k) link_sum = link_sum + ring.at(k).x;
    for (const Vec3 &target : {odt_target(trial.g, trial.v, here, ring), geom::normalized(link_sum)}) {
        // A move this short cannot change a score by the gain required.
        if (geom::norm(target - here.x) < kShortestMove * s_.h_at[trial.v]) continue;
        double step = 1;
        for (int m = 0; m <= kHalvings; ++m, step *= 0.5)
            if (trial.try_move(geom::normalized((1 - step) * here.x + step * target))) return true;
    }
    return false;
}

// A poor star the two targets cannot mend (its worst triangle sits
// between vertex pairs of degree 5 and 7, where both targets pull
// the wrong way): a compass search, the step
// halved until one of them is BETTER.
bool ShapeSweeps::move_by_compass(MoveTrial &trial) {
    const Generator &here = trial.here;
    const LocalQuality &before = trial.before;
    const Vec3 e1 = geom::normalized(geom::cross(here.x, std::fabs(here.x.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0}));
    const Vec3 e2 = geom::cross(here.x, e1);
    double step = 0.25 * s_.h_at[trial.v];
    for (int m = 0; m < kCompassSteps; ++m, step *= 0.5) {
        // The best of the directions at this step, not the first that is
        // BETTER: the worst triangle is what limits the mesh.
        Generator best{};
        double best_worst = -kInfinity;
        for (int d = 0; d < kCompassDirections; ++d) {
            const auto [c, s] = compass_direction(d);
            const Generator moved{geom::normalized(here.x + step * (c * e1 + s * e2)), here.s};
            const LocalQuality now =
                ring_quality<true>(trial.ring, moved, std::max(before.worst, best_worst), before.worst_k);
            if (better(now, before, s_.gain) && now.worst > best_worst && star_is_valid(trial.ring, moved) &&
                trial.keeps_gamma(moved) && trial.keeps_floor(moved))
                best = moved, best_worst = now.worst;
        }
        // Tested already (off Gamma nothing slides): taken as it is.
        if (best_worst > -kInfinity) {
            trial.take(best, s_.on_segment[trial.v]);
            return true;
        }
    }
    return false;
}

// Along the feature both ways: the two targets are projected onto it and
// may both point where the worst triangle gets worse.
bool ShapeSweeps::move_along_gamma(MoveTrial &trial) {
    const int64_t s = s_.on_segment[trial.v];
    const Vec3 tangent = geom::normalized(s_.gamma->segment_b(s) - s_.gamma->segment_a(s));
    double step = 0.25 * s_.h_at[trial.v];
    for (int m = 0; m < 3; ++m, step *= 0.5)
        for (double sign : {1.0, -1.0})
            if (trial.try_move(geom::normalized(trial.here.x + (sign * step) * tangent))) return true;
    return false;
}

}  // namespace um::optim::detail
