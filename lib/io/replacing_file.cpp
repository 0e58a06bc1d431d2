#include "io/replacing_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>

#include "core/error.hpp"
#include "core/text.hpp"
#include "io/error_text.hpp"

namespace um::io {

namespace {

// Temporary names differ between the files one process writes at once.
std::atomic<uint64_t> next_serial{0};

std::string directory_of(const std::string &path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

// Flushes a directory's entries (the rename) to disk; best effort: some
// file systems refuse to open or sync directories.
void sync_directory(const std::string &dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

ReplacingFile::ReplacingFile(const std::string &path, const char *what) : path_(path), what_(what) {
    if (path.empty()) fail(UM_ERR_IO, "cannot write ", what, ": the path is empty");
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) fail(UM_ERR_IO, "cannot write ", what, " '", path, "': it is a directory");
        if (!S_ISREG(st.st_mode))
            fail(UM_ERR_IO, "cannot write ", what, " '", path, "': it is not a regular file (a device, FIFO or socket)");
    }
    const std::string dir = directory_of(path);
    const std::string name = path.substr(path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1);
    for (int attempt = 0; attempt < 100; ++attempt) {
        temporary_ = concat(dir, "/.", name, ".part-", static_cast<long long>(::getpid()), "-",
                            static_cast<unsigned long long>(next_serial.fetch_add(1)));
        fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ >= 0) return;
        if (errno != EEXIST)
            fail(UM_ERR_IO, "cannot write ", what, " '", path, "': cannot create a file in '", dir, "': ",
                 system_error_text(errno));
    }
    fail(UM_ERR_IO, "cannot write ", what, " '", path, "': no free temporary name in '", dir, "'");
}

ReplacingFile::~ReplacingFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(temporary_.c_str());
}

void ReplacingFile::write_at(uint64_t offset, const void *data, size_t n) const {
    const char *p = static_cast<const char *>(data);
    while (n > 0) {
        const ssize_t wrote = ::pwrite(fd_, p, n, static_cast<off_t>(offset));
        if (wrote < 0 && errno == EINTR) continue;
        if (wrote <= 0)
            fail(UM_ERR_IO, "cannot write ", what_, " '", path_, "': ",
                 wrote < 0 ? system_error_text(errno) : std::string("the device took no bytes"));
        p += wrote, offset += static_cast<uint64_t>(wrote), n -= static_cast<size_t>(wrote);
    }
}

void ReplacingFile::start_writeback() const {
#ifdef SYNC_FILE_RANGE_WRITE
    (void)::sync_file_range(fd_, 0, 0, SYNC_FILE_RANGE_WRITE);  // a hint: commit's fsync reports errors
#endif
}

void ReplacingFile::commit() {
    const bool synced = ::fsync(fd_) == 0;
    const int sync_error = errno;
    if (!synced) fail(UM_ERR_IO, "cannot write ", what_, " '", path_, "': flushing it: ", system_error_text(sync_error));
    if (::rename(temporary_.c_str(), path_.c_str()) != 0)
        fail(UM_ERR_IO, "cannot write ", what_, " '", path_, "': renaming it into place: ", system_error_text(errno));
    committed_ = true;
    sync_directory(directory_of(path_));
}

}  // namespace um::io
