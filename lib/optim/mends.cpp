#include "optim/mends.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "optim/slide.hpp"

namespace um::optim::detail {

namespace {

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

}  // namespace

Mends::MendFloors Mends::mend_floors(bool qp_floor) {
    const MeshState::Summary now = s_.summarise(true);  // with the largest angle
    return {qp_floor ? std::min(now.qp_min, kMendQpFloor) : now.qp_min, now.qt_min, now.largest_angle_cosine};
}

Mends::Mended Mends::mend_off_centre_triangles(bool keep_obtuse) {
    const MendGoal moving = keep_obtuse ? MendGoal::off_centre_keeping_obtuse : MendGoal::off_centre;
    auto off_centre = [&](int32_t t) {
        return !s_.touches_cover(t) && staggering_score(s_.generator(s_.tri.vertex(t, 0)), s_.generator(s_.tri.vertex(t, 1)),
                                s_.generator(s_.tri.vertex(t, 2))) < 0;
    };
    const std::vector<int32_t> found = s_.tri.live_triangles_where(s_.ctx, off_centre);
    Mended out;
    out.met = static_cast<int64_t>(found.size());
    if (found.empty()) return out;
    const MendFloors floors = out.floors = mend_floors(true);
    for (int32_t t : found) {
        s_.ctx.progress("optimise", 1.0);  // a cancel point: a triangle's search can take a second
        if (!off_centre(t)) continue;  // mended with an earlier one
        out.mended += mend_off_centre_triangle(t, floors, moving, out);
    }
    return out;
}

// One off-centre triangle t: its three weights, else with the far vertex of
// a neighbour, else sliding along Gamma, else a flip of one of its edges.
bool Mends::mend_off_centre_triangle(int32_t t, const MendFloors &floors, MendGoal moving, Mended &out) {
    int32_t v[4] = {s_.tri.vertex(t, 0), s_.tri.vertex(t, 1), s_.tri.vertex(t, 2), -1};
    std::vector<Candidate> c[4];
    for (int i = 0; i < 3; ++i) c[i] = mend_candidates(v[i], kMendSteps, 0);
    bool done = mend_jointly(v, 3, c, floors, false);
    // Else with the far vertex of a neighbour too: a pair that a weight
    // common to both cannot mend.
    for (int i = 0; i < 3 && !done; ++i) c[i] = mend_candidates(v[i], kMendPairSteps, 0);
    for (int k = 0; k < 3 && !done; ++k) {
        const int32_t u = s_.tri.neighbour(t, k);
        v[3] = s_.tri.vertex(u, s_.tri.mirror_edge(t, k));  // opposite the shared edge
        if (s_.cover(v[3])) continue;
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
        if (mend_by_flip(holder, s_.tri.local_index(holder, v[i]), floors, moving)) done = true, ++out.flipped;
    return done;
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
Mends::Mended Mends::mend_obtuse_triangles() {
    auto obtuse = [&](int32_t t) {
        return !s_.touches_cover(t) && largest_angle_cosine(s_.tri.direction(s_.tri.vertex(t, 0)), s_.tri.direction(s_.tri.vertex(t, 1)),
                                    s_.tri.direction(s_.tri.vertex(t, 2))) < 0;
    };
    const std::vector<int32_t> found = s_.tri.live_triangles_where(s_.ctx, obtuse);
    Mended out;
    out.met = static_cast<int64_t>(found.size());
    if (found.empty()) return out;
    const MendFloors floors = out.floors = mend_floors(false);  // the off-centre mend may have changed them
    for (size_t i = 0; i < found.size(); ++i) {
        const int32_t t = found[i];
        if (i % 256 == 255) s_.ctx.progress("optimise", 1.0);  // a cancel point: up to a second here
        if (!obtuse(t)) continue;  // mended with an earlier one
        const int32_t v[3] = {s_.tri.vertex(t, 0), s_.tri.vertex(t, 1), s_.tri.vertex(t, 2)};
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
            const Vec3 e = s_.tri.direction(v[(j + 1) % 3]) - s_.tri.direction(v[(j + 2) % 3]);
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
bool Mends::mend_by_flip(int32_t &t, int k, const MendFloors &floors, MendGoal goal) {
    const int32_t u = s_.tri.neighbour(t, k);
    const int32_t a = s_.tri.vertex(t, k), b = s_.tri.vertex(t, (k + 1) % 3), c = s_.tri.vertex(t, (k + 2) % 3);
    const int32_t d = s_.tri.vertex(u, s_.tri.mirror_edge(t, k));
    if (s_.runs_along_gamma(b, c, a, d) || s_.cover(d)) return false;
    const int32_t quad[4] = {a, b, c, d};
    // The triangles around the quad (the same slots after the flip) and
    // how many of them are off-centre now.
    // (Those the joint search judges: JointSearch::judged.)
    std::vector<int32_t> around;
    for (int32_t v : quad) s_.tri.for_each_in_star(v, [&](int32_t s) { around.push_back(s); });
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    const auto current = [&](int32_t u) { return s_.generator(u); };
    Baseline before{0, 0, s_.stars_gamma_crossings(quad, 4, current, false)};
    for (int32_t s : around) {
        if (s_.touches_cover(s)) continue;
        const Generator x = s_.generator(s_.tri.vertex(s, 0)), y = s_.generator(s_.tri.vertex(s, 1)),
                        z = s_.generator(s_.tri.vertex(s, 2));
        before.off_centre += staggering_score(x, y, z) < 0;
        before.obtuse += largest_angle_cosine(x.x, y.x, z.x) < 0;
    }
    if (!s_.tri.flip(t, k)) return false;  // t = (a, b, d), u = (d, c, a)
    // The candidates: first the four weights alone (7^4 combinations), then
    // with the vertices on Gamma sliding too (15^3 x 7 at most). For an
    // obtuse triangle (there are hundreds) only the second, with the
    // sliding vertices' weights held (5^3 x 7): the weights alone mend none
    // of them, and with the sliding ones' weights too the search mends 2.5
    // times as many (coastlines at 60 km: 33 against 13) for 1 s more.
    const bool sliding = s_.gamma && !s_.options.fix_boundary;
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
        const bool on_gamma = sliding && s_.on_segment[quad[i]] >= 0;
        candidates[i] = on_gamma ? mend_candidates(quad[i], slide_weights, kFlipSlides)
                                 : mend_candidates(quad[i], off_weights, 0);
        slides |= on_gamma;
    }
    if (slides && !mended) mended = mend_jointly(quad, 4, candidates, floors, true, goal, &before);
    if (!mended) {
        s_.tri.flip(t, 1);  // the edge (d, a) of (a, b, d): back to (b, c), t now (b, d, c) and u (c, a, b)
        t = u;
        return false;
    }
    for (int32_t v : quad)
        for (int32_t s : s_.tri.star(v))
            for (int j = 0; j < 3; ++j) s_.changed_at[s_.tri.vertex(s, j)] = s_.clock;
    return true;
}

// The candidates of a joint search for vertex v: its weight `steps` steps
// of kMendStep either way, at each of its positions: where it is, and when
// `slides` > 0, `slides` steps of kMendSlide h either way along Gamma (v on
// it) or, with off_gamma_moves, half as many in four directions (v off it).
std::vector<Mends::Candidate> Mends::mend_candidates(int32_t v, int steps, int slides, bool off_gamma_moves) const {
    const Generator here = s_.generator(v);
    double spoke2 = 0;  // the weight steps' unit; only with steps
    if (steps > 0) {
        int spokes = 0;
        s_.tri.for_each_neighbour(v, [&](int32_t w) {
            const Vec3 d = here.x - s_.tri.direction(w);
            spoke2 += geom::dot(d, d), ++spokes;
        });
        spoke2 /= spokes;
    }
    const double weight = 2.0 * (1.0 - 1.0 / here.s);
    // The positions: here, then along Gamma either way (on it), or with
    // `off_gamma_moves`, off it in four directions at half as many steps
    // (as many positions).
    std::vector<Candidate> at{{here, s_.on_segment[v]}};
    const int64_t segment = s_.on_segment[v];
    const double step = kMendSlide * s_.h_at[v];
    if (slides > 0 && segment >= 0 && s_.gamma && !s_.options.fix_boundary) {
        const Vec3 tangent = geom::normalized(s_.gamma->segment_b(segment) - s_.gamma->segment_a(segment));
        for (int k = 1; k <= slides; ++k)
            for (double sign : {1.0, -1.0}) {
                const PointOnGamma p =
                    slide_along(*s_.gamma, segment, geom::normalized(here.x + (sign * k * step) * tangent));
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

// A joint search's state: the n vertices v (at most 4) and their
// candidates, the triangles around them and the trial's generators.
struct Mends::JointSearch {
    JointSearch(MeshState &s, const int32_t *v, int n, const std::vector<Candidate> *candidates,
                const MendFloors &floors, bool moves, MendGoal goal);
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
    static constexpr int kAny = std::numeric_limits<int>::max();
    static constexpr Score kRefused{kAny, -kInfinity, kAny, kAny};
    Generator at(int32_t u) const {
        for (int i = 0; i < n; ++i)
            if (u == v[i]) return trial[i];
        return s.generator(u);
    }
    static double shortest_edge2(const Generator &a, const Generator &b, const Generator &c) {
        const Vec3 ab = a.x - b.x, bc = b.x - c.x, ca = c.x - a.x;
        return std::min({geom::dot(ab, ab), geom::dot(bc, bc), geom::dot(ca, ca)});
    }
    Score judge(int limit, int off_limit, int obtuse_limit) const;
    bool regular_with_trial();
    // Every combination, as the digits of a counter: the best with fewer
    // than `now` counted (its digits to `chosen`), else `now`.
    Score best_combination(const Score &now, int crossings_now, int off_limit, int obtuse_limit, int *chosen);

    MeshState &s;
    const int32_t *v;
    int n;
    const std::vector<Candidate> *candidates;
    const MendFloors &floors;
    bool moves;
    MendGoal goal;
    std::vector<int32_t> around;  // the triangles around the vertices, each once (kept regular)
    // Those the search scores: around but a regional mesh's cover (no output
    // reads it), in the order judge() takes them.
    std::vector<int32_t> judged;
    Generator trial[4];
    double edge2_floor = 0;
    // With a floor: per triangle around, which of its edges (bit k: the edge
    // opposite corner k) join two generators off the land; the floor's
    // squared chord and how many of those edges are below it now (a move
    // may add none).
    std::vector<uint8_t> off_land_edges;
    double floor2 = 0;
    int below_floor_now = 0;
    void keep_floor();
    int below_floor(const Generator *x, size_t j) const;
};

Mends::JointSearch::JointSearch(MeshState &s, const int32_t *v, int n, const std::vector<Candidate> *candidates,
                                const MendFloors &floors, bool moves, MendGoal goal)
    : s(s), v(v), n(n), candidates(candidates), floors(floors), moves(moves), goal(goal) {
    for (int i = 0; i < n; ++i) s.tri.for_each_in_star(v[i], [&](int32_t u) { around.push_back(u); });
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    for (int32_t u : around)
        if (!s.touches_cover(u)) judged.push_back(u);
    // Moves make no edge around shorter than h/2 (h at the first vertex: the
    // three are within an edge of each other) or, if one is already, than
    // the shortest there (squared chords).
    if (moves) {
        edge2_floor = kInfinity;
        for (int32_t u : judged)
            edge2_floor = std::min(edge2_floor, shortest_edge2(s.generator(s.tri.vertex(u, 0)),
                                                           s.generator(s.tri.vertex(u, 1)),
                                                           s.generator(s.tri.vertex(u, 2))));
        const double half_h = kMendEdgeFloor * s.h_at[v[0]];
        edge2_floor = std::min(edge2_floor, half_h * half_h);
    }
}

// (After `judged` is in its final order.)
void Mends::JointSearch::keep_floor() {
    if (moves && s.options.ocean_floor > 0) {
        const double floor = s.options.ocean_floor * s.h_at[v[0]];
        floor2 = floor * floor;
        off_land_edges.resize(judged.size(), 0);
        for (size_t j = 0; j < judged.size(); ++j) {
            bool off[3];
            for (int k = 0; k < 3; ++k) off[k] = s.off_land(s.tri.vertex(judged[j], k));
            for (int k = 0; k < 3; ++k) off_land_edges[j] |= (off[(k + 1) % 3] && off[(k + 2) % 3]) << k;
            const Generator x[3] = {s.generator(s.tri.vertex(judged[j], 0)), s.generator(s.tri.vertex(judged[j], 1)),
                                    s.generator(s.tri.vertex(judged[j], 2))};
            below_floor_now += below_floor(x, j);
        }
    }
}

int Mends::JointSearch::below_floor(const Generator *x, size_t j) const {
    int below = 0;
    for (int k = 0; k < 3; ++k) {
        if (!(off_land_edges[j] >> k & 1)) continue;
        const Vec3 e = x[(k + 1) % 3].x - x[(k + 2) % 3].x;
        below += geom::dot(e, e) < floor2;
    }
    return below;
}

Mends::JointSearch::Score Mends::JointSearch::judge(int limit, int off_limit, int obtuse_limit) const {
    Score out{0, kInfinity, 0, 0};
    int below_floor_then = 0;  // (the floor's count over the triangles judged so far)
    for (size_t j = 0; j < judged.size(); ++j) {
        const int32_t u = judged[j];
        double qp = 0;
        const Generator a = at(s.tri.vertex(u, 0)), b = at(s.tri.vertex(u, 1)), c = at(s.tri.vertex(u, 2));
        if (!off_land_edges.empty() && off_land_edges[j]) {
            const Generator x[3] = {a, b, c};
            if ((below_floor_then += below_floor(x, j)) > below_floor_now) return kRefused;
        }
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
}

bool Mends::JointSearch::regular_with_trial() {  // stored for the exact tests, then put back
    Vec3 kept[4];
    for (int i = 0; i < n; ++i) kept[i] = s.tri.lifted(v[i]), s.set_generator(v[i], trial[i]);
    bool regular = true;
    for (size_t j = 0; j < around.size() && regular; ++j)
        for (int k = 0; k < 3 && regular; ++k) regular = s.tri.is_locally_regular(around[j], k);
    for (int i = 0; i < n; ++i) s.tri.set_lifted(v[i], kept[i]);
    return regular;
}

Mends::JointSearch::Score Mends::JointSearch::best_combination(const Score &now, int crossings_now, int off_limit,
                                                               int obtuse_limit, int *chosen) {
    auto trial_at = [&](int32_t u) { return at(u); };
    Score best = now;
    int digit[4] = {0, 0, 0, 0};
    for (;;) {
        for (int i = 0; i < n; ++i) trial[i] = candidates[i][digit[i]].g;
        const Score q = judge(std::min(best.count, now.count - 1), off_limit, obtuse_limit);
        const bool better = q.count < best.count || (q.count == best.count && q.worst > best.worst + s.gain);
        if (better && q.count < now.count) {
            const int crossings = s.stars_gamma_crossings(v, n, trial_at, true);
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
    return best;
}

// The search of mend_off_centre_triangles over every combination of the
// candidates of the n vertices v; applies the best and returns true when it
// has fewer off-centre triangles around.
bool Mends::mend_jointly(const int32_t *v, int n, const std::vector<Candidate> *candidates,
                         const MendFloors &floors, bool moves, MendGoal goal, const Baseline *baseline) {
    using Score = JointSearch::Score;
    JointSearch search(s_, v, n, candidates, floors, moves, goal);
    for (int i = 0; i < n; ++i) {
        if (candidates[i].empty()) return false;
        search.trial[i] = s_.generator(v[i]);
    }
    // Gamma's crossings now, or before the flip that left the mesh as it is
    // (its quad's stars are those v lists: the same spokes but the diagonal).
    auto at = [&](int32_t u) { return search.at(u); };
    const int crossings_now = baseline ? baseline->gamma_crossings : s_.stars_gamma_crossings(v, n, at, false);
    if (crossings_now < 0) return false;
    constexpr int kAny = JointSearch::kAny;
    Score now = search.judge(kAny, kAny, kAny);
    // (After a flip, its new triangles need not meet the floors yet.)
    if (baseline)
        now = {goal == MendGoal::obtuse ? baseline->obtuse : baseline->off_centre, -kInfinity, baseline->off_centre,
               baseline->obtuse};
    if (now.count == JointSearch::kRefused.count) return false;  // (the floors are the mesh's: not met here)
    // The obtuse goal adds no off-centre triangle, and the keeping one no obtuse one.
    const int off_limit = goal == MendGoal::obtuse ? now.off_centre : kAny;
    const int obtuse_limit = goal == MendGoal::off_centre_keeping_obtuse ? now.obtuse : kAny;
    // The counted ones first: the count passes the limit sooner.
    std::stable_partition(search.judged.begin(), search.judged.end(), [&](int32_t u) {
        const Generator a = s_.generator(s_.tri.vertex(u, 0)), b = s_.generator(s_.tri.vertex(u, 1)),
                        c = s_.generator(s_.tri.vertex(u, 2));
        return goal == MendGoal::obtuse ? largest_angle_cosine(a.x, b.x, c.x) < 0 : staggering_score(a, b, c) < 0;
    });
    search.keep_floor();
    int chosen[4] = {-1, -1, -1, -1};
    const Score best = search.best_combination(now, crossings_now, off_limit, obtuse_limit, chosen);
    if (best.count >= now.count) return false;
    for (int i = 0; i < n; ++i) {
        const Candidate &c = candidates[i][chosen[i]];
        s_.set_generator(v[i], c.g), s_.changed_at[v[i]] = s_.clock;
        s_.on_segment[v[i]] = c.segment, s_.h_at[v[i]] = static_cast<float>(s_.h(c.g.x));
    }
    return true;
}

}  // namespace um::optim::detail
