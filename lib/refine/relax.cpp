// Edge-length relaxation after refinement (see relax.hpp).
#include "refine/relax.hpp"

#include <algorithm>
#include <cmath>

#include "geom/predicates.hpp"

namespace um::refine {

using geom::Vec3;

namespace {

// Length of the arc a-b over h at its midpoint.
double length_ratio(const Vec3 &a, const Vec3 &b, const SpacingRadians &h) {
    return geom::arc_length(a, b) / h(geom::normalized(a + b));
}

struct Band {
    double lower, upper;
    bool holds(double r) const { return r > lower && r < upper; }
    double excess(double r) const { return r <= lower ? lower - r : (r >= upper ? r - upper : 0.0); }
};

// A vertex's edges outside the band: how many, and by how much in all (in
// units of h), compared in that order.
struct BandScore {
    int outside = 0;
    double excess = 0;
    static BandScore vetoed() { return {1 << 30, 0.0}; }
    bool better_than(const BandScore &o) const {
        return outside != o.outside ? outside < o.outside : excess < o.excess - 1e-12;
    }
};

// Whether an arc of Gamma has its box within 4 h of x (a chord, a little
// shorter than the arc): a box test, quicker than a distance.
bool near_gamma(const Vec3 &x, const SpacingRadians &h, const RelaxOptions &o) {
    if (!o.gamma || o.gamma->size() == 0) return false;
    geom::Box near;
    near.add(x);
    near.grow(4 * h(x));
    return o.gamma->any_overlaps(near);
}

// Vertices on Gamma stay, and so do those whose move could change a dual edge
// near Gamma: a move changes the orthocentres of the triangles around v
// (within r < 0.77 h of their corners), so the dual edges it changes lie
// within about 2.2 h of v; 4 h leaves room for varying h.
bool stays_put(const tri::Triangulation &tri, int32_t v, const SpacingRadians &h,
               const RelaxOptions &o) {
    if (o.on_gamma) {
        auto on = [&](int32_t u) { return static_cast<size_t>(u) < o.on_gamma->size() && (*o.on_gamma)[u] >= 0; };
        if (on(v)) return true;
        bool near = false;
        tri.for_each_in_star(v, [&](int32_t t) {
            for (int k = 0; k < 3; ++k) near = near || on(tri.vertex(t, k));
        });
        if (near) return true;
    }
    return near_gamma(tri.direction(v), h, o);
}

// The vertices within `rings` edges of `seeds`, ascending. *mask (one byte
// per vertex slot) must be clear for them on entry; they are flagged in it.
std::vector<int32_t> rings_around(const tri::Triangulation &tri, const std::vector<int32_t> &seeds,
                                  int rings, std::vector<uint8_t> *mask) {
    std::vector<int32_t> found;
    for (int32_t v : seeds)
        if (!(*mask)[v]) (*mask)[v] = 1, found.push_back(v);
    size_t ring_begin = 0;
    for (int ring = 0; ring < rings; ++ring) {
        const size_t ring_end = found.size();
        for (size_t i = ring_begin; i < ring_end; ++i)
            tri.for_each_in_star(found[i], [&](int32_t t) {
                for (int k = 0; k < 3; ++k) {
                    const int32_t u = tri.vertex(t, k);
                    if (!(*mask)[u]) (*mask)[u] = 1, found.push_back(u);
                }
            });
        ring_begin = ring_end;
    }
    std::sort(found.begin(), found.end());
    return found;
}

class Relaxer {
public:
    Relaxer(tri::Triangulation &tri, const SpacingRadians &h, const RelaxOptions &o)
        : tri_(tri), h_(h), o_(o), hard_{o.lower, o.upper}, target_(hard_),
          state_(static_cast<size_t>(tri.vertex_slots()), kUnknown) {}

    void set_target(const Band &band) { target_ = band; }
    int64_t moves() const { return moves_; }

    // Whether v and a neighbour across an edge outside `band` could both
    // move: only then can room made around them help.
    bool stuck_between_free(int32_t v, const Band &band) {
        if (fixed(v)) return false;
        gather_link(v);
        const Vec3 x = tri_.direction(v);
        for (int32_t j : link_)
            if (!band.holds(length_ratio(x, tri_.direction(j), h_)) && !fixed(j)) return true;
        return false;
    }
    // The same for many at once, in parallel.
    void settle_fixed(Context &ctx, const std::vector<int32_t> &vertices) {
        ctx.parallel_for(static_cast<int64_t>(vertices.size()), 1024, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) fixed(vertices[i]);  // distinct slots: no race
        });
    }
    // The vertices moved so far (each once, ascending).
    std::vector<int32_t> moved() const {
        std::vector<int32_t> m = moved_;
        std::sort(m.begin(), m.end());
        m.erase(std::unique(m.begin(), m.end()), m.end());
        return m;
    }

