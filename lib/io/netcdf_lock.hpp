// netCDF-C is not thread-safe: every netCDF call of the library, whatever
// file it is on, runs while holding this one process-wide mutex (on the host
// thread, outside the context's arena). Readers and writers (spacing files,
// the MPAS mesh writer) take it for the whole of their file's lifetime.
#pragma once

#include <mutex>

namespace um::io {

std::mutex &netcdf_mutex();

// Holds netcdf_mutex() for its lifetime.
class NetcdfLock {
public:
    NetcdfLock() : lock_(netcdf_mutex()) {}

private:
    std::lock_guard<std::mutex> lock_;
};

}  // namespace um::io
