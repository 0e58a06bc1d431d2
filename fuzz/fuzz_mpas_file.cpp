// libFuzzer target: the readers of MPAS mesh files on arbitrary bytes,
// written to a scratch file first: `unimesh check` and `unimesh quality`
// (the command line's reader and checks), and the library's reader behind
// um_mpas_file_write_components (which then cuts the components and writes
// their files into a scratch directory). Each must judge the file or refuse
// it, never read outside what it allocated (ASan) or crash. The commands'
// reports go to stdout: run with -close_fd_mask=1 (tools/fuzz.sh does).
#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "mesh_file_commands.hpp"
#include "scratch_file.hpp"
#include "unimesh.h"

namespace {

um_context *context() {
    static um_context *ctx = [] {
        um_context *c = nullptr;
        if (um_context_create(&c) != UM_OK) __builtin_trap();
        um_context_set_threads(c, 1);
        um_context_set_memory_cap(c, int64_t(1) << 30);  // the fuzzer's RSS limit is 3 GB
        return c;
    }();
    return ctx;
}

const std::string &components_dir() {
    static const std::string dir = [] {
        std::string d = "/tmp/unimesh-fuzz-components-" + std::to_string(getpid());
        mkdir(d.c_str(), 0700);
        return d;
    }();
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string path = write_scratch_file("mpas", ".nc", data, size);
    if (path.empty()) return 0;
    for (int status : {run_check(path), run_quality(path, false), run_quality(path, true)})
        if (status != 0 && status != 1) __builtin_trap();  // 0 judged, 1 refused or failed
    const um_status status = um_mpas_file_write_components(context(), path.c_str(), components_dir().c_str());
    if (status == UM_ERR_INTERNAL) __builtin_trap();  // an exception the library did not expect
    um_context_clear_error(context());
    return 0;
}
