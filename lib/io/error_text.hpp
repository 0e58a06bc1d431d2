// Error texts of the readers and writers, in fixed English: strerror (and
// netCDF-C's text for system errors, which calls it) follows the host's
// locale, and messages must not change with it.
#pragma once

#include <string>

namespace um::io {

// A system error number (errno) as text.
std::string system_error_text(int error);
// A netCDF-C status as text: its own fixed message, or system_error_text for
// the system errors (status > 0) it passes through.
std::string netcdf_status_text(int status);

}  // namespace um::io