    // A crowded spot: when an edge of v to a free neighbour is too short,
    // v is removed if the hole's new triangles meet the surface criteria
    // with their new edges inside [lower, upper]; else it is put back at the
    // circumcentre of the hole's largest triangle (where the surface pass
    // would put a point) if that leaves every triangle around within the
    // criteria and fewer edges there outside the band. Appends the link to
    // *opened when it changed anything.
    bool try_removal(int32_t v, std::vector<int32_t> *opened) {
        if (fixed(v) || !tri_.in_triangulation(v)) return false;
        gather_link(v);
        const Vec3 x = tri_.direction(v);
        bool crowded = false;
        for (int32_t j : link_) crowded = crowded || (length_ratio(x, tri_.direction(j), h_) <= hard_.lower && !fixed(j));
        if (!crowded) return false;
        const std::vector<int32_t> link = link_;
        const std::vector<int32_t> around = two_rings(v);
        const RegionScore before = region_score(around);
        const Vec3 stored = tri_.lifted(v);
        int32_t hint = tri_.remove(v);
        if (hole_is_good(link)) {
            state_[v] = kFixed;  // gone: nothing more to do there
            ++removed_;
            opened->insert(opened->end(), link.begin(), link.end());
            return true;
        }
        const Vec3 centre = largest_circumcentre(link, &hint);
        if (near_gamma(centre, h_, o_)) {  // the 4 h margin holds where it goes too
            tri_.restore_removed(v, hint);
            return false;
        }
        tri_.set_lifted(v, centre);  // weight 0: the lifted point is the direction
        tri_.restore_removed(v, hint);
        const RegionScore after = region_score(around);
        if (after.improves_on(before, hard_)) {
            ++replaced_;
            opened->insert(opened->end(), around.begin(), around.end());
            return true;
        }
        hint = tri_.remove(v);
        tri_.set_lifted(v, stored);  // bit for bit: the same regular triangulation again
        tri_.restore_removed(v, hint);
        return collapse_shortest_edge(v, around, before, opened);
    }
    int64_t removed() const { return removed_; }
    int64_t replaced() const { return replaced_; }

    // Fixed vertices are left out: they never move.
    void relax(int32_t v, std::vector<int32_t> &still_outside) {
        if (fixed(v)) return;
        gather_link(v);
        const Vec3 x = tri_.direction(v);
        const BandScore old = score_here(x);
        if (old.outside == 0) return;
        try_moves(v, x, old);
        const Vec3 now = tri_.direction(v);
        for (int32_t j : link_)
            if (!target_.holds(length_ratio(now, tri_.direction(j), h_))) {
                still_outside.push_back(v);
                still_outside.push_back(j);
            }
    }

private:
    enum : uint8_t { kUnknown, kFree, kFixed };
    // Per link vertex, its edge's state before the move.
    enum : uint8_t { kOutsideTarget = 1, kOutsideHard = 2 };

    void gather_link(int32_t v) {
        link_.clear();
        tri_.for_each_neighbour(v, [&](int32_t w) { link_.push_back(w); });
    }

    uint8_t status(double r) const {
        return uint8_t((target_.holds(r) ? 0 : kOutsideTarget) | (hard_.holds(r) ? 0 : kOutsideHard));
    }

    // The score where v is, remembering each edge's status, length and h.
    BandScore score_here(const Vec3 &x) {
        status_.clear(), length_.clear(), spacing_.clear();
        BandScore s;
        for (int32_t j : link_) {
            const Vec3 y = tri_.direction(j);
            length_.push_back(geom::arc_length(x, y));
            spacing_.push_back(h_(geom::normalized(x + y)));
            const double r = length_.back() / spacing_.back();
            status_.push_back(status(r));
            if (!target_.holds(r)) ++s.outside, s.excess += target_.excess(r);
        }
        return s;
    }

