// libFuzzer target: the MPAS-tools spacing-file reader (netCDF) on arbitrary
// bytes, written to a scratch file first (netCDF reads paths). Refusals are
// um::Error; anything else is a bug. A netCDF-4 (HDF5) input goes first
// through the command line's trial read (tools/cli/spacing_probe): libhdf5
// may crash on it, in the child, which the probe must turn into a refusal;
// read here only when the child survived, as unimesh build does.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/context.hpp"
#include "core/error.hpp"
#include "io/spacing_file.hpp"
#include "scratch_file.hpp"
#include "spacing_probe.hpp"

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
