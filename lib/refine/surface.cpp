#include "refine/surface.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <array>
#include <deque>
#include <exception>
#include <memory>
#include <limits>
#include <set>

#include "core/error.hpp"
#include "core/text.hpp"
#include "hfun/spacing.hpp"
#include "refine/lattice.hpp"
#include "refine/restricted.hpp"

namespace um::refine {

using geom::Vec3;

namespace {

// A queued bad triangle: its vertices identify it (slots are reused).
struct Candidate {
    int32_t t;
    int32_t v0, v1, v2;
};

Candidate candidate_of(const tri::Triangulation &tri, int32_t t) {
    return {t, tri.vertex(t, 0), tri.vertex(t, 1), tri.vertex(t, 2)};
}

bool still_there(const tri::Triangulation &tri, const Candidate &c) {
    return !tri.is_free(c.t) && tri.vertex(c.t, 0) == c.v0 && tri.vertex(c.t, 1) == c.v1 &&
           tri.vertex(c.t, 2) == c.v2;
}

// The point at arc distance d from m towards c along their great circle.
Vec3 towards(const Vec3 &m, const Vec3 &c, double d) {
    Vec3 t = c - geom::dot(c, m) * m;  // tangent at m pointing to c
    double tl = geom::norm(t);
    if (tl == 0) return m;
    t = (1.0 / tl) * t;
    return geom::normalized(std::cos(d) * m + std::sin(d) * t);
}

// A triangle is sized by h at its circumcentre, unless its circumcircle holds
// a spacing below that by more than kSteepGradient times the circle's radius:
// a feature of the spacing narrower than the triangle, which sampling h at
// points would miss (a fine spot between them). Smooth spacings never do
// that (|grad h| up to about 0.17 km per km, the bound being taken over the
// circle's lon/lat box, up to about 1.4 radii away). Such a triangle is sized
// by the least value plus that allowance, so it shrinks until it resolves
// the feature, where h at circumcentres takes over.
constexpr double kSteepGradient = 0.25;

// Whether any Gamma arc comes within (about) `reach` of p: a surface ball
// holding p has its centre on Gamma within its radius, below ~h, so farther
// candidates need no encroachment search.
constexpr double kEncroachReach = 3;  // in units of the target spacing
bool near_gamma(const geom::ArcTree &gamma, const Vec3 &p, double reach) {
    geom::Box box;
    box.add(p);
    box.grow(reach);
    return gamma.any_overlaps(box);
}


// A restricted edge whose surface ball holds p. Such a ball lies within the
// circumcircles of the edge's two triangles (balls through the edge's ends
// centred on its dual edge do), so one of them holds p: only the edges of
// p's cavity (the triangles whose circumcircle holds p, connected to the one
// containing p) need a look. Cavity order, each edge once: deterministic.
// The triangles looked at and their orthocentres are kept in the caller's
// lists (between calls: this runs for most points near Gamma); a triangle
// found outside the cavity is not measured again.
struct EncroachLists {
    std::vector<int32_t> cavity, outside;
    std::vector<Vec3> cavity_centre, outside_centre;
};

// With a territory, the cavity must be its own (else `deferred`: another
// territory may be changing the triangles beyond).
enum class Encroach { none, encroached, deferred };
Encroach encroached_edge(const tri::Triangulation &tri, const tri::Triangulation::Territory *g,
                         const Vec3 &p, int32_t hint, const geom::ArcTree &gamma,
                         RestrictedEdge *out, EncroachLists &l) {
    constexpr size_t kMaxCavity = 256;  // a huge cavity (coarse start): its first triangles
    const int32_t start = g ? tri.locate_in(*g, p, hint) : tri.locate(p, hint);
    if (start == tri::Triangulation::kNone) return Encroach::deferred;
    l.cavity.assign(1, start);
    l.cavity_centre.assign(1, tri.orthocentre(l.cavity[0]));
    l.outside.clear(), l.outside_centre.clear();
    auto index_in = [](const std::vector<int32_t> &list, int32_t t) {
        for (size_t i = 0; i < list.size(); ++i)
            if (list[i] == t) return static_cast<int>(i);
        return -1;
    };
    for (size_t i = 0; i < l.cavity.size() && l.cavity.size() < kMaxCavity; ++i)
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri.neighbour(l.cavity[i], k);
            if (index_in(l.cavity, u) >= 0 || index_in(l.outside, u) >= 0) continue;
            const Vec3 c = tri.orthocentre(u);
            const Vec3 a = tri.direction(tri.vertex(u, 0));
            const bool inside = geom::dot(p - c, p - c) < geom::dot(a - c, a - c);
            if (inside && g && !tri.owns(*g, u)) return Encroach::deferred;
            (inside ? l.cavity : l.outside).push_back(u);
            (inside ? l.cavity_centre : l.outside_centre).push_back(c);
        }
    for (size_t i = 0; i < l.cavity.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const int32_t u = tri.neighbour(l.cavity[i], k);
            const int j = index_in(l.cavity, u);
            if (j >= 0 && static_cast<size_t>(j) < i) continue;  // seen from u
            Vec3 cu;
            if (j >= 0) {
                cu = l.cavity_centre[j];
            } else {
                const int o = index_in(l.outside, u);  // -1 past the cavity's cap
                cu = o >= 0 ? l.outside_centre[o] : tri.orthocentre(u);
            }
            RestrictedEdge e;
            if (restricted_crossing(tri, l.cavity[i], k, l.cavity_centre[i], cu, gamma, &e) &&
                geom::arc_length(p, e.centre) < e.radius)
                return *out = e, Encroach::encroached;
        }
    return Encroach::none;
}

}  // namespace