    // The score at x, vetoed when an edge inside a band there would leave
    // it, or one outside [lower, upper] would go farther out (so no edge ever
    // gets worse: none shorter than the shortest before, say).
    BandScore score_at(const Vec3 &x) const {
        BandScore s;
        for (size_t i = 0; i < link_.size(); ++i) {
            const double r = length_ratio(x, tri_.direction(link_[i]), h_);
            if ((status(r) & ~status_[i]) != 0) return BandScore::vetoed();
            if (hard_.excess(r) > hard_.excess(length_[i] / spacing_[i])) return BandScore::vetoed();
            if (!target_.holds(r)) ++s.outside, s.excess += target_.excess(r);
        }
        return s;
    }

    // Halving steps along two pulls in turn: every edge's, and only the edges
    // outside the target's (when the others are nearly balanced, they would
    // only hold v back). A step that would take v within 4 h of Gamma (moves
    // add up) is not tried.
    void try_moves(int32_t v, const Vec3 &x, const BandScore &old) {
        const Vec3 stored = tri_.lifted(v);  // put back bit for bit when a trial fails
        const Vec3 pulls[2] = {pull_at(x, false), pull_at(x, true)};
        for (int trial = 0; trial < 8; ++trial) {
            const double step = 0.5 / double(1 << (trial / 2));
            const Vec3 y = geom::normalized(x + step * pulls[trial % 2]);
            if (!score_at(y).better_than(old) || near_gamma(y, h_, o_)) continue;
            tri_.set_lifted(v, y);  // weight 0: the lifted point is the direction
            if (star_is_valid(v)) {
                ++moves_;
                moved_.push_back(v);
                return;
            }
            tri_.set_lifted(v, stored);
        }
    }

    // Springs along the edges, each pulling (or pushing) by its length error,
    // in the tangent plane at x: an edge of 1.4 h pulls 0.4 h towards its
    // other end, and half a step of that, with the other end doing the same,
    // makes it about h.
    Vec3 pull_at(const Vec3 &x, bool outside_only) const {
        Vec3 f{0, 0, 0};
        for (size_t i = 0; i < link_.size(); ++i) {
            if (outside_only && (status_[i] & kOutsideTarget) == 0) continue;
            const Vec3 y = tri_.direction(link_[i]);
            const Vec3 tangent = y - geom::dot(x, y) * x;
            const double norm = geom::norm(tangent);
            if (norm > 0) f = f + ((length_[i] - spacing_[i]) / norm) * tangent;
        }
        return f;
    }

    bool fixed(int32_t v) {
        if (state_[v] == kUnknown) state_[v] = stays_put(tri_, v, h_, o_) ? kFixed : kFree;
        return state_[v] == kFixed;
    }

    struct RegionScore {
        int bad_triangles = 0, outside_edges = 0;
        double shortest = 1e300, longest = 0;  // edges, in units of h
        // No worse anywhere, and better in all: no triangle outside the
        // criteria, fewer edges outside the band, none shorter or longer
        // beyond it than the extremes before.
        bool improves_on(const RegionScore &o, const Band &band) const {
            return bad_triangles == 0 && outside_edges < o.outside_edges &&
                   shortest >= std::min(o.shortest, band.lower) && longest <= std::max(o.longest, band.upper);
        }
    };
    // Over the triangles around `vertices`: those outside the surface
    // criteria, and their edges outside [lower, upper], each once.
    RegionScore region_score(const std::vector<int32_t> &vertices) const {
        RegionScore s;
        std::vector<std::pair<int32_t, int32_t>> outside;
        for (int32_t u : vertices)
            tri_.for_each_in_star(u, [&](int32_t t) {
                if (!meets_criteria(t)) ++s.bad_triangles;
                for (int k = 0; k < 3; ++k) {
                    const int32_t a = tri_.vertex(t, k == 2 ? 0 : k + 1), b = tri_.vertex(t, k == 0 ? 2 : k - 1);
                    const double r = length_ratio(tri_.direction(a), tri_.direction(b), h_);
                    s.shortest = std::min(s.shortest, r), s.longest = std::max(s.longest, r);
                    if (!hard_.holds(r)) outside.push_back({std::min(a, b), std::max(a, b)});
                }
            });
        std::sort(outside.begin(), outside.end());
        s.outside_edges = static_cast<int>(std::unique(outside.begin(), outside.end()) - outside.begin());
        // A triangle is seen from each of its vertices in the list: the count
        // is only compared with itself, over the same list.
        return s;
    }
    // The last resort for a crowded spot: v's shortest edge to a free
    // neighbour j collapses, v removed and j put at the edge's midpoint, if
    // that improves the region (the two rings of v, which hold j's star).
    bool collapse_shortest_edge(int32_t v, const std::vector<int32_t> &around,
                                const RegionScore &before, std::vector<int32_t> *opened) {
        gather_link(v);
        const Vec3 x = tri_.direction(v);
        int32_t j = -1;
        double shortest = hard_.lower;
        for (int32_t u : link_) {
            const double r = length_ratio(x, tri_.direction(u), h_);
            if (r <= shortest && !fixed(u)) j = u, shortest = r;
        }
        if (j < 0) return false;
        const Vec3 mid = geom::normalized(x + tri_.direction(j));
        if (near_gamma(mid, h_, o_)) return false;
        const Vec3 stored_j = tri_.lifted(j);
        tri_.remove(v);
        int32_t hint = tri_.remove(j);
        tri_.set_lifted(j, mid);  // weight 0
        tri_.restore_removed(j, hint);
        if (region_score(around).improves_on(before, hard_)) {
            state_[v] = kFixed;
            ++removed_;
            moved_.push_back(j);
            opened->insert(opened->end(), around.begin(), around.end());
            return true;
        }
        hint = tri_.remove(j);
        tri_.set_lifted(j, stored_j);
        tri_.restore_removed(j, hint);
        tri_.restore_removed(v, hint);
        return false;
    }

