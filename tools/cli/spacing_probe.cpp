#include "spacing_probe.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "unimesh.h"

namespace {

// The HDF5 superblock's signature, at offset 0 or at 512, 1024, 2048, ...
// (a user block before it): the HDF5 file format specification.
bool is_hdf5_file(const std::string &path) {
    static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
    std::ifstream f(path, std::ios::binary);
    for (std::streamoff at = 0;; at = at == 0 ? 512 : 2 * at) {
        char head[8];
        f.seekg(at);
        if (!f.read(head, sizeof head)) return false;
        if (std::memcmp(head, kSignature, sizeof head) == 0) return true;
    }
}

// The child: the read the build will make, then out without the parent's
// exit handlers or buffered output.
[[noreturn]] void read_in_child(const std::string &path, int64_t memory_cap_bytes, unsigned seconds) {
    alarm(seconds);  // SIGALRM's default action ends the child
    um_context *ctx = nullptr;
    um_spacing *h = nullptr;
    if (um_context_create(&ctx) == UM_OK && um_context_set_threads(ctx, 1) == UM_OK &&
        um_context_set_memory_cap(ctx, memory_cap_bytes) == UM_OK)
        um_spacing_create_from_file(ctx, path.c_str(), &h);
    _exit(0);
}

}  // namespace

unsigned trial_read_seconds(const std::string &path) {
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(path, error);
    return 20 + (error ? 0 : static_cast<unsigned>(std::min<std::uintmax_t>(bytes / (50u << 20), 100000)));
}

std::string crash_reading_spacing_file(const std::string &path, int64_t memory_cap_bytes, unsigned seconds) {
    if (!is_hdf5_file(path)) return "";
    std::fflush(nullptr);
    const pid_t child = fork();
    if (child < 0) return "";  // no child to try it in: the build reads it as it is
    if (child == 0) read_in_child(path, memory_cap_bytes, seconds);
    int status = 0;
    while (waitpid(child, &status, 0) < 0)
        if (errno != EINTR) return "";
    if (!WIFSIGNALED(status)) return "";
    const int signal = WTERMSIG(status);
    if (signal == SIGALRM)
        return "reading this netCDF-4 (HDF5) file did not finish in " + std::to_string(seconds) +
               " s in a trial process (the HDF5 library loops for ever on some damaged files): the file is "
               "damaged, or too slow to read (a classic netCDF copy of it is read without this trial)";
    return "reading this netCDF-4 (HDF5) file killed the HDF5 library (signal " + std::to_string(signal) +
           ", " + strsignal(signal) + ") in a trial process: the file is damaged";
}
