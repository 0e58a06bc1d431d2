#include "optim/optimise.hpp"

#include <algorithm>
#include <iterator>
#include <array>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "core/error.hpp"
#include "core/growth.hpp"
#include "core/text.hpp"
#include "geom/arc_tree.hpp"
#include "geom/predicates.hpp"
#include "optim/local_quality.hpp"
#include "optim/optimiser.hpp"
#include "optim/slide.hpp"
#include "optim/star_graph.hpp"
#include "refine/restricted.hpp"

namespace um::optim {

namespace detail {

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr int kHalvings = 5;  // line searches try steps 1, 1/2, ..., 1/32
// Edge orthocentres must stay this far inside their primal edge (as a share
// of it): the generator stays in its own power cell and no weight can hide
// a vertex (issue "Weighted primal-dual optimisation", item 3).
constexpr double kCrossingMargin = 0.05;

// An update must raise its star's worst (or mean) quality by this many
// tolerances: smaller gains cost a sweep each and change no summary.
constexpr double kGainOverTolerance = 10;

// Stars whose worst staggering score is at least this keep their weights:
// kWeightedBelow in the bulk, kWeightedBelowNearGamma within kNearGamma h of
// Gamma, where the features force triangles that need weights to hold their
// orthocentres (with 0.95 there too, the coastline case at 60 km kept one
// triangle off-centre; with 0.99 everywhere, curl errors at 120 km were 3x
// larger). An ascent lifts the worst triangle only kWeightedMargin past the
// threshold, not to its star's mean as eq. 6 would.
constexpr double kWeightedBelow = 0.95;
constexpr double kWeightedBelowNearGamma = 0.99;
constexpr double kWeightedMargin = 0.001;

// Targets closer than this (in units of h) are not searched towards.
constexpr double kShortestMove = 1e-4;

// Vertices this many h from Gamma get the crossing test of their updates
// (flag_near_gamma): a cell reaches about h from its generator, and a vertex
// moves less than h in an outer iteration.
constexpr double kNearGamma = 2.5;

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

// ----------------------------------------------------------- per-slot state

Optimiser::Optimiser(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
                     const features::Network *gamma, const refine::SpacingRadians &h, const OptimiseOptions &o)
    : ctx_(ctx), tri_(tri), on_segment_(on_segment), gamma_(gamma), h_(h), o_(o),
      gain_(kGainOverTolerance * o.tolerance), arcs_(features::segment_arc_tree(gamma)) {}

void Optimiser::grow_slots() {
    const size_t n = static_cast<size_t>(tri_.vertex_slots());
    if (h_at_.capacity() == 0) {  // the room the triangulation has (Triangulation::reserve_extra)
        const size_t room = std::max(n, tri_.vertex_capacity());
        h_at_.reserve(room), changed_at_.reserve(room), move_failed_at_.reserve(room);
        on_segment_.reserve(room);
    }
    reserve_for(h_at_, n), reserve_for(changed_at_, n);
    reserve_for(move_failed_at_, n), reserve_for(on_segment_, n);
    h_at_.resize(n, 0);
    changed_at_.resize(n, clock_);
    move_failed_at_.resize(n, 0);
    on_segment_.resize(n, -1);
    // Only from the weight phase on (the shape phase, where the topology
    // changes and memory peaks, has no use for it).
    if (weighing_) reserve_for(weight_failed_at_, n), weight_failed_at_.resize(n, 0);
}

void Optimiser::load_spacing() {
    grow_slots();
    ctx_.parallel_for(tri_.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v)
            if (tri_.in_triangulation(static_cast<int32_t>(v)))
                h_at_[v] = static_cast<float>(h_(tri_.direction(static_cast<int32_t>(v))));
    });
}

// ------------------------------------------------------------------ sweeps

int64_t Optimiser::sweep(const StarGraph &g, Sweep kind, bool forward,
                         const std::vector<uint8_t> *only) {
    const auto &colours = g.colours();
    const int n_colours = static_cast<int>(colours.size());
    int64_t accepted = 0;
    std::vector<int32_t> subset;
    for (int i = 0; i < n_colours; ++i) {
        const std::vector<int32_t> *list = &colours[forward ? i : n_colours - 1 - i];
        if (only) {
            subset.clear();
            for (int32_t v : *list)
                if ((*only)[v]) subset.push_back(v);
            list = &subset;
        }
        std::vector<uint8_t> took(list->size(), 0);
        ctx_.parallel_for(static_cast<int64_t>(list->size()), 256, [&](int64_t b, int64_t e) {
            for (int64_t k = b; k < e; ++k)
                took[k] = kind == Sweep::moves     ? update_position(g, (*list)[k])
                          : kind == Sweep::weights ? update_weight(g, (*list)[k])
                                                   : update_centroidal(g, (*list)[k]);
        });
        for (uint8_t t : took) accepted += t;
        ++clock_;  // the next colour sees this one's changes as newer than its failures
    }
    return accepted;
}

int64_t Optimiser::polish_poor_stars(const StarGraph &g) {
    std::vector<double> score(static_cast<size_t>(tri_.triangle_slots()), kInfinity);
    ctx_.parallel_for(tri_.triangle_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t)
            if (!tri_.is_free(static_cast<int32_t>(t)))
                score[t] = shape_score(tri_.direction(tri_.vertex(t, 0)), tri_.direction(tri_.vertex(t, 1)),
                                       tri_.direction(tri_.vertex(t, 2)));
    });
    const double worst = *std::min_element(score.begin(), score.end());
    poor_star_ = std::max(kObtuseOffset, std::min(kPoorStar, worst + kPoorMargin));
    std::vector<uint8_t> poor(static_cast<size_t>(tri_.vertex_slots()), 0);
    for (int32_t t = 0; t < tri_.triangle_slots(); ++t)
        if (score[t] < poor_star_)
            for (int k = 0; k < 3; ++k) {
                const int32_t v = tri_.vertex(t, k);
                poor[v] = 1;
                move_failed_at_[v] = 0;  // a new search: failures without it do not count
            }
    release(score);
    int64_t moved = 0;
    for (int round = 0; round < kPolishRounds; ++round) {
        const int64_t now = sweep(g, Sweep::moves, round % 2 == 0, &poor);
        moved += now;
        if (now == 0) break;
    }
    poor_star_ = -kInfinity;
    return moved;
}

bool Optimiser::nothing_changed_since(const StarGraph &g, int32_t v, int32_t tried) const {
    if (changed_at_[v] >= tried) return false;
    const int32_t *link = g.link(v);
    for (int k = 0; k < g.degree(v); ++k)
        if (changed_at_[link[k]] >= tried) return false;
    return true;
}

bool Optimiser::gather_ring(const StarGraph &g, int32_t v, Ring &ring) const {
    ring.m = g.degree(v);
    if (ring.m > Ring::kMax) return false;
    const int32_t *link = g.link(v);
    for (int k = 0; k < ring.m; ++k) ring.g[k] = generator(link[k]), ring.q[k] = tri_.lifted(link[k]);
    return true;
}

// (Without Gamma the flags stay empty: no update is guarded.)
void Optimiser::flag_near_gamma() {
    if (arcs_.size() == 0) return;
    near_gamma_.assign(static_cast<size_t>(tri_.vertex_slots()), 0);
    ctx_.parallel_for(tri_.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            if (!tri_.in_triangulation(static_cast<int32_t>(v))) continue;
            geom::Box box;
            box.add(tri_.direction(static_cast<int32_t>(v)));
            box.grow(kNearGamma * static_cast<double>(h_at_[v]));
            near_gamma_[v] = arcs_.any_overlaps(box);
        }
    });
}

bool Optimiser::crosses_gamma(const Vec3 &c0, const Vec3 &c1) const {
    return arcs_.query_until(geom::arc_box(c0, c1), [&](int32_t i) {
        Vec3 x;
        return geom::arc_intersection(c0, c1, arcs_.arc(i).a, arcs_.arc(i).b, x);
    });
}

