#include "tri/triangulation.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/cyclic.hpp"
#include "core/error.hpp"
#include "core/radix_sort.hpp"
#include "core/text.hpp"
#include "core/growth.hpp"
#include "geom/predicates.hpp"
#include "tri/spatial_order.hpp"

namespace um::tri {

using geom::orient3d_perturbed;
using geom::orient_origin;

namespace {
// Length of the virtual octahedron's lifted points: a power of two (exact
// coordinates), tiny enough that real points around the whole sphere always
// bury them.
constexpr double kVirtualScale = 0x1p-30;
}  // namespace

// ----------------------------------------------------------------- building

void Triangulation::init_virtual_octahedron() {
    const double r = kVirtualScale;
    const Vec3 axes[kVirtual] = {{r, 0, 0}, {0, r, 0}, {0, 0, r},
                                 {-r, 0, 0}, {0, -r, 0}, {0, 0, -r}};
    for (int i = 0; i < kVirtual; ++i) q_[i] = axes[i], id_[i] = -1 - i;
    // Faces counter-clockwise seen from outside: (+x,+y,+z) and its mirror images.
    const int32_t faces[8][3] = {{0, 1, 2}, {1, 3, 2}, {3, 4, 2}, {4, 0, 2},
                                 {1, 0, 5}, {3, 1, 5}, {4, 3, 5}, {0, 4, 5}};
    tris_.clear();
    for (auto &f : faces) tris_.push_back({{f[0], f[1], f[2]}, {kNone, kNone, kNone}});
    // Neighbours by matching reversed edges (8 faces: quadratic is fine).
    for (int32_t t = 0; t < 8; ++t)
        for (int k = 0; k < 3; ++k) {
            int32_t a = tris_[t].v[next_of_three(k)], b = tris_[t].v[prev_of_three(k)];
            for (int32_t u = 0; u < 8; ++u)
                for (int m = 0; m < 3; ++m)
                    if (tris_[u].v[next_of_three(m)] == b && tris_[u].v[prev_of_three(m)] == a) tris_[t].n[k] = u;
        }
    for (int32_t t = 0; t < 8; ++t)
        for (int k = 0; k < 3; ++k) vertex_tri_[tris_[t].v[k]] = t;
    mark_.assign(8, Mark::none);
    free_.clear();
}

Triangulation::BuildRoom &Triangulation::reserve_build(int64_t n) {
    check_brio_count(n);
    // A triangulated sphere of V vertices has 2V - 4 triangles: 2 (n + 6)
    // with the virtual octahedron is room enough. Sized, not only reserved,
    // so that the room lies within the vector (unwritten: UninitVector);
    // insertion starts with clear().
    const size_t max_triangles = 2 * (static_cast<size_t>(n) + kVirtual);
    room_.close();
    // On huge pages when they fill one: only a build from many points.
    size_on_huge_pages(tris_, max_triangles);
    room_.begin_ = room_.next_ = reinterpret_cast<unsigned char *>(tris_.data());
    room_.end_ = room_.begin_ + max_triangles * sizeof(Tri);
    room_.n_ = n;
    return room_;
}

void Triangulation::insert_all(Context &ctx) {
    // The static bound holds for prepare()'s points only: off when done,
    // however it ends.
    struct BoundsOff {
        Triangulation &t;
        ~BoundsOff() { t.build_bound_ = t.walk_bound_ = kNoBound; }
    } bounds_off{*this};
    const int64_t n_real = static_cast<int64_t>(q_.size()) - kVirtual;
    // A triangulated sphere of V vertices has 2V - 4 triangles (prepare()
    // made the room already: reserve_build).
    size_t max_triangles = 2 * q_.size();
    tris_.reserve(max_triangles);
    mark_.reserve(max_triangles);
    advise_huge_pages(mark_.data(), mark_.capacity());
    init_virtual_octahedron();

    // prepare() sorted the slots by BRIO round and kept their Hilbert keys:
    // the big rounds go in parallel by regions, the small first ones (big,
    // overlapping cavities) one by one.
    constexpr int32_t kParallelRound = 8192;
    const int32_t last = static_cast<int32_t>(q_.size());
    auto round_of = [&](int32_t v) { return brio_round(id_[v], n_real); };
    int32_t hint = 0;
    int32_t prev_begin = kVirtual;  // the previous round's first slot
    int64_t in_parallel = 0, deferred = 0, deferred_by_regions = 0;
    for (int32_t begin = kVirtual; begin < last;) {
        const int round = round_of(begin);
        int32_t end = last;  // the first slot of a later round (rounds ascend)
        if (round_of(last - 1) != round) {
            int32_t lo = begin;  // round_of(lo) == round != round_of(end)
            while (end - lo > 1) {
                int32_t mid = lo + (end - lo) / 2;
                (round_of(mid) == round ? lo : end) = mid;
            }
        }
        if (end - begin >= kParallelRound && key_.size() == q_.size()) {
            const RoundDeferred count = insert_round_in_parallel(ctx, prev_begin, begin, end, hint);
            deferred += count.to_serial, deferred_by_regions += count.by_regions;
            in_parallel += end - begin;
        } else {
            for (int32_t v = begin; v < end; ++v) {
                int32_t other = kNone;
                if (insert_slot(v, hint, &other) == InsertResult::duplicate) fail_on_duplicates();
            }
        }
        ctx.progress("triangulate", double(end - kVirtual) / double(n_real));
        prev_begin = begin;
        begin = end;
    }
    release(key_);
    // bench_triangulation reads this line (the share left to the serial pass).
    ctx.log(UM_LOG_DEBUG, concat("triangulate: ", n_real, " points, ", in_parallel,
                                 " in parallel rounds, ", deferred, " of them deferred (",
                                 deferred_by_regions, " by the regions, the rest by the bands)"));
    for (int32_t v = 0; v < kVirtual; ++v)
        if (vertex_tri_[v] >= 0)
            fail(UM_ERR_DEGENERATE_INPUT,
                 "the points do not surround the centre of the sphere (they lie in one "
                 "hemisphere or on one great circle, or too few are visible): a spherical "
                 "triangulation needs points all around the sphere");
    compact_after_build(ctx);
}

// Points stored so far that share a lifted point (direction and weight),
// reported as the two smallest input indices of the group with the smallest
// index: the same message whatever the insertion order or thread count.
void Triangulation::fail_on_duplicates() const {
    std::vector<int32_t> slots;
    for (int32_t v = 0; v < static_cast<int32_t>(q_.size()); ++v)
        if (id_[v] >= 0) slots.push_back(v);
    // Duplicates have equal lifted points (find_visible_start).
    std::sort(slots.begin(), slots.end(), [&](int32_t a, int32_t b) {
        const Vec3 &x = q_[a], &y = q_[b];
        if (x.x != y.x) return x.x < y.x;
        if (x.y != y.y) return x.y < y.y;
        if (x.z != y.z) return x.z < y.z;
        return id_[a] < id_[b];
    });
    int32_t best_i = -1, best_j = -1, best_v = -1;
    for (size_t k = 1; k < slots.size(); ++k) {
        const Vec3 &x = q_[slots[k - 1]], &y = q_[slots[k]];
        if (x.x != y.x || x.y != y.y || x.z != y.z) continue;
        // The group's first member is its smallest index (sorted by id last).
        size_t g = k - 1;
        while (g > 0) {
            const Vec3 &z = q_[slots[g - 1]];
            if (z.x != x.x || z.y != x.y || z.z != x.z) break;
            --g;
        }
        int32_t i = id_[slots[g]], j = id_[slots[g + 1]];
        if (best_i < 0 || i < best_i) best_i = i, best_j = j, best_v = slots[g];
    }
    if (best_i < 0)  // coinciding directions that are not bit-identical vectors
        fail(UM_ERR_DUPLICATE_POINTS, "two points are at exactly the same location");
    double lon, lat;
    geom::lonlat_deg_from_unit(direction(best_v), lon, lat);
    fail(UM_ERR_DUPLICATE_POINTS, "points ", best_i, " and ", best_j,
         " are at the same location (lon ", lon, ", lat ", lat, " degrees); remove one of them");
}

// Renumbers live triangles into 0..live-1 in order, and vertices v into
// v - vertex_shift (to drop the virtual octahedron after construction).
void Triangulation::compact_triangles(int32_t vertex_shift) {
    std::vector<int32_t> new_index(tris_.size(), kNone);
    int32_t live = 0;
    for (size_t t = 0; t < new_index.size(); ++t)
        if (tris_[t].v[0] != kNone) new_index[t] = live++;
    // In place, in increasing order: a slot moves only down (to <= t), onto
    // a slot already read.
    for (size_t t = 0; t < new_index.size(); ++t) {
        int32_t to = new_index[t];
        if (to == kNone) continue;
        for (int k = 0; k < 3; ++k) {
            tris_[to].v[k] = tris_[t].v[k] - vertex_shift;
            tris_[to].n[k] = new_index[tris_[t].n[k]];
        }
    }
    tris_.resize(static_cast<size_t>(live));
    for (auto &t : vertex_tri_)
        if (t >= 0) t = new_index[t];
    mark_.assign(static_cast<size_t>(live), Mark::none);
    free_.clear();
}

void Triangulation::compact() {
    if (!free_.empty()) compact_triangles(0);
    // Growth by insertion leaves up to twice the room the mesh needs; a
    // mesh handed on (and copied, by the optimisation) keeps only its size.
    tris_.shrink_to_fit(), mark_.shrink_to_fit(), free_.shrink_to_fit();
    q_.shrink_to_fit(), id_.shrink_to_fit(), vertex_tri_.shrink_to_fit();
}

namespace {

// From keys sorted with the old slot in their low 32 bits: each new slot's
// old one and each old slot's new one (keys released).
void orders_of_sorted(Context &ctx, Buffer<uint64_t> &keys, std::vector<int32_t> &old_of_new,
                      std::vector<int32_t> &new_of_old) {
    const int64_t n = static_cast<int64_t>(keys.size());
    old_of_new.resize(static_cast<size_t>(n)), new_of_old.resize(static_cast<size_t>(n));
    ctx.parallel_for(n, 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            old_of_new[i] = static_cast<int32_t>(keys[i] & 0xffffffffu);
            new_of_old[old_of_new[i]] = static_cast<int32_t>(i);
        }
    });
    release(keys);
}

}  // namespace

