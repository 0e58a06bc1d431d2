// libFuzzer target: the command-line tool's case-file reader (TOML) on
// arbitrary bytes. It must read the file or give a one-line error.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "case_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const std::string path = "/tmp/unimesh-fuzz-case-" + std::to_string(getpid()) + ".toml";
    FILE *f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data, 1, size, f);
    std::fclose(f);
    BuildArgs args;
    std::string error;
    if (!read_case_file(path, GivenFlags{}, args, &error) && (error.empty() || error.find('\n') != std::string::npos))
        __builtin_trap();  // a refusal must say why, on one line
    return 0;
}