// One tree query for the whole star (the box of the spokes' dual arcs),
// then each dual arc against the arcs it found: the per-spoke queries were
// 7 % of the Mid-Atlantic case's time. Counts what crosses_gamma per spoke
// would (the same arcs pass the same box test).
int Optimiser::gamma_crossings(int32_t v, const Ring &ring, const int32_t *link, const Generator &at) const {
    const Vec3 q = at.lifted();
    const bool v_on_gamma = on_segment_[v] >= 0;
    // The orthocentre of triangle k, (v, link k, link k+1): its facet's outward normal.
    Vec3 ortho[Ring::kMax];
    for (int k = 0; k < ring.m; ++k)
        ortho[k] = geom::normalized(geom::cross(ring.q[k] - q, ring.q[k + 1 == ring.m ? 0 : k + 1] - q));
    // Spoke (v, link k) is the dual arc between triangles k - 1 and k.
    geom::Box spoke_box[Ring::kMax], star_box;
    bool counted[Ring::kMax];
    for (int k = 0; k < ring.m; ++k) {
        counted[k] = !(v_on_gamma && on_segment_[link[k]] >= 0);
        if (!counted[k]) continue;
        spoke_box[k] = geom::arc_box(ortho[k == 0 ? ring.m - 1 : k - 1], ortho[k]);
        star_box.add(spoke_box[k]);
    }
    constexpr int kMaxNear = 64;
    int32_t near[kMaxNear];
    geom::Box near_box[kMaxNear];
    int n_near = 0;
    const bool overflow = arcs_.query_until(star_box, [&](int32_t i) {
        if (n_near == kMaxNear) return true;
        near_box[n_near] = geom::arc_box(arcs_.arc(i).a, arcs_.arc(i).b);
        near[n_near++] = i;
        return false;
    });
    int count = 0;
    for (int k = 0; k < ring.m; ++k) {
        if (!counted[k]) continue;
        const Vec3 &c0 = ortho[k == 0 ? ring.m - 1 : k - 1], &c1 = ortho[k];
        if (overflow) {  // Gamma is dense here: a query per spoke
            count += crosses_gamma(c0, c1);
            continue;
        }
        for (int j = 0; j < n_near; ++j) {
            Vec3 x;
            if (near_box[j].overlaps(spoke_box[k]) &&
                geom::arc_intersection(c0, c1, arcs_.arc(near[j]).a, arcs_.arc(near[j]).b, x)) {
                ++count;
                break;
            }
        }
    }
    return count;
}

bool star_is_valid(const Ring &ring, const Generator &at) {
    const Vec3 q = at.lifted();  // what set_generator stores
    for (int k = 0; k < ring.m; ++k) {
        const Vec3 &a = ring.q[k], &b = ring.q[k + 1 == ring.m ? 0 : k + 1];
        if (geom::orient_origin(q.data(), a.data(), b.data()) <= 0) return false;
        const double share = edge_crossing_share(at, ring.at(k));
        if (!(share > kCrossingMargin && share < 1 - kCrossingMargin)) return false;
    }
    return true;
}

// Eq. 7-8: the mean of the star's orthocentres weighted by spacing-weighted
// areas A_j / hbar_j^2.
Vec3 Optimiser::odt_target(const StarGraph &g, int32_t v, const Generator &c, const Ring &ring) const {
    const int32_t *link = g.link(v);
    const int m = ring.m;
    Vec3 sum{};
    for (int k = 0; k < m; ++k) {
        const Generator &a = ring.at(k), &b = ring.after(k);
        const double area = 0.5 * geom::norm(geom::cross(a.x - c.x, b.x - c.x));
        const double hbar = (h_at_[v] + h_at_[link[k]] + h_at_[link[k + 1 == m ? 0 : k + 1]]) / 3;
        const Vec3 ortho =
            geom::normalized(geom::cross(a.lifted() - c.lifted(), b.lifted() - c.lifted()));
        sum = sum + (area / (hbar * hbar)) * ortho;
    }
    return geom::normalized(sum);
}
// Eq. 7: towards the ODT target with halving steps, taken at the first step
// that is BETTER. When none is (the worst triangle of the star is not the
// one the ODT step helps), the same search towards the centre of the link
// polygon, which evens the star's triangles out.
bool Optimiser::update_position(const StarGraph &g, int32_t v) {
    const bool on_gamma = on_segment_[v] >= 0;
    if (g.degree(v) < 3 || (on_gamma && (o_.fix_boundary || !gamma_))) return false;
    if (nothing_changed_since(g, v, move_failed_at_[v])) return false;
    Ring ring;
    if (!gather_ring(g, v, ring)) return false;
    const Generator here = generator(v);
    const LocalQuality before = ring_quality<true>(ring, here, -kInfinity);
    // A move may not let Gamma into more cells off it around v (the count
    // as it is taken once, when a trial first gets this far).
    const bool guarded = !near_gamma_.empty() && near_gamma_[v];
    int crossings = -1;
    auto keeps_gamma = [&](const Generator &moved) {
        if (!guarded) return true;
        if (crossings < 0) crossings = gamma_crossings(v, ring, g.link(v), here);
        return gamma_crossings(v, ring, g.link(v), moved) <= crossings;
    };
    // Tries the move to x (slid onto Gamma when v is on it); true if taken.
    auto take = [&](const Generator &moved, int64_t segment) {
        set_generator(v, moved);
        on_segment_[v] = static_cast<int32_t>(segment);
        h_at_[v] = static_cast<float>(h_(moved.x));
        changed_at_[v] = clock_;
    };
    auto try_move = [&](const Vec3 &x) {
        Generator moved = here;
        moved.x = x;
        int64_t segment = on_segment_[v];
        if (on_gamma) {
            PointOnGamma p = slide_along(*gamma_, segment, moved.x);
            moved.x = p.x, segment = p.segment;
        }
        // The cheaper test first: most trials fail on quality.
        if (!better(ring_quality<true>(ring, moved, before.worst, before.worst_k), before, gain_)) return false;
        if (!star_is_valid(ring, moved) || !keeps_gamma(moved)) return false;
        take(moved, segment);
        return true;
    };
    Vec3 link_sum{};
    for (int k = 0; k < ring.m; ++k) link_sum = link_sum + ring.at(k).x;
    for (const Vec3 &target : {odt_target(g, v, here, ring), geom::normalized(link_sum)}) {
        // A move this short cannot change a score by the gain required.
        if (geom::norm(target - here.x) < kShortestMove * h_at_[v]) continue;
        double step = 1;
        for (int m = 0; m <= kHalvings; ++m, step *= 0.5)
            if (try_move(geom::normalized((1 - step) * here.x + step * target))) return true;
    }
    if (!on_gamma && before.worst < poor_star_) {
        // A poor star the two targets cannot mend (its worst triangle sits
        // between vertex pairs of degree 5 and 7, where both targets pull
        // the wrong way): a compass search, the step
        // halved until one of them is BETTER.
        const Vec3 e1 = geom::normalized(geom::cross(here.x, std::fabs(here.x.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0}));
        const Vec3 e2 = geom::cross(here.x, e1);
        double step = 0.25 * h_at_[v];
        for (int m = 0; m < kCompassSteps; ++m, step *= 0.5) {
            // The best of the directions at this step, not the first that is
            // BETTER: the worst triangle is what limits the mesh.
            Generator best{};
            double best_worst = -kInfinity;
            for (int d = 0; d < kCompassDirections; ++d) {
                const auto [c, s] = compass_direction(d);
                const Generator moved{geom::normalized(here.x + step * (c * e1 + s * e2)), here.s};
                const LocalQuality now = ring_quality<true>(ring, moved, std::max(before.worst, best_worst), before.worst_k);
                if (better(now, before, gain_) && now.worst > best_worst && star_is_valid(ring, moved) &&
                    keeps_gamma(moved))
                    best = moved, best_worst = now.worst;
            }
            // Tested already (off Gamma nothing slides): taken as it is.
            if (best_worst > -kInfinity) {
                take(best, on_segment_[v]);
                return true;
            }
        }
    }
    if (on_gamma) {
        // Along the feature both ways: the two targets above are projected
        // onto it and may both point where the worst triangle gets worse.
        const int64_t s = on_segment_[v];
        const Vec3 tangent = geom::normalized(gamma_->segment_b(s) - gamma_->segment_a(s));
        double step = 0.25 * h_at_[v];
        for (int m = 0; m < 3; ++m, step *= 0.5)
            for (double sign : {1.0, -1.0})
                if (try_move(geom::normalized(here.x + (sign * step) * tangent))) return true;
    }
    move_failed_at_[v] = clock_;
    return false;
}

// Eq. 4-6: ascend the Q^P of the worst adjacent triangle, starting from the
// first-order step that would lift it to the star's mean.
bool Optimiser::update_weight(const StarGraph &g, int32_t v) {
    if (g.degree(v) < 3) return false;
    if (nothing_changed_since(g, v, weight_failed_at_[v])) return false;
    Ring ring;
    if (!gather_ring(g, v, ring)) return false;
    const int m = ring.m;
    const Generator here = generator(v);
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
    const double weighted_below = !near_gamma_.empty() && near_gamma_[v] ? kWeightedBelowNearGamma : kWeightedBelow;
    if (before.worst >= weighted_below) {
        weight_failed_at_[v] = clock_;
        return false;
    }
    const double slope =
        primal_dual_weight_derivative(here, ring.at(worst_k), ring.after(worst_k));
    // Only as far as the threshold: a larger weight moves xEdge further.
    const double gain = std::min(sum_qp / m, weighted_below + kWeightedMargin) - worst_qp;
    if (slope != 0 && gain > 0) {
        const double w = 2.0 * (1.0 - 1.0 / here.s);
        // A weight may not let Gamma into more cells off it around v (counted once, when first needed).
        const bool guarded = !near_gamma_.empty() && near_gamma_[v];
        int crossings = -1;
        double dw = gain / slope;  // eq. 6
        for (int i = 0; i <= kHalvings; ++i, dw *= 0.5) {
            Generator weighted = here;
            weighted.s = tri::lifted_scale(w + dw);
            if (!(weighted.s > 0) || !std::isfinite(weighted.s)) continue;
            const LocalQuality now = ring_quality<false>(ring, weighted, before.worst + gain_, worst_k);
            if (!(now.worst > before.worst + gain_)) continue;
            if (!star_is_valid(ring, weighted)) continue;
            if (crossings < 0) crossings = guarded ? gamma_crossings(v, ring, g.link(v), here) : 0;
            if (guarded && gamma_crossings(v, ring, g.link(v), weighted) > crossings) continue;
            set_generator(v, weighted);
            changed_at_[v] = clock_;
            return true;
        }
    }
    weight_failed_at_[v] = clock_;
    return false;
}