std::vector<int32_t> Triangulation::reorder_spatially(Context &ctx, Reorder how) {
    if (how == Reorder::copying) {
        // Only the free slots go first: the copies below are sized exactly,
        // and compact()'s shrinking would copy each array once more, serially.
        if (!free_.empty()) compact_triangles(0);
        mark_.shrink_to_fit(), free_.shrink_to_fit();
    } else {
        compact();
    }
    const int32_t n = vertex_slots();
    // Hilbert key above the slot: unique, so the order is the same for any
    // sort; slots outside the triangulation get a key past every curve index.
    constexpr uint64_t kPastCurve = uint64_t(1) << 31;
    Buffer<uint64_t> keys(static_cast<size_t>(n));
    ctx.parallel_for(n, 4096, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v) {
            const uint64_t key = vertex_tri_[v] >= 0 ? hilbert_key(q_[v]) : kPastCurve;
            keys[v] = key << 32 | static_cast<uint64_t>(v);
        }
    });
    radix_sort(ctx, keys, 32, 64);  // the slot below makes every key unique
    std::vector<int32_t> old_of_new, new_of_old;
    orders_of_sorted(ctx, keys, old_of_new, new_of_old);
    const bool copying = how == Reorder::copying;
    if (copying) {
        gather_copy(ctx, q_, old_of_new), gather_copy(ctx, id_, old_of_new), gather_copy(ctx, vertex_tri_, old_of_new);
    } else {
        permute_vertices_in_place(new_of_old);
    }
    // Triangles by smallest new vertex, ties in slot order.
    auto smallest = [&](const Tri &t) {
        return std::min({new_of_old[t.v[0]], new_of_old[t.v[1]], new_of_old[t.v[2]]});
    };
    auto remap = [&](const std::vector<int32_t> &new_tri) {
        return [&](Tri t) {
            for (int k = 0; k < 3; ++k) t.v[k] = new_of_old[t.v[k]], t.n[k] = new_tri[t.n[k]];
            return t;
        };
    };
    const std::vector<int32_t> new_tri =
        copying ? reorder_triangles_copying(ctx, smallest, remap) : reorder_triangles_in_place(n, smallest, remap);
    ctx.parallel_for(static_cast<int64_t>(vertex_tri_.size()), 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t v = b; v < e; ++v)
            if (vertex_tri_[v] >= 0) vertex_tri_[v] = new_tri[vertex_tri_[v]];
    });
    return old_of_new;
}

// values[i] = values[old_of_new[i]], through a copy gathered in parallel.
template <class Vector>
void Triangulation::gather_copy(Context &ctx, Vector &values, const std::vector<int32_t> &old_of_new) {
    Vector out(values.get_allocator());
    out.resize(values.size());  // unwritten: every element gathered below
    ctx.parallel_for(static_cast<int64_t>(values.size()), 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) out[i] = values[old_of_new[i]];
    });
    values.swap(out);
}

