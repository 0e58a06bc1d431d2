// Territories: parallel insertion of points that are not known in advance
// (the surface refinement places each from the mesh it has made so far).
//
// The ownership rule is a parallel build round's (parallel_insertion.cpp):
// a territory owns the vertices whose Hilbert keys fall in its range, reads
// only triangles with at least two of its vertices (those it owns and their
// neighbours) and changes only those, so no two territories touch the same
// triangle. What is new here is that the points come one at a time from the
// caller, so each territory also gets its own run of vertex slots (reserved
// up front: the arrays must not move while the territories work), and a
// proximity test before the insertion commits, since taking a vertex back
// (remove) would reach beyond the new vertex's star.
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/growth.hpp"
#include "tri/spatial_order.hpp"
#include "tri/triangulation.hpp"

namespace um::tri {

// The second layout's rotation: about the axis (1, 2, 3) by 1 radian, so that
// none of its cube-face edges or Hilbert cuts lies along the first layout's.
namespace {
struct Turn {
    double m[3][3];
    Turn() {
        const double n = std::sqrt(14.0), x = 1 / n, y = 2 / n, z = 3 / n;
        const double c = std::cos(1.0), s = std::sin(1.0), k = 1 - c;
        const double r[3][3] = {{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                                {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                                {z * x * k - y * s, z * y * k + x * s, c + z * z * k}};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m[i][j] = r[i][j];
    }
};
}  // namespace

uint32_t Triangulation::territory_key(const Vec3 &p, int layout) {
    if (layout == 0) return static_cast<uint32_t>(hilbert_key(p));
    static const Turn turn;
    const Vec3 q{turn.m[0][0] * p.x + turn.m[0][1] * p.y + turn.m[0][2] * p.z,
                 turn.m[1][0] * p.x + turn.m[1][1] * p.y + turn.m[1][2] * p.z,
                 turn.m[2][0] * p.x + turn.m[2][1] * p.y + turn.m[2][2] * p.z};
    return static_cast<uint32_t>(hilbert_key(q));
}

std::vector<Triangulation::Territory> Triangulation::open_territories(
    Context &ctx, const std::vector<uint32_t> &cuts, const std::vector<int32_t> &vertex_budget,
    int32_t first_id, int layout) {
    if (vertex_budget.size() != cuts.size() + 1)
        fail(UM_ERR_INTERNAL, "open_territories: ", vertex_budget.size(), " budgets for ",
             cuts.size() + 1, " territories");
    int64_t total = 0;
    for (int32_t b : vertex_budget) total += std::max(b, 0);
    const int32_t first_slot = vertex_slots();
    if (total + first_slot > INT32_MAX / 3 || total + first_id > INT32_MAX)
        fail(UM_ERR_LIMIT, "refinement by territories: ", total, " new vertex slots");
    const size_t slots = static_cast<size_t>(first_slot + total);
    const size_t triangles_before = tris_.size();
    // What a failure below (out of memory) puts back: the sizes (shrinking
    // does not allocate) and the keys; free_ changes only at the end. (The
    // allocations stay in this order: another one raised the pipeline's
    // peak by 7 bytes per cell, the allocator keeping freed buffers.)
    auto put_back = [&] {
        q_.resize(static_cast<size_t>(first_slot)), id_.resize(static_cast<size_t>(first_slot));
        vertex_tri_.resize(static_cast<size_t>(first_slot));
        tris_.resize(triangles_before), mark_.resize(triangles_before);
        release(key_);
    };
    // Exactly (a vector's doubling would hold twice the room for a moment,
    // and keep it).
    auto grow = [](auto &values, size_t size, auto value) {
        if (values.capacity() < size) values.reserve(size);
        values.resize(size, value);
    };
    std::vector<Territory> territories(vertex_budget.size());
    size_t free_used = 0;
    int32_t first_fresh = 0;
    try {
        // Keys of the vertices there are; the reserved slots get theirs on
        // use (until then, the virtual vertices' key: owned by none).
        key_.assign(slots, ~uint32_t(0));
        ctx.parallel_for(first_slot, 8192, [&](int64_t b, int64_t e) {
            for (int64_t v = b; v < e; ++v)
                if (vertex_tri_[v] >= 0) key_[v] = territory_key(direction(static_cast<int32_t>(v)), layout);
        });
        grow(q_, slots, Vec3{});
        grow(id_, slots, kNone);
        grow(vertex_tri_, slots, kRemoved);
        // Triangle slots: two per vertex slot, the free ones first (in slot
        // order, a run to each territory), then fresh ones at the end.
        std::sort(free_.begin(), free_.end());
        int64_t fresh_needed = 0;
        for (size_t i = 0; i < territories.size(); ++i) {
            const size_t want = 2 * static_cast<size_t>(std::max(vertex_budget[i], 0));
            const size_t take = std::min(want, free_.size() - free_used);
            // Reversed: the pool takes them from the back, so in slot order.
            territories[i].reuse_.assign(free_.rbegin() + static_cast<std::ptrdiff_t>(free_.size() - free_used - take),
                                         free_.rbegin() + static_cast<std::ptrdiff_t>(free_.size() - free_used));
            territories[i].given_ = territories[i].reuse_;
            free_used += take;
            fresh_needed += static_cast<int64_t>(want - take);
        }
        first_fresh = triangle_slots();
        grow(tris_, tris_.size() + static_cast<size_t>(fresh_needed), Tri{{kNone, kNone, kNone}, {kNone, kNone, kNone}});
        grow(mark_, tris_.size(), Mark::none);
    } catch (...) {
        put_back();
        throw;
    }
    free_.erase(free_.begin(), free_.begin() + static_cast<std::ptrdiff_t>(free_used));

    int32_t slot = first_slot, fresh = first_fresh;
    for (size_t i = 0; i < territories.size(); ++i) {
        Territory &g = territories[i];
        g.keys_ = {key_.data(), i == 0 ? 0u : cuts[i - 1], i == cuts.size() ? ~uint32_t(0) : cuts[i]};
        g.layout_ = layout;
        const int32_t budget = std::max(vertex_budget[i], 0);
        g.first_vertex_ = g.next_vertex_ = slot;
        g.first_id_ = first_id + (slot - first_slot);
        g.vertex_end_ = slot + budget;
        for (int32_t v = slot; v < slot + budget; ++v) id_[v] = first_id + (v - first_slot);
        slot += budget;
        const int32_t from_end = 2 * budget - static_cast<int32_t>(g.reuse_.size());
        g.first_fresh_ = fresh;
        g.pool_ = {nullptr, fresh, fresh + from_end};
        fresh += from_end;
    }
    return territories;
}

bool Triangulation::owns(const Territory &g, int32_t t) const { return owns(g.keys_, t); }

bool Triangulation::owns_point(const Territory &g, const Vec3 &p) const {
    const uint32_t key = territory_key(p, g.layout_);
    return key >= g.keys_.lo && key < g.keys_.hi;
}

int32_t Triangulation::walk_in(const Territory &g, const Vec3 &p, int32_t hint, int &n_zero) const {
    if (hint < 0 || hint >= triangle_slots() || is_free(hint) || !owns(g.keys_, hint)) return kNone;
    int zero_edges[3];
    int32_t last_owned = hint;
    constexpr int64_t kMaxSteps = 4096;
    const int32_t t = walk(p, hint, zero_edges, n_zero, g.walk_, kMaxSteps, &g.keys_, &last_owned);
    return t != kNone && owns(g.keys_, t) ? t : kNone;
}

int32_t Triangulation::locate_in(const Territory &g, const Vec3 &p, int32_t hint) const {
    int n_zero = 0;
    return walk_in(g, p, hint, n_zero);
}

Triangulation::TerritoryInsert Triangulation::insert_in(Territory &g, const Vec3 &p, int32_t hint,
                                                        double min_chord, int32_t *v_out) {
    if (g.next_vertex_ == g.vertex_end_) return TerritoryInsert::deferred;  // its budget is spent
    const uint32_t key = territory_key(p, g.layout_);
    if (key < g.keys_.lo || key >= g.keys_.hi) return TerritoryInsert::deferred;
    int n_zero = 0;
    const int32_t t = walk_in(g, p, hint, n_zero);
    // On an edge or a vertex: the serial path's special cases.
    if (t == kNone || n_zero != 0) return TerritoryInsert::deferred;
    const int32_t v = g.next_vertex_;
    q_[v] = p;  // weight 0; the slot is this territory's alone
    key_[v] = key;
    if (!visible(t, v)) return TerritoryInsert::hidden;
    Scratch &s = g.scratch_;
    if (!fill_cavity(v, t, s, &g.keys_)) return TerritoryInsert::deferred;
    // Weights are 0: a cavity with a vertex inside would mean a duplicate.
    const bool buries = s.cavity_buries();
    const size_t room = g.reuse_.size() + s.cavity.size() + static_cast<size_t>(g.pool_.fresh_end - g.pool_.fresh);
    if (buries || room < s.horizon.size()) {
        clear_cavity_marks(s);
        return TerritoryInsert::deferred;
    }
    const double min_chord2 = min_chord * min_chord;
    for (const HorizonEdge &h : s.horizon) {
        const Vec3 d = p - direction(h.a);
        if (geom::dot(d, d) < min_chord2) {
            clear_cavity_marks(s);
            return TerritoryInsert::too_close;
        }
    }
    g.pool_.reuse = &g.reuse_;  // (the territories may have moved since they opened)
    stitch_new_triangles(v, s, g.pool_);
    ++g.next_vertex_;
    *v_out = v;
    return TerritoryInsert::inserted;
}

Triangulation::TerritoryClose Triangulation::close_territories(Context &ctx,
                                                               std::vector<Territory> &territories) {
    TerritoryClose out;
    out.first_slot = vertex_slots();
    out.next_id = 0;
    if (territories.empty()) return out;
    out.first_slot = territories.front().first_vertex_;
    const int32_t end = territories.back().vertex_end_;
    const int32_t first_id = territories.front().first_id_;
    // The allocations first: a failure leaves the territories open.
    out.new_slot.assign(static_cast<size_t>(end - out.first_slot), kNone);
    size_t handed_back = 0;
    for (const Territory &g : territories)
        handed_back += g.reuse_.size() + static_cast<size_t>(g.pool_.fresh_end - g.pool_.fresh);
    free_.reserve(free_.size() + handed_back);
    int32_t to = out.first_slot;
    for (Territory &g : territories)
        for (int32_t v = g.first_vertex_; v < g.next_vertex_; ++v, ++to) {
            out.new_slot[v - out.first_slot] = to;
            q_[to] = q_[v], vertex_tri_[to] = vertex_tri_[v];
            id_[to] = first_id + (to - out.first_slot);
        }
    out.next_id = first_id + (to - out.first_slot);
    q_.resize(to), id_.resize(to), vertex_tri_.resize(to);
    // The triangles' vertices in the moved slots (the only ones that moved).
    ctx.parallel_for(triangle_slots(), 16384, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t) {
            if (tris_[t].v[0] == kNone) continue;
            for (int32_t &u : tris_[t].v)
                if (u >= out.first_slot) u = out.new_slot[u - out.first_slot];
        }
    });
    for (Territory &g : territories) {
        free_.insert(free_.end(), g.reuse_.begin(), g.reuse_.end());
        for (int32_t t = g.pool_.fresh; t < g.pool_.fresh_end; ++t) free_.push_back(t);
        release(g.reuse_);
        release(g.given_);
        g.pool_.fresh = g.pool_.fresh_end;
    }
    release(key_);
    territories.clear();
    return out;
}

}  // namespace um::tri
