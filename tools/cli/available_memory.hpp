// The machine's available memory, for the command line's default memory
// cap (build) and the refusal of mesh files too large to judge (check,
// quality).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

// MemAvailable from /proc/meminfo in bytes, or 0 when unknown.
inline int64_t available_memory() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key, unit;
    int64_t kb = 0;
    while (meminfo >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024;
    return 0;
}