// The three vertex arrays in one walk of the cycles: the walk is a chain of
// dependent cache misses (most of the time here), the moves are not.
void Triangulation::permute_vertices_in_place(const std::vector<int32_t> &new_of_old) {
    struct Vertex {
        Vec3 q;
        int32_t id, tri;
    };
    const int32_t n = vertex_slots();
    std::vector<bool> placed(static_cast<size_t>(n), false);
    for (int32_t start = 0; start < n; ++start) {
        if (placed[start]) continue;
        Vertex carried{q_[start], id_[start], vertex_tri_[start]};
        int32_t at = start;
        do {  // carried is the old value of slot `at`: it goes to new_of_old[at]
            const int32_t to = new_of_old[at];
            const Vertex next{q_[to], id_[to], vertex_tri_[to]};
            q_[to] = carried.q, id_[to] = carried.id, vertex_tri_[to] = carried.tri;
            placed[to] = true;
            carried = next, at = to;
        } while (at != start);
    }
}

// The triangles' new slots by their key smallest(t) (a radix sort of key
// and slot, in parallel), and the triangles gathered into a copy.
template <class Smallest, class Remap>
std::vector<int32_t> Triangulation::reorder_triangles_copying(Context &ctx, Smallest smallest, Remap remap) {
    const int64_t nt = triangle_slots();
    Buffer<uint64_t> keys(static_cast<size_t>(nt));
    ctx.parallel_for(nt, 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t) keys[t] = uint64_t(uint32_t(smallest(tris_[t]))) << 32 | uint64_t(t);
    });
    radix_sort(ctx, keys, 32, 64);  // stable: ties stay in slot order
    std::vector<int32_t> old_of_new, new_tri;
    orders_of_sorted(ctx, keys, old_of_new, new_tri);
    const auto moved = remap(new_tri);
    HugePageVector<Tri> out(tris_.get_allocator());
    out.resize(tris_.size());  // unwritten: every triangle gathered below
    ctx.parallel_for(nt, 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) out[i] = moved(tris_[old_of_new[i]]);
    });
    tris_.swap(out);
    return new_tri;
}

// The same order by a stable counting sort, the triangles moved cycle by
// cycle on this thread.
template <class Smallest, class Remap>
std::vector<int32_t> Triangulation::reorder_triangles_in_place(int32_t n, Smallest smallest, Remap remap) {
    const int32_t nt = triangle_slots();
    std::vector<int32_t> first(static_cast<size_t>(n) + 1, 0), new_tri(static_cast<size_t>(nt));
    for (const Tri &t : tris_) ++first[smallest(t) + 1];
    for (int32_t i = 0; i < n; ++i) first[i + 1] += first[i];
    for (int32_t t = 0; t < nt; ++t) new_tri[t] = first[smallest(tris_[t])]++;
    const auto moved = remap(new_tri);
    std::vector<bool> placed(static_cast<size_t>(nt), false);
    for (size_t start = 0; start < tris_.size(); ++start) {
        if (placed[start]) continue;
        Tri carried = tris_[start];
        size_t at = start;
        do {  // carried is the old value of slot `at`: it goes to new_tri[at]
            const size_t to = static_cast<size_t>(new_tri[at]);
            const Tri next = tris_[to];
            tris_[to] = moved(carried);
            placed[to] = true;
            carried = next, at = to;
        } while (at != start);
    }
    return new_tri;
}

std::vector<int32_t> Triangulation::triangles_around(const std::vector<int32_t> &vertices) const {
    std::vector<int32_t> out;
    for (int32_t v : vertices)
        if (in_triangulation(v)) for_each_in_star(v, [&](int32_t t) { out.push_back(t); });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void Triangulation::reserve_extra(Context &ctx, double vertices, double triangles) {
    auto grow = [&](auto &values, double share) {
        grow_capacity(ctx, values, values.size() + static_cast<size_t>(share * double(values.size())) + 16);
    };
    grow(q_, vertices), grow(id_, vertices), grow(vertex_tri_, vertices);
    grow(tris_, triangles), grow(mark_, triangles);
}

template <class Vector>
void Triangulation::grow_capacity(Context &ctx, Vector &values, size_t capacity) {
    if (capacity <= values.capacity()) return;
    Vector out(values.get_allocator());
    out.reserve(capacity);
    out.resize(values.size());  // unwritten: every element copied below
    ctx.parallel_for(static_cast<int64_t>(values.size()), 1 << 14, [&](int64_t b, int64_t e) {
        std::copy(values.begin() + b, values.begin() + e, out.begin() + b);
    });
    values.swap(out);
}

Triangulation::Snapshot Triangulation::snapshot(Context &ctx) const {
    Snapshot s;
    s.free = free_;
    const int64_t nv = static_cast<int64_t>(q_.size()), nt = static_cast<int64_t>(tris_.size());
    s.q.resize(q_.size()), s.id.resize(id_.size()), s.vertex_tri.resize(vertex_tri_.size());  // unwritten
    s.triangles.resize(tris_.size());
    ctx.parallel_for(nv, 1 << 14, [&](int64_t b, int64_t e) {
        std::copy(q_.begin() + b, q_.begin() + e, s.q.begin() + b);
        std::copy(id_.begin() + b, id_.begin() + e, s.id.begin() + b);
        std::copy(vertex_tri_.begin() + b, vertex_tri_.begin() + e, s.vertex_tri.begin() + b);
    });
    ctx.parallel_for(nt, 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t t = b; t < e; ++t) s.triangles[t] = {tris_[t].v[0], tris_[t].v[1], tris_[t].v[2]};
    });
    return s;
}