    // Both surface bounds: sqrt(3) r < alpha h (at the circumcentre), r / e_min < rho.
    bool meets_criteria(int32_t t) const {
        double r, e;
        Vec3 centre;
        triangle_size(tri_, t, &r, &e, &centre);
        return std::sqrt(3.0) * r < o_.alpha * h_(centre) && r / e < o_.rho;
    }

    // v and the vertices within two edges of it, ascending.
    std::vector<int32_t> two_rings(int32_t v) {
        if (ring_mask_.empty()) ring_mask_.assign(state_.size(), 0);
        std::vector<int32_t> ring = rings_around(tri_, {v}, 2, &ring_mask_);
        for (int32_t u : ring) ring_mask_[u] = 0;
        return ring;
    }

    // The circumcentre of the largest triangle (against the size bound)
    // around the link vertices; *hint: that triangle.
    Vec3 largest_circumcentre(const std::vector<int32_t> &link, int32_t *hint) const {
        double worst = -1;
        Vec3 best{0, 0, 0};
        for (int32_t j : link)
            tri_.for_each_in_star(j, [&](int32_t t) {
                double r, e;
                Vec3 centre;
                triangle_size(tri_, t, &r, &e, &centre);
                const double size = r / h_(centre);
                if (size > worst) worst = size, best = centre, *hint = t;
            });
        return best;
    }

    // After removing the vertex whose link (counter-clockwise) this was:
    // every triangle around the link within the surface criteria, and every
    // edge between two link vertices that were not neighbours (a new one)
    // inside [lower, upper].
    bool hole_is_good(const std::vector<int32_t> &link) const {
        auto position = [&](int32_t u) {
            return static_cast<int>(std::find(link.begin(), link.end(), u) - link.begin());
        };
        const int n = static_cast<int>(link.size());
        bool ok = true;
        for (int32_t j : link)
            tri_.for_each_in_star(j, [&](int32_t t) {
                if (!ok) return;
                ok = meets_criteria(t);
                for (int k = 0; k < 3 && ok; ++k) {
                    const int32_t a = tri_.vertex(t, k == 2 ? 0 : k + 1), b = tri_.vertex(t, k == 0 ? 2 : k - 1);
                    const int pa = position(a), pb = position(b);
                    if (pa == n || pb == n) continue;
                    const int gap = (pa - pb + n) % n;
                    if (gap == 1 || gap == n - 1) continue;  // a link edge: there before
                    ok = hard_.holds(length_ratio(tri_.direction(a), tri_.direction(b), h_));
                }
            });
        return ok;
    }

