// libFuzzer target: the MPAS-tools spacing-file reader (netCDF) on arbitrary
// bytes, written to a scratch file first (netCDF reads paths). Refusals are
// um::Error; anything else is a bug. A netCDF-4 (HDF5) input goes first
// through the command line's trial read (tools/cli/hdf5_trial): libhdf5
// may crash on it, in the child, which the probe must turn into a refusal;
// read here only when the child survived, as unimesh build does.
#include <netcdf.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/context.hpp"
#include "core/error.hpp"
#include "io/spacing_file.hpp"
#include "scratch_file.hpp"
#include "hdf5_trial.hpp"

// libhdf5 allocates its global state with the first netCDF-4 file a process
// writes or reads, and keeps it: done here, before the fuzzer counts
// allocations, so that it is not taken for a leak of the first such input.
extern "C" int LLVMFuzzerInitialize(int *, char ***) {
    const std::string path = "/tmp/unimesh-fuzz-hdf5-" + std::to_string(getpid()) + ".nc";
    int id = 0;
    if (nc_create(path.c_str(), NC_NETCDF4 | NC_CLOBBER, &id) == NC_NOERR && nc_close(id) == NC_NOERR &&
        nc_open(path.c_str(), NC_NOWRITE, &id) == NC_NOERR)
        nc_close(id);
    std::remove(path.c_str());
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string path = write_scratch_file("spacing", ".nc", data, size);
    if (path.empty()) return 0;
    constexpr int64_t kCap = int64_t(256) << 20;  // a hostile header may claim a huge grid
    constexpr unsigned kTrialSeconds = 5;  // well inside the fuzzer's timeout: a loop is the probe's to stop
    if (!crash_reading_spacing_file(path, kCap, kTrialSeconds).empty()) return 0;
    um::Context ctx;
    ctx.set_memory_cap(kCap);
    try {
        auto grid = um::io::read_spacing_file(path, ctx);
        (void)grid;
    } catch (const um::Error &) {
    }
    return 0;
}