void Triangulation::restore(Snapshot &&s) {
    // The arrays being replaced go first: an undo is often taken because
    // memory ran out. Then the neighbours are found through the triangles
    // around each vertex (about 32 bytes per vertex of scratch): the triangle
    // across edge (a, b) of t is the other one around a that has b.
    q_.swap(s.q), id_.swap(s.id), vertex_tri_.swap(s.vertex_tri), free_.swap(s.free);
    release(s.q);
    release(s.id), release(s.vertex_tri), release(s.free);
    release(tris_);
    release(mark_);
    try {
        const size_t nv = q_.size(), nt = s.triangles.size();
        std::vector<int64_t> first(nv + 1, 0);  // 3 per triangle: past int32 above ~357 M vertices
        std::vector<int32_t> around;
        for (const auto &v : s.triangles)
            if (v[0] != kNone)
                for (int k = 0; k < 3; ++k) ++first[v[k] + 1];
        for (size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
        around.resize(static_cast<size_t>(first[nv]));
        std::vector<int64_t> fill(first.begin(), first.end() - 1);
        for (size_t t = 0; t < nt; ++t)
            if (s.triangles[t][0] != kNone)
                for (int k = 0; k < 3; ++k) around[fill[s.triangles[t][k]]++] = static_cast<int32_t>(t);
        release(fill);
        tris_.resize(nt);
        for (size_t t = 0; t < nt; ++t) {
            const auto &v = s.triangles[t];
            for (int k = 0; k < 3; ++k) tris_[t].v[k] = v[k], tris_[t].n[k] = kNone;
            if (v[0] == kNone) continue;
            for (int k = 0; k < 3; ++k) {
                const int32_t a = v[next_of_three(k)], b = v[prev_of_three(k)];
                for (int64_t i = first[a]; i < first[a + 1]; ++i) {
                    const auto &w = s.triangles[around[i]];
                    if (around[i] != static_cast<int32_t>(t) && (w[0] == b || w[1] == b || w[2] == b))
                        tris_[t].n[k] = around[i];
                }
            }
        }
        mark_.assign(nt, Mark::none);
    } catch (...) {
        // Not even that much memory: an empty triangulation, not a broken one.
        q_.clear(), id_.clear(), vertex_tri_.clear(), free_.clear(), tris_.clear(), mark_.clear();
        throw;
    }
}

namespace {
// values.erase(begin, begin + by) for a long array, in parallel: chunks of
// the destination each move their own stretch down, after the `by` values
// each needs from the next chunk's stretch were set aside.
template <class Values>
void drop_front(Context &ctx, Values &values, size_t by) {
    constexpr size_t kChunks = 64;
    const size_t n = values.size() - by;
    if (n < kChunks * 1024) {
        values.erase(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(by));
        return;
    }
    auto end_of = [&](size_t c) { return n * (c + 1) / kChunks; };
    std::vector<typename Values::value_type> side(kChunks * by);
    for (size_t c = 0; c < kChunks; ++c)
        std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(end_of(c)), by, side.begin() + static_cast<std::ptrdiff_t>(c * by));
    ctx.parallel_for(kChunks, 1, [&](int64_t c0, int64_t c1) {
        for (size_t c = static_cast<size_t>(c0); c < static_cast<size_t>(c1); ++c) {
            const size_t b = n * c / kChunks, e = end_of(c);
            auto at = [&](size_t i) { return values.begin() + static_cast<std::ptrdiff_t>(i); };
            std::copy(at(b + by), at(e), at(b));
            std::copy_n(side.begin() + static_cast<std::ptrdiff_t>(c * by), by, at(e - by));
        }
    });
    values.resize(n);
}
}  // namespace

// Drops the virtual octahedron and the free triangle slots.
void Triangulation::compact_after_build(Context &ctx) {
    if (!free_.empty()) {
        compact_triangles(kVirtual);
    } else {
        // The usual case: every fan took its cavity's slots and fresh ones,
        // so no slot is free and only the vertex numbers move (the marks
        // are all back to 0).
        ctx.parallel_for(triangle_slots(), 16384, [&](int64_t b, int64_t e) {
            for (int64_t t = b; t < e; ++t)
                for (int32_t &u : tris_[t].v) u -= kVirtual;
        });
    }
    drop_front(ctx, q_, kVirtual);
    drop_front(ctx, id_, kVirtual);
    drop_front(ctx, vertex_tri_, kVirtual);
}

// ---------------------------------------------------------------- insertion

int64_t Triangulation::priority(int32_t v) const {
    // Smaller = perturbed more. Real points by input index, then the virtual ones.
    int32_t i = id_[v];
    return i >= 0 ? i : (int64_t(1) << 40) - i;
}

bool Triangulation::visible_on_tie(int32_t t, int32_t v) const {
    const int32_t *tv = &tris_[t].v[0];
    return geom::orient3d_tie_break(q_[tv[0]].data(), q_[tv[1]].data(), q_[tv[2]].data(),
                                    q_[v].data(), priority(tv[0]), priority(tv[1]),
                                    priority(tv[2]), priority(v)) > 0;
}

void Triangulation::set_neighbour(int32_t outer, int32_t from, int32_t to, int32_t t) {
    Tri &o = tris_[outer];
    for (int m = 0; m < 3; ++m)
        if (o.v[next_of_three(m)] == from && o.v[prev_of_three(m)] == to) o.n[m] = t;
}

Triangulation::InsertResult Triangulation::insert_slot(int32_t v, int32_t &hint,
                                                       int32_t *other) {
    int zero_edges[3], n_zero = 0;
    const int32_t t = locate(q_[v], hint, zero_edges, n_zero);
    int32_t coincident = kNone;
    int32_t start = find_visible_start(v, t, zero_edges, n_zero, &coincident);
    if (coincident != kNone) {
        *other = coincident;
        return InsertResult::duplicate;
    }
    if (start == kNone) {
        hint = t;
        return InsertResult::hidden;
    }
    fill_cavity(v, start, scratch_, nullptr);
    SlotPool pool{&free_};
    stitch_new_triangles(v, scratch_, pool);
    hint = vertex_tri_[v];  // a triangle of the new fan
    return InsertResult::inserted;
}

// Visibility walk over the cones of the triangles (the hull contains the
// centre, so their cones tile the directions): cross any edge that has p on
// its outer side. Exact tests; a rotating first edge keeps the walk from
// cycling, and a brute-force scan is the last resort.
int32_t Triangulation::locate(const Vec3 &p, int32_t t, int zero_edges[3],
                              int &n_zero) const {
    const int64_t max_steps = 64 + 4 * static_cast<int64_t>(tris_.size());
    const int32_t found = walk(p, t, zero_edges, n_zero, walk_counter_, max_steps, nullptr, nullptr);
    if (found != kNone) return found;
    t = locate_brute_force(p);
    n_zero = 0;
    for (int k = 0; k < 3; ++k)
        if (orient_origin(q_[tris_[t].v[next_of_three(k)]].data(), q_[tris_[t].v[prev_of_three(k)]].data(),
                          p.data()) == 0)
            zero_edges[n_zero++] = k;
    return t;
}

int32_t Triangulation::walk(const Vec3 &p, int32_t t, int zero_edges[3], int &n_zero,
                            uint32_t &counter, int64_t max_steps, const KeyRange *owner,
                            int32_t *last_owned) const {
    // Two copies of the loop, so that neither asks at each test which filter
    // it uses (the static one decides nearly every test while building).
    return walk_bound_ < kNoBound
               ? walk_with<true, false>(p, t, zero_edges, n_zero, counter, max_steps, owner, last_owned)
               : walk_with<false, false>(p, t, zero_edges, n_zero, counter, max_steps, owner, last_owned);
}

int32_t Triangulation::walk_filtered(const Vec3 &p, int32_t t, int undecided[3], int &n_undecided,
                                     uint32_t &counter, int64_t max_steps, const KeyRange *owner,
                                     int32_t *last_owned) const {
    if (!(walk_bound_ < kNoBound)) fail(UM_ERR_INTERNAL, "walk_filtered: no static bound (not building)");
    return walk_with<true, true>(p, t, undecided, n_undecided, counter, max_steps, owner, last_owned);
}