// Chords compared, one asin.
double nearest_neighbour(const tri::Triangulation &tri, int32_t v) {
    double d2 = 1e300;
    const Vec3 x = tri.direction(v);
    tri.for_each_neighbour(v, [&](int32_t w) {
        const Vec3 d = x - tri.direction(w);
        d2 = std::min(d2, geom::dot(d, d));
    });
    return geom::arc_of_chord(std::sqrt(d2));
}

void triangle_size(const tri::Triangulation &tri, int32_t t, double *radius, double *shortest,
                   Vec3 *circumcentre) {
    // Chords first, one arc conversion each (2 asin(chord / 2)): this runs
    // for every new triangle of the refinement.
    Vec3 a = tri.direction(tri.vertex(t, 0)), b = tri.direction(tri.vertex(t, 1)),
         c = tri.direction(tri.vertex(t, 2));
    double e2 = std::min({geom::dot(a - b, a - b), geom::dot(b - c, b - c), geom::dot(c - a, c - a)});
    Vec3 centre = tri.orthocentre(t);
    if (circumcentre) *circumcentre = centre;
    double r2 = geom::dot(centre - a, centre - a);
    *radius = geom::arc_of_chord(std::sqrt(r2));
    *shortest = geom::arc_of_chord(std::sqrt(e2));
}

tri::Triangulation icosahedron(Context &ctx) {
    const std::vector<Vec3> corners = geodesic_lattice(1);
    tri::Triangulation tri;
    tri.build(ctx, 12, [&](int64_t i) { return corners[i]; }, nullptr);
    return tri;
}

namespace {

// Per triangle slot: bad or not (and whether only for a spacing feature
// narrower than itself), and whether an entry of it waits on the front (a
// triangle joins once, however many good neighbours it gets).
enum : uint8_t { kGood = 0, kBad = 1, kOnFront = 2, kNarrowFeature = 4 };

// The surface pass's state. Each triangle slot caches whether its triangle is
// bad, so a front test reads three bytes instead of re-measuring neighbours
// (only the new fan of an insertion changes). Bad triangles wait in two
// queues:
//  - the front: bad triangles beside a good one, first in, first out. Their
//    point is placed off the shared (front) edge so that the new triangle is
//    about equilateral with side h, as in frontal-Delaunay refinement: the
//    mesh grows in layers of well-sized triangles, with edges close to h;
//  - the reserve: bad triangles with no good neighbour, last in, first out,
//    so that refinement goes depth-first at one place until the first good
//    triangle starts a front (at 120 km, 36 of 40,000 points come from here).
//    While a front exists, new bad triangles off it are not queued (the
//    front soon reaches or destroys them); those left when the front runs
//    out are collected from the cache.
// Against one first-in first-out queue of all bad triangles, this leaves 2 %
// rather than 7 % of uniform edges above 1.35 h, none below 0.77 h, and an
// optimisation that takes half the time to a better mesh.
class SurfaceRefiner {
public:
    using Territory = tri::Triangulation::Territory;
    // With a territory, it refines only there (see refine_by_territories):
    // candidates that need more are left as they are, for the serial pass
    // after it, and the ids are the territory's.
    SurfaceRefiner(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                   const SurfaceOptions &options, int32_t next_id, std::vector<uint8_t> &state,
                   Territory *territory = nullptr)
        : ctx_(ctx), tri_(tri), h_(h), options_(options), state_(state), territory_(territory) {
        stats_.next_id = next_id;
    }

    // Classifies the triangles `measure`, then queues the bad ones of `queue`
    // (the others are known to be classified), and refines until no bad
    // triangle is left that it may refine. A territory's `queue` is the
    // triangles it owns at the start.
    SurfaceStats run(const std::vector<int32_t> &measure, const std::vector<int32_t> &queue) {
        if (!territory_) ctx_.progress("refine surface", 0.0);  // the phase starts (timed by its reports)
        first_owned_ = &queue;
        this->measure(measure);
        for (int32_t t : queue)
            if (bad(t)) enqueue(t);
        Candidate c;
        while (pop(&c)) {
            if (territory_ && territory_->vertex_budget_left() == 0) break;  // the rest is the serial pass's
            if (!still_there(tri_, c)) continue;
            state_[c.t] &= ~kOnFront;  // its entry is taken: it may join again
            if (territory_ && !tri_.owns(*territory_, c.t)) continue;  // the serial pass's
            if (given_up_.count(key_of(c)) || deferred_.count(key_of(c))) continue;
            if (!territory_) ctx_.heartbeat("refine surface", 0.0);
            refine(c);
        }
        return std::move(stats_);
    }

