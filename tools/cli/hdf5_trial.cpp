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

// The sanitizers' run-time, when this program is built with one (fuzzing,
// tests): a child's death by libhdf5's fault is the expected outcome of a
// trial, not a finding of the parent's run, so the child drops the death
// callback through which a fuzzer records the input as crashing.
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*callback)(void));

namespace {

// In the child: the dispositions it needs whatever the parent installed (a
// SIGALRM handler would keep it from being stopped; a fuzzer's or
// sanitizer's crash handler would report its death as the parent's).
void prepare_trial_child(unsigned seconds) {
    if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
    for (int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGALRM}) std::signal(sig, SIG_DFL);
    if (seconds > 0) alarm(seconds);  // SIGALRM's default action ends the child
}

// SIGCHLD ignored (inherited across exec from a parent that ignores it)
// reaps children on their own, and waitpid could not tell how the trial
// ended: the default disposition while a trial runs.
class ChildrenWaitable {
public:
    ChildrenWaitable() {
        struct sigaction now {};
        sigaction(SIGCHLD, nullptr, &now);
        restore_ = now.sa_handler == SIG_IGN;
        if (restore_) {
            saved_ = now;
            struct sigaction dfl {};
            dfl.sa_handler = SIG_DFL;
            sigemptyset(&dfl.sa_mask);
            sigaction(SIGCHLD, &dfl, nullptr);
        }
    }
    ~ChildrenWaitable() {
        if (restore_) sigaction(SIGCHLD, &saved_, nullptr);
    }
    ChildrenWaitable(const ChildrenWaitable &) = delete;
    ChildrenWaitable &operator=(const ChildrenWaitable &) = delete;

private:
    bool restore_ = false;
    struct sigaction saved_ {};
};

}  // namespace

int run_in_trial_process(const std::function<int()> &fn, unsigned seconds, std::string *death) {
    std::fflush(nullptr);
    const ChildrenWaitable waitable;
    const pid_t child = fork();
    if (child < 0) {
        *death = std::string("could not be tried in a child process (fork: ") + std::strerror(errno) + ")";
        return kTrialNotRun;
    }
    if (child == 0) {
        prepare_trial_child(seconds);
        const int code = fn();
        std::fflush(nullptr);
        _exit(code);  // without the parent's exit handlers
    }
    int status = 0;
    while (waitpid(child, &status, 0) < 0) {
        if (errno == EINTR) continue;
        *death = std::string("ended unseen in a trial process (waitpid: ") + std::strerror(errno) + ")";
        return kTrialNotRun;
    }
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    const int signal = WTERMSIG(status);
    *death = signal == SIGALRM
                 ? "did not finish in " + std::to_string(seconds) +
                       " s in a trial process (the HDF5 library loops for ever on some damaged files)"
                 : "killed the HDF5 library (signal " + std::to_string(signal) + ", " + strsignal(signal) +
                       ") in a trial process";
    return kTrialDied;
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
    const int code = run_in_trial_process(read, seconds, &death);
    if (code >= 0) return "";
    if (code == kTrialNotRun) return "reading this netCDF-4 (HDF5) file: it " + death;
    return "reading this netCDF-4 (HDF5) file " + death + ": the file is damaged" +
           (death.find("did not finish") == 0 ? ", or too slow to read (a classic netCDF copy of it is read without this trial)" : "");
}

unsigned trial_read_seconds(const std::string &path) {
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(path, error);
    return 20 + (error ? 0 : static_cast<unsigned>(std::min<std::uintmax_t>(bytes / (50u << 20), 100000)));
}