template <bool kStaticBound, bool kFilterOnly>
int32_t Triangulation::walk_with(const Vec3 &p, int32_t t, int zero_edges[3], int &n_zero,
                                 uint32_t &counter, int64_t max_steps, const KeyRange *owner,
                                 int32_t *last_owned) const {
    // Locals for everything the loop reads or writes more than once, so that
    // the compiler keeps them in registers.
    const Tri *const tris = tris_.data();
    const Vec3 *const q = q_.data();
    const double pv[3] = {p.x, p.y, p.z};
    const double bound = walk_bound_;
    int zeros[3], n = 0;
    int32_t owned = owner ? *last_owned : kNone;
    int32_t from = kNone;  // the edge just crossed is known to have p inside
    // Edge k of tr: kNone if p is not strictly outside it (a zero is
    // listed), else the neighbour across it. The edge just crossed is not
    // tested: it had p strictly outside in the triangle before, and the
    // exact sign is antisymmetric. kFilterOnly: an edge the static filter
    // cannot decide is listed and not crossed.
    auto cross = [&](const Tri &tr, auto edge) -> int32_t {
        constexpr int k = decltype(edge)::value;
        if (tr.n[k] == from) return kNone;
        const double *a = q[tr.v[(k + 1) % 3]].data(), *b = q[tr.v[(k + 2) % 3]].data();
        const int s = kFilterOnly    ? geom::orient_origin_static_filter(a, b, pv, bound)
                      : kStaticBound ? geom::orient_origin_static(a, b, pv, bound)
                                     : orient_origin(a, b, pv);
        if (s == 0) zeros[n++] = k;
        return s < 0 ? tr.n[k] : kNone;
    };
    // The edges in the order k0, k0 + 1, k0 + 2 (mod 3), the first one
    // with p outside taken; constant indices, one copy per first edge.
    auto step_from = [&](const Tri &tr, auto e0, auto e1, auto e2) -> int32_t {
        int32_t to = cross(tr, e0);
        if (to == kNone) to = cross(tr, e1);
        if (to == kNone) to = cross(tr, e2);
        return to;
    };
    using E0 = std::integral_constant<int, 0>;
    using E1 = std::integral_constant<int, 1>;
    using E2 = std::integral_constant<int, 2>;
    // The first edge tested rotates with `counter` (one step per triangle),
    // which keeps the walk from cycling.
    int k0 = static_cast<int>(counter % 3);
    int64_t step = 0;
    int32_t found = kNone;
    for (; step < max_steps; ++step) {
        const Tri &tr = tris[t];
        n = 0;
        const int32_t to = k0 == 0   ? step_from(tr, E0{}, E1{}, E2{})
                           : k0 == 1 ? step_from(tr, E1{}, E2{}, E0{})
                                     : step_from(tr, E2{}, E0{}, E1{});
        k0 = k0 == 2 ? 0 : k0 + 1;
        if (to == kNone) {
            found = t;
            break;
        }
        // Beyond a triangle the region does not own, another region may be
        // changing the mesh.
        if (owner) {
            if (!owns(*owner, t)) break;
            owned = t;
        }
        from = t;
        t = to;
    }
    counter += static_cast<uint32_t>(step < max_steps ? step + 1 : max_steps);
    if (owner) *last_owned = owned;
    n_zero = n;
    for (int i = 0; i < n; ++i) zero_edges[i] = zeros[i];
    return found;
}

int32_t Triangulation::live_triangle_near(int32_t t) const {
    if (t < 0 || t >= static_cast<int32_t>(tris_.size())) t = 0;
    while (tris_[t].v[0] == kNone) t = t + 1 == static_cast<int32_t>(tris_.size()) ? 0 : t + 1;
    return t;
}

int32_t Triangulation::locate_brute_force(const Vec3 &p) const {
    for (int32_t t = 0; t < static_cast<int32_t>(tris_.size()); ++t) {
        if (tris_[t].v[0] == kNone) continue;
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k)
            inside = orient_origin(q_[tris_[t].v[next_of_three(k)]].data(),
                                   q_[tris_[t].v[prev_of_three(k)]].data(), p.data()) >= 0;
        if (inside) return t;
    }
    fail(UM_ERR_INTERNAL, "point location failed: the triangulation is not a sphere");
}

// A point outside the hull sees the facet whose cone holds its direction.
// On a cone boundary it may see only the facet across it; on a vertex's
// direction it coincides with that vertex when their lifted points are
// equal (a duplicate: same direction, same weight), and otherwise buries it
// or is hidden, as any heavier or lighter point near it would.
int32_t Triangulation::find_visible_start(int32_t v, int32_t t, const int zero_edges[3],
                                          int n_zero, int32_t *coincident) {
    if (n_zero >= 2) {
        int32_t w = tris_[t].v[(3 - zero_edges[0] - zero_edges[1])];
        const Vec3 &a = q_[w], &b = q_[v];
        if (id_[w] >= 0 && a.x == b.x && a.y == b.y && a.z == b.z) {
            *coincident = w;
            return kNone;
        }
        // Another weight on w's direction (or w virtual): v buries w when
        // its lifted point lies farther out, and is hidden otherwise.
        for (int32_t u : star(w))
            if (visible(u, v)) return u;
        return kNone;
    }
    if (visible(t, v)) return t;
    if (n_zero == 1) {
        int32_t u = tris_[t].n[zero_edges[0]];
        if (visible(u, v)) return u;
    }
    return kNone;
}

// The cavity grows across every edge to a visible triangle; each edge to
// a triangle that is not visible is a horizon edge, recorded as it is met
// (with its index in the outside triangle, which stitching rewrites). The
// horizon is a simple cycle, but stitching needs no order: each new
// triangle finds the next around v through its vertex (vertex_tri_).
bool Triangulation::fill_cavity(int32_t v, int32_t start, Scratch &s, const KeyRange *owner) {
    // The triangles added share an edge with one in the cavity, so with
    // `start` owned, each is owned when its apex is.
    if (owner && !owns(*owner, start)) return false;
    // Two copies of the loop, as for walk().
    return build_bound_ < kNoBound ? fill_cavity_with<true>(v, start, s, owner)
                                   : fill_cavity_with<false>(v, start, s, owner);
}