// After the schedule, the triangles still not holding their orthocentre
// (a few, beside Gamma, where a weight that mends one unmends a neighbour:
// one vertex at a time cannot get out) get a joint search over the weights
// of their three vertices: every combination of kMendSteps steps either
// way of kMendStep times each vertex's mean squared spoke. The combination
// with the fewest such triangles around the three (then the best worst
// staggering score there) is taken when it has fewer than now, lowers no
// Q^P there below the mesh's least or kMendQpFloor, whichever is lower,
// keeps the three stars valid and every edge around them locally regular
// (so no flip follows that could undo it). If none does, the same with the
// far vertex of a neighbour as a fourth. If none does either, the three
// with their positions too, those on Gamma sliding kMendSlides steps of
// kMendSlide h either way along it (then kMendWideSlides steps, with fewer
// weights): most triangles left by then have all three vertices on Gamma,
// at bends and narrow features, where a weight cannot move the orthocentre
// far enough without unmending a neighbour. A move must also keep every
// Q^T around above the mesh's least and every angle below its largest.
// Serial, in slot order: deterministic.
constexpr int kMendSteps = 4;
constexpr int kMendPairSteps = 3;  // with a neighbour's far vertex: 7^4 combinations
constexpr double kMendStep = 0.1;
constexpr double kMendSlide = 0.05;  // of h, along Gamma
constexpr int kMendSlides = 4;
constexpr int kMendSlideWeightSteps = 3;
constexpr int kMendWideSlides = 8;  // the last try: 5 weights at 17 positions, 85^3 combinations
constexpr int kMendWideWeightSteps = 2;
constexpr int kObtuseSlides = 4;  // mend_obtuse_triangles: 9 positions a vertex
constexpr int kFlipSlides = 2;  // mend_by_flip, vertices on Gamma: 5 positions, 3 weights
constexpr int kFlipSlideWeightSteps = 1;
constexpr double kMendEdgeFloor = 0.5;  // of h: the edges moves may make
// The Q^P a mend may go down to when the mesh's least is above it: a
// triangle holding its orthocentre matters more to MPAS than Q^P between
// this and the least.
constexpr double kMendQpFloor = 0.9;

Optimiser::MendFloors Optimiser::mend_floors(bool qp_floor) {
    const Summary now = summarise(true);  // with the largest angle
    return {qp_floor ? std::min(now.qp_min, kMendQpFloor) : now.qp_min, now.qt_min, now.largest_angle_cosine};
}

Optimiser::Mended Optimiser::mend_off_centre_triangles(bool keep_obtuse) {
    const MendGoal moving = keep_obtuse ? MendGoal::off_centre_keeping_obtuse : MendGoal::off_centre;
    auto off_centre = [&](int32_t t) {
        return staggering_score(generator(tri_.vertex(t, 0)), generator(tri_.vertex(t, 1)),
                                generator(tri_.vertex(t, 2))) < 0;
    };
    const std::vector<int32_t> found = live_triangles_where(off_centre);
    Mended out;
    out.met = static_cast<int64_t>(found.size());
    if (found.empty()) return out;
    const MendFloors floors = out.floors = mend_floors(true);
    for (int32_t t : found) {
        ctx_.progress("optimise", 1.0);  // a cancel point: a triangle's search can take a second
        if (!off_centre(t)) continue;  // mended with an earlier one
        int32_t v[4] = {tri_.vertex(t, 0), tri_.vertex(t, 1), tri_.vertex(t, 2), -1};
        std::vector<Candidate> c[4];
        for (int i = 0; i < 3; ++i) c[i] = mend_candidates(v[i], kMendSteps, 0);
        bool done = mend_jointly(v, 3, c, floors, false);
        // Else with the far vertex of a neighbour too: a pair that a weight
        // common to both cannot mend.
        for (int i = 0; i < 3 && !done; ++i) c[i] = mend_candidates(v[i], kMendPairSteps, 0);
        for (int k = 0; k < 3 && !done; ++k) {
            const int32_t u = tri_.neighbour(t, k);
            v[3] = tri_.vertex(u, tri_.mirror_edge(t, k));  // opposite the shared edge
            c[3] = mend_candidates(v[3], kMendPairSteps, 0);
            done = mend_jointly(v, 4, c, floors, false);
        }
        // Else the three sliding along Gamma too, where they lie on it.
        bool slides = false;
        for (int i = 0; i < 3 && !done; ++i) {
            c[i] = mend_candidates(v[i], kMendSlideWeightSteps, kMendSlides);
            slides |= c[i].size() > 2 * kMendSlideWeightSteps + 1;
        }
        if (slides && mend_jointly(v, 3, c, floors, true, moving)) done = true, ++out.slid;
        // Else farther along Gamma, with fewer weights.
        for (int i = 0; i < 3 && slides && !done; ++i) c[i] = mend_candidates(v[i], kMendWideWeightSteps, kMendWideSlides);
        if (slides && !done && mend_jointly(v, 3, c, floors, true, moving)) done = true, ++out.slid;
        // Else a flip of one of its edges, the quad's weights searched so
        // that the new diagonal is regular.
        // (An undone flip leaves t's triangle in another slot: each edge is
        // found again by its opposite corner.)
        int32_t holder = t;
        for (int i = 0; i < 3 && !done; ++i)
            if (mend_by_flip(holder, tri_.local_index(holder, v[i]), floors, moving)) done = true, ++out.flipped;
        out.mended += done;
    }
    return out;
}

// After the off-centre mend, each obtuse triangle gets a joint search over
// the positions of its three vertices (kObtuseSlides steps of kMendSlide h
// either way along Gamma for those on it, half as many in four directions
// for the others; 9^3 combinations): the combination with the fewest obtuse
// triangles around them (then the least obtuse largest angle) is taken when
// it has fewer than now, adds no triangle not holding its orthocentre there,
// keeps Q^P, Q^T and the largest angle within the mesh's, makes no edge
// shorter than h/2 (or the shortest there), keeps the stars valid and every
// edge around them regular. Moving one vertex at a time cannot mend most of
// these (the sweeps' local optimum: at a vertex on Gamma between a short
// Gamma edge and a vertex off it, any single move makes a neighbour
// worse); on the coastline at 60 km this takes 1,333 obtuse triangles to
// 654. Serial, in slot order: deterministic.
Optimiser::Mended Optimiser::mend_obtuse_triangles() {
    auto obtuse = [&](int32_t t) {
        return largest_angle_cosine(tri_.direction(tri_.vertex(t, 0)), tri_.direction(tri_.vertex(t, 1)),
                                    tri_.direction(tri_.vertex(t, 2))) < 0;
    };
    const std::vector<int32_t> found = live_triangles_where(obtuse);
    Mended out;
    out.met = static_cast<int64_t>(found.size());
    if (found.empty()) return out;
    const MendFloors floors = out.floors = mend_floors(false);  // the off-centre mend may have changed them
    for (size_t i = 0; i < found.size(); ++i) {
        const int32_t t = found[i];
        if (i % 256 == 255) ctx_.progress("optimise", 1.0);  // a cancel point: up to a second here
        if (!obtuse(t)) continue;  // mended with an earlier one
        const int32_t v[3] = {tri_.vertex(t, 0), tri_.vertex(t, 1), tri_.vertex(t, 2)};
        std::vector<Candidate> c[3];
        for (int i = 0; i < 3; ++i) c[i] = mend_candidates(v[i], 0, kObtuseSlides, true);
        if (mend_jointly(v, 3, c, floors, true, MendGoal::obtuse)) {
            ++out.mended;
            continue;
        }
        // Else a flip of its longest edge, opposite the obtuse angle.
        int k = 0;
        double longest = -1;
        for (int j = 0; j < 3; ++j) {
            const Vec3 e = tri_.direction(v[(j + 1) % 3]) - tri_.direction(v[(j + 2) % 3]);
            if (geom::dot(e, e) > longest) longest = geom::dot(e, e), k = j;
        }
        int32_t holder = t;
        if (mend_by_flip(holder, k, floors, MendGoal::obtuse)) ++out.mended, ++out.flipped;
    }
    return out;
}

