#include "io/nc_output.hpp"

#include <netcdf.h>

#include "core/error.hpp"
#include "io/error_text.hpp"

namespace um::io {

NcOutput::NcOutput(const std::string &path, int mode, const char *what)
    : path_(path), what_(what), file_(path, what) {
    // netCDF's classic I/O goes through its own buffer, by default the file
    // system's block (4 KiB); 1 MiB wrote a mesh file in half the time when
    // its values went through netCDF (4 MiB no faster, 16 and 64 MiB slower:
    // tools/bench/HISTORY.md). The MPAS writer now puts a classic file's
    // values itself; other files still use it.
    size_t buffer_bytes = size_t(1) << 20;
    int status = nc__create(file_.temporary_path().c_str(), mode | NC_CLOBBER, 0, &buffer_bytes, &id_);
    if (status != NC_NOERR) {
        id_ = -1;
        fail(UM_ERR_IO, "cannot create ", what_, " '", path, "': ", netcdf_status_text(status));
    }
}

NcOutput::~NcOutput() {
    if (id_ >= 0) nc_abort(id_);
}

void NcOutput::check(int status, const char *doing, const char *name) const {
    if (status != NC_NOERR)
        fail(UM_ERR_IO, "cannot write ", what_, " '", path_, "': ", doing, name, ": ", netcdf_status_text(status));
}

void NcOutput::put_text(int var, const char *name, const std::string &value) const {
    check(nc_put_att_text(id_, var, name, value.size(), value.data()), "writing attribute ", name);
}

void NcOutput::close() {
    close_netcdf();
    commit();
}

void NcOutput::close_netcdf() {
    int status = nc_close(id_);
    id_ = -1;  // nc_close frees the id even when flushing fails
    check(status, "closing the file");
}

}  // namespace um::io