template <bool kStaticBound>
bool Triangulation::fill_cavity_with(int32_t v, int32_t start, Scratch &s, const KeyRange *owner) {
    const Tri *const tris = tris_.data();
    Mark *const mark = mark_.data();
    const Vec3 *const q = q_.data();
    const double p[3] = {q[v].x, q[v].y, q[v].z};
    const double bound = build_bound_;
    std::vector<int32_t> &cavity = s.cavity;
    std::vector<HorizonEdge> &horizon = s.horizon;
    cavity.clear();
    horizon.clear();
    cavity.push_back(start);
    mark[start] = Mark::cavity;
    for (size_t i = 0; i < cavity.size(); ++i) {
        const Tri c = tris[cavity[i]];
#pragma GCC unroll 3
        for (int k = 0; k < 3; ++k) {
            const int32_t u = c.n[k];
            const Mark m = mark[u];
            if (m == Mark::cavity) continue;
            // The edge runs a -> b in c and b -> a in u: in u it is the edge
            // after a's corner, and u is (apex, b, a) counter-clockwise.
            const int32_t a = c.v[next_of_three(k)], b = c.v[prev_of_three(k)];
            const int32_t *uv = tris[u].v;
            const int j = (uv[0] == a) | (uv[1] == a) << 1;  // 1, 2, or 0 when uv[2] == a
            if (m == Mark::none) {
                const int32_t apex = uv[j];
                const double *qa = q[apex].data(), *qb = q[b].data(), *qc = q[a].data();
                const int sign = kStaticBound ? geom::orient3d_static(qa, qb, qc, p, bound)
                                              : geom::orient3d(qa, qb, qc, p);
                if (sign > 0 || (sign == 0 && visible_on_tie(u, v))) {
                    if (owner && !owns_vertex(*owner, apex)) {
                        clear_cavity_marks(s);
                        return false;
                    }
                    mark[u] = Mark::cavity;
                    cavity.push_back(u);
                    continue;
                }
                mark[u] = Mark::outside;  // (and listed with its horizon edge below)
            }
            horizon.push_back({a, b, u, j});
        }
    }
    return true;
}

void Triangulation::clear_cavity_marks(const Scratch &s) {
    for (int32_t t : s.cavity) mark_[t] = Mark::none;
    for (const HorizonEdge &h : s.horizon) mark_[h.outside] = Mark::none;
}

int32_t Triangulation::new_triangle_slot_slow(SlotPool &pool) {
    if (!pool.reuse->empty()) {
        int32_t t = pool.reuse->back();
        pool.reuse->pop_back();
        return t;
    }
    int32_t t = static_cast<int32_t>(tris_.size());
    reserve_for(tris_, tris_.size() + 1), reserve_for(mark_, mark_.size() + 1);
    tris_.push_back({{kNone, kNone, kNone}, {kNone, kNone, kNone}});
    mark_.push_back(Mark::none);
    return t;
}

void Triangulation::stitch_new_triangles(int32_t v, Scratch &s, SlotPool &pool) {
    // Only when v buries vertices (Scratch::cavity_buries) do the cavity's
    // vertices need a fresh incident triangle from the new fan.
    const size_t k = s.cavity.size(), m = s.horizon.size();
    const bool buries = s.cavity_buries();
    s.cavity_vertices.clear();
    if (buries)
        for (int32_t t : s.cavity)
            for (int c = 0; c < 3; ++c) {
                const int32_t u = tris_[t].v[c];
                if (vertex_tri_[u] >= 0) s.cavity_vertices.push_back(u);
                vertex_tri_[u] = kNone;
            }
    // The fan takes the cavity's slots first (in cavity order), then the
    // pool's, appended to s.cavity (not needed as the cavity after this);
    // the slots first, since the serial path's pool may grow tris_. A cavity
    // slot the fan does not take gets its mark back to none here, the fan's
    // below.
    for (size_t i = m; i < k; ++i) {
        mark_[s.cavity[i]] = Mark::none;
        free_triangle_slot(s.cavity[i], pool);
    }
    for (size_t i = k; i < m; ++i) s.cavity.push_back(new_triangle_slot(pool));
    Tri *const tris = tris_.data();
    Mark *const mark = mark_.data();
    int32_t *const vertex_tri = vertex_tri_.data();
    const HorizonEdge *const horizon = s.horizon.data();
    const int32_t *const fan = s.cavity.data();
    for (size_t i = 0; i < m; ++i) {
        const HorizonEdge &h = horizon[i];
        const int32_t t = fan[i];
        // The marks go back to none: the fan's (the cavity's, or a fresh
        // slot's, unwritten) and the triangles' outside the horizon.
        mark[h.outside] = Mark::none, mark[t] = Mark::none;
        tris[t].v[0] = v, tris[t].v[1] = h.a, tris[t].v[2] = h.b;
        tris[t].n[0] = h.outside;
        tris[h.outside].n[h.outside_edge] = t;
        vertex_tri[h.a] = t;
    }
    // Around v: the fan triangle after (v, a, b) is the one that starts at b.
    for (size_t i = 0; i < m; ++i) {
        const int32_t t = fan[i], after = vertex_tri[horizon[i].b];
        tris[t].n[1] = after;
        tris[after].n[2] = t;
    }
    vertex_tri[v] = fan[0];
}

// ------------------------------------------------------------------ updates

void Triangulation::free_triangle_slot(int32_t t, SlotPool &pool) {
    tris_[t].v[0] = tris_[t].v[1] = tris_[t].v[2] = kNone;
    pool.reuse->push_back(t);
}

void Triangulation::free_triangle_slot(int32_t t) {
    SlotPool pool{&free_};
    free_triangle_slot(t, pool);
}

int32_t Triangulation::insert(const Vec3 &direction, double weight, int32_t id,
                              std::vector<int32_t> *buried, int32_t hint) {
    int32_t v = static_cast<int32_t>(q_.size());
    reserve_for(q_, q_.size() + 1), reserve_for(id_, id_.size() + 1);
    reserve_for(vertex_tri_, vertex_tri_.size() + 1);
    q_.push_back(lifted_scale(weight) * direction);
    id_.push_back(id);
    vertex_tri_.push_back(kNone);
    try {
        return reinsert(v, buried, hint);
    } catch (...) {
        q_.pop_back(), id_.pop_back(), vertex_tri_.pop_back();
        throw;
    }
}

int32_t Triangulation::insert_into_removed(int32_t slot, const Vec3 &direction, double weight, int32_t id,
                                           std::vector<int32_t> *buried, int32_t hint) {
    if (slot < 0 || slot >= vertex_slots() || vertex_tri_[slot] != kRemoved)
        fail(UM_ERR_INTERNAL, "insert_into_removed: vertex slot ", slot, " is not removed");
    const Vec3 q = q_[slot];
    const int32_t old_id = id_[slot];
    q_[slot] = lifted_scale(weight) * direction, id_[slot] = id, vertex_tri_[slot] = kNone;
    try {
        return reinsert(slot, buried, hint);
    } catch (...) {
        q_[slot] = q, id_[slot] = old_id, vertex_tri_[slot] = kRemoved;  // removed, as before the call
        throw;
    }
}