// A triangle whose orthocentre no weight or slide of its own vertices
// brings inside (most often three vertices on Gamma: a bend, or a narrow
// inlet) may be mended by flipping an edge: the edge (b, c) of t opposite
// corner k becomes (a, d), d the apex across, and the four weights are
// searched (7^4 combinations) for a configuration where the new diagonal is
// locally regular - so the triangulation stays the regular one of its
// generators - with fewer off-centre triangles around than before the flip,
// every floor of the mesh kept (Q^P, Q^T, largest angle, edges). An edge
// that runs along Gamma is never flipped: it is how the mesh follows the
// feature. If no combination does, the flip is undone.
bool Optimiser::mend_by_flip(int32_t &t, int k, const MendFloors &floors, MendGoal goal) {
    const int32_t u = tri_.neighbour(t, k);
    const int32_t a = tri_.vertex(t, k), b = tri_.vertex(t, (k + 1) % 3), c = tri_.vertex(t, (k + 2) % 3);
    const int32_t d = tri_.vertex(u, tri_.mirror_edge(t, k));
    if (runs_along_gamma(b, c, a, d)) return false;
    const int32_t quad[4] = {a, b, c, d};
    // The triangles around the quad (the same slots after the flip) and
    // how many of them are off-centre now.
    std::vector<int32_t> around;
    for (int32_t v : quad) tri_.for_each_in_star(v, [&](int32_t s) { around.push_back(s); });
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    const auto current = [&](int32_t u) { return generator(u); };
    Baseline before{0, 0, stars_gamma_crossings(quad, 4, current, false)};
    for (int32_t s : around) {
        const Generator x = generator(tri_.vertex(s, 0)), y = generator(tri_.vertex(s, 1)), z = generator(tri_.vertex(s, 2));
        before.off_centre += staggering_score(x, y, z) < 0;
        before.obtuse += largest_angle_cosine(x.x, y.x, z.x) < 0;
    }
    if (!tri_.flip(t, k)) return false;  // t = (a, b, d), u = (d, c, a)
    // The candidates: first the four weights alone (7^4 combinations), then
    // with the vertices on Gamma sliding too (15^3 x 7 at most). For an
    // obtuse triangle (there are hundreds) only the second, with the
    // sliding vertices' weights held (5^3 x 7): the weights alone mend none
    // of them, and with the sliding ones' weights too the search mends 2.5
    // times as many (coastlines at 60 km: 33 against 13) for 1 s more.
    const bool sliding = gamma_ && !o_.fix_boundary;
    std::vector<Candidate> candidates[4];
    bool mended = false;
    if (goal != MendGoal::obtuse) {
        for (int i = 0; i < 4; ++i) candidates[i] = mend_candidates(quad[i], kMendPairSteps, 0);
        mended = mend_jointly(quad, 4, candidates, floors, true, goal, &before);
    }
    const int slide_weights = goal == MendGoal::obtuse ? 0 : kFlipSlideWeightSteps;
    const int off_weights = kMendPairSteps;
    bool slides = false;
    for (int i = 0; i < 4 && !mended; ++i) {
        const bool on_gamma = sliding && on_segment_[quad[i]] >= 0;
        candidates[i] = on_gamma ? mend_candidates(quad[i], slide_weights, kFlipSlides)
                                 : mend_candidates(quad[i], off_weights, 0);
        slides |= on_gamma;
    }
    if (slides && !mended) mended = mend_jointly(quad, 4, candidates, floors, true, goal, &before);
    if (!mended) {
        tri_.flip(t, 1);  // the edge (d, a) of (a, b, d): back to (b, c), t now (b, d, c) and u (c, a, b)
        t = u;
        return false;
    }
    for (int32_t v : quad)
        for (int32_t s : tri_.star(v))
            for (int j = 0; j < 3; ++j) changed_at_[tri_.vertex(s, j)] = clock_;
    return true;
}

// Whether the edge (b, c), between the apexes a and d, follows Gamma: both
// ends on one part of it, that part passing within a quarter of the edge's
// length of its midpoint, and neither apex on the part between them (a
// chord across a bend or an inlet does not follow it).
bool Optimiser::runs_along_gamma(int32_t b, int32_t c, int32_t a, int32_t d) const {
    if (!gamma_) return false;
    const int32_t sb = on_segment_[b], sc = on_segment_[c];
    if (sb < 0 || sc < 0) return false;
    const int64_t part = gamma_->segment_part(sb);
    if (gamma_->segment_part(sc) != part) return false;
    const Vec3 xb = tri_.direction(b), xc = tri_.direction(c);
    const Vec3 mid = geom::normalized(xb + xc);
    if (geom::norm(slide_along(*gamma_, sb, mid).x - mid) >= 0.25 * geom::norm(xb - xc)) return false;
    // Between b and c along the part: on a closed one, the shorter way round.
    const double pb = position_along_part(b), pc = position_along_part(c);
    const double lo = std::min(pb, pc), hi = std::max(pb, pc);
    const features::Part &p = gamma_->part(part);
    const bool wraps = p.closed && hi - lo > 0.5 * double(p.n_segments);
    for (int32_t apex : {a, d}) {
        if (apex < 0 || on_segment_[apex] < 0 || gamma_->segment_part(on_segment_[apex]) != part) continue;
        const double pa = position_along_part(apex);
        if (wraps ? (pa < lo || pa > hi) : (pa > lo && pa < hi)) return false;
    }
    return true;
}

// Where vertex v (on Gamma) lies along its part: the index of its segment
// within the part plus the fraction of that segment's chord up to v.
double Optimiser::position_along_part(int32_t v) const {
    const int32_t s = on_segment_[v];
    const features::Part &p = gamma_->part(gamma_->segment_part(s));
    const Vec3 a = gamma_->segment_a(s), b = gamma_->segment_b(s), x = tri_.direction(v);
    const double length = geom::norm(b - a);
    const double along = length > 0 ? std::min(1.0, geom::norm(x - a) / length) : 0.0;
    return double(s - p.first_segment) + along;
}

// The candidates of a joint search for vertex v: its weight `steps` steps
// of kMendStep either way, at each of its positions: where it is, and when
// `slides` > 0, `slides` steps of kMendSlide h either way along Gamma (v on
// it) or, with off_gamma_moves, half as many in four directions (v off it).
std::vector<Optimiser::Candidate> Optimiser::mend_candidates(int32_t v, int steps, int slides, bool off_gamma_moves) const {
    const Generator here = generator(v);
    double spoke2 = 0;  // the weight steps' unit; only with steps
    if (steps > 0) {
        int spokes = 0;
        tri_.for_each_neighbour(v, [&](int32_t w) {
            const Vec3 d = here.x - tri_.direction(w);
            spoke2 += geom::dot(d, d), ++spokes;
        });
        spoke2 /= spokes;
    }
    const double weight = 2.0 * (1.0 - 1.0 / here.s);
    // The positions: here, then along Gamma either way (on it), or with
    // `off_gamma_moves`, off it in four directions at half as many steps
    // (as many positions).
    std::vector<Candidate> at{{here, on_segment_[v]}};
    const int64_t segment = on_segment_[v];
    const double step = kMendSlide * h_at_[v];
    if (slides > 0 && segment >= 0 && gamma_ && !o_.fix_boundary) {
        const Vec3 tangent = geom::normalized(gamma_->segment_b(segment) - gamma_->segment_a(segment));
        for (int k = 1; k <= slides; ++k)
            for (double sign : {1.0, -1.0}) {
                const PointOnGamma p = slide_along(*gamma_, segment, geom::normalized(here.x + (sign * k * step) * tangent));
                at.push_back({{p.x, here.s}, static_cast<int32_t>(p.segment)});
            }
    } else if (slides > 0 && segment < 0 && off_gamma_moves) {
        const Vec3 e1 = geom::normalized(geom::cross(here.x, std::fabs(here.x.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0}));
        const Vec3 e2 = geom::cross(here.x, e1);
        for (int k = 1; k <= std::max(1, slides / 2); ++k)
            for (const Vec3 &d : {e1, -1.0 * e1, e2, -1.0 * e2})
                at.push_back({{geom::normalized(here.x + (k * step) * d), here.s}, -1});
    }
    std::vector<Candidate> out;
    for (const Candidate &a : at)
        for (int j = -steps; j <= steps; ++j) {
            Candidate c = a;
            c.g.s = tri::lifted_scale(weight + kMendStep * j * spoke2);
            if (c.g.s > 0 && std::isfinite(c.g.s)) out.push_back(c);
        }
    return out;
}