    // Classifies triangles (without queueing them), in parallel: a pass
    // over a whole mesh's triangles is a large part of a lattice start's
    // refinement, which otherwise places few points. Each writes only its
    // own triangle's state. A worker does not throw (the spacing may be the
    // caller's callback): it notes the lowest triangle that failed, which is
    // classified again here to report the error the serial pass would.
    void measure(const std::vector<int32_t> &triangles) {
        size_state();
        hfun::FirstInvalid failed;
        ctx_.parallel_for_with_heartbeat(
            "refine surface", static_cast<int64_t>(triangles.size()), 4096, [&](int64_t b, int64_t e) {
                for (int64_t i = b; i < e; ++i) {
                    try {
                        classify_sized(triangles[i]);
                    } catch (...) {
                        failed.note(i);
                        return;  // (the rest of the range lies above it)
                    }
                }
            });
        if (failed.any()) classify_sized(triangles[failed.index()]);
    }

    // The candidates given up (whose point was rejected), for the serial pass
    // after the territories; with the vertex slots renumbered by `slot`.
    template <class SlotMap>
    void hand_over_given_up(std::set<std::array<int32_t, 3>> &to, SlotMap slot) const {
        for (const auto &k : given_up_) {
            const Candidate c{0, slot(k[0]), slot(k[1]), slot(k[2])};
            to.insert(key_of(c));
        }
    }
    void take_given_up(std::set<std::array<int32_t, 3>> &&from) { given_up_ = std::move(from); }

private:
    bool bad(int32_t t) const { return static_cast<size_t>(t) < state_.size() && (state_[t] & kBad); }

    void size_state() {
        if (state_.size() < static_cast<size_t>(tri_.triangle_slots()))  // (a territory's is sized)
            state_.resize(static_cast<size_t>(tri_.triangle_slots()), kGood);
    }
    void classify(int32_t t) {
        size_state();
        classify_sized(t);
    }
    void classify_sized(int32_t t) {
        double r, e;
        Vec3 centre;
        triangle_size(tri_, t, &r, &e, &centre);
        double ht = h_(centre);
        if (!(ht > 0) || !std::isfinite(ht))
            fail(UM_ERR_NUMERICAL, "the spacing is ", ht, " (not a positive length) at a "
                 "triangle's circumcentre");
        const bool too_big = std::sqrt(3.0) * r >= options_.alpha * ht;
        const bool badly_shaped = r / e >= options_.rho;
        if (too_big || badly_shaped) {
            state_[t] = kBad;
            return;
        }
        // (Asked only of triangles good by h at their circumcentre.)
        const bool misses_a_feature = std::sqrt(3.0) * r >= options_.alpha * narrow_feature_size(t, centre, ht);
        state_[t] = misses_a_feature ? kBad | kNarrowFeature : kGood;
    }

    // The size a spacing feature narrower than t asks of it (kSteepGradient)
    // when that is below ht (h at its circumcentre), else infinity.
    double narrow_feature_size(int32_t t, const Vec3 &centre, double ht) const {
        constexpr double kNone = std::numeric_limits<double>::infinity();
        if (!options_.smallest) return kNone;
        double chord2 = 0;  // the farthest vertex: its circle holds t, weights or not
        for (int k = 0; k < 3; ++k) {
            const Vec3 d = tri_.direction(tri_.vertex(t, k)) - centre;
            chord2 = std::max(chord2, geom::dot(d, d));
        }
        const double cap = geom::arc_of_chord(std::sqrt(chord2));
        // In the spacing's own units (the seed pass scales it).
        const double h = ht / options_.smallest_scale, allowance = kSteepGradient * cap;
        if (!(h > allowance)) return kNone;  // far too big already
        const double size = options_.smallest_scale * (options_.smallest(centre, cap, h - allowance) + allowance);
        return size < ht ? size : kNone;
    }
    double narrow_feature_size(int32_t t) const {
        const Vec3 centre = tri_.orthocentre(t);
        return narrow_feature_size(t, centre, h_(centre));
    }

    bool on_front(int32_t t) const {
        for (int k = 0; k < 3; ++k)
            if (!bad(tri_.neighbour(t, k))) return true;
        return false;
    }

    void enqueue(int32_t t) {
        if (on_front(t)) {
            join_front(t);
        } else {
            reserve_.push_back(candidate_of(tri_, t));
        }
    }

    void join_front(int32_t t) {
        if (state_[t] & kOnFront) return;
        state_[t] |= kOnFront;
        front_.push_back(candidate_of(tri_, t));
    }

    bool pop(Candidate *c) {
        if (!front_.empty()) {
            *c = front_.front();
            front_.pop_front();
            return true;
        }
        if (reserve_.empty()) collect_unqueued();
        if (!reserve_.empty()) {
            *c = reserve_.back();
            reserve_.pop_back();
            return true;
        }
        return false;
    }

