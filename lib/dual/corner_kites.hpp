// The kites of a staggered mesh: per vertex row v and corner j the signed
// area of the quad (v, xEdge, xCell, xEdge') that cellsOnVertex(v, j) holds
// at v (kiteAreasOnVertex, m^2). The vertex rows write them and the TRSK
// stencils turn a cell's into the fractions of its area at its corners, so
// they are made once, in parallel, and kept (24 bytes per vertex row, 48
// per cell): made for each, they were the MPAS stage's largest repeated
// work. Internal to lib/dual.
#pragma once

#include <cstdint>

#include "core/context.hpp"
#include "core/uninit_vector.hpp"
#include "dual/mpas_layout.hpp"

namespace um::dual {

class CornerKites {
public:
    static constexpr int64_t kBytesPerCell = 48;  // 3 kites a vertex, 2 vertices a cell

    CornerKites(Context &ctx, const MpasLayout &layout, double radius);

    // Kite j of vertex row r.
    double of_row(int64_t r, int j) const { return kites_[3 * r + j]; }
    // The kite of cell c (whole numbering) at its corner v (whole
    // numbering, a vertex row).
    double of_cell(const MpasLayout &layout, int32_t v, int32_t c) const;

private:
    UninitVector<double> kites_;
};

}  // namespace um::dual
