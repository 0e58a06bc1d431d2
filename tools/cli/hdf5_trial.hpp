// netCDF-4 files are read by libhdf5, which is not hardened against damaged
// files: one wrong byte can crash it, or make it read for ever (found by
// mutating files; netCDF-C cannot check an HDF5 file before it opens it, as
// the library does for classic spacing files). The library cannot protect
// its host from that; the command line can: it reads such files in a
// forked child first (spacing files), or wholly (check and quality).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

// Whether path starts with the HDF5 signature (at 0 or 512, 1024, ...).
bool is_hdf5_file(const std::string &path);

// fn run in a forked child (stdout flushed before and in it), stopped after
// `seconds` (0: no limit): its exit code; or kTrialDied with *death saying
// how it died, or kTrialNotRun with *death saying why no trial could be
// made (fn is then not run: a crash it risks stays out of this process).
constexpr int kTrialDied = -1, kTrialNotRun = -2;
int run_in_trial_process(const std::function<int()> &fn, unsigned seconds, std::string *death);

// "" when path is no HDF5 file, or when a child read it without dying (the
// read may still have failed: the build's own read reports that); else why
// the file is refused. memory_cap_bytes is the cap the child's read runs
// under (0: none); a child still reading after `seconds` is stopped and the
// file refused.
std::string crash_reading_spacing_file(const std::string &path, int64_t memory_cap_bytes, unsigned seconds);

// The time a trial read of a file of this size gets: 20 s, and 1 s more per
// 50 MB (reading at well above 50 MB/s).
unsigned trial_read_seconds(const std::string &path);
