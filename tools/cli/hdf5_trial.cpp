#include "hdf5_trial.hpp"

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

int run_in_trial_process(const std::function<int()> &fn, unsigned seconds, std::string *death) {
    std::fflush(nullptr);
    const pid_t child = fork();
    if (child < 0) return fn();  // no child to try it in: run it here
    if (child == 0) {
        if (seconds > 0) alarm(seconds);  // SIGALRM's default action ends the child
        const int code = fn();
        std::fflush(nullptr);
        _exit(code);  // without the parent's exit handlers
    }
    int status = 0;
    while (waitpid(child, &status, 0) < 0)
        if (errno != EINTR) return fn();
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    const int signal = WTERMSIG(status);
    *death = signal == SIGALRM
                 ? "did not finish in " + std::to_string(seconds) +
                       " s in a trial process (the HDF5 library loops for ever on some damaged files)"
                 : "killed the HDF5 library (signal " + std::to_string(signal) + ", " + strsignal(signal) +
                       ") in a trial process";
    return -1;
}

std::string crash_reading_spacing_file(const std::string &path, int64_t memory_cap_bytes, unsigned seconds) {
    if (!is_hdf5_file(path)) return "";
    // The read the build will make.
    auto read = [&] {
        um_context *ctx = nullptr;
        um_spacing *h = nullptr;
        if (um_context_create(&ctx) == UM_OK && um_context_set_threads(ctx, 1) == UM_OK &&
            um_context_set_memory_cap(ctx, memory_cap_bytes) == UM_OK)
            um_spacing_create_from_file(ctx, path.c_str(), &h);
        return 0;
    };
    std::string death;
    if (run_in_trial_process(read, seconds, &death) >= 0) return "";
    return "reading this netCDF-4 (HDF5) file " + death + ": the file is damaged" +
           (death.find("did not finish") == 0 ? ", or too slow to read (a classic netCDF copy of it is read without this trial)" : "");
}

unsigned trial_read_seconds(const std::string &path) {
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(path, error);
    return 20 + (error ? 0 : static_cast<unsigned>(std::min<std::uintmax_t>(bytes / (50u << 20), 100000)));
}