    // After moving v: every triangle around it still counter-clockwise, still
    // within the surface criteria, and every edge of them locally regular, so
    // that the triangulation is still the regular one of its points (exact
    // tests).
    bool star_is_valid(int32_t v) const {
        bool ok = true;
        tri_.for_each_in_star(v, [&](int32_t t) {
            if (!ok) return;
            const int i = tri_.local_index(t, v);
            const int32_t a = tri_.vertex(t, i == 2 ? 0 : i + 1), b = tri_.vertex(t, i == 0 ? 2 : i - 1);
            ok = geom::orient_origin(tri_.lifted(a).data(), tri_.lifted(b).data(),
                                     tri_.lifted(v).data()) > 0;
            ok = ok && meets_criteria(t);
            for (int k = 0; k < 3 && ok; ++k) ok = tri_.is_locally_regular(t, k);
        });
        return ok;
    }

    tri::Triangulation &tri_;
    const SpacingRadians &h_;
    const RelaxOptions &o_;
    const Band hard_;
    Band target_;
    std::vector<uint8_t> state_;   // per vertex slot: kUnknown, kFree, kFixed
    std::vector<uint8_t> ring_mask_;  // per vertex slot, clear between calls of two_rings
    std::vector<int32_t> moved_;
    std::vector<int32_t> link_;    // of the vertex being relaxed, counter-clockwise
    std::vector<uint8_t> status_;  // per link vertex, before the move
    std::vector<double> length_, spacing_;  // per link vertex: its edge's length and h, before
    int64_t moves_ = 0, removed_ = 0, replaced_ = 0;
};

// The edges outside `band`, each once (its ends, the smaller first), in
// triangle order.
std::vector<std::pair<int32_t, int32_t>> edges_outside(Context &ctx, const tri::Triangulation &tri,
                                                      const SpacingRadians &h, const Band &band) {
    const int32_t n = tri.triangle_slots();
    std::vector<uint8_t> outside(static_cast<size_t>(n), 0);  // bit k: edge k of the triangle
    ctx.parallel_for_with_heartbeat("refine relax", n, 256, [&](int64_t b, int64_t e) {
        for (int32_t t = static_cast<int32_t>(b); t < e; ++t) {
            if (tri.is_free(t)) continue;
            for (int k = 0; k < 3; ++k) {
                if (tri.neighbour(t, k) < t) continue;  // each edge from its smaller triangle
                const Vec3 a = tri.direction(tri.vertex(t, k == 2 ? 0 : k + 1));
                const Vec3 c = tri.direction(tri.vertex(t, k == 0 ? 2 : k - 1));
                if (!band.holds(length_ratio(a, c, h))) outside[t] |= uint8_t(1u << k);
            }
        }
    });
    std::vector<std::pair<int32_t, int32_t>> edges;
    for (int32_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k)
            if (outside[t] & (1u << k)) {
                const int32_t a = tri.vertex(t, k == 2 ? 0 : k + 1), c = tri.vertex(t, k == 0 ? 2 : k - 1);
                edges.push_back({std::min(a, c), std::max(a, c)});
            }
    return edges;
}

// Their ends, ascending, each once.
std::vector<int32_t> ends_of(const std::vector<std::pair<int32_t, int32_t>> &edges) {
    std::vector<int32_t> ends;
    for (const auto &[a, b] : edges) ends.push_back(a), ends.push_back(b);
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    return ends;
}

}  // namespace

int64_t count_edges_outside(Context &ctx, const tri::Triangulation &tri, const SpacingRadians &h,
                            double lower, double upper) {
    return static_cast<int64_t>(edges_outside(ctx, tri, h, Band{lower, upper}).size());
}

namespace {

// Rounds of relaxation towards `target` from the vertices in `todo`; the
// ends of the edges still outside it are what is left (with `region`, only
// those in it are followed).
std::vector<int32_t> relax_towards(Context &ctx, Relaxer &relaxer, const Band &target,
                                   std::vector<int32_t> todo, int rounds,
                                   const std::vector<uint8_t> *region) {
    relaxer.set_target(target);
    std::vector<int32_t> left;
    for (int round = 0; round < rounds && !todo.empty(); ++round) {
        ctx.progress("refine relax", 0.0);
        left.clear();
        const int64_t moves_before = relaxer.moves();
        for (int32_t v : todo) {
            ctx.heartbeat("refine relax", 0.0);  // (a slow spacing callback: still cancellable)
            relaxer.relax(v, left);
        }
        if (region)
            left.erase(std::remove_if(left.begin(), left.end(), [&](int32_t u) { return !(*region)[u]; }),
                       left.end());
        std::sort(left.begin(), left.end());
        left.erase(std::unique(left.begin(), left.end()), left.end());
        todo.swap(left);
        if (relaxer.moves() == moves_before) break;  // stuck: another round would do the same
    }
    return todo;
}


}  // namespace