    // The bad triangles no queue holds any more (bad beside bad ones only,
    // made while a front grew elsewhere; or a triangle whose point landed
    // elsewhere, on Gamma), last slot first out. Not those whose point was
    // rejected: they would come back for ever.
    // A territory looks only at its triangles: those it started with and
    // those in the slots it was given.
    void collect_unqueued() {
        auto collect = [&](int32_t t) {
            if (tri_.is_free(t) || !bad(t)) return;
            if (territory_ && !tri_.owns(*territory_, t)) return;
            const Candidate c = candidate_of(tri_, t);
            if (!given_up_.count(key_of(c)) && !deferred_.count(key_of(c))) reserve_.push_back(c);
        };
        if (!territory_) {
            for (int32_t t = 0; t < tri_.triangle_slots(); ++t) collect(t);
            return;
        }
        for (int32_t t : *first_owned_) collect(t);
        for (int32_t t : territory_->free_slots_given()) collect(t);
        for (int32_t t = territory_->first_fresh_slot(); t < territory_->fresh_slot_end(); ++t) collect(t);
    }

    // A triangle by its vertices from the smallest on (removal may rebuild
    // it with another first vertex).
    static std::array<int32_t, 3> key_of(const Candidate &c) {
        if (c.v0 < c.v1 && c.v0 < c.v2) return {c.v0, c.v1, c.v2};
        if (c.v1 < c.v2) return {c.v1, c.v2, c.v0};
        return {c.v2, c.v0, c.v1};
    }

    // A territory's candidate that needs more than it owns: left for the
    // serial pass (and not collected again).
    void defer(const Candidate &c) { deferred_.insert(key_of(c)); }

    void give_up(const Candidate &c) {
        ++stats_.rejected;
        given_up_.insert(key_of(c));
    }


    // Classifies the fan of a new vertex and queues its bad triangles; the
    // bad triangles beside its good ones have just joined the front.
    void after_insertion(int32_t v) {
        tri_.for_each_in_star(v, [&](int32_t t) { classify(t); });
        tri_.for_each_in_star(v, [&](int32_t t) {
            if (bad(t)) {
                // Off the front, it waits only while no front exists (the
                // reserve would fill with triangles the front soon destroys).
                if (on_front(t)) join_front(t);
                else if (front_.empty()) reserve_.push_back(candidate_of(tri_, t));
                return;
            }
            int32_t across = tri_.neighbour(t, tri_.local_index(t, v));
            if (bad(across)) join_front(across);
        });
    }

    void refine(const Candidate &c) {
        // A narrow feature caps the lengths the point is placed and filtered
        // by, which h about it (much larger) would set.
        const double feature = state_[c.t] & kNarrowFeature ? narrow_feature_size(c.t)
                                                            : std::numeric_limits<double>::infinity();
        double target = 0;
        Vec3 p = place(c.t, &target);
        if (feature < target) {
            target = feature;
            p = shortest_edge_point(c.t, &target, feature);
        }
        int32_t arc = -1;
        RestrictedEdge enc;
        const bool near = options_.gamma && near_gamma(*options_.gamma, p, kEncroachReach * target);
        const Encroach encroach =
            near ? encroached_edge(tri_, territory_, p, c.t, *options_.gamma, &enc, encroach_) : Encroach::none;
        if (encroach == Encroach::deferred) return defer(c);
        if (encroach == Encroach::encroached) {
            if (enc.radius < options_.filter.on_arc(enc.arc) * h_(enc.centre)) {
                give_up(c);  // left as it is: refining would over-refine Gamma
                return;
            }
            p = enc.centre, arc = enc.arc;
        }
        // How far the insertion may change dual edges: its cavity holds t,
        // whose dual edges lie within about 2 r_t of p, and the new
        // triangles, within about 2 r < 2 alpha h / sqrt(3) (1.54 h).
        double change_reach = 1.2 * options_.alpha * target;
        if (options_.gamma) {
            double r, e;
            triangle_size(tri_, c.t, &r, &e);
            change_reach = std::max(change_reach, 2 * r);
        }
        const double filter = options_.filter.on_arc(arc);
        int32_t v = tri::Triangulation::kNone;
        if (territory_) {
            if (!insert_in_territory(c, p, filter, feature, &v)) return;
        } else {
            v = insert_serially(p, c.t);
            if (!tri_.in_triangulation(v)) {
                give_up(c);
                return;
            }
        }
        // A point this close to an existing vertex (one on Gamma, placed
        // where the front did not expect it) would over-refine: take it back,
        // and re-measure the re-triangulated hole (not queued again).
        if (!territory_ && nearest_neighbour(tri_, v) < filter * std::min(h_(p), feature)) {
            const std::vector<int32_t> link = tri_.link(v);
            tri_.remove(v);
            if (options_.free_vertex_slots) options_.free_vertex_slots->push_back(v);
            for (int32_t u : link) tri_.for_each_in_star(u, [&](int32_t t) { classify(t); });
            give_up(c);
            return;
        }
        if (options_.on_gamma) {
            if (!territory_) options_.on_gamma->resize(static_cast<size_t>(tri_.vertex_slots()), -1);
            (*options_.on_gamma)[v] = arc;  // (a territory's slots are there, and its own)
        }
        ++stats_.inserted;
        // Only within that reach of Gamma may it have changed Tri|Gamma.
        // (Not near within the encroachment reach, p unmoved: not near within
        // less either.)
        const bool may_reach = near || change_reach > kEncroachReach * target;
        if (options_.gamma && may_reach && near_gamma(*options_.gamma, p, change_reach))
            stats_.near_gamma.push_back(v);
        after_insertion(v);
    }

