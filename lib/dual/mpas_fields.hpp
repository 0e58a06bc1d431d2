// The variables of the MPAS mesh contract (shared/mpas-format.md) as one
// table over an MpasMesh: name, dimensions, how the values are stored, and
// the attributes. The netCDF writer and the C API's copy-out both read it,
// so a variable is declared once.
#pragma once

#include <cstdint>
#include <vector>

#include "dual/mpas_mesh.hpp"

namespace um::dual {

enum class MpasDim { nCells, nEdges, nVertices, maxEdges, maxEdges2, TWO, vertexDegree, Time };
constexpr int kMpasDimCount = 8;
const char *mpas_dim_name(MpasDim d);
// The length of a dimension of m (Time: 1, one record).
int64_t mpas_dim_length(const MpasMesh &m, MpasDim d);

// How a variable's values are stored.
enum class MpasKind {
    real,     // double as is
    integer,  // int32 as is
    index,    // 0-based index with kNone padding (1-based, 0 padding in MPAS)
    id        // no array: 1..N along the first dimension (indexTo*ID)
};

struct MpasField {
    const char *name;
    std::vector<MpasDim> dims;
    MpasKind kind;
    const std::vector<double> *reals;
    const std::vector<int32_t> *ints;
    const char *long_name;
    const char *units;  // nullptr: dimensionless or an index
    // CF flag attributes of the tag variables (n_flags == 0: none).
    const int32_t *flag_values = nullptr;
    int n_flags = 0;
    const char *flag_meanings = nullptr;

    int64_t rows(const MpasMesh &m) const { return mpas_dim_length(m, dims[0]); }
    int64_t columns(const MpasMesh &m) const { return dims.size() > 1 ? mpas_dim_length(m, dims[1]) : 1; }
};

// Every variable of m, in the order of the file; the tag variables only
// when m has them. The pointers point into m.
std::vector<MpasField> mpas_fields(const MpasMesh &m);

}  // namespace um::dual
