// libFuzzer target: `unimesh check` and `unimesh quality` (the command
// line's MPAS-file reader and checks) on arbitrary bytes, written to a
// scratch file first. Each must judge the file or refuse it (exit 1), never
// read outside what it allocated (ASan) or crash. Their reports go to
// stdout: run with -close_fd_mask=1 (tools/fuzz.sh does).
#include <cstddef>
#include <cstdint>
#include <string>

#include "mesh_file_commands.hpp"
#include "scratch_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string path = write_scratch_file("mpas", ".nc", data, size);
    if (path.empty()) return 0;
    for (int status : {run_check(path), run_quality(path, false), run_quality(path, true)})
        if (status != 0 && status != 1) __builtin_trap();  // 0 judged, 1 refused or failed
    return 0;
}