// The search of mend_off_centre_triangles over every combination of the
// candidates of the n vertices v; applies the best and returns true when it
// has fewer off-centre triangles around.
bool Optimiser::mend_jointly(const int32_t *v, int n, const std::vector<Candidate> *candidates,
                             const MendFloors &floors, bool moves, MendGoal goal, const Baseline *baseline) {
    // The triangles around the vertices, each once.
    std::vector<int32_t> around;
    for (int i = 0; i < n; ++i) tri_.for_each_in_star(v[i], [&](int32_t u) { around.push_back(u); });
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    Generator trial[4];
    auto at = [&](int32_t u) {
        for (int i = 0; i < n; ++i)
            if (u == v[i]) return trial[i];
        return generator(u);
    };
    // Moves make no edge around shorter than h/2 (h at the first vertex: the
    // three are within an edge of each other) or, if one is already, than
    // the shortest there (squared chords).
    auto shortest_edge2 = [&](const Generator &a, const Generator &b, const Generator &c) {
        const Vec3 ab = a.x - b.x, bc = b.x - c.x, ca = c.x - a.x;
        return std::min({geom::dot(ab, ab), geom::dot(bc, bc), geom::dot(ca, ca)});
    };
    double edge2_floor = 0;
    if (moves) {
        edge2_floor = kInfinity;
        for (int32_t u : around)
            edge2_floor = std::min(edge2_floor, shortest_edge2(generator(tri_.vertex(u, 0)), generator(tri_.vertex(u, 1)),
                                                               generator(tri_.vertex(u, 2))));
        const double half_h = kMendEdgeFloor * h_at_[v[0]];
        edge2_floor = std::min(edge2_floor, half_h * half_h);
    }
    // The trial's score around: how many triangles the goal counts (then the
    // worst staggering score, or largest-angle cosine, there) and how many
    // are off-centre. Refused (a count above any) when a Q^P, Q^T, angle or
    // edge there would pass its floor, or when the count passes `limit` or
    // the off-centre ones `off_limit` (such a trial cannot be taken).
    struct Score {
        int count;
        double worst;
        int off_centre, obtuse;
    };
    constexpr int kAny = std::numeric_limits<int>::max();
    constexpr Score kRefused{kAny, -kInfinity, kAny, kAny};
    auto judge = [&](int limit, int off_limit, int obtuse_limit) {
        Score out{0, kInfinity, 0, 0};
        for (int32_t u : around) {
            double qp = 0;
            const Generator a = at(tri_.vertex(u, 0)), b = at(tri_.vertex(u, 1)), c = at(tri_.vertex(u, 2));
            const double q = staggering_score(a, b, c, &qp);
            const double cosine = moves ? largest_angle_cosine(a.x, b.x, c.x) : 1.0;
            const bool below = qp < floors.qp || (moves && (area_length_ratio(a.x, b.x, c.x) < floors.qt ||
                                                            cosine < floors.largest_angle_cosine ||
                                                            shortest_edge2(a, b, c) < edge2_floor));
            if (below || (out.off_centre += q < 0) > off_limit || (out.obtuse += cosine < 0) > obtuse_limit)
                return kRefused;
            const double score = goal == MendGoal::obtuse ? cosine : q;
            out.count += score < 0, out.worst = std::min(out.worst, score);
            if (out.count > limit) return kRefused;
        }
        return out;
    };
    auto regular_with_trial = [&] {  // stored for the exact tests, then put back
        Vec3 kept[4];
        for (int i = 0; i < n; ++i) kept[i] = tri_.lifted(v[i]), set_generator(v[i], trial[i]);
        bool regular = true;
        for (size_t j = 0; j < around.size() && regular; ++j)
            for (int k = 0; k < 3 && regular; ++k) regular = tri_.is_locally_regular(around[j], k);
        for (int i = 0; i < n; ++i) tri_.set_lifted(v[i], kept[i]);
        return regular;
    };
    for (int i = 0; i < n; ++i) {
        if (candidates[i].empty()) return false;
        trial[i] = generator(v[i]);
    }
    // Gamma's crossings now, or before the flip that left the mesh as it is
    // (its quad's stars are those v lists: the same spokes but the diagonal).
    const int crossings_now = baseline ? baseline->gamma_crossings : stars_gamma_crossings(v, n, at, false);
    if (crossings_now < 0) return false;
    Score now = judge(kAny, kAny, kAny);
    // (After a flip, its new triangles need not meet the floors yet.)
    if (baseline)
        now = {goal == MendGoal::obtuse ? baseline->obtuse : baseline->off_centre, -kInfinity, baseline->off_centre,
               baseline->obtuse};
    if (now.count == kRefused.count) return false;  // (the floors are the mesh's: not met here)
    // The obtuse goal adds no off-centre triangle, and the keeping one no obtuse one.
    const int off_limit = goal == MendGoal::obtuse ? now.off_centre : kAny;
    const int obtuse_limit = goal == MendGoal::off_centre_keeping_obtuse ? now.obtuse : kAny;
    // The counted ones first: the count passes the limit sooner.
    std::stable_partition(around.begin(), around.end(), [&](int32_t u) {
        const Generator a = generator(tri_.vertex(u, 0)), b = generator(tri_.vertex(u, 1)), c = generator(tri_.vertex(u, 2));
        return goal == MendGoal::obtuse ? largest_angle_cosine(a.x, b.x, c.x) < 0 : staggering_score(a, b, c) < 0;
    });
    Score best = now;
    int chosen[4] = {-1, -1, -1, -1};
    // Every combination, as the digits of a counter.
    int digit[4] = {0, 0, 0, 0};
    for (;;) {
        for (int i = 0; i < n; ++i) trial[i] = candidates[i][digit[i]].g;
        const Score q = judge(std::min(best.count, now.count - 1), off_limit, obtuse_limit);
        const bool better = q.count < best.count || (q.count == best.count && q.worst > best.worst + gain_);
        if (better && q.count < now.count) {
            const int crossings = stars_gamma_crossings(v, n, at, true);
            if (crossings >= 0 && crossings <= crossings_now && regular_with_trial()) {
                best = q;
                for (int j = 0; j < n; ++j) chosen[j] = digit[j];
            }
        }
        int i = 0;
        while (i < n && digit[i] + 1 == static_cast<int>(candidates[i].size())) digit[i++] = 0;
        if (i == n) break;
        ++digit[i];
    }
    if (best.count >= now.count) return false;
    for (int i = 0; i < n; ++i) {
        const Candidate &c = candidates[i][chosen[i]];
        set_generator(v[i], c.g), changed_at_[v[i]] = clock_;
        on_segment_[v[i]] = c.segment, h_at_[v[i]] = static_cast<float>(h_(c.g.x));
    }
    return true;
}

// ---------------------------------------------------------------- topology

// Flips from the triangles around every vertex that changed since `since`.
int64_t Optimiser::restore_regularity(int32_t since) {
    // The seeds: triangles with a vertex changed since `since` and an edge
    // that is not locally regular, found in parallel (the exact tests are
    // most of the work, and most triangles pass them); the flips are serial.
    // A triangle left out cannot need a flip before one next to it has
    // flipped, and the flip puts it back on the stack.
    std::vector<int32_t> seeds =
        ctx_.collect_in_order<int32_t>(tri_.triangle_slots(), 8192, [&](int64_t t, std::vector<int32_t> &out) {
            const int32_t ti = static_cast<int32_t>(t);
            if (tri_.is_free(ti)) return;
            bool changed = false, regular = true;
            for (int k = 0; k < 3; ++k) changed |= changed_at_[tri_.vertex(ti, k)] >= since;
            for (int k = 0; k < 3 && changed && regular; ++k) regular = tri_.is_locally_regular(ti, k);
            if (!regular) out.push_back(ti);
        });
    return tri_.restore_regularity(std::move(seeds));
}

// A fingerprint of each vertex's link that does not depend on where the
// cycle starts: the sum of a mix of every (neighbour, next neighbour) pair.
uint64_t link_fingerprint(const StarGraph &g, int32_t v) {
    const int32_t *link = g.link(v);
    const int m = g.degree(v);
    uint64_t sum = static_cast<uint64_t>(m);
    for (int k = 0; k < m; ++k) {
        const uint64_t here = static_cast<uint32_t>(link[k]);
        const uint64_t next = static_cast<uint32_t>(link[(k + 1) % m]);
        uint64_t z = (here << 32 | next) + 0x9e3779b97f4a7c15ull;  // splitmix64
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        sum += z ^ (z >> 31);
    }
    return sum;
}

// Kept in 32 bits (4 bytes per vertex at the moment the new graph is built,
// where memory peaks): a collision only leaves one changed link unmarked.
uint32_t folded(uint64_t x) { return static_cast<uint32_t>(x ^ (x >> 32)); }

std::vector<uint32_t> link_fingerprints(Context &ctx, const StarGraph &g) {
    std::vector<uint32_t> out(static_cast<size_t>(g.vertex_slots()), 0);
    ctx.parallel_for(g.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) out[v] = folded(link_fingerprint(g, static_cast<int32_t>(v)));
    });
    return out;
}

