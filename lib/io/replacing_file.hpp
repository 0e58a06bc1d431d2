// An output file written under a temporary name in the directory of its
// final path and renamed over that path only when complete (after an
// fsync), so that a failed or interrupted write never removes or damages
// what was there: readers see the old file or the whole new one. A path
// that names something other than a regular file (a directory, a device, a
// FIFO) is refused before anything is written: renaming over it would
// replace it, and writing into it in place could not be undone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace um::io {

class ReplacingFile {
public:
    // `what` names the file in errors ("MPAS mesh file"). Throws UM_ERR_IO
    // when the path cannot be written this way; creates the temporary file
    // (empty, with the permissions a new file gets).
    ReplacingFile(const std::string &path, const char *what);
    ~ReplacingFile();  // removes the temporary file unless committed
    ReplacingFile(const ReplacingFile &) = delete;
    ReplacingFile &operator=(const ReplacingFile &) = delete;

    // Where to write.
    const std::string &temporary_path() const { return temporary_; }
    // Writes n bytes at byte `offset` of the temporary file (pwrite: the
    // file's position is not used); throws UM_ERR_IO naming the path.
    void write_at(uint64_t offset, const void *data, size_t n) const;
    // Flushes the temporary file to disk and renames it over the final
    // path; throws UM_ERR_IO naming the path when that fails (the old file
    // is then still there).
    void commit();
    // Starts writing to disk what has been written so far, without waiting
    // for it (Linux's sync_file_range; elsewhere nothing), so that commit's
    // flush of a large file is not one long wait at the end while the
    // writes could have gone on beside the work.
    void start_writeback() const;

private:
    std::string path_, temporary_, what_;
    int fd_ = -1;  // the temporary file (later the final one), open until destroyed
    bool committed_ = false;
};

}  // namespace um::io
