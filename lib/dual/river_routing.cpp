#include "dual/river_routing.hpp"

#include <algorithm>
#include <deque>

#include "core/disjoint_sets.hpp"
#include "unimesh.h"

namespace um::dual {

namespace {

// The river graph over the cells, in compressed rows: the land cells across
// each land-land river edge, in edge order.
struct RiverGraph {
    std::vector<int64_t> start;  // n_cells + 1
    std::vector<int32_t> next;  // across river edges and bridges
    std::vector<uint8_t> on_river;  // land cell with a river edge (to land or to ocean)

    int32_t degree(int32_t c) const { return static_cast<int32_t>(start[c + 1] - start[c]); }
};

bool is_land(const MpasMesh &m, int32_t c) { return m.cell_land_mask.empty() || m.cell_land_mask[c] != 0; }

// Whether a river's line crosses edge e (edge_on_river), or, where the mesh
// does not know that, whether its dual crosses a river.
bool on_a_river_line(const MpasMesh &m, int64_t e) {
    return m.edge_on_river.empty() ? m.edge_feature_kind[e] == UM_FEATURE_RIVER : m.edge_on_river[e] != 0;
}
// An edge of the river graph: one on a river's line between two cells.
bool is_river_edge(const MpasMesh &m, int64_t e) {
    return on_a_river_line(m, e) && m.cells_on_edge[2 * e] != kNone && m.cells_on_edge[2 * e + 1] != kNone;
}
// Where a river leaves a regional mesh across its open boundary: an edge a
// river's line crosses whose second cell is missing (cellsOnEdge(1) is
// always a cell). Its cell drains out of the mesh there, as at a mouth.
bool leaves_the_mesh(const MpasMesh &m, int64_t e) {
    return m.cells_on_edge[2 * e + 1] == kNone && on_a_river_line(m, e);
}

// The land-land pairs of the graph, in edge order: every river edge, then
// the bridges. A river network's chain of cells breaks between neighbouring
// river cells: the input's lines seldom share their end points (the shipped
// GSHHG rivers: 5 of 2,565 ends), and where the mesh has no edgeOnRiver the
// chain of restricted edges has gaps (one crossing kept per face, rivers
// finer than the cells not followed). A bridge joins two neighbouring river
// cells of different pieces, or two across one land cell between them
// (which joins the river), once per pair of pieces (a spanning forest:
// bridges never make a cycle).
std::vector<std::pair<int32_t, int32_t>> land_pairs(const MpasMesh &m, std::vector<uint8_t> &on_river,
                                                    int32_t *bridges) {
    std::vector<std::pair<int32_t, int32_t>> pairs;
    DisjointSets pieces(static_cast<size_t>(m.n_cells));
    for (int64_t e = 0; e < m.n_edges; ++e) {
        if (!is_river_edge(m, e)) continue;
        const int32_t a = m.cells_on_edge[2 * e], b = m.cells_on_edge[2 * e + 1];
        if (is_land(m, a) && is_land(m, b)) pairs.emplace_back(a, b), pieces.join(a, b);
    }
    *bridges = 0;
    for (int64_t e = 0; e < m.n_edges; ++e) {
        const int32_t a = m.cells_on_edge[2 * e], b = m.cells_on_edge[2 * e + 1];
        if (b == kNone || !on_river[a] || !on_river[b] || is_river_edge(m, e)) continue;
        if (pieces.join(a, b)) pairs.emplace_back(a, b), ++*bridges;
    }
    // Gaps of one land cell: the cell between joins the river.
    const size_t w = static_cast<size_t>(m.max_edges);
    for (int32_t x = 0; x < m.n_cells; ++x) {
        if (on_river[x] || !is_land(m, x)) continue;
        int32_t first = kNone;
        for (int32_t j = 0; j < m.n_edges_on_cell[x]; ++j) {
            const int32_t a = m.cells_on_cell[w * x + j];
            if (a == kNone || !on_river[a]) continue;
            if (first == kNone) {
                first = a;
            } else if (pieces.join(first, a)) {
                if (!on_river[x]) on_river[x] = 1, pairs.emplace_back(first, x), pieces.join(first, x);
                pairs.emplace_back(x, a), ++*bridges;
            }
        }
    }
    return pairs;
}

RiverGraph river_graph(const MpasMesh &m, int32_t *bridges) {
    RiverGraph g;
    g.start.assign(static_cast<size_t>(m.n_cells) + 1, 0);
    g.on_river.assign(static_cast<size_t>(m.n_cells), 0);
    for (int64_t e = 0; e < m.n_edges; ++e) {
        if (leaves_the_mesh(m, e) && is_land(m, m.cells_on_edge[2 * e])) g.on_river[m.cells_on_edge[2 * e]] = 1;
        if (!is_river_edge(m, e)) continue;
        for (int k = 0; k < 2; ++k)
            if (is_land(m, m.cells_on_edge[2 * e + k])) g.on_river[m.cells_on_edge[2 * e + k]] = 1;
    }
    const std::vector<std::pair<int32_t, int32_t>> pairs = land_pairs(m, g.on_river, bridges);
    for (const auto &[a, b] : pairs) ++g.start[a + 1], ++g.start[b + 1];
    for (size_t c = 0; c < static_cast<size_t>(m.n_cells); ++c) g.start[c + 1] += g.start[c];
    g.next.resize(static_cast<size_t>(g.start.back()));
    std::vector<int64_t> fill(g.start.begin(), g.start.end() - 1);
    for (const auto &[a, b] : pairs) g.next[fill[a]++] = b, g.next[fill[b]++] = a;
    return g;
}

// A land cell beside an ocean cell.
bool on_coast(const MpasMesh &m, int32_t c) {
    if (m.cell_land_mask.empty() || !is_land(m, c)) return false;
    const size_t w = static_cast<size_t>(m.max_edges);
    for (int32_t j = 0; j < m.n_edges_on_cell[c]; ++j) {
        const int32_t other = m.cells_on_cell[w * c + j];
        if (other != kNone && !is_land(m, other)) return true;
    }
    return false;
}

// Numbers the networks (connected parts of the graph) by their lowest cell
// and notes each one's size and cycles.
std::vector<int32_t> label_networks(const MpasMesh &m, const RiverGraph &g, std::vector<RiverNetworkNote> &notes) {
    std::vector<int32_t> network(static_cast<size_t>(m.n_cells), -1);
    std::vector<int32_t> stack;
    for (int32_t c = 0; c < m.n_cells; ++c) {
        if (!g.on_river[c] || network[c] >= 0) continue;
        RiverNetworkNote note;
        note.network = static_cast<int32_t>(notes.size());
        note.cell = c;
        int64_t ends = 0;  // edge ends: twice the edges
        network[c] = note.network;
        stack.assign(1, c);
        while (!stack.empty()) {
            const int32_t x = stack.back();
            stack.pop_back();
            ++note.cells;
            ends += g.degree(x);
            for (int64_t k = g.start[x]; k < g.start[x + 1]; ++k)
                if (network[g.next[k]] < 0) network[g.next[k]] = note.network, stack.push_back(g.next[k]);
        }
        note.cycles = static_cast<int32_t>(ends / 2 - note.cells + 1);
        notes.push_back(note);
    }
    return network;
}

// Per cell: 1 where a river crosses from this land cell into an ocean cell
// (a mouth), 2 in a network that has a mouth elsewhere, 0 otherwise. A
// network with mouths drains to them alone: a river that runs along the
// coast or through an estuary touches other coastal cells on its way, and
// those are not where it leaves the land. A network without a mouth (its
// line ends short of the sea) drains to its cells on the coast; one with
// neither, in a regional mesh, to where its lines leave the mesh across the
// open boundary (mouths too; `leaving` counts them): a river that enters
// the domain and reaches the sea inside drains to the sea.
std::vector<uint8_t> river_mouths(const MpasMesh &m, const std::vector<int32_t> &network, size_t networks,
                                  int32_t *leaving) {
    std::vector<uint8_t> mouth(static_cast<size_t>(m.n_cells), 0), has_mouth(networks, 0);
    for (int64_t e = 0; e < m.n_edges; ++e) {
        if (!is_river_edge(m, e)) continue;
        const int32_t a = m.cells_on_edge[2 * e], b = m.cells_on_edge[2 * e + 1];
        if (is_land(m, a) == is_land(m, b)) continue;
        const int32_t land = is_land(m, a) ? a : b;
        mouth[land] = 1, has_mouth[network[land]] = 1;
    }
    std::vector<uint8_t> reaches_sea = has_mouth;  // by a mouth, or on the coast
    for (int32_t c = 0; c < m.n_cells; ++c)
        if (network[c] >= 0 && on_coast(m, c)) reaches_sea[network[c]] = 1;
    *leaving = 0;
    for (int64_t e = 0; e < m.n_edges; ++e) {
        const int32_t cell = m.cells_on_edge[2 * e];
        if (!leaves_the_mesh(m, e) || !is_land(m, cell) || network[cell] < 0 || mouth[cell] != 0) continue;
        if (reaches_sea[network[cell]]) continue;
        mouth[cell] = 1, has_mouth[network[cell]] = 1, ++*leaving;
    }
    for (int32_t c = 0; c < m.n_cells; ++c)
        if (mouth[c] == 0 && network[c] >= 0 && has_mouth[network[c]]) mouth[c] = 2;
    return mouth;
}

// Each river edge's flow (+1 from cellsOnEdge 1 to 2, -1 back, 0 none):
// down the routing, from the farther cell to the nearer one where the edge
// closes a cycle; into the sea from an outlet; none where the distances
// (steps to the outlet, -1 unrouted) tie or no coast is reached. A regional
// mesh's river edges across its boundary flow out of an outlet there and in
// elsewhere.
std::vector<int32_t> edge_flows(const MpasMesh &m, const std::vector<int32_t> &distance) {
    std::vector<int32_t> flows(static_cast<size_t>(m.n_edges), 0);
    for (int64_t e = 0; e < m.n_edges; ++e) {
        // Across a regional mesh's boundary: out of an outlet there, in
        // towards an outlet elsewhere.
        if (leaves_the_mesh(m, e) && is_land(m, m.cells_on_edge[2 * e])) {
            const int32_t steps = distance[m.cells_on_edge[2 * e]];
            flows[e] = steps == 0 ? 1 : steps > 0 ? -1 : 0;
        }
        if (!is_river_edge(m, e)) continue;
        const int32_t a = m.cells_on_edge[2 * e], b = m.cells_on_edge[2 * e + 1];
        const bool land_a = is_land(m, a), land_b = is_land(m, b);
        if (land_a && land_b) {
            if (distance[a] >= 0 && distance[b] >= 0 && distance[a] != distance[b])
                flows[e] = distance[a] > distance[b] ? 1 : -1;
        } else if (land_a != land_b) {
            flows[e] = land_a ? 1 : -1;
        }
    }
    return flows;
}

}  // namespace

RiverRouting river_routing(const MpasMesh &m) {
    RiverRouting out;
    RiverReport &report = out.report;
    if (m.edge_feature_kind.empty() && m.edge_on_river.empty()) return out;
    const RiverGraph g = river_graph(m, &report.bridges);
    std::vector<RiverNetworkNote> notes;
    const std::vector<int32_t> network = label_networks(m, g, notes);
    report.networks = static_cast<int32_t>(notes.size());

    // Breadth-first from every outlet at once: each cell drains to the cell
    // it was reached from, one step nearer the coast.
    std::vector<int32_t> &downstream = out.cell_downstream, &kind = out.cell_river_kind;
    downstream.assign(static_cast<size_t>(m.n_cells), kNone);
    kind.assign(static_cast<size_t>(m.n_cells), kNotRiver);
    std::vector<int32_t> distance(static_cast<size_t>(m.n_cells), -1);
    std::deque<int32_t> queue;
    std::vector<uint8_t> reaches_coast(notes.size(), 0);
    const std::vector<uint8_t> mouth = river_mouths(m, network, notes.size(), &report.boundary_outlets);
    for (int32_t c = 0; c < m.n_cells; ++c) {
        if (!g.on_river[c]) continue;
        ++report.river_cells;
        if (!(mouth[c] == 1 || (mouth[c] == 0 && on_coast(m, c)))) continue;
        kind[c] = kOutlet, distance[c] = 0, queue.push_back(c);
        reaches_coast[network[c]] = 1;
        ++report.outlets;
    }
    while (!queue.empty()) {
        const int32_t x = queue.front();
        queue.pop_front();
        for (int64_t k = g.start[x]; k < g.start[x + 1]; ++k) {
            const int32_t y = g.next[k];
            if (distance[y] >= 0) continue;
            distance[y] = distance[x] + 1;
            downstream[y] = x, kind[y] = kRouted;
            ++report.routed_cells;
            queue.push_back(y);
        }
    }
    for (int32_t c = 0; c < m.n_cells; ++c)
        if (g.on_river[c] && distance[c] < 0) kind[c] = kInland;
    for (const RiverNetworkNote &note : notes) {
        if (!reaches_coast[note.network]) report.inland.push_back(note);
        if (note.cycles > 0) report.with_cycles.push_back(note);
    }

    out.edge_river_downstream = edge_flows(m, distance);
    return out;
}

RiverReport route_rivers(MpasMesh &m) {
    RiverRouting routing = river_routing(m);
    m.cell_downstream = std::move(routing.cell_downstream);
    m.cell_river_kind = std::move(routing.cell_river_kind);
    if (!m.edge_feature_kind.empty() || !m.edge_on_river.empty())
        m.edge_river_downstream = std::move(routing.edge_river_downstream);
    return routing.report;
}

}  // namespace um::dual
