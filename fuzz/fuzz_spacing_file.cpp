// libFuzzer target: the MPAS-tools spacing-file reader (netCDF) on arbitrary
// bytes, written to a scratch file first (netCDF reads paths). Refusals are
// um::Error; anything else is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/context.hpp"
#include "core/error.hpp"
#include "io/spacing_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const std::string path = "/tmp/unimesh-fuzz-spacing-" + std::to_string(getpid()) + ".nc";
    FILE *f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data, 1, size, f);
    std::fclose(f);
    um::Context ctx;
    ctx.set_memory_cap(int64_t(256) << 20);  // a hostile header may claim a huge grid
    try {
        auto grid = um::io::read_spacing_file(path, ctx);
        (void)grid;
    } catch (const um::Error &) {
    }
    return 0;
}
