#include "quality/ocean_connectivity.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <tuple>

#include "core/disjoint_sets.hpp"
#include "geom/sphere.hpp"

namespace um::quality {

namespace {

// Per vertex slot, the index of its ocean region (-1: not in the ocean
// mesh); regions numbered by their lowest slot.
std::vector<int32_t> region_of_cells(const tri::Triangulation &tri, const std::vector<uint8_t> &ocean_cell,
                                     int32_t &n_regions) {
    const int32_t n = tri.vertex_slots();
    auto ocean = [&](int32_t v) {
        return static_cast<size_t>(v) < ocean_cell.size() && ocean_cell[v] != 0 && tri.in_triangulation(v);
    };
    DisjointSets cells(static_cast<size_t>(n));
    for (int32_t v = 0; v < n; ++v)
        if (ocean(v))
            tri.for_each_neighbour(v, [&](int32_t w) {
                if (w > v && ocean(w)) cells.join(v, w);
            });
    std::vector<int32_t> region(static_cast<size_t>(n), -1);
    n_regions = 0;
    for (int32_t v = 0; v < n; ++v)
        if (ocean(v)) region[v] = cells.root(v) == v ? n_regions++ : region[cells.root(v)];
    return region;
}

std::vector<OceanConnectivity::Region> region_list(const tri::Triangulation &tri, const std::vector<int32_t> &region,
                                                   int32_t n_regions, const geom::Surface &surface) {
    std::vector<OceanConnectivity::Region> list(static_cast<size_t>(n_regions), {0, 0, 0});
    std::vector<uint8_t> placed(static_cast<size_t>(n_regions), 0);
    for (int32_t v = 0; v < static_cast<int32_t>(region.size()); ++v) {
        if (region[v] < 0) continue;
        OceanConnectivity::Region &r = list[region[v]];
        ++r.cells;
        if (!placed[region[v]]) surface.geodetic(tri.direction(v), r.lon, r.lat), placed[region[v]] = 1;
    }
    std::stable_sort(list.begin(), list.end(), [](const auto &p, const auto &q) { return p.cells > q.cells; });
    return list;
}

// Per region, its body of water (the lowest region index of the body).
std::vector<int32_t> body_of_regions(const std::vector<int32_t> &region, int32_t n_regions,
                                     const std::vector<std::pair<int32_t, int32_t>> &contacts) {
    std::vector<int32_t> rings;
    for (const auto &c : contacts) rings.push_back(c.second);
    std::sort(rings.begin(), rings.end());
    rings.erase(std::unique(rings.begin(), rings.end()), rings.end());
    // Nodes: the regions, then the rings.
    DisjointSets bodies(static_cast<size_t>(n_regions) + rings.size());
    for (const auto &[v, ring] : contacts) {
        if (static_cast<size_t>(v) >= region.size() || region[v] < 0) continue;
        const auto at = std::lower_bound(rings.begin(), rings.end(), ring) - rings.begin();
        bodies.join(region[v], n_regions + static_cast<int32_t>(at));
    }
    std::vector<int32_t> body(static_cast<size_t>(n_regions));
    for (int32_t r = 0; r < n_regions; ++r) body[r] = bodies.root(r);
    return body;
}

// What crossing a cell outside the ocean mesh costs: a cell a coastline
// passes through may hide water the cells do not resolve (a channel), so
// the path from a region to the rest of its body is the one through the
// fewest dry cells first, then the fewest wet ones.
constexpr int64_t kDryCell = int64_t(1) << 32;

int64_t land_cells(int64_t cost) { return cost / kDryCell + cost % kDryCell; }

// From every ocean cell at once over the other cells (Dijkstra with those
// costs): per cell the region reached first (-1 when none) and the cost of
// the way to it (0 for ocean cells). Slot order breaks ties.
void grow_regions(const tri::Triangulation &tri, const std::vector<uint8_t> &wet, std::vector<int32_t> &label,
                  std::vector<int64_t> &cost) {
    cost.assign(label.size(), std::numeric_limits<int64_t>::max());
    using Entry = std::pair<int64_t, int32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (int32_t v = 0; v < static_cast<int32_t>(label.size()); ++v)
        if (label[v] >= 0) cost[v] = 0, queue.push({0, v});
    while (!queue.empty()) {
        // Not a structured binding: lambdas capture those from C++20 only
        // (clang 14, which builds the fuzz targets, refuses it).
        const int64_t c = queue.top().first;
        const int32_t v = queue.top().second;
        queue.pop();
        if (c != cost[v]) continue;
        tri.for_each_neighbour(v, [&](int32_t w) {
            const int64_t through = c + (wet[w] ? 1 : kDryCell);
            if (through >= cost[w]) return;
            cost[w] = through, label[w] = label[v];
            queue.push({through, w});
        });
    }
}

}  // namespace

OceanConnectivity ocean_connectivity(const tri::Triangulation &tri, const std::vector<uint8_t> &ocean_cell,
                                     const std::vector<std::pair<int32_t, int32_t>> &contacts,
                                     const geom::Surface &surface) {
    OceanConnectivity out;
    int32_t n_regions = 0;
    std::vector<int32_t> label = region_of_cells(tri, ocean_cell, n_regions);
    out.regions = region_list(tri, label, n_regions, surface);
    const std::vector<int32_t> body = body_of_regions(label, n_regions, contacts);
    for (int32_t r = 0; r < n_regions; ++r) out.water_bodies += body[r] == r;
    if (out.water_bodies == n_regions) return out;

    // Where two regions of one body come nearest: the edges between cells
    // reached from different regions of one body, thinnest land first; each
    // that joins two groups not yet joined is a passage the mesh closed.
    std::vector<uint8_t> wet(label.size(), 0);
    for (const auto &c : contacts)
        if (static_cast<size_t>(c.first) < wet.size()) wet[c.first] = 1;
    std::vector<int64_t> cost;
    grow_regions(tri, wet, label, cost);
    std::vector<std::tuple<int64_t, int32_t, int32_t>> meetings;  // (cost, v, w)
    for (int32_t v = 0; v < static_cast<int32_t>(label.size()); ++v) {
        if (label[v] < 0) continue;
        tri.for_each_neighbour(v, [&](int32_t w) {
            if (w > v && label[w] >= 0 && label[w] != label[v] && body[label[w]] == body[label[v]])
                meetings.emplace_back(cost[v] + cost[w], v, w);
        });
    }
    std::sort(meetings.begin(), meetings.end());
    DisjointSets joined(static_cast<size_t>(n_regions));
    for (const auto &[c, v, w] : meetings) {
        if (!joined.join(label[v], label[w])) continue;
        OceanConnectivity::ClosedPassage p{0, 0, land_cells(c)};
        surface.geodetic(geom::normalized(tri.direction(v) + tri.direction(w)), p.lon, p.lat);
        out.closed_passages.push_back(p);
    }
    return out;
}

}  // namespace um::quality
