// Obtuse corners on Gamma (the shape phase's support_gamma_corners): a
// vertex off Gamma where one fits, else a vertex on Gamma taken out.
#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

#include "core/error.hpp"
#include "geom/sphere.hpp"
#include "optim/gamma_corners.hpp"
#include "refine/boundary.hpp"
#include "refine/restricted.hpp"

namespace um::optim::detail {

namespace {

// A vertex support_gamma_corners adds may be this close (in units of h) to
// a vertex on Gamma, and collapse_ratio h to others: Gamma's own vertices
// are often closer together than h where it bends. On the coastline case
// at 60 km (before the bisector tries), 0.3 takes the obtuse triangles from
// 668 to 342 (0.4: 359; the collapse ratio, 0.5: 435). Its ODT steps: 3 (6
// mend 4 more). With the neighbours' steps (relax_link) and the removals
// of vertices on Gamma (try_gamma_vertex_removal), 0.2 leaves 40 obtuse
// triangles at 60 km, 11 at 120 km and 16 at 240 km (0.25: 40, 12, 22;
// 0.3: 44, 18 and one off-centre, 18).
constexpr double kCornerEdge = 0.2;
constexpr int kCornerSteps = 3;
// Where a corner vertex is tried when the circumcentre fails: these many h
// from the corner along its bisector, in turn. On the coastline at 60 km:
// 0.6 alone leaves 304 obtuse triangles (0.45: 314, 0.75: 311), then 0.8 and
// 0.45 276 (and 1.0 after those 272).
constexpr double kBisectorSpokes[] = {0.6, 0.8, 0.45};
// ... and across the corner's wedge (corner_sites).
constexpr double kWedgeShares[] = {0.2, 0.35, 0.5, 0.65, 0.8};
constexpr double kWedgeSpokes[] = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
// The first tier of sites (support_gamma_corner): the circumcentre's and
// the bisector's.
constexpr size_t kFirstTierSites = 1 + std::size(kBisectorSpokes);

}  // namespace

// Obtuse corners on Gamma. A vertex on Gamma with a single spoke off it on
// one side shares that side's half turn between two triangles, and a
// triangle across a bend or a narrow inlet with all three vertices on Gamma
// has the bend's angle: no move along Gamma mends either (they are most of
// the obtuse triangles left on coastlines). Each such triangle gets a
// vertex off Gamma near its circumcentre, pulled towards the obtuse corner
// (so strictly inside the circumcircle: the triangle goes, the corner gains
// a spoke and splits its angle), or along the corner's bisector or across
// its wedge (corner_sites), kept only when the triangle is gone, the
// triangles around have no more obtuse ones than before (an obtuse angle moved off Gamma's corner
// is one the sweeps and mends can still reshape: coast + rivers 60 km,
// 277 -> 124 obtuse, against "fewer": Mid-Atlantic 612 -> 318),
// its edges are at least kCornerEdge h to Gamma's vertices and
// collapse_ratio h to others, and every edge along Gamma there is still an
// edge (try_corner_vertex, corner_vertex_helps). Where none is kept, a
// vertex of the triangle on Gamma may be taken out instead
// (try_gamma_vertex_removal). Serial, in slot order, one change per
// neighbourhood (support_gamma_corner); returns the changes (counted in
// s_.stats by kind).
int64_t GammaCorners::support_gamma_corners() {
    if (!s_.gamma) return 0;
    auto gamma_corner = [&](int32_t t) {  // the obtuse corner's index, when on Gamma; else -1
        // (Most triangles have no vertex on Gamma: known before any geometry.)
        const int32_t v[3] = {s_.tri.vertex(t, 0), s_.tri.vertex(t, 1), s_.tri.vertex(t, 2)};
        if (s_.on_segment[v[0]] < 0 && s_.on_segment[v[1]] < 0 && s_.on_segment[v[2]] < 0) return -1;
        if (s_.touches_cover(t)) return -1;
        Vec3 x[3];
        for (int k = 0; k < 3; ++k) x[k] = s_.tri.direction(v[k]);
        double l[3];
        for (int k = 0; k < 3; ++k) l[k] = geom::dot(x[(k + 1) % 3] - x[(k + 2) % 3], x[(k + 1) % 3] - x[(k + 2) % 3]);
        const int k = l[0] >= l[1] && l[0] >= l[2] ? 0 : (l[1] >= l[2] ? 1 : 2);
        return s_.on_segment[v[k]] >= 0 && largest_angle_cosine(x[0], x[1], x[2]) < 0 ? k : -1;
    };
    const std::vector<int32_t> found = s_.tri.live_triangles_where(s_.ctx, [&](int32_t t) { return gamma_corner(t) >= 0; });
    std::vector<uint8_t> locked(static_cast<size_t>(s_.tri.vertex_slots()), 0);
    int64_t done = 0;
    for (int32_t t : found) {
        if (s_.tri.is_free(t)) continue;
        const int k = gamma_corner(t);
        if (k < 0) continue;
        const int32_t b = s_.tri.vertex(t, k), p = s_.tri.vertex(t, (k + 1) % 3), q = s_.tri.vertex(t, (k + 2) % 3);
        const int32_t y = s_.tri.vertex(s_.tri.neighbour(t, k), s_.tri.mirror_edge(t, k));
        const bool opposite_gamma = s_.runs_along_gamma(p, q, b, y);
        // The region the new vertex may change, claimed: the closed stars of t's vertices.
        const std::vector<int32_t> region = s_.closed_stars({b, p, q});
        if (!s_.claim(region, locked)) continue;
        auto release = [&] {  // nothing changed there: free again
            for (int32_t u : region) locked[u] = 0;
        };
        const GammaCorner corner{t, b, p, q, region, s_.gamma_edges_among(region), s_.obtuse_touching(region)};
        switch (support_gamma_corner(corner, opposite_gamma, locked)) {
            case CornerChange::none: release(); break;
            case CornerChange::vertex_added: ++s_.stats.corner_vertices, ++done; break;
            case CornerChange::vertex_removed: ++s_.stats.gamma_vertices_removed, ++done; break;
        }
    }
    return done;
}

// One corner: a corner vertex at the best of its sites, else one taking the
// place of a vertex off Gamma too near a site, else a vertex of the corner's
// triangle on Gamma taken out. What changed is marked for the sweeps.
GammaCorners::CornerChange GammaCorners::support_gamma_corner(const GammaCorner &corner, bool opposite_gamma,
                                                        std::vector<uint8_t> &locked) {
    // (A vertex beyond an edge along Gamma would sit across it: no sites.)
    const std::vector<Vec3> sites = opposite_gamma ? std::vector<Vec3>{} : corner_sites(corner);
    const size_t first_sites = std::min(sites.size(), kFirstTierSites);
    int32_t d = keep_best_corner_vertex(sites, 0, first_sites, corner);
    if (d < 0) d = keep_best_corner_vertex(sites, first_sites, sites.size(), corner);
    // Failing those, a site too near a vertex off Gamma may take its place
    // (any site: against the first tier's only, coast + rivers 60 km 23 -> 20
    // obtuse, 240 km 12 -> 9, Mid-Atlantic 82 -> 80, at about the same time).
    for (size_t i = 0; i < sites.size() && d < 0; ++i) d = try_corner_relocation(sites[i], corner, locked);
    if (d >= 0) {
        s_.corner_supports.insert(s_.tri.id(d));
        s_.changed_at[d] = s_.clock;
        for (int32_t s : s_.tri.star(d))
            for (int j = 0; j < 3; ++j) s_.changed_at[s_.tri.vertex(s, j)] = s_.clock;
        locked.resize(static_cast<size_t>(s_.tri.vertex_slots()), 1);
        return CornerChange::vertex_added;
    }
    for (int32_t v : {corner.b, corner.p, corner.q}) {
        if (!try_gamma_vertex_removal(v, corner)) continue;
        for (int32_t u : corner.region)
            if (u != v) s_.changed_at[u] = s_.clock;
        return CornerChange::vertex_removed;
    }
    return CornerChange::none;
}

// The sites [from, to) are one tier: every one is tried and undone (up to
// one that leaves no obtuse triangle around), and those that helped are put
// in again, fewest obtuse triangles left first (then in site order), until
// one is kept (a trial done again after others may find other slots, and so
// come out otherwise); its slot, or -1. Tiers against keeping the first
// site that helps, coast + rivers 60 km: 29 -> 23 obtuse, Mid-Atlantic
// 93 -> 82; against trying every site as one tier (24 and 79), half the
// trials.
int32_t GammaCorners::keep_best_corner_vertex(const std::vector<Vec3> &sites, size_t from, size_t to,
                                           const GammaCorner &corner) {
    std::vector<std::pair<int, size_t>> helping;  // (obtuse left, site)
    for (size_t i = from; i < to; ++i) {
        const CornerTrial trial = try_corner_vertex(sites[i], corner, false);
        if (trial.obtuse >= 0) helping.push_back({trial.obtuse, i});
        if (trial.obtuse == 0) break;
    }
    std::sort(helping.begin(), helping.end());
    for (const auto &[obtuse, i] : helping) {
        const int32_t d = try_corner_vertex(sites[i], corner).vertex;
        if (d >= 0) return d;
    }
    return -1;
}

// Where a corner vertex is tried: near the circumcentre of the corner's
// triangle, along the corner's bisector (kBisectorSpokes), then across the
// corner's wedge (kWedgeShares of the way from the leg to p to the leg to
// q, kWedgeSpokes h from the corner). The wedge sites meet corners whose
// legs are short or unequal: on the coastlines and rivers at 60 km they
// take the obtuse triangles left from 40 to 23 (Mid-Atlantic: 115 to 82).
std::vector<Vec3> GammaCorners::corner_sites(const GammaCorner &corner) const {
    constexpr double kPull = 0.2;  // of the way from the circumcentre to the corner
    const Vec3 xb = s_.tri.direction(corner.b), xp = s_.tri.direction(corner.p), xq = s_.tri.direction(corner.q);
    const Vec3 centre = geom::normalized(geom::cross(xp - xb, xq - xb));
    const Vec3 to_p = geom::normalized(xp - geom::dot(xb, xp) * xb), to_q = geom::normalized(xq - geom::dot(xb, xq) * xb);
    const double h = static_cast<double>(s_.h_at[corner.b]);
    std::vector<Vec3> sites{geom::normalized(centre + kPull * (xb - centre))};
    const Vec3 bisector = geom::normalized(to_p + to_q);
    for (double spoke : kBisectorSpokes) sites.push_back(geom::normalized(xb + (spoke * h) * bisector));
    for (double share : kWedgeShares) {
        const Vec3 direction = geom::normalized((1 - share) * to_p + share * to_q);
        for (double spoke : kWedgeSpokes) sites.push_back(geom::normalized(xb + (spoke * h) * direction));
    }
    return sites;
}

// Inserts a corner vertex at `at` (near the corner's triangle) and keeps it
// if it helps where it is put or after one of its ODT steps, each followed
// by one of its neighbours off Gamma (relax_link; the sweeps will move them,
// and a vertex just past the chord it cut leaves the triangles beyond it
// obtuse until they do). Without `keep` it is taken out again even then
// (a trial, scored by the obtuse triangles it leaves around). Not kept,
// the mesh is as it was (every point back bit for bit, what was hidden back
// in).
GammaCorners::CornerTrial GammaCorners::try_corner_vertex(const Vec3 &at, const GammaCorner &corner, bool keep) {
    std::vector<int32_t> buried;
    int32_t d = -1;
    try {
        d = s_.tri.insert(at, 0.0, s_.next_id++, &buried, corner.triangle);
    } catch (const Error &e) {
        // A vertex is already there (one kept at this corner before, not
        // moved since): nothing to add, and the insertion left the mesh as it was.
        if (e.status() == UM_ERR_DUPLICATE_POINTS) return {};
        throw;
    }
    s_.grow_slots();
    s_.h_at[d] = static_cast<float>(s_.h(at));
    std::vector<MovedVertex> moved;  // d's neighbours the steps moved, as they were before
    CornerTrial trial;
    if (buried.empty()) trial.obtuse = corner_vertex_helps(d, corner);
    for (int step = 0; step < kCornerSteps && trial.obtuse < 0 && buried.empty() && s_.tri.in_triangulation(d); ++step) {
        buried = odt_step(d);
        if (buried.empty() && s_.tri.in_triangulation(d)) buried = relax_link(d, corner, moved);
        if (buried.empty()) trial.obtuse = corner_vertex_helps(d, corner);
    }
    if (trial.obtuse >= 0 && keep) {
        for (const MovedVertex &m : moved) s_.changed_at[m.v] = s_.clock;
        trial.vertex = d;
        return trial;
    }
    // Out again, its neighbours back where they were, and what was hidden
    // (among lightly weighted vertices) back in.
    std::vector<int32_t> hidden = buried;
    const int32_t near = s_.tri.remove(d);
    for (auto m = moved.rbegin(); m != moved.rend(); ++m) {
        const std::vector<int32_t> hid = s_.tri.place(m->v, m->lifted);
        hidden.insert(hidden.end(), hid.begin(), hid.end());
        s_.h_at[m->v] = m->h;
    }
    for (int32_t u : hidden)
        if (u != d && !s_.tri.in_triangulation(u) && !s_.tri.is_removed(u)) s_.tri.restore_hidden(u, near);
    return trial;
}

// An ODT step of v to its star's ODT point; the vertices it hid.
std::vector<int32_t> GammaCorners::odt_step(int32_t v) {
    const Vec3 to = s_.star_odt_point(v);
    std::vector<int32_t> buried = s_.tri.move(v, to);
    s_.h_at[v] = static_cast<float>(s_.h(to));
    return buried;
}

// An ODT step of each of new vertex d's neighbours off Gamma in the corner's
// region, so that the neighbourhood makes room for d: alone, d keeps an
// obtuse angle among neighbours placed for the mesh without it (coast +
// rivers 60 km: 83 -> 54 obtuse; Mid-Atlantic: 239 -> 132). As in the
// sweeps, a step that lets Gamma into more of the cells around is put back.
// Each vertex's first position goes to `moved` (for the undo); returns the
// vertices a step hid (then it stops).
std::vector<int32_t> GammaCorners::relax_link(int32_t d, const GammaCorner &corner, std::vector<MovedVertex> &moved) {
    const std::vector<int32_t> link = s_.tri.link(d);
    auto crossings = [&](int32_t u) {
        return s_.stars_gamma_crossings(&u, 1, [&](int32_t w) { return s_.generator(w); }, false);
    };
    std::vector<int32_t> buried;
    for (int32_t u : link) {
        if (s_.on_segment[u] >= 0 || s_.cover(u) || !std::binary_search(corner.region.begin(), corner.region.end(), u)) continue;
        if (!s_.move_keeps_floor(u, s_.star_odt_point(u))) continue;  // (keeps the floor)
        const MovedVertex before{u, s_.tri.lifted(u), s_.h_at[u]};
        if (std::none_of(moved.begin(), moved.end(), [&](const MovedVertex &m) { return m.v == u; }))
            moved.push_back(before);
        const int crossed = crossings(u);
        buried = odt_step(u);
        if (!buried.empty()) break;
        const int now = crossings(u);
        if (now < 0 || now > crossed) {
            buried = s_.tri.place(u, before.lifted);
            s_.h_at[u] = before.h;
            if (!buried.empty()) break;
        }
    }
    return buried;
}

// A site nearer than collapse_ratio h to a vertex off Gamma has no room for
// a vertex of its own (the most common reason a corner vertex is not kept):
// that vertex, removed, gives it the room, the new one taking its place
// (the neighbourhood then has as many vertices as before). Judged as
// try_corner_vertex judges, over the corner's region and the removed
// vertex's closed star, both claimed; the slot of the new vertex, or -1 with
// the mesh as it was (the vertex restored).
int32_t GammaCorners::try_corner_relocation(const Vec3 &at, const GammaCorner &corner, std::vector<uint8_t> &locked) {
    int32_t u = -1;
    double nearest = s_.options.collapse_ratio * s_.h(at);
    for (int32_t w : corner.region) {
        if (s_.on_segment[w] >= 0 || s_.cover(w) || w == corner.p || w == corner.q) continue;
        const double distance = geom::norm(s_.tri.direction(w) - at);
        if (distance < nearest) nearest = distance, u = w;
    }
    if (u < 0) return -1;
    const std::vector<int32_t> star = s_.closed_stars({u});
    std::vector<int32_t> beyond;  // u's closed star outside the corner's region
    std::set_difference(star.begin(), star.end(), corner.region.begin(), corner.region.end(), std::back_inserter(beyond));
    for (int32_t w : beyond)
        if (locked[w]) return -1;
    GammaCorner wider = corner;
    wider.region.clear();
    std::set_union(corner.region.begin(), corner.region.end(), star.begin(), star.end(), std::back_inserter(wider.region));
    wider.gamma_edges = s_.gamma_edges_among(wider.region);
    wider.obtuse_before = s_.obtuse_touching(wider.region);
    // (u is not a vertex of the corner's triangle: its slot stays the same.)
    const int32_t near_u = s_.tri.remove(u);
    const int32_t d = try_corner_vertex(at, wider).vertex;
    if (d < 0) {
        s_.tri.restore_removed(u, near_u);
        return -1;
    }
    for (int32_t w : beyond) locked[w] = 1;
    for (int32_t w : star) s_.changed_at[w] = s_.clock;
    return d;
}

// support_gamma_corners' test of its new vertex d.
// The obtuse triangles around when it helps, else -1.
int GammaCorners::corner_vertex_helps(int32_t d, const GammaCorner &corner) const {
    if (!s_.tri.in_triangulation(d)) return -1;
    const Vec3 x = s_.tri.direction(d);
    // (Nothing is added in or beside a regional mesh's cover; nor a vertex
    // of degree 4 or less, which the valence repair would take out again.)
    bool ok = (!s_.domain || s_.domain->contains(x)) && s_.tri.link(d).size() > 4;
    s_.tri.for_each_neighbour(d, [&](int32_t u) {
        ok = ok && !s_.cover(u);
        const double h = 0.5 * (static_cast<double>(s_.h_at[d]) + static_cast<double>(s_.h_at[u]));
        const double floor = s_.on_segment[u] >= 0 ? kCornerEdge : s_.options.collapse_ratio;
        ok = ok && std::binary_search(corner.region.begin(), corner.region.end(), u) &&
             geom::norm(x - s_.tri.direction(u)) >= floor * h;
    });
    // (A corner's support is lifted only below the floor itself in the shape
    // phase too: MeshState::corner_supports.)
    ok = ok && s_.gamma_edges_stay(corner.gamma_edges) && s_.clear_of_floor(d);
    if (!ok || has_triangle(corner.b, corner.p, corner.q)) return -1;
    // With corner_cells_clear, its cell stays clear of Gamma (gamma_crossings):
    // at 60 km on the coastlines and rivers that keeps 380 edges to cells off
    // Gamma out of Tri|Gamma, and 110 obtuse triangles in the mesh.
    // (d is off Gamma: every spoke of its star counts.)
    auto at = [&](int32_t u) { return s_.generator(u); };
    if (s_.options.corner_cells_clear && s_.stars_gamma_crossings(&d, 1, at, false) != 0) return -1;
    std::vector<int32_t> around = corner.region;
    around.push_back(d);
    const int obtuse = s_.obtuse_touching(around);
    return obtuse <= corner.obtuse_before ? obtuse : -1;
}

// A corner no vertex can support (its legs along Gamma are too short to
// make room for one: Gamma wiggles below the spacing there, its vertices
// 0.3-0.6 h apart) may lose one of its triangle's vertices on Gamma
// instead: the chord between that vertex's two neighbours along Gamma then
// carries Gamma, as the boundary refinement would have left it had the
// chord met its bounds. Taken only when the chord does (chord_carries_gamma:
// l < alpha h, eps < beta h), every other edge along Gamma there stays,
// Gamma enters no more cells off it, no edge at v's neighbours (the hole's
// new ones among them) is longer than split_ratio h, and the triangles
// around have no more obtuse
// ones (the obtuse angle then sits off Gamma's corner, where the sweeps and
// mends can reshape it: coast + rivers 60 km, 43 obtuse left with "fewer",
// 40 with "no more"). Else v is put back
// (restore_removed: the same regular triangles).
bool GammaCorners::try_gamma_vertex_removal(int32_t v, const GammaCorner &corner) {
    if (s_.on_segment[v] < 0 || !s_.tri.in_triangulation(v)) return false;
    int32_t along[2], n_along = 0;  // v's neighbours along Gamma
    for (const auto &[a, c] : corner.gamma_edges) {
        if (a != v && c != v) continue;
        if (n_along == 2) return false;  // a junction of Gamma: its vertex stays
        along[n_along++] = a == v ? c : a;
    }
    if (n_along != 2) return false;
    const std::vector<int32_t> link = s_.tri.link(v);
    auto at = [&](int32_t u) { return s_.generator(u); };
    const int crossed = s_.stars_gamma_crossings(link.data(), static_cast<int>(link.size()), at, false);
    if (crossed < 0 || !s_.removable(v)) return false;
    std::vector<int32_t> with_v = link;
    with_v.push_back(v);
    const int below = s_.below_floor_at(with_v);
    const int32_t near = s_.tri.remove(v);
    bool ok = s_.chord_carries_gamma(along[0], along[1], s_.options.gamma_alpha, s_.options.gamma_beta);
    ok = ok && s_.below_floor_at(link) <= below;  // (the hole's new edges off the land keep the floor)
    ok = ok && s_.gamma_edges_stay(corner.gamma_edges, v);
    for (int32_t u : link) {
        if (!ok) break;
        s_.tri.for_each_neighbour(u, [&](int32_t w) {
            const double h = 0.5 * (static_cast<double>(s_.h_at[u]) + static_cast<double>(s_.h_at[w]));
            ok = ok && geom::norm(s_.tri.direction(u) - s_.tri.direction(w)) <= s_.options.split_ratio * h;
        });
    }
    if (ok) {
        const int now = s_.stars_gamma_crossings(link.data(), static_cast<int>(link.size()), at, false);
        ok = now >= 0 && now <= crossed;
    }
    if (ok) {
        std::vector<int32_t> around;
        std::copy_if(corner.region.begin(), corner.region.end(), std::back_inserter(around),
                     [&](int32_t u) { return u != v; });
        ok = s_.obtuse_touching(around) <= corner.obtuse_before;
    }
    if (!ok) s_.tri.restore_removed(v, near);
    return ok;
}

bool GammaCorners::has_triangle(int32_t a, int32_t b, int32_t c) const {
    bool found = false;
    s_.tri.for_each_in_star(a, [&](int32_t s) {
        const int i = s_.tri.local_index(s, a);
        const int32_t u = s_.tri.vertex(s, (i + 1) % 3), w = s_.tri.vertex(s, (i + 2) % 3);
        found = found || (u == b && w == c) || (u == c && w == b);
    });
    return found;
}


}  // namespace um::optim::detail
