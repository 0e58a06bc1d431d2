// Reading an MPAS mesh file back (netCDF-C): what graph.info, mesh.vtu,
// `unimesh check` and `unimesh quality` need. Header-only and small.
#pragma once

#include <netcdf.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

// A classic-format file's (CDF-1, CDF-2, CDF-5) header walked as the format
// specification lays it out, before netCDF-C opens the file: netCDF-C
// trusts the counts and name lengths a header declares, and a corrupt one
// makes it allocate what it claims (seconds of work under a sanitizer for a
// 10 KB file, found by fuzzing check) or copy a name past NC_MAX_NAME. When
// sound, *end is where its data ends by the header: the largest begin + size
// over its fixed-size variables (record variables are not used in mesh
// files and are left out); netCDF-C reads a classic file's missing tail as
// zeros, so a cut file would otherwise read as a valid one.
enum class ClassicHeader { not_classic, damaged, sound };

inline ClassicHeader walk_classic_header(const std::string &path, uint64_t *end) {
    std::ifstream in(path, std::ios::binary);
    unsigned char magic[4];
    if (!in.read(reinterpret_cast<char *>(magic), 4) || magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F')
        return ClassicHeader::not_classic;
    const int version = magic[3];
    if (version != 1 && version != 2 && version != 5) return ClassicHeader::not_classic;
    auto uint = [&](int bytes, uint64_t *v) {
        unsigned char b[8];
        if (!in.read(reinterpret_cast<char *>(b), bytes)) return false;
        *v = 0;
        for (int i = 0; i < bytes; ++i) *v = (*v << 8) | b[i];
        return true;
    };
    const int count_bytes = version == 5 ? 8 : 4;
    auto skip = [&](uint64_t bytes) {
        if (bytes > (uint64_t(1) << 40)) return false;
        in.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
        return static_cast<bool>(in);
    };
    auto padded = [](uint64_t n) { return (n + 3) / 4 * 4; };
    auto name = [&]() {
        uint64_t n = 0;
        return uint(count_bytes, &n) && n <= NC_MAX_NAME && skip(padded(n));
    };
    auto type_size = [](uint64_t type) -> uint64_t {
        switch (type) {
            case 1: case 2: case 7: return 1;  // byte, char, ubyte
            case 3: case 8: return 2;          // short, ushort
            case 4: case 5: case 9: return 4;  // int, float, uint
            case 6: case 10: case 11: return 8;  // double, int64, uint64
            default: return 0;
        }
    };
    // A list: its tag (0 when absent) and its number of elements.
    auto list = [&](uint64_t *tag, uint64_t *n) { return uint(4, tag) && uint(count_bytes, n); };
    auto attributes = [&]() {
        uint64_t tag = 0, n = 0;
        if (!list(&tag, &n) || (tag != 0 && tag != 0x0C) || n > (uint64_t(1) << 32)) return false;
        for (uint64_t i = 0; i < n; ++i) {
            uint64_t type = 0, count = 0;
            if (!name() || !uint(4, &type) || !uint(count_bytes, &count) || type_size(type) == 0 ||
                count > (uint64_t(1) << 40) || !skip(padded(count * type_size(type))))
                return false;
        }
        return true;
    };
    uint64_t records = 0, tag = 0, n_dims = 0;
    if (!uint(count_bytes, &records) || !list(&tag, &n_dims) || (tag != 0 && tag != 0x0A) ||
        n_dims > (uint64_t(1) << 20))
        return ClassicHeader::damaged;
    std::vector<uint64_t> dim_length(static_cast<size_t>(n_dims));
    for (uint64_t &length : dim_length)
        if (!name() || !uint(count_bytes, &length)) return ClassicHeader::damaged;
    if (!attributes()) return ClassicHeader::damaged;
    uint64_t n_vars = 0;
    if (!list(&tag, &n_vars) || (tag != 0 && tag != 0x0B) || n_vars > (uint64_t(1) << 20)) return ClassicHeader::damaged;
    *end = 0;
    for (uint64_t i = 0; i < n_vars; ++i) {
        uint64_t rank = 0, type = 0, vsize = 0, begin = 0;
        if (!name() || !uint(count_bytes, &rank) || rank > 1024) return ClassicHeader::damaged;
        bool record = false;
        long double size = 1;
        for (uint64_t k = 0; k < rank; ++k) {
            uint64_t dim = 0;
            if (!uint(count_bytes, &dim) || dim >= n_dims) return ClassicHeader::damaged;
            if (dim_length[dim] == 0) record = true;
            else size *= static_cast<long double>(dim_length[dim]);
        }
        if (!attributes() || !uint(4, &type) || !uint(count_bytes, &vsize) || !uint(version == 1 ? 4 : 8, &begin) ||
            type_size(type) == 0)
            return ClassicHeader::damaged;
        size *= static_cast<long double>(type_size(type));
        if (!record && size < 1e19L) *end = std::max<uint64_t>(*end, begin + static_cast<uint64_t>(size));
    }
    return ClassicHeader::sound;
}

struct NcFile {
    int id = -1;
    explicit NcFile(const std::string &path) {
        if (nc_open(path.c_str(), NC_NOWRITE, &id) != NC_NOERR) id = -1;
    }
    // "" or why the file cannot be read as it is: its classic header is
    // damaged, or the file is shorter than the header says.
    static std::string header_problem(const std::string &path) {
        uint64_t end = 0;
        const ClassicHeader header = walk_classic_header(path, &end);
        if (header == ClassicHeader::damaged)
            return "the netCDF header is damaged (a count, length or name it declares does not fit the file)";
        std::error_code ec;
        const uintmax_t size = std::filesystem::file_size(path, ec);
        if (header != ClassicHeader::sound || ec || size >= end) return "";
        return "the file is truncated: it has " + std::to_string(size) + " bytes, its header promises " +
               std::to_string(end);
    }
    ~NcFile() {
        if (id >= 0) nc_close(id);
    }
    NcFile(const NcFile &) = delete;
    NcFile &operator=(const NcFile &) = delete;
    bool ok() const { return id >= 0; }

    bool dim(const char *name, size_t *n) const {
        int d = 0;
        return nc_inq_dimid(id, name, &d) == NC_NOERR && nc_inq_dimlen(id, d, n) == NC_NOERR;
    }
    // Whether variable v holds exactly n numbers (the product of its
    // dimensions, without overflow).
    bool holds(int v, size_t n) const {
        int ndims = 0, dims[NC_MAX_VAR_DIMS];
        nc_type type = NC_NAT;
        if (nc_inq_varndims(id, v, &ndims) != NC_NOERR || ndims < 0 || ndims > NC_MAX_VAR_DIMS ||
            nc_inq_vardimid(id, v, dims) != NC_NOERR || nc_inq_vartype(id, v, &type) != NC_NOERR)
            return false;
        if (type == NC_CHAR || type == NC_STRING || type > NC_MAX_ATOMIC_TYPE) return false;
        size_t count = 1;
        for (int k = 0; k < ndims; ++k) {
            size_t length = 0;
            if (nc_inq_dimlen(id, dims[k], &length) != NC_NOERR) return false;
            if (length != 0 && count > SIZE_MAX / length) return false;
            count *= length;
        }
        return count == n;
    }
    // The whole variable, n values (int32 or double by T); false when it is
    // missing or does not hold exactly n numbers (nothing is read then).
    template <class T>
    bool var(const char *name, std::vector<T> &out, size_t n) const {
        int v = 0;
        if (nc_inq_varid(id, name, &v) != NC_NOERR || !holds(v, n)) return false;
        out.resize(n);
        if constexpr (sizeof(T) == 4) return nc_get_var_int(id, v, reinterpret_cast<int *>(out.data())) == NC_NOERR;
        else return nc_get_var_double(id, v, reinterpret_cast<double *>(out.data())) == NC_NOERR;
    }
    bool global(const char *name, double *value) const {
        return nc_get_att_double(id, NC_GLOBAL, name, value) == NC_NOERR;
    }
};
