#include "io/mpas_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include <netcdf.h>

#include "core/error.hpp"
#include "dual/mpas_fields.hpp"
#include "io/error_text.hpp"
#include "io/nc_output.hpp"
#include "io/netcdf_lock.hpp"

namespace um::io {

namespace {

using dual::MpasMesh;

using dual::MpasDim;
using dual::MpasField;
using dual::MpasKind;

// ----------------------------------------------------------------- file_id

struct Hash {
    uint64_t h = 0x6a09e667f3bcc908ull;
    void word(uint64_t w) {
        h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
    }
    void bytes(const void *data, size_t n) {
        const unsigned char *p = static_cast<const unsigned char *>(data);
        word(n);
        size_t i = 0;
        for (; i + 8 <= n; i += 8) {
            uint64_t w;
            std::memcpy(&w, p + i, 8);
            word(w);
        }
        uint64_t tail = 0;
        if (n > i) std::memcpy(&tail, p + i, n - i);
        word(tail);
    }
};

// ----------------------------------------------------------------- netCDF

size_t dim_length(const MpasMesh &m, MpasDim d) {
    return static_cast<size_t>(dual::mpas_dim_length(m, d));
}

size_t row_width(const MpasMesh &m, const MpasField &f) { return static_cast<size_t>(f.columns(m)); }

// 64-bit offset files hold fixed-size variables of up to 2^32 - 4 bytes;
// larger meshes (weightsOnEdge passes it at about 8 M cells) need CDF-5.
int format_for(const MpasMesh &m, const std::vector<MpasField> &fields, uint64_t limit) {
    for (const MpasField &f : fields) {
        uint64_t bytes = f.kind == MpasKind::real ? 8 : 4;
        for (MpasDim d : f.dims) bytes *= dim_length(m, d);
        if (bytes > limit) return NC_64BIT_DATA;
    }
    return NC_64BIT_OFFSET;
}

void define(const NcOutput &nc, const MpasMesh &m, const std::vector<MpasField> &fields,
            std::vector<int> &var_ids) {
    int dim_ids[dual::kMpasDimCount];
    for (int d = 0; d < dual::kMpasDimCount; ++d) {
        const MpasDim dim = static_cast<MpasDim>(d);
        const size_t length = dim == MpasDim::Time ? NC_UNLIMITED : dim_length(m, dim);
        nc.check(nc_def_dim(nc.id(), dual::mpas_dim_name(dim), length, &dim_ids[d]),
                 "defining dimension ", dual::mpas_dim_name(dim));
    }
    for (const MpasField &f : fields) {
        int dims[2], var = -1;
        for (size_t k = 0; k < f.dims.size(); ++k) dims[k] = dim_ids[static_cast<int>(f.dims[k])];
        nc_type type = f.kind == MpasKind::real ? NC_DOUBLE : NC_INT;
        nc.check(nc_def_var(nc.id(), f.name, type, static_cast<int>(f.dims.size()), dims, &var),
                 "defining variable ", f.name);
        nc.put_text(var, "long_name", f.long_name);
        if (f.units) nc.put_text(var, "units", f.units);
        if (f.n_flags > 0) {
            nc.check(nc_put_att_int(nc.id(), var, "flag_values", NC_INT, f.n_flags, f.flag_values),
                     "writing attribute flag_values of ", f.name);
            nc.put_text(var, "flag_meanings", f.flag_meanings);
        }
        var_ids.push_back(var);
    }
    nc.put_text(NC_GLOBAL, "on_a_sphere", "YES");
    nc.check(nc_put_att_double(nc.id(), NC_GLOBAL, "sphere_radius", NC_DOUBLE, 1, &m.radius_m),
             "writing attribute sphere_radius");
    nc.put_text(NC_GLOBAL, "is_periodic", "NO");
    nc.put_text(NC_GLOBAL, "mesh_spec", "1.0");
    nc.put_text(NC_GLOBAL, "Conventions", "MPAS");
    nc.put_text(NC_GLOBAL, "source", "unimesh " UM_VERSION_STRING);
    nc.put_text(NC_GLOBAL, "file_id", mpas_file_id(m));
}

// Writes a variable in blocks of rows, so that the 1-based copy of a large
// index array never needs a second full-size buffer.
void put_field(const NcOutput &nc, const MpasMesh &m, const MpasField &f, int var) {
    const size_t rows = dim_length(m, f.dims[0]), width = row_width(m, f);
    const size_t block = std::max<size_t>(1, (size_t(1) << 20) / std::max<size_t>(width, 1));
    std::vector<int32_t> buffer;
    for (size_t r0 = 0; r0 < rows; r0 += block) {
        const size_t r1 = std::min(rows, r0 + block);
        size_t start[2] = {r0, 0}, count[2] = {r1 - r0, width};
        int status;
        if (f.kind == MpasKind::real) {
            status = nc_put_vara_double(nc.id(), var, start, count, f.reals->data() + r0 * width);
        } else if (f.kind == MpasKind::integer) {
            status = nc_put_vara_int(nc.id(), var, start, count, f.ints->data() + r0 * width);
        } else {
            buffer.resize((r1 - r0) * width);
            for (size_t i = 0; i < buffer.size(); ++i)
                buffer[i] = f.kind == MpasKind::id ? static_cast<int32_t>(r0 + i + 1)
                                               : (*f.ints)[r0 * width + i] + 1;  // kNone -> 0
            status = nc_put_vara_int(nc.id(), var, start, count, buffer.data());
        }
        nc.check(status, "writing variable ", f.name);
    }
}

}  // namespace

std::string mpas_file_id(const MpasMesh &m) {
    Hash hash;
    hash.bytes(&m.radius_m, sizeof m.radius_m);
    for (const MpasField &f : dual::mpas_fields(m)) {
        hash.bytes(f.name, std::strlen(f.name));
        if (f.reals) hash.bytes(f.reals->data(), f.reals->size() * sizeof(double));
        if (f.ints) hash.bytes(f.ints->data(), f.ints->size() * sizeof(int32_t));
        if (f.kind == MpasKind::id) hash.word(dim_length(m, f.dims[0]));
    }
    // Final avalanche, then 10 base-36 digits (36^10 < 2^52).
    uint64_t h = hash.h;
    h ^= h >> 31, h *= 0x94d049bb133111ebull, h ^= h >> 29;
    const char digits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
    std::string id(10, '0');
    for (char &c : id) c = digits[h % 36], h /= 36;
    return id;
}

void write_mpas_mesh(const MpasMesh &m, const std::string &path, uint64_t variable_limit) {
    const std::vector<MpasField> fields = dual::mpas_fields(m);
    for (const MpasField &f : fields) {
        size_t n = 1;
        for (MpasDim d : f.dims) n *= dim_length(m, d);
        size_t have = f.reals ? f.reals->size() : f.ints ? f.ints->size() : n;
        if (have != n)
            fail(UM_ERR_INTERNAL, "MPAS mesh: variable ", f.name, " has ", have,
                 " values instead of ", n);
    }
    NetcdfLock lock;
    NcOutput nc(path, format_for(m, fields, variable_limit), "MPAS mesh file");
    int old_fill = 0;
    nc.check(nc_set_fill(nc.id(), NC_NOFILL, &old_fill), "setting no-fill mode");
    std::vector<int> var_ids;
    define(nc, m, fields, var_ids);
    nc.check(nc_enddef(nc.id()), "ending define mode");
    for (size_t i = 0; i < fields.size(); ++i) put_field(nc, m, fields[i], var_ids[i]);
    nc.close();
}

}  // namespace um::io