// (Re)inserts the point already stored in slot v.
int32_t Triangulation::reinsert(int32_t v, std::vector<int32_t> *buried, int32_t hint) {
    hint = live_triangle_near(hint);
    int32_t other = kNone;
    InsertResult r = insert_slot(v, hint, &other);
    if (r == InsertResult::duplicate) {
        double lon, lat;
        geom::lonlat_deg_from_unit(direction(v), lon, lat);
        fail(UM_ERR_DUPLICATE_POINTS, "point ", id_[v], " is at the location of point ",
             id_[other], " (lon ", lon, ", lat ", lat, " degrees)");
    }
    if (r == InsertResult::inserted && buried)
        for (int32_t u : scratch_.cavity_vertices)
            if (vertex_tri_[u] == kNone) buried->push_back(u);
    return v;
}

bool Triangulation::flippable(int32_t t, int k) const {
    const Tri &tr = tris_[t];
    int32_t a = tr.v[k], b = tr.v[next_of_three(k)], c = tr.v[prev_of_three(k)];
    int32_t u = tr.n[k];
    int32_t d = tris_[u].v[prev_of_three(local_index(u, c))];
    // New triangles (a, b, d) and (d, c, a) must both face outwards.
    return orient_origin(q_[a].data(), q_[b].data(), q_[d].data()) > 0 &&
           orient_origin(q_[d].data(), q_[c].data(), q_[a].data()) > 0;
}

bool Triangulation::flip(int32_t t, int k) {
    if (!flippable(t, k)) return false;
    Tri &tr = tris_[t];
    int32_t a = tr.v[k], b = tr.v[next_of_three(k)], c = tr.v[prev_of_three(k)];
    int32_t u = tr.n[k];
    int ku = next_of_three(next_of_three(local_index(u, c)));  // apex of u
    Tri &ur = tris_[u];
    int32_t d = ur.v[ku];
    // Outer neighbours of the quad a -> b -> d -> c.
    int32_t n_ab = tr.n[prev_of_three(k)], n_ca = tr.n[next_of_three(k)];
    int32_t n_bd = ur.n[next_of_three(ku)], n_dc = ur.n[prev_of_three(ku)];
    // t becomes (a, b, d), u becomes (d, c, a).
    tr = {{a, b, d}, {n_bd, u, n_ab}};
    ur = {{d, c, a}, {n_ca, t, n_dc}};
    set_neighbour(n_bd, d, b, t);
    set_neighbour(n_ca, a, c, u);
    vertex_tri_[a] = t, vertex_tri_[b] = t, vertex_tri_[d] = u, vertex_tri_[c] = u;
    return true;
}

// The ear (link[i-1], link[i], link[i+1]) of a vertex's link is a facet of
// the hull of the remaining points: convex seen from the centre, and no other
// link vertex beyond its plane.
bool Triangulation::ear_is_hull_facet(const std::vector<int32_t> &link, size_t i) const {
    const size_t k = link.size();
    int32_t a = link[(i + k - 1) % k], b = link[i], c = link[(i + 1) % k];
    if (orient_origin(q_[a].data(), q_[b].data(), q_[c].data()) <= 0) return false;
    for (size_t j = 0; j < k; ++j) {
        int32_t x = link[j];
        if (x == a || x == b || x == c) continue;
        auto ids = [&](int64_t out[4]) {
            out[0] = priority(a), out[1] = priority(b), out[2] = priority(c), out[3] = priority(x);
        };
        if (geom::orient3d_perturbed(q_[a].data(), q_[b].data(), q_[c].data(), q_[x].data(), ids) > 0)
            return false;
    }
    return true;
}

int32_t Triangulation::remove(int32_t v) {
    if (vertex_tri_[v] < 0) {
        vertex_tri_[v] = kRemoved;
        return live_triangle_near(0);
    }
    // Clip ears by flipping the spoke (v, link[i]) until v has degree 3.
    std::vector<int32_t> link_vertices;  // kept when the link was degenerate
    const Vec3 kept = q_[v];
    bool nudged = false;
    for (;;) {
        std::vector<int32_t> st = star(v);
        if (st.size() <= 3) break;
        std::vector<int32_t> link(st.size());
        for (size_t i = 0; i < st.size(); ++i) link[i] = tris_[st[i]].v[next_of_three(local_index(st[i], v))];
        // The spoke (v, link[i]) is shared by st[i-1] = (v, link[i-1], link[i])
        // and st[i]; in st[i-1] it is the edge opposite link[i-1]. Flipping it
        // creates the ear (link[i-1], link[i], link[i+1]).
        auto clip = [&](size_t i) {
            const size_t h = (i + st.size() - 1) % st.size();
            return flip(st[h], local_index(st[h], link[h]));
        };
        bool clipped = false;
        for (size_t i = 0; i < link.size() && !clipped; ++i)
            if (ear_is_hull_facet(link, i)) clipped = clip(i);
        if (!clipped) {
            // A link with points on one great circle (a grid of meridians
            // and the equator, say) can leave every hull ear flat, or pass
            // every diagonal through v itself. Any convex ear keeps the
            // sphere triangulated, and v may be nudged off the diagonals -
            // it is going anyway; Lawson flips after the removal make the
            // region regular again.
            for (size_t i = 0; i < link.size() && !clipped; ++i) clipped = clip(i);
            if (!clipped && !nudged) {
                nudged = true;
                clipped = nudge_off_diagonals(v, link);
            }
            if (!clipped) fail(UM_ERR_INTERNAL, "vertex removal found no ear to clip");
            link_vertices.insert(link_vertices.end(), link.begin(), link.end());
        }
    }
    const int32_t t = remove_degree_three(v);
    q_[v] = kept;
    if (!link_vertices.empty()) {
        std::vector<int32_t> around;
        for (int32_t u : link_vertices)
            if (vertex_tri_[u] >= 0)
                for (int32_t s : star(u)) around.push_back(s);
        restore_regularity(std::move(around));
        return live_triangle_near(t);
    }
    return t;
}

void Triangulation::restore_removed(int32_t v, int32_t hint) {
    if (vertex_tri_[v] != kRemoved) fail(UM_ERR_INTERNAL, "restore_removed: vertex slot ", v, " is not removed");
    vertex_tri_[v] = kNone;
    try {
        reinsert(v, nullptr, hint);
    } catch (...) {
        vertex_tri_[v] = kRemoved;  // still removed, as before the call
        throw;
    }
}

void Triangulation::restore_hidden(int32_t v, int32_t hint) {
    if (vertex_tri_[v] != kNone) fail(UM_ERR_INTERNAL, "restore_hidden: vertex slot ", v, " is not hidden");
    reinsert(v, nullptr, hint);
}

