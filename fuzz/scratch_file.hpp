// For the fuzz targets whose reader takes a path: the input bytes written
// to a file of this process (one per target and process, reused).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

// The path written, or "" when the file cannot be written (the input is
// then skipped).
inline std::string write_scratch_file(const char *target, const char *suffix, const uint8_t *data, size_t size) {
    const std::string path = std::string("/tmp/unimesh-fuzz-") + target + "-" + std::to_string(getpid()) + suffix;
    FILE *f = std::fopen(path.c_str(), "wb");
    if (!f) return "";
    const bool written = std::fwrite(data, 1, size, f) == size;
    return std::fclose(f) == 0 && written ? path : "";
}