// A vertex whose link changed (by flips, collapses or splits) counts as
// changed, so that it and its neighbours are tried again.
void Optimiser::mark_changed_links(const std::vector<uint32_t> &before, const StarGraph &now) {
    // Compared as they are computed: a second list would be alive with the
    // new graph, where the optimisation's memory peaks.
    ctx_.parallel_for(now.vertex_slots(), 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v)
            if (v >= static_cast<int64_t>(before.size()) ||
                before[v] != folded(link_fingerprint(now, static_cast<int32_t>(v))))
                changed_at_[v] = clock_;
    });
}
// The edges whose length over the spacing is below `below` or above `above`.
std::vector<Optimiser::EdgeRatio> Optimiser::edge_ratios(double below, double above) const {
    return ctx_.collect_in_order<EdgeRatio>(tri_.triangle_slots(), 16384, [&](int64_t t, std::vector<EdgeRatio> &out) {
        const int32_t ti = static_cast<int32_t>(t);
        if (tri_.is_free(ti)) return;
        for (int k = 0; k < 3; ++k) {
            if (tri_.neighbour(ti, k) < ti) continue;  // each edge once
            const int32_t a = tri_.vertex(ti, (k + 1) % 3), b = tri_.vertex(ti, (k + 2) % 3);
            const double ratio = geom::norm(tri_.direction(a) - tri_.direction(b)) / (0.5 * (h_at_[a] + h_at_[b]));
            if (ratio < below || ratio > above) out.push_back({ratio, std::min(a, b), std::max(a, b)});
        }
    });
}

std::vector<int32_t> Optimiser::closed_stars(std::initializer_list<int32_t> vertices) const {
    std::vector<int32_t> around(vertices);
    for (int32_t v : vertices)
        tri_.for_each_in_star(v, [&](int32_t t) {
            for (int k = 0; k < 3; ++k) around.push_back(tri_.vertex(t, k));
        });
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    return around;
}

// (An edge's two ends are claimed at once, through closed_stars: claimed one
// after the other, the second would always find itself claimed, as a
// neighbour of the first.)
bool Optimiser::claim(const std::vector<int32_t> &vertices, std::vector<uint8_t> &locked) {
    for (int32_t u : vertices)
        if (locked[u]) return false;
    for (int32_t u : vertices) locked[u] = 1;
    return true;
}

// Section 6.4, collapse and refinement from one edge scan.
std::pair<int64_t, int64_t> Optimiser::collapse_and_split() {
    const double below = o_.collapse_ratio > 0 ? o_.collapse_ratio : -kInfinity;
    std::vector<EdgeRatio> edges = edge_ratios(below, o_.split_ratio);
    const int64_t collapsed = collapse_short_edges(edges);
    if (collapsed > 0) edges = edge_ratios(-kInfinity, o_.split_ratio);
    return {collapsed, split_long_edges(std::move(edges))};
}

// An edge much shorter than h, between two vertices off Gamma, loses its
// later slot, the other moving to the edge's midpoint. Shortest first, one
// change per neighbourhood per pass.
int64_t Optimiser::collapse_short_edges(std::vector<Optimiser::EdgeRatio> edges) {
    if (o_.collapse_ratio <= 0) return 0;
    edges.erase(std::remove_if(edges.begin(), edges.end(),
                               [&](const EdgeRatio &e) { return !(e.ratio < o_.collapse_ratio); }),
                edges.end());
    std::sort(edges.begin(), edges.end(), [](const EdgeRatio &x, const EdgeRatio &y) {
        return x.ratio != y.ratio ? x.ratio < y.ratio : (x.a != y.a ? x.a < y.a : x.b < y.b);
    });
    std::vector<uint8_t> locked(static_cast<size_t>(tri_.vertex_slots()), 0);
    int64_t done = 0;
    for (const EdgeRatio &e : edges) {
        if (!tri_.in_triangulation(e.a) || !tri_.in_triangulation(e.b)) continue;
        // Gamma keeps its vertices, and taking out the vertex off it next
        // to one leaves that one a spoke fewer on its side (Mid-Atlantic
        // case: 2 -> 4 triangles not holding their orthocentre).
        if (on_segment_[e.a] >= 0 || on_segment_[e.b] >= 0) continue;
        const int32_t gone = e.b, kept = e.a;  // e.a < e.b
        const Vec3 mid = geom::normalized(tri_.direction(e.a) + tri_.direction(e.b));
        if (leaves_long_edge(mid, static_cast<double>(h_at_[kept]), {gone, kept})) continue;
        if (!lock_neighbourhood({e.a, e.b}, locked)) continue;
        tri_.remove(gone);
        for (int32_t u : tri_.move(kept, mid)) changed_at_[u] = clock_;
        h_at_[kept] = static_cast<float>(h_(tri_.direction(kept)));
        changed_at_[kept] = clock_;
        ++done;
    }
    return done;
}

// Section 6.4: an edge much longer than h gets a vertex at its midpoint,
// with the mean of its ends' weights. Longest first, one change per
// neighbourhood per pass.
int64_t Optimiser::split_long_edges(std::vector<Optimiser::EdgeRatio> edges) {
    edges.erase(std::remove_if(edges.begin(), edges.end(),
                               [&](const EdgeRatio &e) { return !(e.ratio > o_.split_ratio); }),
                edges.end());
    std::sort(edges.begin(), edges.end(), [](const EdgeRatio &x, const EdgeRatio &y) {
        return x.ratio != y.ratio ? x.ratio > y.ratio : (x.a != y.a ? x.a < y.a : x.b < y.b);
    });
    std::vector<uint8_t> locked(static_cast<size_t>(tri_.vertex_slots()), 0);
    int64_t done = 0;
    for (const EdgeRatio &e : edges) {
        if (!tri_.in_triangulation(e.a) || !tri_.in_triangulation(e.b)) continue;
        // Gamma gets its vertices from the refinement (a midpoint off it
        // would sit on it, with a degree of 4, and be taken out again).
        if (on_segment_[e.a] >= 0 && on_segment_[e.b] >= 0) continue;
        if (leaves_short_edge(e.a, e.b)) continue;
        if (!lock_neighbourhood({e.a, e.b}, locked)) continue;
        done += insert_between(e.a, e.b) >= 0;
        locked.resize(static_cast<size_t>(tri_.vertex_slots()), 1);
    }
    return done;
}

// Whether a vertex at x (spacing h_x) joined to the links of `ends` would
// have an edge longer than split_ratio h: a collapse that makes one is not
// made, else the split that follows would undo it (and the next collapse
// redo it, each outer iteration, so that the schedule never settles).
bool Optimiser::leaves_long_edge(const Vec3 &x, double h_x, std::initializer_list<int32_t> ends) const {
    bool long_edge = false;
    for (int32_t v : ends)
        tri_.for_each_in_star(v, [&](int32_t t) {
            for (int k = 0; k < 3; ++k) {
                const int32_t u = tri_.vertex(t, k);
                if (std::find(ends.begin(), ends.end(), u) != ends.end()) continue;
                const double h = 0.5 * (h_x + static_cast<double>(h_at_[u]));
                long_edge = long_edge || geom::norm(x - tri_.direction(u)) > o_.split_ratio * h;
            }
        });
    return long_edge;
}

// Whether the midpoint of the edge (a, b) is nearer than collapse_ratio h
// to an apex of the edge: such a split is not made (the collapse that
// would follow undoes it).
bool Optimiser::leaves_short_edge(int32_t a, int32_t b) const {
    const Vec3 mid = geom::normalized(tri_.direction(a) + tri_.direction(b));
    const double h = 0.5 * (static_cast<double>(h_at_[a]) + static_cast<double>(h_at_[b]));
    bool short_edge = false;
    tri_.for_each_in_star(a, [&](int32_t t) {
        const int i = tri_.local_index(t, a);
        if (tri_.vertex(t, (i + 1) % 3) != b && tri_.vertex(t, (i + 2) % 3) != b) return;
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri_.vertex(t, k);
            if (u != a && u != b)
                short_edge = short_edge || geom::norm(mid - tri_.direction(u)) < o_.collapse_ratio * h;
        }
    });
    return short_edge;
}

// A new vertex at the midpoint of (a, b), with the mean of their weights;
// its slot, or -1 if it came out hidden (it is then removed again).
int32_t Optimiser::insert_between(int32_t a, int32_t b) {
    const Vec3 mid = geom::normalized(tri_.direction(a) + tri_.direction(b));
    const double w = 0.5 * (tri_.weight(a) + tri_.weight(b));
    std::vector<int32_t> buried;
    const int32_t v = tri_.insert(mid, w, next_id_++, &buried, tri_.star(a).front());
    for (int32_t u : buried) changed_at_[u] = clock_;
    grow_slots();
    if (!tri_.in_triangulation(v)) {
        tri_.remove(v);
        return -1;
    }
    h_at_[v] = static_cast<float>(h_(mid));
    changed_at_[v] = clock_;
    for (int32_t t : tri_.star(v))
        for (int k = 0; k < 3; ++k) changed_at_[tri_.vertex(t, k)] = clock_;
    return v;
}