RelaxStats relax_edge_lengths(Context &ctx, tri::Triangulation &tri, const SpacingRadians &h,
                              const RelaxOptions &options) {
    ctx.progress("refine relax", 0.0);  // the phase starts (timed by its reports)
    RelaxStats stats;
    const Band hard{options.lower, options.upper};
    Relaxer relaxer(tri, h, options);
    const std::vector<std::pair<int32_t, int32_t>> outside_before = edges_outside(ctx, tri, h, hard);
    stats.outside_before = static_cast<int64_t>(outside_before.size());
    const std::vector<int32_t> ends_before = ends_of(outside_before);
    relaxer.settle_fixed(ctx, ends_before);
    // First the band itself, from the ends of the edges outside it.
    std::vector<int32_t> left = relax_towards(ctx, relaxer, hard, ends_before, options.rounds, nullptr);
    // Where that is stuck, the mesh around is crowded or stretched as a
    // whole: the rings around make room, relaxed towards narrower bands,
    // before the band is tried again; wider rings when that is not enough.
    // What is still too short after that is a crowded spot, a vertex too
    // many: removing one end, or putting it where the hole needs a point,
    // then relaxing around, mends it. A spot that needed that may need it
    // again around its new neighbours: a few attempts while any change.
    std::vector<uint8_t> mask;
    for (int attempt = 0; attempt < options.crowded_attempts && !left.empty(); ++attempt) {
        for (int rings : options.rings) {
            left.erase(std::remove_if(left.begin(), left.end(),
                                      [&](int32_t v) { return !relaxer.stuck_between_free(v, hard); }),
                       left.end());
            if (left.empty()) break;
            mask.assign(static_cast<size_t>(tri.vertex_slots()), 0);
            const std::vector<int32_t> region = rings_around(tri, left, rings, &mask);
            for (double margin : options.margins)
                relax_towards(ctx, relaxer, Band{options.lower + margin, options.upper - margin},
                              region, options.rounds, &mask);
            left = relax_towards(ctx, relaxer, hard, region, options.rounds, nullptr);
        }
        const int64_t changes_before = relaxer.removed() + relaxer.replaced();
        std::vector<int32_t> opened;
        for (int32_t v : left) relaxer.try_removal(v, &opened);
        if (relaxer.removed() + relaxer.replaced() == changes_before) break;
        std::sort(opened.begin(), opened.end());
        opened.erase(std::unique(opened.begin(), opened.end()), opened.end());
        left = relax_towards(ctx, relaxer, hard, opened, options.rounds, nullptr);
    }
    stats.removed = relaxer.removed();
    stats.replaced = relaxer.replaced();
    stats.moves = relaxer.moves();
    // After a removal or a replacement, whose flips may reach a little
    // beyond what they touched, a full count.
    if (stats.removed + stats.replaced > 0) {
        stats.outside_after = count_edges_outside(ctx, tri, h, options.lower, options.upper);
        return stats;
    }
    // Else only moves changed edges, those of the vertices moved: an edge
    // outside the band now was so at the start with neither end moved since,
    // or has a moved end. Count those, each once.
    const std::vector<int32_t> moved = relaxer.moved();
    auto has_moved = [&](int32_t v) { return std::binary_search(moved.begin(), moved.end(), v); };
    for (const auto &[a, b] : outside_before) stats.outside_after += !has_moved(a) && !has_moved(b);
    std::vector<int32_t> outside(moved.size(), 0);
    ctx.parallel_for(static_cast<int64_t>(moved.size()), 1024, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t v = moved[i];
            const Vec3 x = tri.direction(v);
            tri.for_each_in_star(v, [&](int32_t t) {
                const int c = tri.local_index(t, v);
                const int32_t j = tri.vertex(t, c == 2 ? 0 : c + 1);
                if (!hard.holds(length_ratio(x, tri.direction(j), h)) && (v < j || !has_moved(j)))
                    ++outside[i];
            });
        }
    });
    for (int32_t n : outside) stats.outside_after += n;
    return stats;
}

}  // namespace um::refine
