// netCDF-4 spacing files are read by libhdf5, which is not hardened against
// damaged files: one wrong byte can crash it inside the library (found by
// mutating files; netCDF-C cannot check an HDF5 file before it opens it, as
// the library does for classic files). The library cannot protect its host
// from that; the command line can: it reads such a file once in a child
// process first, and refuses it with a message when the child dies.
#pragma once

#include <cstdint>
#include <string>

// "" when path is no HDF5 file, or when a child read it without dying (the
// read may still have failed: the build's own read reports that); else why
// the file is refused. memory_cap_bytes is the cap the child's read runs
// under (0: none); a child still reading after `seconds` is stopped (libhdf5
// loops for ever on some damaged files) and the file refused.
std::string crash_reading_spacing_file(const std::string &path, int64_t memory_cap_bytes, unsigned seconds);

// The time a trial read of a file of this size gets: 20 s, and 1 s more per
// 50 MB (reading at well above 50 MB/s).
unsigned trial_read_seconds(const std::string &path);
