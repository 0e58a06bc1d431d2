// A netCDF file opened for reading, closed on every way out, after the
// checks a hostile or damaged file needs before netCDF-C trusts it: a
// regular file (input_file.hpp), a sound classic header (netcdf_header.hpp)
// and, for the classic formats, a length that holds the header and every
// variable (netCDF-C reads a truncated file's missing tail as zeros). Lives
// inside a NetcdfLock.
#pragma once

#include <string>

#include "io/netcdf_header.hpp"

namespace um::io {

class NcInput {
public:
    // what names the kind of file in errors ("spacing file"): UM_ERR_IO when
    // the file cannot be opened, UM_ERR_FILE_FORMAT "<what> '<path>': ..."
    // when it is not a sound netCDF file.
    NcInput(const std::string &path, const char *what);
    ~NcInput();
    NcInput(const NcInput &) = delete;
    NcInput &operator=(const NcInput &) = delete;
    int id() const { return id_; }

private:
    // netCDF-C reads the missing tail of a truncated classic file as zeros
    // without an error: the length is checked against what the header declares.
    void check_classic_length(const std::string &path, const char *what, const ClassicLayout &layout) const;
    int id_ = -1;
};

}  // namespace um::io
