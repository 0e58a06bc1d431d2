#include "io/nc_input.hpp"

#include <filesystem>
#include <system_error>

#include <netcdf.h>

#include "core/error.hpp"
#include "io/error_text.hpp"
#include "io/input_file.hpp"
#include "io/netcdf_header.hpp"

namespace um::io {

NcInput::NcInput(const std::string &path, const char *what) {
    require_regular_input(path, what);
    // netCDF-C trusts a classic header's counts and name lengths.
    ClassicLayout layout;
    const std::string problem = read_classic_layout(path, layout);
    if (!problem.empty()) fail(UM_ERR_FILE_FORMAT, what, " '", path, "': its netCDF header is malformed: ", problem);
    int status = nc_open(path.c_str(), NC_NOWRITE, &id_);
    // netCDF returns errno values (> 0) for system errors and its own
    // negative codes when the bytes are not a readable netCDF file.
    if (status > 0) fail(UM_ERR_IO, "cannot open ", what, " '", path, "': ", netcdf_status_text(status));
    if (status != NC_NOERR) {
        id_ = -1;
        fail(UM_ERR_FILE_FORMAT, what, " '", path, "': not a readable netCDF file (", netcdf_status_text(status),
             "): not netCDF, damaged or truncated");
    }
    try {
        check_classic_length(path, what, layout);
    } catch (...) {
        nc_close(id_);
        throw;
    }
}

NcInput::~NcInput() {
    if (id_ >= 0) nc_close(id_);
}

void NcInput::check_classic_length(const std::string &path, const char *what, const ClassicLayout &layout) const {
    if (!layout.classic) return;
    const uint64_t needed = layout.header_bytes + layout.data_bytes;
    std::error_code error;
    const auto actual = std::filesystem::file_size(path, error);
    if (!error && uint64_t(actual) < needed)
        fail(UM_ERR_FILE_FORMAT, what, " '", path, "': the file is truncated: it has ", uint64_t(actual),
             " bytes, its header and data need at least ", needed);
}

}  // namespace um::io