    int32_t insert_serially(const Vec3 &p, int32_t hint) {
        std::vector<int32_t> *slots = options_.free_vertex_slots;
        if (!slots || slots->empty()) return tri_.insert(p, 0.0, stats_.next_id++, nullptr, hint);
        const int32_t v = tri_.insert_into_removed(slots->back(), p, 0.0, stats_.next_id++, nullptr, hint);
        slots->pop_back();
        return v;
    }

    // The territory's insertion, with the serial path's proximity rule tested
    // before it commits (the link of the new vertex holds its nearest
    // neighbour): false when the candidate is left, given up or deferred.
    bool insert_in_territory(const Candidate &c, const Vec3 &p, double filter, double feature, int32_t *v) {
        const double min_arc = filter * std::min(h_(p), feature);
        const double min_chord = min_arc < M_PI ? 2 * std::sin(0.5 * min_arc) : 2.0;
        switch (tri_.insert_in(*territory_, p, c.t, min_chord, v)) {
            case tri::Triangulation::TerritoryInsert::inserted:
                return true;
            case tri::Triangulation::TerritoryInsert::deferred:
                defer(c);
                return false;
            case tri::Triangulation::TerritoryInsert::too_close:
            case tri::Triangulation::TerritoryInsert::hidden:
                break;
        }
        give_up(c);
        return false;
    }

    // The new point for bad triangle t, and the spacing there (*target).
    Vec3 place(int32_t t, double *target) {
        Vec3 p;
        if (frontal_point(t, &p, target)) return p;
        return shortest_edge_point(t, target);
    }

    // On the front edge's bisector, on t's side: the apex of the triangle
    // whose new edges have length h, or t's circumcentre if nearer; only
    // inside t's circumcircle (so that t is in the cavity). The front edge
    // is the one shared with a good triangle whose length is nearest h.
    bool frontal_point(int32_t t, Vec3 *p, double *target) {
        int k_front = -1;
        double best = 1e300, e_front = 0, h_front = 0;
        for (int k = 0; k < 3; ++k) {
            if (bad(tri_.neighbour(t, k))) continue;
            Vec3 a = tri_.direction(tri_.vertex(t, (k + 1) % 3)), b = tri_.direction(tri_.vertex(t, (k + 2) % 3));
            const double e = geom::arc_length(a, b), h_mid = h_(geom::normalized(a + b));
            const double score = std::fabs(e - h_mid);
            if (score < best) best = score, k_front = k, e_front = e, h_front = h_mid;
        }
        if (k_front < 0) return false;
        const Vec3 a = tri_.direction(tri_.vertex(t, (k_front + 1) % 3));
        const Vec3 b = tri_.direction(tri_.vertex(t, (k_front + 2) % 3));
        const Vec3 m = geom::normalized(a + b);
        Vec3 side = geom::normalized(geom::cross(a, b));  // the bisector's tangent at m
        if (geom::dot(side, tri_.direction(tri_.vertex(t, k_front))) < 0) side = -1.0 * side;
        const Vec3 centre = tri_.orthocentre(t);
        const double d_centre = std::atan2(geom::dot(centre, side), geom::dot(centre, m));  // signed
        const double radius = geom::arc_length(centre, a);
        *target = h_front;  // h at m
        double d = std::min(frontal_height(*target, e_front), shape_height(e_front));
        if (d_centre > 0) d = std::min(d, d_centre);
        if (!(d > 1e-3 * e_front && d < 0.98 * (radius + d_centre))) return false;
        *p = geom::normalized(std::cos(d) * m + std::sin(d) * side);
        // Beside an obtuse apex (circumcentre across the front edge) the
        // point may come close to the apex: the other rule then does better.
        const Vec3 apex = tri_.direction(tri_.vertex(t, k_front));
        return geom::arc_length(*p, apex) >= options_.filter.filter * *target;
    }