// Moves v a little towards one of its link vertices, keeping its star facing
// outwards; true when it moved.
bool Triangulation::nudge_off_diagonals(int32_t v, const std::vector<int32_t> &link) {
    const Vec3 original = q_[v];
    const double s = geom::norm(original);
    const std::vector<int32_t> st = star(v);
    for (int32_t toward : link)
        for (double share : {1e-2, 1e-4}) {
            q_[v] = s * geom::normalized(direction(v) + share * (direction(toward) - direction(v)));
            bool outwards = true;
            for (int32_t t : st)
                outwards &= orient_origin(q_[tris_[t].v[0]].data(), q_[tris_[t].v[1]].data(),
                                          q_[tris_[t].v[2]].data()) > 0;
            if (outwards) return true;
            q_[v] = original;
        }
    return false;
}

int32_t Triangulation::remove_degree_three(int32_t v) {
    std::vector<int32_t> st = star(v);
    int32_t t1 = st[0], t2 = st[1], t3 = st[2];
    int j1 = local_index(t1, v), j2 = local_index(t2, v), j3 = local_index(t3, v);
    int32_t a = tris_[t1].v[next_of_three(j1)], b = tris_[t2].v[next_of_three(j2)], c = tris_[t3].v[next_of_three(j3)];
    int32_t n_ab = tris_[t1].n[j1], n_bc = tris_[t2].n[j2], n_ca = tris_[t3].n[j3];
    tris_[t1] = {{a, b, c}, {n_bc, n_ca, n_ab}};
    set_neighbour(n_bc, c, b, t1);
    set_neighbour(n_ca, a, c, t1);
    free_triangle_slot(t2);
    free_triangle_slot(t3);
    vertex_tri_[a] = vertex_tri_[b] = vertex_tri_[c] = t1;
    vertex_tri_[v] = kRemoved;
    return t1;
}

// Removes v, stores its new lifted point and inserts it again: insertion is
// exact for any configuration, so this is correct however far v moves. On a
// duplicate the old point is put back and the error rethrown.
std::vector<int32_t> Triangulation::replace_point(int32_t v, const Vec3 &lifted) {
    std::vector<int32_t> buried;
    const Vec3 old = q_[v];
    const bool was_in = vertex_tri_[v] >= 0;
    int32_t hint = was_in ? remove(v) : 0;
    q_[v] = lifted;
    try {
        reinsert(v, &buried, hint);
    } catch (...) {
        q_[v] = old;
        if (was_in) reinsert(v, nullptr, hint);
        throw;
    }
    if (vertex_tri_[v] < 0) buried.push_back(v);
    return buried;
}

std::vector<int32_t> Triangulation::move(int32_t v, const Vec3 &direction) {
    return replace_point(v, geom::norm(q_[v]) * direction);
}

std::vector<int32_t> Triangulation::set_weight(int32_t v, double weight) {
    return replace_point(v, lifted_scale(weight) * geom::normalized(q_[v]));
}

int64_t Triangulation::restore_regularity(std::vector<int32_t> triangles) {
    int64_t flips = 0;
    std::vector<int32_t> &stack = triangles;
    std::reverse(stack.begin(), stack.end());  // the first given is looked at first
    for (int round = 0;; ++round) {
        std::vector<int32_t> knotted;  // apexes of non-regular edges no flip can mend
        while (!stack.empty()) {
            const int32_t t = stack.back();
            stack.pop_back();
            if (is_free(t)) continue;
            for (int k = 0; k < 3; ++k) {
                if (is_locally_regular(t, k)) continue;
                const int32_t u = tris_[t].n[k];
                if (flip(t, k)) {
                    ++flips;
                    stack.push_back(u), stack.push_back(t);
                    break;  // t is a new triangle: look at it again from the start
                }
                knotted.push_back(tris_[t].v[k]);
            }
        }
        std::sort(knotted.begin(), knotted.end());
        knotted.erase(std::unique(knotted.begin(), knotted.end()), knotted.end());
        if (knotted.empty()) return flips;
        if (round == 8)
            fail(UM_ERR_INTERNAL, "restoring regularity left ", knotted.size(),
                 " edges that no flip can mend");
        // Re-inserting a vertex is exact for any configuration around it.
        for (int32_t v : knotted) {
            if (vertex_tri_[v] < 0) continue;
            replace_point(v, q_[v]);
            ++flips;  // counted with the flips: the caller learns the topology changed
            if (vertex_tri_[v] >= 0)
                for (int32_t t : star(v)) stack.push_back(t);
            else
                stack.push_back(live_triangle_near(0));
        }
    }
}

// ------------------------------------------------------------------ queries

int64_t Triangulation::vertex_count() const {
    int64_t n = 0;
    for (int32_t t : vertex_tri_) n += t >= 0;
    return n;
}

std::vector<int32_t> Triangulation::hidden_ids() const {
    std::vector<int32_t> out;
    for (size_t v = 0; v < vertex_tri_.size(); ++v)
        if (vertex_tri_[v] == kNone && id_[v] >= 0) out.push_back(id_[v]);
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<int32_t> Triangulation::star(int32_t v) const {
    std::vector<int32_t> out;
    for_each_in_star(v, [&](int32_t t) { out.push_back(t); });
    return out;
}

std::vector<int32_t> Triangulation::link(int32_t v) const {
    std::vector<int32_t> out;
    for_each_neighbour(v, [&](int32_t w) { out.push_back(w); });
    return out;
}

Vec3 Triangulation::orthocentre(int32_t t) const {
    const Vec3 &a = q_[tris_[t].v[0]], &b = q_[tris_[t].v[1]], &c = q_[tris_[t].v[2]];
    return geom::normalized(geom::cross(b - a, c - a));
}

Vec3 Triangulation::edge_orthocentre(int32_t t, int k) const {
    // p = alpha x_i + beta x_j with p . (q_i - q_j) = 0, alpha, beta > 0.
    const Vec3 &qi = q_[tris_[t].v[next_of_three(k)]], &qj = q_[tris_[t].v[prev_of_three(k)]];
    double si = geom::norm(qi), sj = geom::norm(qj);
    Vec3 xi = (1.0 / si) * qi, xj = (1.0 / sj) * qj;
    double c = geom::dot(xi, xj);
    return geom::normalized((sj - si * c) * xi + (si - sj * c) * xj);
}

std::vector<Vec3> Triangulation::power_cell(int32_t v) const {
    std::vector<Vec3> out;
    for (int32_t t : star(v)) out.push_back(orthocentre(t));
    return out;
}

bool Triangulation::is_locally_regular(int32_t t, int k) const {
    int32_t u = tris_[t].n[k];
    int32_t apex = tris_[u].v[next_of_three(next_of_three(local_index(u, tris_[t].v[prev_of_three(k)])))];
    // Convex across the edge iff the far apex is not beyond t's facet.
    return !visible(t, apex);
}

}  // namespace um::tri
