#include "optim/defect_reseeding.hpp"

#include <algorithm>

#include "optim/star_graph.hpp"
#include "refine/surface.hpp"

namespace um::optim::detail {

DefectReseeding::Round DefectReseeding::reseed(int rings, int64_t most_defects) {
    const std::vector<uint8_t> free = free_to_move();
    std::vector<int32_t> out = defects(free);
    Round round;
    round.defects = static_cast<int64_t>(out.size());
    if (round.defects > most_defects || round.defects == 0) return round;
    add_rings(out, rings, free);
    std::vector<int32_t> slots;
    const std::vector<int32_t> rim = remove(out, slots);
    round.removed = static_cast<int64_t>(slots.size());
    round.inserted = refill(rim, slots);
    // The slots filled again hold new vertices: new to the sweeps.
    for (int32_t v : out)
        if (s_.tri.in_triangulation(v)) s_.changed_at[v] = s_.clock, s_.move_failed_at[v] = 0;
    return round;
}

// Per vertex slot: in the triangulation, off Gamma, not near it and with no
// neighbour that is. With Gamma, the slots added since flag_near_gamma (the
// corner vertices, on or next to Gamma) count as near it.
std::vector<uint8_t> DefectReseeding::free_to_move() const {
    const int32_t n = s_.tri.vertex_slots();
    const bool with_gamma = s_.arcs.size() > 0;
    const size_t flagged = s_.near_gamma.size();
    auto near = [&](int32_t v) { return static_cast<size_t>(v) >= flagged || s_.near_gamma[v]; };
    auto pinned = [&](int32_t v) { return s_.on_segment[v] >= 0 || (with_gamma && near(v)); };
    std::vector<uint8_t> free(static_cast<size_t>(n), 0);
    s_.ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int32_t v = static_cast<int32_t>(i);
            if (!s_.tri.in_triangulation(v) || pinned(v) || s_.cover(v)) continue;
            bool clear = true;
            s_.tri.for_each_neighbour(v, [&](int32_t u) { clear = clear && !pinned(u); });
            free[i] = clear;
        }
    });
    return free;
}

// The free vertices of degree other than 6 with a defect of the other sign
// (degree above 6 against below) within kPairReach edges, in slot order. A
// lone defect is a disclination the sphere's topology needs (the twelve
// pentagons of a geodesic lattice): a hole around it holds the same net
// charge after the refill, so re-seeding it would only move it and break
// the lattice around it.
constexpr int kPairReach = 4;
std::vector<int32_t> DefectReseeding::defects(const std::vector<uint8_t> &free) const {
    const std::vector<int32_t> degree = vertex_degrees(s_.ctx, s_.tri);
    auto sign = [&](int32_t v) { return degree[v] < 6 ? -1 : degree[v] > 6 ? 1 : 0; };
    std::vector<int32_t> found;
    std::vector<int32_t> reached;
    std::vector<uint8_t> seen(degree.size(), 0);
    for (int32_t v = 0; v < s_.tri.vertex_slots(); ++v) {
        if (!free[v] || sign(v) == 0) continue;
        reached.assign(1, v);
        seen[v] = 1;
        bool paired = false;
        for (size_t ring_begin = 0, r = 0; r < kPairReach && !paired; ++r) {
            const size_t ring_end = reached.size();
            for (size_t i = ring_begin; i < ring_end; ++i)
                s_.tri.for_each_neighbour(reached[i], [&](int32_t u) {
                    if (seen[u]) return;
                    seen[u] = 1, reached.push_back(u);
                    paired = paired || sign(u) == -sign(v);
                });
            ring_begin = ring_end;
        }
        for (int32_t u : reached) seen[u] = 0;
        if (paired) found.push_back(v);
    }
    return found;
}

// Adds the free vertices within `rings` edges of `vertices` (breadth first,
// so the order stays fixed).
void DefectReseeding::add_rings(std::vector<int32_t> &vertices, int rings, const std::vector<uint8_t> &free) const {
    std::vector<uint8_t> taken(free.size(), 0);
    for (int32_t v : vertices) taken[v] = 1;
    size_t ring_begin = 0;
    for (int r = 0; r < rings; ++r) {
        const size_t ring_end = vertices.size();
        for (size_t i = ring_begin; i < ring_end; ++i)
            s_.tri.for_each_neighbour(vertices[i], [&](int32_t u) {
                if (free[u] && !taken[u]) taken[u] = 1, vertices.push_back(u);
            });
        ring_begin = ring_end;
    }
}

// Takes the vertices out; their slots go to *slots (to be filled again) and
// the vertices left around the holes are returned, sorted. A vertex whose
// star has grown too large to take out (MeshState::removable: the holes of
// its neighbours merged, on coarse meshes whose defects and rings cover most
// of the sphere) stays.
std::vector<int32_t> DefectReseeding::remove(const std::vector<int32_t> &vertices, std::vector<int32_t> &slots) {
    std::vector<int32_t> rim;
    slots.clear();
    for (int32_t v : vertices) {
        if (!s_.removable(v)) continue;
        s_.tri.for_each_neighbour(v, [&](int32_t u) { rim.push_back(u); });
        s_.tri.remove(v);
        slots.push_back(v);
    }
    std::reverse(slots.begin(), slots.end());  // the refill takes the last first: slot order
    std::sort(rim.begin(), rim.end());
    rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
    rim.erase(std::remove_if(rim.begin(), rim.end(), [&](int32_t u) { return !s_.tri.in_triangulation(u); }),
              rim.end());
    return rim;
}

// The refinement's serial pass over the holes: their triangles are too big
// and their rims good, so each hole fills from its rim inwards.
int64_t DefectReseeding::refill(const std::vector<int32_t> &rim, std::vector<int32_t> &slots) {
    refine::SurfaceOptions o;
    o.alpha = s_.options.refill_alpha, o.rho = s_.options.refill_rho;
    if (s_.arcs.size() > 0) o.gamma = &s_.arcs;
    o.on_gamma = &s_.on_segment;
    o.free_vertex_slots = &slots;
    const refine::SurfaceStats stats = refine::refine_surface(s_.ctx, s_.tri, s_.h, o, s_.next_id, &rim);
    s_.next_id = stats.next_id;
    s_.grow_slots();
    return stats.inserted;
}

}  // namespace um::optim::detail