// Vertices of degree 4 or less crowd their neighbours (their power cells are
// small) and those of degree 8 or more leave a gap: the first are removed,
// the second split in two. Vertices
// on Gamma are left alone. One change per neighbourhood per pass, in slot
// order.
int64_t Optimiser::improve_valence() {
    std::vector<uint8_t> locked(static_cast<size_t>(tri_.vertex_slots()), 0);
    int64_t done = 0;
    const int32_t n = tri_.vertex_slots();
    const std::vector<int32_t> degree = vertex_degrees(ctx_, tri_);
    for (int32_t v = 0; v < n; ++v) {
        if (!tri_.in_triangulation(v) || on_segment_[v] >= 0) continue;
        if (degree[v] > 4 && degree[v] < 8) continue;
        std::vector<int32_t> st = tri_.star(v);  // now: earlier changes may have altered it
        const int degree_now = static_cast<int>(st.size());
        if (degree_now > 4 && degree_now < 8) continue;
        if (!lock_neighbourhood({v}, locked)) continue;
        if (degree_now <= 4) {
            for (int32_t t : st)  // before removal frees these triangles
                for (int k = 0; k < 3; ++k) changed_at_[tri_.vertex(t, k)] = clock_;
            tri_.remove(v);
            ++done, ++stats_.collapses;
            continue;
        }
        split_vertex(v, st);
        ++done, ++stats_.splits;
        locked.resize(static_cast<size_t>(tri_.vertex_slots()), 1);
    }
    return done;
}

// Splits a vertex of high degree into two a quarter of its longest spoke
// either side of where it was, along that spoke: each of the two takes
// about half of the old link (degree ~ 6 for a link of 8).
void Optimiser::split_vertex(int32_t v, const std::vector<int32_t> &star) {
    Vec3 far{};
    double far_l = -1;
    for (int32_t t : star)
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri_.vertex(t, k);
            const double l = geom::norm(tri_.direction(u) - tri_.direction(v));
            if (u != v && l > far_l) far_l = l, far = tri_.direction(u);
        }
    const Vec3 x = tri_.direction(v), along = 0.25 * (far - x);
    const Vec3 back = geom::normalized(x - along), ahead = geom::normalized(x + along);
    for (int32_t u : tri_.move(v, back)) changed_at_[u] = clock_;
    if (tri_.in_triangulation(v)) h_at_[v] = static_cast<float>(h_(tri_.direction(v)));
    changed_at_[v] = clock_;
    const double w = tri_.weight(v);
    std::vector<int32_t> buried;
    const int32_t hint = tri_.in_triangulation(v) ? tri_.star(v).front() : tri_.locate(ahead);
    const int32_t added = tri_.insert(ahead, w, next_id_++, &buried, hint);
    for (int32_t u : buried) changed_at_[u] = clock_;
    grow_slots();
    if (!tri_.in_triangulation(added)) {
        tri_.remove(added);
        return;
    }
    h_at_[added] = static_cast<float>(h_(ahead));
    for (int32_t t : tri_.star(added))
        for (int k = 0; k < 3; ++k) changed_at_[tri_.vertex(t, k)] = clock_;
}

// A quad whose diagonal joins two vertices of degree 7 (or more) between two
// of degree 5 (or less) becomes four of degree 6 when flipped - the pairs
// of defects that smoothing alone leaves as the worst triangles of a
// relaxed mesh. The flip is kept only if a few ODT steps of the quad's
// vertices make the new diagonal regular (the triangulation stays the
// regular triangulation of its points); otherwise it is undone. Vertices
// on Gamma are left alone. Serial, in slot order, one flip per
// neighbourhood per pass.
int64_t Optimiser::flip_for_valence() {
    const int32_t n = tri_.vertex_slots();
    std::vector<int32_t> degree = vertex_degrees(ctx_, tri_);
    auto deviation = [&](int32_t v, int change) { return std::abs(degree[v] + change - 6); };
    std::vector<uint8_t> locked(static_cast<size_t>(n), 0);
    int64_t done = 0;
    for (int32_t t = 0; t < tri_.triangle_slots(); ++t) {
        if (tri_.is_free(t)) continue;
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri_.neighbour(t, k);
            if (u < t) continue;
            // The edge (b, c) of t, apex a; d the apex across it.
            const int32_t a = tri_.vertex(t, k), b = tri_.vertex(t, (k + 1) % 3), c = tri_.vertex(t, (k + 2) % 3);
            // The flip lowers the deviation by 2 or more only if three of a
            // (<= 5), b (>= 7), c (>= 7) and d (<= 5) gain: two of the first
            // three at least (d is read only then).
            if ((degree[a] <= 5) + (degree[b] >= 7) + (degree[c] >= 7) < 2) continue;
            int32_t d = -1;
            for (int j = 0; j < 3; ++j)
                if (tri_.vertex(u, j) != b && tri_.vertex(u, j) != c) d = tri_.vertex(u, j);
            const int32_t quad[4] = {a, b, c, d};
            bool free = true;
            for (int32_t v : quad) free &= on_segment_[v] < 0 && !locked[v];
            if (!free) continue;
            const int before = deviation(a, 0) + deviation(b, 0) + deviation(c, 0) + deviation(d, 0);
            const int after = deviation(a, 1) + deviation(b, -1) + deviation(c, -1) + deviation(d, 1);
            if (before - after < 2 || degree[b] <= 4 || degree[c] <= 4) continue;
            Vec3 saved[4];  // the stored points, bit for bit: the flip back must be regular again
            for (int i = 0; i < 4; ++i) saved[i] = tri_.lifted(quad[i]);
            if (!tri_.flip(t, k)) continue;  // t = (a, b, d), u = (d, c, a)
            if (!relax_into_regularity(quad)) {
                for (int i = 0; i < 4; ++i) tri_.set_lifted(quad[i], saved[i]);
                tri_.flip(t, 1);  // the edge (d, a) of (a, b, d): back to (b, c)
                continue;
            }
            ++degree[a], --degree[b], --degree[c], ++degree[d];
            for (int32_t v : quad) {
                h_at_[v] = static_cast<float>(h_(tri_.direction(v)));
                for (int32_t s : tri_.star(v))
                    for (int j = 0; j < 3; ++j) {
                        locked[tri_.vertex(s, j)] = 1;
                        changed_at_[tri_.vertex(s, j)] = clock_;
                    }
            }
            ++done;
            break;  // t changed
        }
    }
    stats_.flips += done;
    return done;
}

// The ODT point of v's star as the triangulation has it: the mean of its
// triangles' orthocentres weighted by their (chord) areas.
Vec3 Optimiser::star_odt_point(int32_t v) const {
    Vec3 sum{};
    tri_.for_each_in_star(v, [&](int32_t s) {
        const Vec3 a = tri_.direction(tri_.vertex(s, 0));
        const double area = 0.5 * geom::norm(geom::cross(tri_.direction(tri_.vertex(s, 1)) - a,
                                                         tri_.direction(tri_.vertex(s, 2)) - a));
        sum = sum + area * tri_.orthocentre(s);
    });
    return geom::normalized(sum);
}

// Moves the four vertices towards their ODT targets in the current topology
// (a few rounds) until every edge around them is locally regular and every
// triangle around them still faces outwards.
bool Optimiser::relax_into_regularity(const int32_t (&quad)[4]) {
    for (int round = 0; round < 4; ++round) {
        for (int32_t v : quad) set_generator(v, {star_odt_point(v), generator(v).s});
        bool good = true;
        for (int32_t v : quad)
            for (int32_t s : tri_.star(v)) {
                const Vec3 qa = tri_.lifted(tri_.vertex(s, 0)), qb = tri_.lifted(tri_.vertex(s, 1)),
                           qc = tri_.lifted(tri_.vertex(s, 2));
                good &= geom::orient_origin(qa.data(), qb.data(), qc.data()) > 0;
                for (int j = 0; j < 3 && good; ++j) good &= tri_.is_locally_regular(s, j);
            }
        if (good) return true;
    }
    return false;
}

// ---------------------------------------------------------------- stopping

