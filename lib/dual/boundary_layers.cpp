#include "dual/boundary_layers.hpp"

#include <algorithm>

namespace um::dual {

std::vector<int8_t> cell_boundary_layers(Context &ctx, const MpasLayout &layout) {
    if (!layout.regional()) return {};
    const int32_t n = layout.cell_rows();
    std::vector<int8_t> layer(static_cast<size_t>(n), 0);
    // The boundary: cells with a neighbour outside the region.
    std::vector<int32_t> front = ctx.collect_in_order<int32_t>(n, 1 << 12, [&](int64_t r, std::vector<int32_t> &out) {
        thread_local CellRing ring;
        layout.cell_ring(layout.cell_of_row(r), ring);
        for (int32_t c : ring.cells)
            if (layout.row_of_cell(c) == kNone) {
                out.push_back(static_cast<int32_t>(r));
                return;
            }
    });
    for (int32_t r : front) layer[r] = kBoundaryLayers;
    // Each layer inwards from the last (a band along the boundary: serial).
    CellRing ring;
    for (int32_t value = kBoundaryLayers - 1; value >= 1 && !front.empty(); --value) {
        std::vector<int32_t> next;
        for (int32_t r : front) {
            layout.cell_ring(layout.cell_of_row(r), ring);
            for (int32_t c : ring.cells) {
                const int32_t d = layout.row_of_cell(c);
                if (d != kNone && layer[d] == 0) layer[d] = static_cast<int8_t>(value), next.push_back(d);
            }
        }
        front.swap(next);
    }
    return layer;
}

}  // namespace um::dual
