// A netCDF file being created under a temporary name (ReplacingFile):
// errors throw UM_ERR_IO naming the final path and the kind of file; close()
// renames it into place, and without that the destructor aborts it and
// removes the temporary file only. A writer that puts a classic file's
// values at their offsets itself ends netCDF's part with close_netcdf(),
// writes through file() and then commit()s. Callers hold the NetcdfLock
// while netCDF is called.
#pragma once

#include <string>

#include "io/replacing_file.hpp"

namespace um::io {

class NcOutput {
public:
    // what: the kind of file, for errors ("MPAS mesh file"); mode: nc_create's.
    NcOutput(const std::string &path, int mode, const char *what);
    ~NcOutput();
    NcOutput(const NcOutput &) = delete;
    NcOutput &operator=(const NcOutput &) = delete;

    int id() const { return id_; }
    // Throws UM_ERR_IO unless status is NC_NOERR: "cannot write <what> '<path>': <doing><name>: <reason>".
    void check(int status, const char *doing, const char *name = "") const;
    void put_text(int var, const char *name, const std::string &value) const;
    // close_netcdf(), then commit().
    void close();
    // netCDF's nc_close (a classic file is then as long as its header says),
    // leaving the file under its temporary name.
    void close_netcdf();
    const std::string &temporary_path() const { return file_.temporary_path(); }
    // The file itself (ReplacingFile::write_at), after close_netcdf().
    const ReplacingFile &file() const { return file_; }
    void commit() { file_.commit(); }
    // ReplacingFile::start_writeback: for a file written in many blocks.
    void start_writeback() const { file_.start_writeback(); }

private:
    std::string path_, what_;
    ReplacingFile file_;
    int id_ = -1;
};

}  // namespace um::io
