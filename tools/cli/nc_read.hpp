// Reading an MPAS mesh file back (netCDF-C): what graph.info, mesh.vtu,
// `unimesh check` and `unimesh quality` need. Header-only and small.
#pragma once

#include <netcdf.h>

#include <cstdint>
#include <string>
#include <vector>

struct NcFile {
    int id = -1;
    explicit NcFile(const std::string &path) {
        if (nc_open(path.c_str(), NC_NOWRITE, &id) != NC_NOERR) id = -1;
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
    // The whole variable, n values (int32 or double by T).
    template <class T>
    bool var(const char *name, std::vector<T> &out, size_t n) const {
        int v = 0;
        out.resize(n);
        if (nc_inq_varid(id, name, &v) != NC_NOERR) return false;
        if constexpr (sizeof(T) == 4) return nc_get_var_int(id, v, reinterpret_cast<int *>(out.data())) == NC_NOERR;
        else return nc_get_var_double(id, v, reinterpret_cast<double *>(out.data())) == NC_NOERR;
    }
    bool global(const char *name, double *value) const {
        return nc_get_att_double(id, NC_GLOBAL, name, value) == NC_NOERR;
    }
};