    // The earlier rule, for triangles off the front (or whose front point
    // would miss them): on the bisector of the shortest edge towards the
    // circumcentre, at the least of the circumcentre, the off-centre of
    // radius-edge ratio rho and the frontal apex.
    Vec3 shortest_edge_point(int32_t t, double *target,
                             double feature = std::numeric_limits<double>::infinity()) {
        int k_short = 0;
        double e_short = 1e300;
        for (int k = 0; k < 3; ++k) {
            double e = geom::arc_length(tri_.direction(tri_.vertex(t, (k + 1) % 3)),
                                        tri_.direction(tri_.vertex(t, (k + 2) % 3)));
            if (e < e_short) e_short = e, k_short = k;
        }
        Vec3 a = tri_.direction(tri_.vertex(t, (k_short + 1) % 3));
        Vec3 b = tri_.direction(tri_.vertex(t, (k_short + 2) % 3));
        Vec3 m = geom::normalized(a + b);
        Vec3 centre = tri_.orthocentre(t);
        double d_centre = geom::arc_length(m, centre);
        *target = std::min(h_(m), feature);
        double d = std::min({d_centre, shape_height(e_short), frontal_height(*target, e_short)});
        if (d <= 1e-3 * e_short) d = d_centre;
        return towards(m, centre, d);
    }

    // Height over an edge of length e of the apex whose two edges have
    // length target (spherical right triangle: cos(target) = cos(e/2) cos(d)).
    static double frontal_height(double target, double e) {
        double half = 0.5 * e;
        return target > half ? std::acos(std::min(1.0, std::cos(target) / std::cos(half))) : 0.0;
    }
    // Height of the off-centre whose triangle has radius-edge ratio rho.
    double shape_height(double e) const {
        return e * std::sqrt(options_.rho * options_.rho - 0.25);
    }

    Context &ctx_;
    tri::Triangulation &tri_;
    const SpacingRadians &h_;
    const SurfaceOptions &options_;
    SurfaceStats stats_;
    std::vector<uint8_t> &state_;
    Territory *territory_;
    const std::vector<int32_t> *first_owned_ = nullptr;  // a territory's at its start (run's queue)
    std::deque<Candidate> front_, reserve_;
    std::set<std::array<int32_t, 3>> given_up_;  // candidates whose point was rejected
    std::set<std::array<int32_t, 3>> deferred_;  // a territory's, left for the serial pass
    EncroachLists encroach_;                      // encroached_edge's lists
};


// Refinement by territories (Triangulation::Territory), for the first
// surface pass of a big mesh: the refinement in parallel, the same for any
// number of threads.
//  1. A coarse serial pass at kSeedSpacing times the spacing (size bound
//     only) gives every part of the sphere vertices, 1 in about
//     kSeedSpacing^2 of the final ones, so that a territory owns most
//     triangles of its part from the start.
//  2. The key space is cut into kTerritories runs of about equal expected
//     work (the bad triangles' areas over the area of a cell of spacing h,
//     summed along the key order of their centroids), each territory with
//     room for its expected vertices (it leaves the rest).
//  3. The territories refine at once, each as the serial pass does (its own
//     front, reserve and given-up candidates) over the triangles it owns.
//     A candidate that needs a triangle it does not own is left.
//  4. Closing them moves their vertices down into consecutive slots. Steps 2
//     and 3 run again in a second layout (the keys of a turned sphere), whose
//     borders cross the first's, so that the bands left along the first
//     borders are mostly inside a territory now.
//  5. A serial pass refines what is still left.
// The seeds are sparse enough not to disturb the fronts much: at 16 h the
// refined uniform 30 km mesh has 4.2 % of its triangles obtuse, against 4.5 %
// with one front from one seed (7.6 % with seeds at 4 h).
constexpr double kSeedSpacing = 16;
constexpr int kTerritories = 16;
constexpr int kLayouts = 2;
// Below this many seed vertices per territory, the serial pass does it all.
constexpr int64_t kMinSeedsPerTerritory = 32;

struct TerritoryPlan {
    std::vector<uint32_t> cuts;
    std::vector<int32_t> budget;
};

// Cuts by expected work: the cells still to come in each bad triangle.
TerritoryPlan plan_territories(Context &ctx, const tri::Triangulation &tri, const SpacingRadians &h,
                               const std::vector<uint8_t> &state, int layout) {
    const int32_t slots = tri.triangle_slots();
    std::vector<std::pair<uint32_t, double>> work(static_cast<size_t>(slots), {~uint32_t(0), 0.0});
    ctx.parallel_for_with_heartbeat("refine surface", slots, 256, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t) {
            if (tri.is_free(static_cast<int32_t>(t)) || !(state[t] & kBad)) continue;
            const Vec3 a = tri.direction(tri.vertex(t, 0)), p = tri.direction(tri.vertex(t, 1)),
                       c = tri.direction(tri.vertex(t, 2));
            const Vec3 centroid = geom::normalized(a + p + c);
            // A spacing that fails here counts no work: the refinement
            // reports it where it meets it, in a fixed order.
            double ht = 0;
            try {
                ht = h(centroid);
            } catch (...) {
            }
            const double area = std::fabs(geom::signed_triangle_area(a, p, c));
            // A cell of spacing h covers (sqrt(3) / 2) h^2.
            const double cells = ht > 0 && std::isfinite(ht) ? area / (0.8660254 * ht * ht) : 0.0;
            work[t] = {tri::Triangulation::territory_key(centroid, layout), std::min(cells, 1e9)};
        }
    });
    // Only the bad triangles count: the good ones and free slots (key ~0)
    // would sort last and be skipped.
    work.erase(std::remove_if(work.begin(), work.end(), [](const auto &w) { return w.first == ~uint32_t(0); }),
               work.end());
    std::sort(work.begin(), work.end());
    TerritoryPlan plan;
    double expected = 0;  // vertices
    for (const auto &w : work) expected += w.second;
    double sum = 0, since_cut = 0;
    auto budget = [](double cells) { return static_cast<int32_t>(std::min(cells + 256, 1e8)); };
    for (const auto &w : work) {
        const bool cut_due = sum >= expected * static_cast<double>(plan.cuts.size() + 1) / kTerritories;
        if (plan.cuts.size() + 1 < kTerritories && cut_due && (plan.cuts.empty() || w.first > plan.cuts.back())) {
            plan.cuts.push_back(w.first);
            plan.budget.push_back(budget(since_cut));
            since_cut = 0;
        }
        sum += w.second, since_cut += w.second;
    }
    plan.budget.push_back(budget(since_cut));
    return plan;
}

