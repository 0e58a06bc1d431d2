// libFuzzer target: the MPAS-tools spacing-file reader (netCDF) on arbitrary
// bytes, written to a scratch file first (netCDF reads paths). Refusals are
// um::Error; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/context.hpp"
#include "core/error.hpp"
#include "io/spacing_file.hpp"
#include "scratch_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string path = write_scratch_file("spacing", ".nc", data, size);
    if (path.empty()) return 0;
    um::Context ctx;
    ctx.set_memory_cap(int64_t(256) << 20);  // a hostile header may claim a huge grid
    try {
        auto grid = um::io::read_spacing_file(path, ctx);
        (void)grid;
    } catch (const um::Error &) {
    }
    return 0;
}
