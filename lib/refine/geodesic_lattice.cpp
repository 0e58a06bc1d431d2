#include "refine/geodesic_lattice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <utility>

#include "core/growth.hpp"
#include "core/uninit_vector.hpp"

namespace um::refine {

using geom::Vec3;

namespace {

// The relaxation, coarse to fine: frequencies up to kCoarsest are relaxed
// from their placement in kCoarseSweeps sweeps (a few hundred are needed for
// the strain to reach across a face there: Jacobi's rate goes with the
// frequency squared); each finer one starts from the relaxed lattice of half
// its frequency and takes kFineSweeps. Without the stiff part below, this
// reaches the least-squares optimum's spread of the edges at 120 km
// (frequency 64) to 2e-5 (0.0409).
constexpr int64_t kCoarsest = 8;
constexpr int kCoarseSweeps = 1000;
constexpr int kFineSweeps = 8;
// Springs shorter than kShortest of the rest length are kStiffer times as
// stiff (and rest a little longer, so that the stiff part pushes out from
// kShortest): on their own the springs would squeeze the rings around each
// pentagon (a disclination's strain grows with the log of the lattice's
// size: its five spokes went from 0.81 to 0.77 of the mean edge between 240
// and 60 km), and the model's time step goes by the shortest edge. With the
// stiff part the shortest edge is 0.86, 0.85, 0.84 and 0.83 of the mean at
// frequencies 64, 128, 256 and 512 (120 to 15 km); stiff below 0.85 it was
// 0.81 at 128, and below 0.90 the curl's error gained half as much.
constexpr double kShortest = 0.87;
constexpr double kStiffer = 100;
constexpr const char *kStage = "refine lattice";  // progress, and cancel between sweeps
// A frequency-n lattice's edges are about this over n radians long (10 n^2
// hexagons of edge s cover the sphere: s = sqrt(4 pi / (10 sqrt(3) / 2)) / n).
constexpr double kEdgePerFrequency = 1.2;

// A lattice's points (unwritten until placed: a regional lattice places
// only its part).
using Points = UninitVector<Vec3>;

// The point a fraction t of the way from a to b along their great circle.
Vec3 slerp(const Vec3 &a, const Vec3 &b, double t) {
    const double angle = std::acos(std::max(-1.0, std::min(1.0, geom::dot(a, b))));
    if (angle == 0) return a;
    const double s = std::sin(angle);
    return geom::normalized((std::sin((1 - t) * angle) / s) * a + (std::sin(t * angle) / s) * b);
}

std::array<Vec3, 12> icosahedron_corners() {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    const Vec3 v[12] = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                        {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    std::array<Vec3, 12> corners;
    for (int i = 0; i < 12; ++i) corners[i] = geom::normalized(v[i]);
    return corners;
}

// Two corners share an edge when they are nearest neighbours: the edge's
// chord is 1.05 on the unit sphere, the next distance 1.70.
bool adjacent(const Vec3 &a, const Vec3 &b) {
    const Vec3 d = a - b;
    return geom::dot(d, d) < 1.21;
}

// The point of face (a, b, c) with barycentric weights (i, j, k) / n, on the
// row of points at weight i of a: from the point of edge ab to that of edge ac.
Vec3 row_point(const Vec3 &a, const Vec3 &b, const Vec3 &c, int64_t i, int64_t k, int64_t n) {
    const double towards = static_cast<double>(n - i) / static_cast<double>(n);
    const Vec3 from = slerp(a, b, towards), to = slerp(a, c, towards);
    return slerp(from, to, static_cast<double>(k) / static_cast<double>(n - i));
}

// The columns j of a row of a face's points that may hold placed ones:
// [first, last], none when first > last.
struct Span {
    int64_t first = 1, last = 0;
    bool empty() const { return first > last; }
    void add(int64_t j) {
        first = empty() ? j : std::min(first, j), last = std::max(last, j);
    }
};

// Where each point of the frequency-n lattice sits in geodesic_lattice's
// order: the 12 corners, the 30 edges' inner points (edge (a, b), a < b, in
// the order of the corners' pairs, from a to b), the 20 faces' inner points
// (face (a, b, c), a < b < c, rows of weight i = 1 .. n-2 of a, in each the
// weight j = 1 .. n-1-i of b). A face's point (i, j) has weights i, j and
// k = n - i - j of its corners a, b, c.
class LatticeIndex {
public:
    explicit LatticeIndex(int64_t n) : n_(n), size_(10 * n * n + 2) {
        const std::array<Vec3, 12> corner = icosahedron_corners();
        edge_of_.fill({});
        for (auto &row : edge_of_) row.fill(-1);
        for (int a = 0; a < 12; ++a)
            for (int b = a + 1; b < 12; ++b)
                if (adjacent(corner[a], corner[b])) {
                    edge_of_[a][b] = static_cast<int>(edges_.size());
                    edges_.push_back({a, b});
                }
        for (int a = 0; a < 12; ++a)
            for (int b = a + 1; b < 12; ++b)
                for (int c = b + 1; c < 12; ++c)
                    if (edge_of_[a][b] >= 0 && edge_of_[b][c] >= 0 && edge_of_[a][c] >= 0) faces_.push_back({a, b, c});
    }

    // The same lattice holding, of each face's inner row (numbered as
    // row_count says), only the columns kept[row]: a regional level, whose
    // points beyond them are never placed. The points held keep their order
    // and are numbered without the others (global_at: the whole lattice's
    // numbers).
    LatticeIndex(int64_t n, const std::vector<Span> &kept) : LatticeIndex(n) {
        kept_ = kept;
        origin_.resize(kept.size());
        int64_t next = outline_end();
        for (size_t row = 0; row < kept.size(); ++row) {
            origin_[row] = next - kept[row].first;
            if (!kept[row].empty()) next += kept[row].last - kept[row].first + 1;
        }
        size_ = next;
    }

    int64_t frequency() const { return n_; }
    int64_t size() const { return size_; }  // the points held
    int edge_count() const { return static_cast<int>(edges_.size()); }
    int face_count() const { return static_cast<int>(faces_.size()); }
    const std::array<int, 2> &edge(int e) const { return edges_[e]; }
    const std::array<int, 3> &face(int f) const { return faces_[f]; }

    // The point s of n along edge e (0 and n: its corners).
    int64_t on_edge(int e, int64_t s) const {
        if (s == 0) return edges_[e][0];
        if (s == n_) return edges_[e][1];
        return 12 + e * (n_ - 1) + (s - 1);
    }

    // The point (i, j) of face f.
    int64_t at(int f, int64_t i, int64_t j) const {
        const int64_t k = n_ - i - j;
        const std::array<int, 3> &c = faces_[f];
        if (i == n_) return c[0];
        if (j == n_) return c[1];
        if (k == n_) return c[2];
        if (k == 0) return on_edge(edge_of_[c[0]][c[1]], j);
        if (j == 0) return on_edge(edge_of_[c[0]][c[2]], k);
        if (i == 0) return on_edge(edge_of_[c[1]][c[2]], k);
        return row_origin(f, i) + j;
    }
    // (i, j) of face f in the whole lattice's numbering.
    int64_t global_at(int f, int64_t i, int64_t j) const {
        return i == 0 || j == 0 || i + j == n_ ? at(f, i, j) : dense_origin(f, i) + j;
    }
    // Inner row i of face f: its point (i, j) is row_origin(f, i) + j, for
    // the columns it holds.
    int64_t row_origin(int f, int64_t i) const {
        return origin_.empty() ? dense_origin(f, i) : origin_[static_cast<size_t>(f * (n_ - 2) + i - 1)];
    }
    Span held(int64_t row, int64_t i) const {
        return kept_.empty() ? Span{1, n_ - 1 - i} : kept_[static_cast<size_t>(row)];
    }

    // A face's inner rows, numbered f * (n - 2) + (i - 1) for i = 1 .. n-2.
    int64_t row_count() const { return n_ > 2 ? face_count() * (n_ - 2) : 0; }
    int row_face(int64_t row) const { return static_cast<int>(row / (n_ - 2)); }
    int64_t row_in_face(int64_t row) const { return row % (n_ - 2) + 1; }

    // The corners and the edges' inner points are [0, outline_end()).
    int64_t outline_end() const { return 12 + edge_count() * (n_ - 1); }

private:
    int64_t dense_origin(int f, int64_t i) const {
        return outline_end() + f * (n_ - 1) * (n_ - 2) / 2 + (i - 1) * (n_ - 1) - (i - 1) * i / 2 - 1;
    }

    int64_t n_, size_;
    std::vector<int64_t> origin_;
    std::vector<Span> kept_;
    std::array<std::array<int, 12>, 12> edge_of_{};
    std::vector<std::array<int, 2>> edges_;
    std::vector<std::array<int, 3>> faces_;
};

// The six neighbours of each edge point, in the order of the edge points
// (a face's neighbours are found from its (i, j) on the fly).
std::vector<std::array<int64_t, 6>> edge_point_neighbours(const LatticeIndex &index) {
    const int64_t n = index.frequency();
    std::vector<std::array<int64_t, 6>> out(static_cast<size_t>(index.edge_count() * std::max<int64_t>(n - 1, 0)));
    std::vector<int> count(out.size(), 0);
    static constexpr int kStep[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
    // Each face's points on its sides, in the order of (i, j) (so that each
    // point's neighbours come in the same order as a scan of every point
    // would find them); the points inside hold no edge point.
    for (int f = 0; f < index.face_count(); ++f)
        for (int64_t i = 0; i <= n; ++i)
            for (int64_t j = 0; i + j <= n; j = (i == 0 || j == n - i) ? j + 1 : n - i) {
                const int64_t p = index.at(f, i, j);
                if (p < 12 || p >= 12 + static_cast<int64_t>(out.size())) continue;  // a corner or inside
                const size_t slot = static_cast<size_t>(p - 12);
                for (const auto &step : kStep) {
                    const int64_t i2 = i + step[0], j2 = j + step[1];
                    if (i2 < 0 || j2 < 0 || i2 + j2 > n) continue;
                    const int64_t q = index.at(f, i2, j2);
                    int64_t *begin = out[slot].data(), *end = begin + count[slot];
                    if (std::find(begin, end, q) == end && count[slot] < 6) out[slot][count[slot]++] = q;
                }
            }
    return out;
}

// The chords a sweep measured: their sum and how many (each edge twice).
struct Chords {
    double sum = 0;
    int64_t count = 0;
    double mean() const { return count > 0 ? sum / static_cast<double>(count) : 0.0; }
};

// One Jacobi sweep of the springs: each point but the corners goes to the
// mean of where each neighbour's spring of length `rest` would put it (the
// neighbour plus rest along the chord towards the point), weighted by the
// springs' stiffness, back on the sphere; with `rest` 0 it only measures.
// The items of a sweep (below) are the icosahedron's edges, then the
// faces' inner rows.
// With an Active set only its points move (the others hold the same place
// in `from` and `to`), only its items are visited, and only its points'
// chords are measured; only its points and their neighbours are read.
struct Active {
    std::vector<uint8_t> point, item;
};
// Returns the chords, summed by item in a fixed order so that the sum is
// the same for any thread count.
Chords spring_sweep(Context &ctx, const LatticeIndex &index, const std::vector<std::array<int64_t, 6>> &edge_nbrs,
                    const Points &from, Points &to, double rest, const Active *active) {
    const bool measuring = !(rest > 0);
    auto place = [&](int64_t p, const int64_t *nbrs, int count, Chords &chords) {
        if (active && !active->point[p]) return;
        const Vec3 x = from[p];
        chords.count += count;
        Vec3 sum{};
        for (int k = 0; k < count; ++k) {
            const Vec3 &y = from[nbrs[k]];
            const Vec3 d = x - y;
            const double length = geom::norm(d);
            chords.sum += length;
            if (measuring || !(length > 0)) continue;
            if (length >= kShortest * rest) {
                sum = sum + y + (rest / length) * d;
            } else {
                static constexpr double kStiffRest = (1 + kStiffer * kShortest) / (1 + kStiffer);
                sum = sum + (1 + kStiffer) * (y + (kStiffRest * rest / length) * d);
            }
        }
        if (!measuring) to[p] = geom::normalized(sum);
    };
    const int64_t n = index.frequency();
    const int64_t edge_items = index.edge_count(), items = edge_items + index.row_count();
    std::vector<Chords> chords(static_cast<size_t>(items));
    ctx.parallel_for(items, 1, [&](int64_t b, int64_t e) {
        for (int64_t item = b; item < e; ++item) {
            if (active && !active->item[item]) continue;
            Chords &sum = chords[item];
            if (item < edge_items) {
                for (int64_t s = 1; s < n; ++s) {
                    const int64_t p = index.on_edge(static_cast<int>(item), s);
                    place(p, edge_nbrs[static_cast<size_t>(p - 12)].data(), 6, sum);
                }
                continue;
            }
            const int f = static_cast<int>((item - edge_items) / (n - 2));
            const int64_t i = (item - edge_items) % (n - 2) + 1;
            // Rows i - 1, i, i + 1 of the face: away from the face's sides
            // the six neighbours are at fixed offsets from the rows' origins.
            const int64_t row = index.row_origin(f, i);
            const int64_t below = i >= 2 ? index.row_origin(f, i - 1) : 0,
                          above = i <= n - 3 ? index.row_origin(f, i + 1) : 0;
            const Span held = index.held(item - edge_items, i);
            for (int64_t j = held.first; j <= held.last; ++j) {
                const int64_t p = row + j;
                if (i >= 2 && j >= 2 && i + j <= n - 2) {
                    const int64_t nbrs[6] = {above + j, below + j, p + 1, p - 1, above + j - 1, below + j + 1};
                    place(p, nbrs, 6, sum);
                    continue;
                }
                const int64_t nbrs[6] = {index.at(f, i + 1, j), index.at(f, i - 1, j),     index.at(f, i, j + 1),
                                         index.at(f, i, j - 1), index.at(f, i + 1, j - 1), index.at(f, i - 1, j + 1)};
                place(p, nbrs, 6, sum);
            }
        }
    });
    Chords total;
    for (const Chords &c : chords) total.sum += c.sum, total.count += c.count;
    for (int c = 0; c < 12; ++c) {  // the corners stay; their five chords count too
        to[c] = from[c];
        if (active && !active->point[c]) continue;
        for (int e = 0; e < index.edge_count(); ++e)
            if (index.edge(e)[0] == c || index.edge(e)[1] == c) {
                total.sum += geom::norm(from[c] - from[index.on_edge(e, index.edge(e)[0] == c ? 1 : n - 1)]);
                ++total.count;
            }
    }
    return total;
}

// The points of a lattice a relaxation within a cap places: each one
// whose coarser points (those its placement reads) are placed, if it is
// within kHeldMargin edge lengths beyond the points the relaxation moves.
// All of them without a cap, or when that reaches round the sphere.
// Each inner row of each face keeps the span of its placed points, so that
// the scans of a regional lattice visit what lies near the cap only.
class Placed {
public:
    Placed() = default;  // all
    explicit Placed(const LatticeIndex &index)
        : flag_(static_cast<size_t>(index.size()), 0), span_(static_cast<size_t>(index.row_count())) {}
    bool all() const { return flag_.empty(); }
    bool operator[](int64_t p) const { return flag_.empty() || flag_[static_cast<size_t>(p)]; }
    void set(int64_t p, bool placed) { flag_[static_cast<size_t>(p)] = placed; }
    // Inner row `row` (numbered as LatticeIndex::row_count says) of the
    // frequency-n lattice, row i of its face.
    Span span(int64_t row, int64_t n, int64_t i) const {
        return span_.empty() ? Span{1, n - 1 - i} : span_[static_cast<size_t>(row)];
    }
    void set_span(int64_t row, Span s) { span_[static_cast<size_t>(row)] = s; }

private:
    std::vector<uint8_t> flag_;  // (a regional level holds only its part of the lattice)
    std::vector<Span> span_;
};

// Calls scan(first, end), in parallel, on ranges holding every point that
// may be placed: the corners and edge points, and each inner row's span.
template <class Scan>
void scan_placeable(Context &ctx, const LatticeIndex &index, const Placed &placed, Scan &&scan) {
    ctx.parallel_for(index.outline_end(), 4096, [&](int64_t b, int64_t e) { scan(b, e); });
    const int64_t n = index.frequency();
    ctx.parallel_for(index.row_count(), 16, [&](int64_t b, int64_t e) {
        for (int64_t row = b; row < e; ++row) {
            const int f = index.row_face(row);
            const int64_t i = index.row_in_face(row);
            const Span s = placed.span(row, n, i);
            if (!s.empty()) scan(index.at(f, i, s.first), index.at(f, i, s.last) + 1);
        }
    });
}

// The columns J (0 .. m - I) of the placed points of row I (0 .. m) of face
// f, its sides and corners included.
Span closed_row(const LatticeIndex &index, const Placed &placed, int f, int64_t I) {
    const int64_t m = index.frequency();
    if (placed.all()) return {0, m - I};
    Span s;
    if (I >= 1 && I <= m - 2) {
        if (placed[index.at(f, I, 0)]) s.add(0);
        const Span inner = placed.span(f * (m - 2) + I - 1, m, I);
        if (!inner.empty()) s.add(inner.first), s.add(inner.last);
        if (placed[index.at(f, I, m - I)]) s.add(m - I);
        return s;
    }
    for (int64_t J = 0; J <= m - I; ++J)
        if (placed[index.at(f, I, J)]) s.add(J);
    return s;
}

// How far from a cap's centre the frequency-n lattice is relaxed, and
// placed.
double relaxed_reach(const Cap &cap, int64_t n) {
    return cap.radius + kCapMargin * kEdgePerFrequency / static_cast<double>(n);
}
double placed_reach(const Cap &cap, int64_t n) {
    return cap.radius + (kCapMargin + kHeldMargin) * kEdgePerFrequency / static_cast<double>(n);
}

// The points of the frequency-n lattice a relaxation within `cap` moves
// (those within kCapMargin of its edge lengths beyond it) and the items of
// a sweep holding them; null (all) when that reaches round the sphere or
// there is no cap.
std::unique_ptr<Active> active_within(Context &ctx, const LatticeIndex &index, const Points &points,
                                      const Placed &placed, const Cap *cap) {
    const int64_t n = index.frequency();
    if (!cap || n < 3) return nullptr;
    const double reach = relaxed_reach(*cap, n);
    if (reach >= M_PI) return nullptr;
    const double least_cos = std::cos(reach);
    auto active = std::make_unique<Active>();
    active->point.assign(points.size(), 0);
    scan_placeable(ctx, index, placed, [&](int64_t first, int64_t end) {
        for (int64_t p = first; p < end; ++p)
            active->point[p] = placed[p] && geom::dot(points[p], cap->centre) >= least_cos;
    });
    const int64_t edge_items = index.edge_count();
    active->item.assign(static_cast<size_t>(edge_items + index.row_count()), 0);
    for (int64_t item = 0; item < static_cast<int64_t>(active->item.size()); ++item) {
        uint8_t any = 0;
        if (item < edge_items) {
            for (int64_t s = 1; s < n; ++s) any |= active->point[index.on_edge(static_cast<int>(item), s)];
        } else {
            const int f = static_cast<int>((item - edge_items) / (n - 2));
            const int64_t i = (item - edge_items) % (n - 2) + 1, row = index.row_origin(f, i);
            const Span placed_here = placed.span(item - edge_items, n, i);  // (none active beyond)
            for (int64_t j = placed_here.first; j <= placed_here.last; ++j) any |= active->point[row + j];
        }
        active->item[item] = any;
    }
    return active;
}

// `sweeps` spring sweeps of the lattice (of the Active set, when not null),
// the rest length the mean chord of the sweep before (of the start for the
// first).
void relax(Context &ctx, const LatticeIndex &index, Points &points, int sweeps, const Active *active,
           const Placed &placed) {
    if (index.frequency() < 2) return;  // the icosahedron: corners only
    const std::vector<std::array<int64_t, 6>> edge_nbrs = edge_point_neighbours(index);
    // Every point is written each sweep without an Active set; with one,
    // the others keep their places in both buffers.
    Points next(points.size());
    if (active)
        scan_placeable(ctx, index, placed, [&](int64_t first, int64_t end) {
            for (int64_t p = first; p < end; ++p)
                if (placed[p]) next[p] = points[p];
        });
    double rest = spring_sweep(ctx, index, edge_nbrs, points, next, 0, active).mean();
    for (int k = 0; k < sweeps; ++k) {
        ctx.heartbeat(kStage, 0);
        rest = spring_sweep(ctx, index, edge_nbrs, points, next, rest, active).mean();
        points.swap(next);
    }
}

// A level of the relaxation: its lattice (holding, for a regional one, only
// what its placement may fill), its points and which of them are placed.
struct Level {
    LatticeIndex index;
    Points points;
    Placed placed;
};

// The columns J (0 .. m - I) of the placed points of each row I (0 .. m) of
// each face of `coarse`, sides and corners included: face f's row I at
// f * (m + 1) + I.
std::vector<Span> closed_rows(const Level &coarse) {
    const int64_t m = coarse.index.frequency();
    std::vector<Span> rows(static_cast<size_t>(coarse.index.face_count() * (m + 1)));
    for (int f = 0; f < coarse.index.face_count(); ++f)
        for (int64_t I = 0; I <= m; ++I)
            rows[static_cast<size_t>(f * (m + 1) + I)] = closed_row(coarse.index, coarse.placed, f, I);
    return rows;
}

// The columns j of the frequency-n row i whose points the coarse rows I
// and I + 1 (I = i m / n) may place: a point (i, j) is placed only if its
// coarse points (I + 1, J) and (I, J + 1) are (J = j m / n).
Span placeable(const Span &lower_row, const Span &upper_row, int64_t m, int64_t n, int64_t i) {
    if (lower_row.empty() || upper_row.empty()) return {};
    const int64_t J_first = std::max(upper_row.first, lower_row.first - 1),
                  J_last = std::min(upper_row.last, lower_row.last - 1);
    if (J_first > J_last) return {};
    return {std::max<int64_t>(1, (J_first * n + m - 1) / m), std::min(n - 1 - i, ((J_last + 1) * n - 1) / m)};
}

// The frequency-n lattice placed in the relaxed coarser one: each point at
// its barycentric place in the coarse triangle (or along the coarse edge)
// that holds it, back on the sphere. With a cap, only the points whose
// coarse points are placed, and of those `placed` keeps the ones within its
// reach; the level then holds only the rows' columns that may be placed.
Level interpolate(Context &ctx, const Level &coarse, int64_t n, const Cap *cap) {
    const LatticeIndex &ci = coarse.index;
    const Points &at = coarse.points;
    const Placed &at_placed = coarse.placed;
    const int64_t m = ci.frequency();
    const bool regional = cap && placed_reach(*cap, n) < M_PI;
    const double least_cos = regional ? std::cos(placed_reach(*cap, n)) : -2.0;
    const std::vector<Span> coarse_rows = closed_rows(coarse);
    auto coarse_row = [&](int f, int64_t I) -> const Span & {
        return coarse_rows[static_cast<size_t>(f * (m + 1) + I)];
    };
    const LatticeIndex dense(n);
    std::vector<Span> kept(static_cast<size_t>(dense.row_count()));
    for (int64_t row = 0; row < dense.row_count(); ++row) {
        const int f = dense.row_face(row);
        const int64_t i = dense.row_in_face(row), I = i * m / n;
        kept[static_cast<size_t>(row)] = placeable(coarse_row(f, I), coarse_row(f, I + 1), m, n, i);
    }
    Level fine{regional ? LatticeIndex(n, kept) : dense, Points(), Placed()};
    const LatticeIndex &held_index = fine.index;
    fine.points.resize(static_cast<size_t>(held_index.size()));
    if (regional) fine.placed = Placed(held_index);
    Points &points = fine.points;
    Placed &placed = fine.placed;
    auto place = [&](int64_t p, const Vec3 &x) {
        points[p] = x;
        const bool within = !regional || geom::dot(x, cap->centre) >= least_cos;
        if (regional) placed.set(p, within);
        return within;
    };
    for (int c = 0; c < 12; ++c) {
        points[c] = at[c];
        if (regional) placed.set(c, true);
    }
    for (int e = 0; e < held_index.edge_count(); ++e)
        for (int64_t s = 1; s < n; ++s) {
            const int64_t S = s * m / n;
            const double w = static_cast<double>(s * m - S * n) / static_cast<double>(n);
            const int64_t a = ci.on_edge(e, S), b = w > 0 ? ci.on_edge(e, S + 1) : a;
            if (!at_placed[a] || !at_placed[b]) continue;
            place(held_index.on_edge(e, s), w > 0 ? geom::normalized((1 - w) * at[a] + w * at[b]) : at[a]);
        }
    const double scale = 1.0 / static_cast<double>(n);
    ctx.parallel_for(held_index.row_count(), 16, [&](int64_t b, int64_t e) {
        for (int64_t row = b; row < e; ++row) {
            const int f = held_index.row_face(row);
            const int64_t i = held_index.row_in_face(row), I = i * m / n;
            const Span &lower_row = coarse_row(f, I), &upper_row = coarse_row(f, I + 1);
            const Span columns = kept[static_cast<size_t>(row)];
            Span found;
            for (int64_t j = columns.first; j <= columns.last; ++j) {
                const int64_t J = j * m / n;
                const int64_t ri = i * m - I * n, rj = j * m - J * n;  // the fractions' numerators
                const double fi = static_cast<double>(ri) * scale, fj = static_cast<double>(rj) * scale;
                const bool lower = ri + rj <= n;
                // (I, J) or (I + 1, J + 1): read only within its row's
                // placed columns (a regional coarse level holds no others).
                if (lower ? J < lower_row.first : J + 1 > upper_row.last) continue;
                const int64_t p0 = lower ? ci.at(f, I, J) : ci.at(f, I + 1, J + 1),
                              p1 = ci.at(f, I + 1, J), p2 = ci.at(f, I, J + 1);
                if (!at_placed[p0] || !at_placed[p1] || !at_placed[p2]) continue;
                const Vec3 p = lower ? (1 - fi - fj) * at[p0] + fi * at[p1] + fj * at[p2]
                                     : (fi + fj - 1) * at[p0] + (1 - fj) * at[p1] + (1 - fi) * at[p2];
                if (place(held_index.at(f, i, j), geom::normalized(p))) found.add(j);
            }
            if (regional) placed.set_span(row, found);
        }
    });
    return fine;
}

// The relaxed frequency-n lattice (around a cap, when given: the points
// its `placed` says).
Level relaxed_lattice(Context &ctx, int64_t n, const Cap *cap) {
    if (n <= kCoarsest) {
        const std::vector<Vec3> start = geodesic_lattice(n);
        Level level{LatticeIndex(n), Points(start.begin(), start.end()), Placed()};
        relax(ctx, level.index, level.points, kCoarseSweeps, nullptr, level.placed);
        return level;
    }
    Level fine = interpolate(ctx, relaxed_lattice(ctx, (n + 1) / 2, cap), n, cap);
    const std::unique_ptr<Active> active = active_within(ctx, fine.index, fine.points, fine.placed, cap);
    relax(ctx, fine.index, fine.points, kFineSweeps, active.get(), fine.placed);
    return fine;
}

}  // namespace

std::vector<Vec3> geodesic_lattice(int64_t n) {
    const LatticeIndex index(n);
    const std::array<Vec3, 12> corner = icosahedron_corners();
    std::vector<Vec3> points(corner.begin(), corner.end());
    points.reserve(static_cast<size_t>(index.size()));
    for (int e = 0; e < index.edge_count(); ++e)
        for (int64_t s = 1; s < n; ++s)
            points.push_back(slerp(corner[index.edge(e)[0]], corner[index.edge(e)[1]],
                                   static_cast<double>(s) / static_cast<double>(n)));
    for (int f = 0; f < index.face_count(); ++f) {
        const Vec3 &A = corner[index.face(f)[0]], &B = corner[index.face(f)[1]], &C = corner[index.face(f)[2]];
        for (int64_t i = 1; i < n; ++i)
            for (int64_t j = 1; i + j < n; ++j) {
                const int64_t k = n - i - j;
                points.push_back(geom::normalized(row_point(A, B, C, i, k, n) + row_point(B, C, A, j, i, n) +
                                                  row_point(C, A, B, k, j, n)));
            }
    }
    return points;
}

std::vector<Vec3> relaxed_geodesic_lattice(Context &ctx, int64_t n) {
    const Level level = relaxed_lattice(ctx, n, nullptr);
    return std::vector<Vec3>(level.points.begin(), level.points.end());
}

double lattice_region_points(int64_t n, const Cap &cap) {
    const double reach = std::min(M_PI, placed_reach(cap, n));
    const double sphere = 10.0 * static_cast<double>(n) * static_cast<double>(n) + 2;
    return sphere * (1 - std::cos(reach)) / 2;
}

LatticeRegion relaxed_lattice_region(Context &ctx, int64_t n, const Cap &cap) {
    const Level level = relaxed_lattice(ctx, n, &cap);
    const LatticeIndex &index = level.index;
    const Placed &placed = level.placed;
    // The placed points' places in the level and in the whole lattice, found
    // in parallel in fixed chunks (pushed one at a time, the vectors grew by
    // copies): the outline, then each row's placed columns.
    std::vector<int64_t> held =
        ctx.collect_in_order<int64_t>(index.outline_end(), 1 << 16, [&](int64_t p, std::vector<int64_t> &out) {
            if (placed[p]) out.push_back(p);
        });
    LatticeRegion region;
    region.index = held;
    const std::vector<std::array<int64_t, 2>> inside = ctx.collect_in_order<std::array<int64_t, 2>>(
        index.row_count(), 64, [&](int64_t row, std::vector<std::array<int64_t, 2>> &out) {
            const int f = index.row_face(row);
            const int64_t i = index.row_in_face(row);
            const Span s = placed.span(row, n, i);
            for (int64_t j = s.first; j <= s.last; ++j)
                if (placed[index.at(f, i, j)]) out.push_back({index.at(f, i, j), index.global_at(f, i, j)});
        });
    for (const auto &p : inside) held.push_back(p[0]), region.index.push_back(p[1]);
    region.points.resize(held.size());
    ctx.parallel_for(static_cast<int64_t>(held.size()), 1 << 14, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) region.points[i] = level.points[held[i]];
    });
    return region;
}

}  // namespace um::refine