// Whether any live triangle is bad: territories would find nothing to do
// otherwise, and opening them grows the triangulation's arrays.
bool any_bad(Context &ctx, const tri::Triangulation &tri, const std::vector<uint8_t> &state) {
    std::atomic<bool> found{false};
    ctx.parallel_for(static_cast<int64_t>(state.size()), 1 << 16, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e && !found.load(std::memory_order_relaxed); ++t)
            if ((state[t] & kBad) && !tri.is_free(static_cast<int32_t>(t))) found.store(true, std::memory_order_relaxed);
    });
    return found.load();
}

// Appends b's near-Gamma vertices and counts to a's, and takes its next id.
void add_stats(SurfaceStats &a, SurfaceStats &&b) {
    a.inserted += b.inserted, a.rejected += b.rejected;
    a.near_gamma.insert(a.near_gamma.end(), b.near_gamma.begin(), b.near_gamma.end());
    a.next_id = b.next_id;
}

using GivenUp = std::set<std::array<int32_t, 3>>;

// The territories at work: each refines what it owns (unowned: the
// triangles none owns). Throws the first territory's error, if any.
void work_in_territories(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                         const SurfaceOptions &options, std::vector<uint8_t> &state, const GivenUp &given_up,
                         std::vector<tri::Triangulation::Territory> &territories,
                         std::vector<std::unique_ptr<SurfaceRefiner>> &refiners, std::vector<SurfaceStats> &part,
                         std::vector<int32_t> &unowned) {
    const size_t n = territories.size();
    if (options.on_gamma) options.on_gamma->resize(static_cast<size_t>(tri.vertex_slots()), -1);
    // Each triangle to the territory that owns it, if any; the others do
    // not count as good (a front) while the territories work.
    state.resize(static_cast<size_t>(tri.triangle_slots()), kGood);
    std::vector<std::vector<int32_t>> owned(n);
    for (int32_t t = 0; t < tri.triangle_slots(); ++t) {
        if (tri.is_free(t)) continue;
        size_t g = 0;
        while (g < n && !tri.owns(territories[g], t)) ++g;
        if (g < n) {
            owned[g].push_back(t);
        } else {
            unowned.push_back(t);
            state[t] = kBad;
        }
    }
    part.resize(n);
    refiners.resize(n);
    std::vector<std::exception_ptr> error(n);
    const std::vector<int32_t> none;
    ctx.parallel_for(static_cast<int64_t>(n), 1, [&](int64_t b, int64_t e) {
        for (int64_t g = b; g < e; ++g) {
            try {
                refiners[g] = std::make_unique<SurfaceRefiner>(ctx, tri, h, options, 0, state, &territories[g]);
                refiners[g]->take_given_up(GivenUp(given_up));
                part[g] = refiners[g]->run(none, owned[g]);
            } catch (...) {
                error[g] = std::current_exception();
            }
        }
    });
    for (const std::exception_ptr &x : error)  // the first territory's (not the first thread's)
        if (x) std::rethrow_exception(x);
}

// Gamma arcs of the vertices the territories moved down.
void move_on_gamma(const SurfaceOptions &options, const tri::Triangulation &tri,
                   const tri::Triangulation::TerritoryClose &moved) {
    if (!options.on_gamma) return;
    std::vector<int32_t> &on = *options.on_gamma;
    for (size_t i = 0; i < moved.new_slot.size(); ++i)
        if (moved.new_slot[i] != tri::Triangulation::kNone) on[moved.new_slot[i]] = on[moved.first_slot + i];
    on.resize(static_cast<size_t>(tri.vertex_slots()));
}

