// libFuzzer target: the command-line tool's case-file reader (TOML) on
// arbitrary bytes. It must read the file or give a one-line error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "case_file.hpp"
#include "scratch_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string path = write_scratch_file("case", ".toml", data, size);
    if (path.empty()) return 0;
    BuildArgs args;
    std::string error;
    if (!read_case_file(path, GivenFlags{}, args, &error) && (error.empty() || error.find('\n') != std::string::npos))
        __builtin_trap();  // a refusal must say why, on one line
    return 0;
}