// Min and mean of Q^T and Q^P over the live triangles: blocks of a fixed
// size reduced in parallel, then combined in block order, so the sums are
// the same for any thread count.
Optimiser::Summary Optimiser::summarise(bool with_largest_angle) const {
    constexpr int64_t kBlock = 8192;
    const int32_t n = tri_.triangle_slots();
    const int64_t n_blocks = (n + kBlock - 1) / kBlock;
    struct Partial {
        double qt_min = 2, qt_sum = 0, qp_min = 2, qp_sum = 0, largest_angle_cosine = 1;
        int64_t live = 0;
    };
    std::vector<Partial> part(static_cast<size_t>(n_blocks));
    ctx_.parallel_for(n_blocks, 1, [&](int64_t b, int64_t e) {
        for (int64_t blk = b; blk < e; ++blk) {
            Partial &p = part[blk];
            for (int64_t t = blk * kBlock; t < std::min<int64_t>(n, (blk + 1) * kBlock); ++t) {
                const int32_t ti = static_cast<int32_t>(t);
                if (tri_.is_free(ti)) continue;
                const Generator a = generator(tri_.vertex(ti, 0)), b = generator(tri_.vertex(ti, 1)),
                                c = generator(tri_.vertex(ti, 2));
                const TriangleCost cost = triangle_cost(a, b, c);
                if (with_largest_angle)
                    p.largest_angle_cosine = std::min(p.largest_angle_cosine, largest_angle_cosine(a.x, b.x, c.x));
                p.qt_min = std::min(p.qt_min, cost.area_length), p.qt_sum += cost.area_length;
                p.qp_min = std::min(p.qp_min, cost.primal_dual), p.qp_sum += cost.primal_dual;
                ++p.live;
            }
        }
    });
    Partial all;
    for (const Partial &p : part) {
        all.qt_min = std::min(all.qt_min, p.qt_min), all.qt_sum += p.qt_sum;
        all.qp_min = std::min(all.qp_min, p.qp_min), all.qp_sum += p.qp_sum;
        all.largest_angle_cosine = std::min(all.largest_angle_cosine, p.largest_angle_cosine);
        all.live += p.live;
    }
    const double live = double(std::max<int64_t>(all.live, 1));
    return {all.qt_min, all.qt_sum / live, all.qp_min, all.qp_sum / live, all.largest_angle_cosine};
}

// ----------------------------------------------------------------- schedule

OptimiseStats Optimiser::run() {
    for (int32_t v = 0; v < tri_.vertex_slots(); ++v) next_id_ = std::max(next_id_, tri_.id(v) + 1);
    load_spacing();
    Summary last = summarise();
    std::unique_ptr<StarGraph> graph = std::make_unique<StarGraph>(ctx_, tri_);
    // The first half of the outer iterations shapes the triangles (moves,
    // flips, valence repairs, weights held); the second half adds the weight
    // ascent for the staggering. Weights first would lock the topology in:
    // a weighted triangulation keeps badly shaped triangles regular (and
    // well-centred), so no flip would ever mend them.
    const int shape_iterations = o_.weights ? o_.outer_iterations / 2 : o_.outer_iterations;
    for (int n = 0; n < o_.outer_iterations; ++n) {
        ctx_.progress("optimise", double(n) / o_.outer_iterations);
        const bool shape_phase = n < shape_iterations;
        if (!shape_phase && !weighing_) {
            stats_.moves += relax_to_centroids(graph);
            weighing_ = true, grow_slots();
        }
        flag_near_gamma();
        const int32_t outer_start = clock_;
        int64_t changes = 0;
        for (int m = 0; m < o_.inner_iterations; ++m) {
            const bool forward = m % 2 == 0;
            auto t0 = Clock::now();
            // After the shape phase the centroidal pass places the generators.
            int64_t moved = shape_phase ? sweep(*graph, Sweep::moves, forward) : 0;
            stats_.seconds_moves += seconds_since(t0);
            t0 = Clock::now();
            int64_t weighted = o_.weights && !shape_phase ? sweep(*graph, Sweep::weights, forward) : 0;
            stats_.seconds_weights += seconds_since(t0);
            stats_.moves += moved, stats_.weight_updates += weighted;
            changes += moved + weighted;
            ctx_.log(UM_LOG_DEBUG, concat("optimise: inner sweep ", m + 1, ": ", moved, " moves, ",
                                          weighted, " weight updates"));
            if (moved + weighted == 0) break;
        }
        if (shape_phase && o_.inner_iterations > 0 &&
            changes < kPolishAfter * static_cast<double>(tri_.vertex_count())) {
            auto t0 = Clock::now();
            const int64_t polished = polish_poor_stars(*graph);
            stats_.moves += polished, changes += polished;
            stats_.seconds_moves += seconds_since(t0);
        }
        auto t0 = Clock::now();
        const int64_t flips = restore_regularity(outer_start);
        const auto [collapsed, split] = collapse_and_split();
        const int64_t valence =
            n + 1 < o_.outer_iterations ? improve_valence() + (n < 2 ? flip_for_valence() : 0) : 0;
        const int64_t corners = shape_phase && o_.corner_vertices ? support_gamma_corners() : 0;
        stats_.flips += flips, stats_.collapses += collapsed, stats_.splits += split;
        const int64_t topology = flips + collapsed + split + valence + corners;
        if (topology > 0) {  // else the spacing (h_at_) and the graph are still those of the mesh
            load_spacing();
            const std::vector<uint32_t> links_before = link_fingerprints(ctx_, *graph);
            graph.reset();  // one graph alive at a time
            graph = std::make_unique<StarGraph>(ctx_, tri_);
            mark_changed_links(links_before, *graph);
        }
        ++clock_;
        stats_.seconds_topology += seconds_since(t0);
        ++stats_.outer_iterations;

        const Summary now = summarise();
        const bool settled = std::abs(now.qt_min - last.qt_min) <= o_.tolerance &&
                             std::abs(now.qt_mean - last.qt_mean) <= o_.tolerance &&
                             std::abs(now.qp_min - last.qp_min) <= o_.tolerance &&
                             std::abs(now.qp_mean - last.qp_mean) <= o_.tolerance;
        ctx_.log(UM_LOG_INFO,
                 concat("optimise: outer iteration ", n + 1, shape_phase ? " (shape)" : " (weights)",
                        ": ", changes, " updates, ", flips, " flips, ", collapsed + split + valence,
                        " collapses/splits, ", corners, " vertices added or taken out at obtuse corners on Gamma; Q^T min ", now.qt_min, " mean ", now.qt_mean, ", Q^P min ",
                        now.qp_min, " mean ", now.qp_mean, "; ", stats_.seconds_moves, " s moves, ",
                        stats_.seconds_weights, " s weights, ", stats_.seconds_topology, " s topology"));
        last = now;
        const bool quiet = changes + topology == 0 || (settled && topology == 0);
        if (quiet && shape_phase && n + 1 < shape_iterations) {
            n = shape_iterations - 1;  // shaped: go on to the staggering
        } else if (quiet && !shape_phase) {
            break;
        }
    }
    if (!weighing_ && o_.outer_iterations > 0) stats_.moves += relax_to_centroids(graph);
    int64_t off_centre_left = 0;
    if (o_.weights && o_.outer_iterations > 0) {
        auto t0 = Clock::now();
        const Mended m = mend_off_centre_triangles(false);
        off_centre_left = m.met - m.mended;
        stats_.weight_updates += m.mended;
        stats_.seconds_weights += seconds_since(t0);
        // tests/capi/test_optimise_api.c reads this line.
        ctx_.log(UM_LOG_INFO, concat("optimise: joint weights mended ", m.mended, " of ", m.met,
                                     " triangles not holding their orthocentre; Q^P floor ", m.floors.qp, "; ",
                                     m.slid, " of them with vertices sliding along Gamma, ", m.flipped,
                                     " by a flip; ", seconds_since(t0), " s"));
    }
    if (o_.outer_iterations > 0) {
        auto t0 = Clock::now();
        const Mended m = mend_obtuse_triangles();
        stats_.moves += m.mended;
        stats_.seconds_moves += seconds_since(t0);
        // tests/capi/test_optimise_api.c reads this line.
        ctx_.log(UM_LOG_INFO, concat("optimise: joint moves mended ", m.mended, " of ", m.met, " obtuse triangles (",
                                     m.flipped, " by a flip); ", seconds_since(t0), " s"));
    }
    if (off_centre_left > 0) {
        // The moves have changed the neighbourhoods of the off-centre
        // triangles left (without adding any): another search may now mend
        // some. It only ever lowers their number, and its moves add no
        // obtuse triangle (so the obtuse mend's count stands).
        auto t0 = Clock::now();
        const Mended m = mend_off_centre_triangles(true);
        stats_.weight_updates += m.mended;
        stats_.seconds_weights += seconds_since(t0);
        ctx_.log(UM_LOG_INFO, concat("optimise: after the joint moves, joint weights mended ", m.mended, " of ",
                                     m.met, " triangles not holding their orthocentre (", m.flipped, " by a flip); ",
                                     seconds_since(t0), " s"));
    }
    ctx_.progress("optimise", 1.0);
    return stats_;
}

}  // namespace detail

OptimiseStats optimise(Context &ctx, tri::Triangulation &tri, std::vector<int32_t> &on_segment,
                       const features::Network *gamma, const refine::SpacingRadians &h,
                       const OptimiseOptions &options) {
    detail::Optimiser o(ctx, tri, on_segment, gamma, h, options);
    return o.run();
}

}  // namespace um::optim