// One layout's territories (steps 2-4): refines in parallel what they own,
// then closes them. `state` is every live triangle's (the unowned ones are
// measured when this returns); `given_up` gains the territories' given-up
// candidates.
void refine_in_territories(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                           const SurfaceOptions &options, std::vector<uint8_t> &state,
                           GivenUp &given_up, int layout, SurfaceStats &stats) {
    ctx.progress("refine surface", 0.0);  // (a cancel point between layouts)
    if (!any_bad(ctx, tri, state)) return;  // (a lattice start where the spacing is flat)
    const TerritoryPlan plan = plan_territories(ctx, tri, h, state, layout);
    std::vector<tri::Triangulation::Territory> territories =
        tri.open_territories(ctx, plan.cuts, plan.budget, stats.next_id, layout);
    std::vector<std::unique_ptr<SurfaceRefiner>> refiners;
    std::vector<SurfaceStats> part;
    std::vector<int32_t> unowned;
    try {
        work_in_territories(ctx, tri, h, options, state, given_up, territories, refiners, part, unowned);
    } catch (...) {
        move_on_gamma(options, tri, tri.close_territories(ctx, territories));  // a valid mesh again
        throw;
    }
    const tri::Triangulation::TerritoryClose moved = tri.close_territories(ctx, territories);
    move_on_gamma(options, tri, moved);
    auto new_slot = [&](int32_t v) { return v >= moved.first_slot ? moved.new_slot[v - moved.first_slot] : v; };
    for (size_t g = 0; g < part.size(); ++g) {
        stats.by_territories += part[g].inserted;
        for (int32_t &v : part[g].near_gamma) v = new_slot(v);
        part[g].next_id = moved.next_id;
        add_stats(stats, std::move(part[g]));
        refiners[g]->hand_over_given_up(given_up, new_slot);
    }
    refiners.clear();
    for (uint8_t &s : state) s &= ~kOnFront;
    // The unowned triangles, measured (no territory changed them).
    SurfaceRefiner(ctx, tri, h, options, moved.next_id, state).measure(unowned);
}

SurfaceStats refine_by_territories(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                                   const SurfaceOptions &options, int32_t next_id) {
    std::vector<uint8_t> state;
    std::vector<int32_t> all = tri.live_triangles(ctx);
    // Seeds only serve the territories. A seed is a point no front placed:
    // the fronts that meet around it leave 5-7 defects there (measurements:
    // tools/bench/HISTORY.md). When they are too few for territories (a
    // small mesh), the serial pass starts from the triangulation as it was
    // before them.
    // (Seeds only add vertices: a mesh with enough already needs no copy.)
    const bool enough_already = tri.vertex_count() >= kTerritories * kMinSeedsPerTerritory;
    tri::Triangulation unseeded = enough_already ? tri::Triangulation{} : tri;
    const std::vector<int32_t> on_gamma_unseeded =
        options.on_gamma && !enough_already ? *options.on_gamma : std::vector<int32_t>{};
    SurfaceOptions seed_options = options;
    seed_options.rho = std::numeric_limits<double>::infinity();  // the size bound only
    const SpacingRadians seed_spacing = [&h](const Vec3 &p) { return kSeedSpacing * h(p); };
    seed_options.smallest_scale = kSeedSpacing;
    SurfaceStats stats = SurfaceRefiner(ctx, tri, seed_spacing, seed_options, next_id, state).run(all, all);

    all = tri.live_triangles(ctx);
    state.clear();
    GivenUp given_up;
    if (tri.vertex_count() >= kTerritories * kMinSeedsPerTerritory) {
        SurfaceRefiner(ctx, tri, h, options, stats.next_id, state).measure(all);
        for (int layout = 0; layout < kLayouts; ++layout)
            refine_in_territories(ctx, tri, h, options, state, given_up, layout, stats);
        all = tri.live_triangles(ctx);
    } else {
        if (enough_already) fail(UM_ERR_INTERNAL, "refine surface: the seed pass took vertices out");
        tri = std::move(unseeded);
        if (options.on_gamma) *options.on_gamma = on_gamma_unseeded;
        stats = SurfaceStats{};
        stats.next_id = next_id;
        all = tri.live_triangles(ctx);
    }
    // What is left (all of it for a small mesh), serially.
    SurfaceRefiner last(ctx, tri, h, options, stats.next_id, state);
    last.take_given_up(std::move(given_up));
    const std::vector<int32_t> none;
    add_stats(stats, last.run(state.empty() ? all : none, all));
    // bench_refine reads this line.
    ctx.log(UM_LOG_DEBUG, concat("refine surface: ", stats.inserted, " points, ", stats.by_territories,
                                 " of them by territories"));
    return stats;
}

}  // namespace

SurfaceStats refine_surface(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                            const SurfaceOptions &options, int32_t next_id,
                            const std::vector<int32_t> *around) {
    if (!around) return refine_by_territories(ctx, tri, h, options, next_id);
    std::vector<uint8_t> state;
    const std::vector<int32_t> first = tri.triangles_around(*around);  // the others are known to be good
    return SurfaceRefiner(ctx, tri, h, options, next_id, state).run(first, first);
}

}  // namespace um::refine
